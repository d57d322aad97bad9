#include "slosh/api/plan_reply.hpp"

#include "slosh/api/error.hpp"

namespace slosh::api {

bool is_cacheable(SolveStatus status) {
  return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable ||
         status == SolveStatus::kInfeasible;
}

StoredPlan solve_for_storing(const PlanRequest& request) {
  PlanRequest without_series = request;
  without_series.sample_period.reset();
  const PlanResult result = plan_request(request);
  nlohmann::json out = plan_json(without_series, result);
  out.erase("cached");
  return {result.status, dump_json(out)};
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
