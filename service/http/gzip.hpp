#pragma once
// gzip content coding of responses (RFC 9110 8.4.1.3): what a client accepts, and the bytes.

#include <string>
#include <string_view>

namespace slosh::service {

/// Whether an Accept-Encoding header value accepts the gzip coding: a "gzip" (or "x-gzip") or "*"
/// member whose q is not 0 (case-insensitive, whitespace tolerated). An empty header accepts only
/// the identity coding.
[[nodiscard]] bool accepts_gzip(std::string_view accept_encoding);

/// `data` in the gzip format (RFC 1952, deflate at `level` 1..9, no file name, modification time
/// 0): the same input gives the same bytes. Throws std::runtime_error when zlib fails (out of
/// memory).
[[nodiscard]] std::string gzip_compress(std::string_view data, int level = 6);

/// Bodies shorter than this are sent uncompressed even when the client accepts gzip: the coding
/// would save at most a few hundred bytes for a deflate state of 256 kB per response [bytes].
constexpr std::size_t kGzipMinBytes{1024};

/// Whether a body of `content_type` and `bytes` is gzip-coded for a client that accepts it: text
/// (JSON, text/*, JavaScript) of at least kGzipMinBytes.
[[nodiscard]] bool worth_compressing(std::string_view content_type, std::size_t bytes);

/// The gzip level of a body coded for one response (a fresh plan, a batch, an export): its speed
/// matters more than the last 10 % of size. The web page's files are coded once at this level too,
/// so their bytes are the ones a per-response coding gives.
constexpr int kResponseGzipLevel{1};

}  // namespace slosh::service
