#include "http/gzip.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace slosh::service {

namespace {

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool equals_lower(std::string_view a, std::string_view lower) {
  return a.size() == lower.size() &&
         std::equal(a.begin(), a.end(), lower.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == y;
         });
}

// A qvalue (RFC 9110 12.4.2: "0" to "1" with at most three decimals), 0 for any other text: a
// preference that cannot be read is not taken as consent (the identity coding is always
// acceptable).
double qvalue(std::string_view text) {
  if (text.empty() || (text[0] != '0' && text[0] != '1')) return 0.0;
  if (text.size() > 1 && (text[1] != '.' || text.size() > 5)) return 0.0;
  for (const char c : text.substr(std::min<std::size_t>(2, text.size()))) {
    if (!std::isdigit(static_cast<unsigned char>(c)) || (text[0] == '1' && c != '0')) return 0.0;
  }
  return text[0] == '1' ? 1.0 : std::stod(std::string(text));
}

// The q of a member's parameters ("q=0.5"); 1 when absent.
double quality(std::string_view params) {
  while (!params.empty()) {
    const std::size_t semi = params.find(';');
    const std::string_view param = trimmed(params.substr(0, semi));
    if (param.size() >= 2 && (param[0] == 'q' || param[0] == 'Q') && param[1] == '=') {
      return qvalue(param.substr(2));
    }
    if (semi == std::string_view::npos) break;
    params.remove_prefix(semi + 1);
  }
  return 1.0;
}

}  // namespace

bool accepts_gzip(std::string_view header) {
  bool star = false;
  while (!header.empty()) {
    const std::size_t comma = header.find(',');
    const std::string_view member = header.substr(0, comma);
    const std::size_t semi = member.find(';');
    const std::string_view coding = trimmed(member.substr(0, semi));
    const double q = semi == std::string_view::npos ? 1.0 : quality(member.substr(semi + 1));
    // An explicit gzip member decides, whatever a "*" says.
    if (equals_lower(coding, "gzip") || equals_lower(coding, "x-gzip")) return q > 0.0;
    if (coding == "*") star = q > 0.0;
    if (comma == std::string_view::npos) break;
    header.remove_prefix(comma + 1);
  }
  return star;
}

bool worth_compressing(std::string_view content_type, std::size_t bytes) {
  const bool text = content_type.starts_with("application/json") ||
                    content_type.starts_with("text/") ||
                    content_type.starts_with("application/javascript");
  return text && bytes >= kGzipMinBytes;
}

std::string gzip_compress(std::string_view data, int level) {
  z_stream stream{};
  // windowBits 15 + 16: the gzip wrapper with a zeroed header (no name, mtime 0).
  if (deflateInit2(&stream, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
    throw std::runtime_error("gzip: cannot initialise deflate");
  }
  std::string out(deflateBound(&stream, static_cast<uLong>(data.size())), '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&stream, Z_FINISH);
  const std::size_t written = stream.total_out;
  deflateEnd(&stream);
  if (rc != Z_STREAM_END) throw std::runtime_error("gzip: deflate did not finish");
  out.resize(written);
  return out;
}

}  // namespace slosh::service
