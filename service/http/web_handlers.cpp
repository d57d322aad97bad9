// The handler of the web page's files (GET /, GET /assets/{name}), embedded in the binary.

#include <string>

#include "http/gzip.hpp"
#include "http/plan_service.hpp"
#include "http/web_assets.hpp"

namespace slosh::service {

Reply PlanService::web_asset(const std::string& name, const std::string& if_none_match,
                             bool gzip) const {
  const WebAsset* asset = find_web_asset(name.empty() ? "index.html" : name);
  if (asset == nullptr) {
    return error_reply(api::ErrorCode::kNotFound,
                       "no asset '" + name.substr(0, 64) + "' of the web page", "name");
  }
  Reply r;
  const std::string tag(asset->etag);
  r.headers.emplace_back("ETag", tag);
  // Revalidated on every use (a 304 is a few bytes): a new binary's page is never mixed with an
  // older cached script.
  r.headers.emplace_back("Cache-Control", "no-cache");
  r.headers.emplace_back("X-Content-Type-Options", "nosniff");
  r.headers.emplace_back("Content-Security-Policy", "frame-ancestors 'none'");
  if (etag_matches(if_none_match, tag)) {
    r.status = 304;
    r.coded_when_accepted = worth_compressing(asset->content_type, asset->body.size());
    return r;
  }
  r.content_type = std::string(asset->content_type);
  if (gzip && worth_compressing(asset->content_type, asset->body.size())) {
    r.body = std::string(gzipped_body(*asset));
    r.content_encoding = "gzip";
  } else {
    r.body = std::string(asset->body);
  }
  return r;
}

}  // namespace slosh::service
