#pragma once
// The log format of `slosh serve` (config log_format, env SLOSH_LOG_FORMAT, --log-format): "text"
// (spdlog's default lines) or "json" (one JSON object per line on the same stream: time, level,
// msg, and for the access log the request's fields).

#include <optional>
#include <string>

#include "http/plan_facts.hpp"

namespace slosh::service {

/// Makes every later message of the default logger come out in `format` ("text" or "json"; any
/// other value is refused by the configuration before this).
void use_log_format(const std::string& format);

/// One answered request, as the access log writes it.
struct AccessLogEntry {
  std::string request_id;
  std::string method;
  std::string route;  ///< the routes-table path that answered, or "other"
  /// The request path as sent (still percent-encoded, without the query; at most 200 bytes): a
  /// '/' sent as %2F is logged as %2F.
  std::string path;
  int status{0};
  std::optional<double> ms;  ///< from routing to the response written; unset if unknown
  std::size_t bytes{0};      ///< body bytes of the response
  std::string cache;         ///< the X-Cache header ("hit", "miss") or empty
  std::optional<PlanFacts> plan;
};

/// Logs `entry` at info level: in the text format as "request id=... method=... path=...
/// status=... cache=... ms=... bytes=..." (plus "route=", and "plan=... strategy=...
/// plan_status=..." for a plan), in the json format as one object with the members time, level,
/// msg ("request"), request_id, method, route, path, status, ms, bytes, and for a plan plan_key,
/// strategy, plan_status and cached. The text format writes a control, space, DEL, backslash or
/// non-ASCII byte of the method or the path as \xNN, so a request can never start a line of its
/// own in the log.
void log_access(const AccessLogEntry& entry);

}  // namespace slosh::service
