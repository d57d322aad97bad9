#pragma once
// The request and response bodies of the service's endpoints that are not plans or simulations:
// the plan request with the server's budget, the batch body, the batch response, /healthz and
// /readyz. The service moves bytes; the JSON is read and written here.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"

namespace slosh::api {

/// `e` when it is not a refusal of options.time_limit_s by the API's range; else the same
/// refusal naming this server's most, `budget` [s], when that is below the API's ("allowed > 0
/// and <= 10 s (this server's budget)").
[[nodiscard]] ApiError with_server_range(const ApiError& e, double budget);

/// A plan request with the server's budget applied: options.time_limit_s defaults to `budget`;
/// more than `budget` is a 422 naming the field.
[[nodiscard]] PlanRequest parse_plan_with_budget(const nlohmann::json& body, double budget);

/// The same from the body text (400 when it is not JSON).
[[nodiscard]] PlanRequest parse_plan_text(std::string_view text, double budget);

/// A POST /v1/plans/batch body {"requests": [...], "view"?: "full" | "compact"}.
struct BatchBody {
  /// The plan requests (1 to batch_max), unparsed: each item is validated on its own
  /// (parse_batch_item), so one bad item fails alone.
  std::vector<nlohmann::json> requests;
  /// The "view" member as given (nullopt when absent or null); see batch_view.
  std::optional<nlohmann::json> view;
};

/// Reads a batch body (400 when it is not JSON, 422 when it is not of that shape).
[[nodiscard]] BatchBody parse_batch_body(std::string_view text, std::size_t batch_max);

/// The plan requests of a batch body (parse_batch_body's requests).
[[nodiscard]] std::vector<nlohmann::json> parse_batch_text(std::string_view text,
                                                           std::size_t batch_max);

/// One batch item: a plan request with the budget, and no series (a batch answers with plans).
[[nodiscard]] PlanRequest parse_batch_item(const nlohmann::json& item, double budget);

/// One batch item read on its own: its plan request, or why it is not one (so one bad item fails
/// alone while the others are planned).
struct BatchItem {
  std::optional<PlanRequest> request;  ///< set when the item is a valid plan request
  std::optional<ApiError> error;       ///< set otherwise (422 naming the field, ...)
};

/// `item` read as parse_batch_item reads it; never throws (the error is the item's: an
/// unexpected failure is an internal error).
[[nodiscard]] BatchItem read_batch_item(const nlohmann::json& item, double budget);

/// Every item of `items`, in order (read_batch_item).
[[nodiscard]] std::vector<BatchItem> read_batch_items(const std::vector<nlohmann::json>& items,
                                                      double budget);

/// The batch response {"results": [{"index": i, "plan": {...}} | {"index": i, "error": {...}}]},
/// written item by item; a response that would exceed `max_bytes` is refused with a 422 (the
/// plans are cached: smaller batches get them).
class BatchReplyWriter {
 public:
  explicit BatchReplyWriter(std::size_t max_bytes) : max_bytes_(max_bytes) {}
  /// Item i: a rendered plan reply.
  void add_plan(std::size_t index, const std::string& plan);
  /// Item i: an error (its field path is prefixed with requests[i]).
  void add_error(std::size_t index, const ApiError& error);
  /// The whole response text.
  [[nodiscard]] std::string finish();

 private:
  void open_item(std::size_t index, std::size_t extra_bytes);
  std::size_t max_bytes_;
  std::string out_{"{\"results\":["};
  std::size_t items_{0};
};

/// The body of POST /v1/plans/batch for `requests` (the client side: `slosh batch --server`).
[[nodiscard]] std::string batch_body_text(const std::vector<nlohmann::json>& requests);

/// One result of a batch response, read back by the client: the plan as JSON text, or its error
/// with the field path relative to the item's own request (the requests[i]. prefix removed).
struct BatchItemReply {
  std::string plan;
  bool cached{false};
  std::optional<ApiError> error;
};

/// The results of a batch response; nullopt when `text` is not {"results": [...]}.
[[nodiscard]] std::optional<std::vector<BatchItemReply>> parse_batch_reply(std::string_view text);

/// The message of an error envelope (empty when `text` is not one).
[[nodiscard]] std::string envelope_message(std::string_view text);

/// GET /healthz.
[[nodiscard]] std::string health_body(std::string_view version);

/// What GET /readyz reports.
struct ReadyReport {
  std::string status;  ///< ready, degraded, stalled or stopping
  std::string reason;  ///< why not ready; empty when ready
  std::size_t workers{}, busy_workers{}, queue_depth{};
  bool cache_persistent{false};
  std::size_t cache_memory_entries{}, cache_memory_bytes{};
  std::string cache_storage_error;  ///< empty when the store works
  /// The shared Redis level (config cache = redis://...): shown when configured.
  bool redis_configured{false};
  std::string redis_url{};  ///< as RedisUrl::display (no password)
  bool redis_up{false};
  bool redis_required{false};  ///< config redis_required: 503 while down
  std::string redis_error{};   ///< the last failure while down
  /// Why batch jobs' rows or records are held on this replica only (the shared job store refuses
  /// or fails their writes, e.g. Redis at maxmemory); shown as jobs.store_warning when set.
  std::string job_store_warning{};
};

/// GET /readyz.
[[nodiscard]] std::string ready_body(const ReadyReport& report);

}  // namespace slosh::api
