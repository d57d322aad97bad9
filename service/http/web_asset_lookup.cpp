#include <memory>
#include <mutex>
#include <string>

#include "http/gzip.hpp"
#include "http/web_assets.hpp"

namespace slosh::service {

const WebAsset* find_web_asset(std::string_view name) {
  for (const WebAsset& asset : web_assets()) {
    if (asset.name == name) return &asset;
  }
  return nullptr;
}

std::string_view gzipped_body(const WebAsset& asset) {
  // One slot per embedded asset, filled once: every later request copies the kept bytes.
  struct Coded {
    std::once_flag once;
    std::string body;
  };
  static const std::unique_ptr<Coded[]> coded(new Coded[web_assets().size()]);
  Coded& slot = coded[static_cast<std::size_t>(&asset - web_assets().data())];
  std::call_once(slot.once, [&] { slot.body = gzip_compress(asset.body, kResponseGzipLevel); });
  return slot.body;
}

}  // namespace slosh::service
