#pragma once
// An HTTP answer as the handlers build it (status, headers, body, coding), the one way an error
// becomes its reply (the envelope, Retry-After on every 503) and the one exception wrapper every
// handler runs behind. The HTTP library never sees these types: http_server.cpp writes them.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/engine_errors.hpp"
#include "http/plan_facts.hpp"
#include "slosh/api/error.hpp"

namespace slosh::service {

/// An HTTP-level answer.
struct Reply {
  int status{200};
  std::string body;
  std::string content_type{"application/json"};
  /// "gzip" when `body` is already gzip-coded (a cached plan's stored coding); empty: `body` is
  /// the identity coding (the HTTP layer may compress it for a client that accepts gzip).
  std::string content_encoding;
  /// A 304 whose 200 would have been gzip-coded for a client that accepts gzip: its ETag is then
  /// the `;gzip` tag that 200 would carry (RFC 9110 §15.4.5), never the identity tag.
  bool coded_when_accepted{false};
  std::vector<std::pair<std::string, std::string>> headers;
  /// Kept alive until the body has been written to the client (a cam export's reservation of
  /// the export budget); empty for most replies.
  std::shared_ptr<const void> hold;
  /// Set when the reply carries a plan (POST /v1/plans, GET /v1/plans/{key}): for the access log.
  std::optional<PlanFacts> plan;
};

/// The reply of an API error: its status and envelope; every 503 (overloaded, unavailable) adds
/// Retry-After.
Reply reply_of(const api::ApiError& error);

/// The envelope reply of an error code with a message (and optional field): reply_of its error.
Reply error_reply(api::ErrorCode code, const std::string& message, const std::string& field = "");

/// The reply of the 500 envelope for an exception that is not an api::ApiError.
Reply internal_error_reply(const char* what);

/// What `body` returns; an api::ApiError thrown by it becomes its reply (reply_of) and any other
/// exception the 500 envelope, so that an endpoint never throws.
template <typename F>
Reply guarded_reply(F&& body) {
  try {
    return body();
  } catch (const api::ApiError& e) {
    return reply_of(e);
  } catch (const std::exception& e) {
    return internal_error_reply(e.what());
  } catch (...) {
    return internal_error_reply("unknown error");
  }
}

/// "\"<key>\"": the strong entity tag of a body named by `key`.
[[nodiscard]] std::string etag(const std::string& key);

/// The entity tag of the gzip coding of the body tagged `tag` ("\"<key>\"" -> "\"<key>;gzip\""):
/// a strong tag names bytes, and the coded bytes differ from the identity ones (RFC 9110 8.8.3.3).
[[nodiscard]] std::string gzip_etag(const std::string& tag);

/// Whether an If-None-Match header names `tag` or its gzip coding's tag (either coding of the
/// same body is still fresh): "*", or a list of tags compared weakly (RFC 9110 13.1.2: W/"x"
/// matches "x").
[[nodiscard]] bool etag_matches(const std::string& header, const std::string& tag);

}  // namespace slosh::service
