#include "slosh/api/plan_reply.hpp"

#include <algorithm>

#include "slosh/api/error.hpp"
#include "slosh/api/plan_warnings.hpp"

namespace slosh::api {

bool is_cacheable(SolveStatus status) {
  return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable ||
         status == SolveStatus::kInfeasible;
}

bool budget_limited(const PlanResult& result) {
  if (result.status == SolveStatus::kTimeLimit) return true;
  return std::ranges::any_of(result.candidates, [](const PlanCandidate& c) {
    return c.status == SolveStatus::kTimeLimit;
  });
}

bool budget_limited(std::string_view stored_body) {
  // The stored body is compact JSON (dump_json): a status member reads exactly this way, and no
  // other member holds this text.
  return stored_body.find(R"("status":"time_limit")") != std::string_view::npos;
}

std::string budget_warning(const PlanResult& result) {
  if (result.status == SolveStatus::kTimeLimit) return {};
  std::string names;
  for (const PlanCandidate& c : result.candidates) {
    if (c.status != SolveStatus::kTimeLimit) continue;
    names += (names.empty() ? "" : ", ") + std::string(to_string(c.strategy));
  }
  if (names.empty()) return {};
  return std::string(kTimeLimitedCandidates) + ": the time budget ran out for candidate " + names +
         " (status time_limit), so the choice depends on the budget and the machine's load; "
         "this plan is not cached (a larger options.time_limit_s may choose another law)";
}

bool is_cacheable(const StoredPlan& plan) {
  return is_cacheable(plan.status) && !plan.budget_limited;
}

StoredPlan solve_for_storing(const PlanRequest& request) {
  PlanRequest without_series = request;
  without_series.sample_period.reset();
  const PlanResult result = plan_request(request);
  nlohmann::json out = plan_json(without_series, result);
  out.erase("cached");
  return {result.status, dump_json(out), budget_limited(result)};
}

std::string with_cached_flag(std::string_view stored, bool cached) {
  return std::string("{\"cached\":") + (cached ? "true" : "false") + "," +
         std::string(stored.substr(1));
}

std::string render_plan_reply(std::string_view stored_body, bool cached, const PlanRequest* request,
                              std::optional<double> sample_period, PlanView view) {
  if (view == PlanView::kCompact) return compact_plan_text(with_cached_flag(stored_body, cached));
  if (!sample_period || request == nullptr) return with_cached_flag(stored_body, cached);
  nlohmann::json plan = nlohmann::json::parse(stored_body);
  plan["cached"] = cached;
  PlanRequest with_series = *request;
  with_series.sample_period = sample_period;
  add_series(with_series, plan);
  return dump_json(plan);
}

}  // namespace slosh::api
