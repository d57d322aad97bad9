#pragma once
// The web page of `slosh serve` (web/ and the pinned Chart.js), embedded at build time by
// cmake/embed_assets.cmake: the binary serves it with no files beside it and no internet.

#include <span>
#include <string_view>

namespace slosh::service {

struct WebAsset {
  std::string_view name;          ///< "index.html", "app.js", ...
  std::string_view content_type;  ///< media type with charset
  std::string_view body;          ///< the file's bytes
  std::string_view etag;          ///< strong ETag: the quoted SHA-256 of the bytes
};

/// Every embedded asset.
[[nodiscard]] std::span<const WebAsset> web_assets();

/// The asset named `name`; nullptr when there is none.
[[nodiscard]] const WebAsset* find_web_asset(std::string_view name);

/// The gzip coding (kResponseGzipLevel) of `asset`, one of web_assets(): compressed at its first
/// use and kept for the life of the process (the files never change while it runs).
/// Thread-safe.
[[nodiscard]] std::string_view gzipped_body(const WebAsset& asset);

}  // namespace slosh::service
