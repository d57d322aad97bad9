#pragma once
// A plan as the service keeps and serves it: rendered once per recipe (StoredPlan), and per reply
// with the members that depend on the request (`cached`, `series`).

#include <optional>
#include <string>
#include <string_view>

#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh::api {

/// A rendered plan without the per-reply members `cached` and `series`.
struct StoredPlan {
  SolveStatus status{SolveStatus::kFailed};
  std::string body;  ///< the plan's JSON object as text
  /// The plan or one of auto's candidates ran out of its time budget (budget_limited).
  bool budget_limited{false};
};

/// Whether a plan with this status is worth keeping: optimal, acceptable and infeasible answers
/// depend only on the recipe; a time-limited or failed one depends on the load.
[[nodiscard]] bool is_cacheable(SolveStatus status);

/// Whether the answer depended on a time budget running out: the plan's status is time_limit, or
/// one of auto's candidates ended time_limit (auto then chose among the others, so a larger
/// budget or a quieter machine may choose another law). Such a plan is never cached: its key
/// holds no time_limit_s, so it would become the answer for every budget.
[[nodiscard]] bool budget_limited(const PlanResult& result);
/// The same read from a stored plan body (the status of the plan or of any candidate is
/// time_limit), for values a cache level holds that an older build may have written.
[[nodiscard]] bool budget_limited(std::string_view stored_body);
/// The warning a plan carries when a candidate ran out of its time budget (empty when none did,
/// or when the plan itself is time_limit: its status says so).
[[nodiscard]] std::string budget_warning(const PlanResult& result);
/// Whether a stored plan body may be kept and served by the cache (is_cacheable of its status
/// and not budget_limited).
[[nodiscard]] bool is_cacheable(const StoredPlan& plan);

/// Plans a validated request (its series are not rendered) for storing; throws ApiError when the
/// planner refuses the inputs (as run_plan).
[[nodiscard]] StoredPlan solve_for_storing(const PlanRequest& request);

/// A stored answer (a non-empty JSON object without `cached`) with `cached` as its first member.
[[nodiscard]] std::string with_cached_flag(std::string_view stored, bool cached);

/// The reply body of a stored plan: `cached` set, and when `sample_period` is given, the series of
/// the plan's law at that period (`request` is the plan's recipe; required with a period); in the
/// compact view (`view`), the compact plan of it (no series: see require_no_series).
[[nodiscard]] std::string render_plan_reply(std::string_view stored_body, bool cached,
                                            const PlanRequest* request = nullptr,
                                            std::optional<double> sample_period = std::nullopt,
                                            PlanView view = PlanView::kFull);

}  // namespace slosh::api
