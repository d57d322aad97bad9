#include "http/http_reply.hpp"

#include <string>

namespace slosh::service {

Reply reply_of(const api::ApiError& error) {
  Reply r;
  r.status = error.status();
  r.body = api::error_body(error);
  // Every 503 says when to retry: overloaded, and unavailable (the shared store cannot answer now).
  if (error.code() == api::ErrorCode::kOverloaded || error.code() == api::ErrorCode::kUnavailable) {
    r.headers.emplace_back("Retry-After", std::to_string(kRetryAfterSeconds));
  }
  return r;
}

Reply error_reply(api::ErrorCode code, const std::string& message, const std::string& field) {
  return reply_of(api::ApiError(code, field, message));
}

Reply internal_error_reply(const char* what) {
  return error_reply(api::ErrorCode::kInternal, what);
}

std::string etag(const std::string& key) {
  return "\"" + key + "\"";
}

std::string gzip_etag(const std::string& tag) {
  if (tag.size() < 2 || tag.back() != '"') return tag;
  return tag.substr(0, tag.size() - 1) + ";gzip\"";
}

bool etag_matches(const std::string& header, const std::string& tag) {
  const std::string coded = gzip_etag(tag);
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    std::string item = header.substr(at, end - at);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.rfind("W/", 0) == 0) item.erase(0, 2);
    if (item == "*" || item == tag || item == coded) return true;
    at = end + 1;
  }
  return false;
}

}  // namespace slosh::service
