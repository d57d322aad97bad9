#include "slosh/api/plan_law.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

PlanLaw plan_law(std::string_view plan_text) {
  const nlohmann::json plan = parse_json_body(plan_text);
  if (!plan.is_object() || !plan.contains("law") || !plan.contains("format")) {
    throw ApiError(ErrorCode::kInternal, "", "the plan has no law to export");
  }
  // A plan along an arc or a path echoes its motion beside stroke_mm (the path length): the law
  // spans that length, the motion is read by plan_path_motion.
  nlohmann::json plain = plan["format"];
  if (plain.is_object()) plain.erase("motion");
  const Format format = parse_format(plain);
  const ParsedLaw law = parse_law(plan["law"], "law", format, ranges::kMinRampS.lo);
  PlanLaw out;
  out.key = plan.value("key", std::string());
  out.strategy = plan.value("strategy", std::string());
  out.cached = plan.value("cached", false);
  out.status = enum_from_name<SolveStatus>(plan.value("status", std::string()))
                   .value_or(SolveStatus::kFailed);
  out.message = plan.value("message", std::string());
  if (const auto w = plan.find("warnings"); w != plan.end() && w->is_array()) {
    for (const nlohmann::json& text : *w) {
      if (text.is_string()) out.warnings.push_back(text.get<std::string>());
    }
  }
  out.type = law.type;
  out.law = law.law;
  if (law.durations) out.seven.emplace(*law.durations, format.stroke);
  out.stroke = format.stroke;
  return out;
}

bool exportable(SolveStatus status) {
  return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable;
}

std::string not_exportable_message(const PlanLaw& plan, std::string_view how_to_force) {
  // A message that ends its last sentence already gets no second full stop.
  const bool ended = !plan.message.empty() && plan.message.back() == '.';
  return "the plan is " + to_string(plan.status) +
         ", its law misses the requested limits: " + plan.message + (ended ? " " : ". ") +
         "Not exported; " + std::string(how_to_force) + " to export the best reachable law anyway";
}

}  // namespace slosh::api
