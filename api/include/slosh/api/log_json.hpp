#pragma once
// The JSON log format of `slosh serve` (log_format "json"): the quoting of any message and the
// members of an access-log line. The service's logger writes the bytes; the JSON is made here.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace slosh::api {

/// `text` as a JSON string literal (quotes included); invalid UTF-8 is replaced by U+FFFD, never
/// thrown on, so any request byte can be logged.
[[nodiscard]] std::string json_quoted(std::string_view text);

/// What a plan reply adds to its access-log line.
struct LoggedPlan {
  std::string key;       ///< the recipe key
  std::string strategy;  ///< the plan's strategy
  std::string status;    ///< the plan's status as in its JSON (optimal, time_limit, ...)
  bool cached{false};    ///< answered from the cache
};

/// One answered request as the JSON access log writes it.
struct LoggedRequest {
  std::string request_id;
  std::string method;
  std::string route;
  std::string path;
  int status{0};
  std::optional<double> ms;  ///< rounded to 1 µs; null when unset
  std::size_t bytes{0};
  std::string cache;  ///< left out when empty
  std::optional<LoggedPlan> plan;
};

/// The access-log line as one JSON object (members sorted by name): msg ("request"), request_id,
/// method, route, path, status, ms, bytes, cache (when set), and for a plan plan_key, strategy,
/// plan_status and cached.
[[nodiscard]] std::string request_log_object(const LoggedRequest& request);

}  // namespace slosh::api
