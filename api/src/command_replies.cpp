#include "slosh/api/command_replies.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/calibration_json.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_summary.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/api/spatial_simulate.hpp"

namespace slosh::api {

namespace {

std::string pretty(const nlohmann::json& value) {
  return dump_json(value, 2);
}

// format.motion of the move flags; nullopt when none is given.
std::optional<nlohmann::json> motion_of_flags(const QuickMotion& q) {
  std::optional<nlohmann::json> motion;
  if (q.arc_radius_mm) {
    motion = {{"type", "arc"}, {"radius_mm", *q.arc_radius_mm}, {"angle_deg", *q.arc_angle_deg}};
    if (q.turns) (*motion)["container_turns"] = *q.turns;
  }
  if (q.motion_text) {
    motion = nlohmann::json::parse(*q.motion_text, nullptr, false);
    if (motion->is_discarded()) {
      throw ApiError(ErrorCode::kInvalidValue, "--motion",
                     "--motion " + q.motion_source +
                         " is not JSON: it must hold format.motion, e.g. {\"type\": \"arc\", "
                         "\"radius_mm\": 300, \"angle_deg\": 90}");
    }
  }
  return motion;
}

// The plan request the format flags stand for.
nlohmann::json quick_request(const QuickPlan& q) {
  nlohmann::json container{{"radius_mm", q.radius_mm}};
  if (const auto& r = q.rectangular) {
    container = {{"shape", "rectangular"}, {"length_mm", r->length_mm}, {"width_mm", r->width_mm}};
    if (r->orientation_deg) container["orientation_deg"] = *r->orientation_deg;
  }
  if (q.height_mm) container["height_mm"] = *q.height_mm;
  nlohmann::json fluid = q.fluid ? nlohmann::json(*q.fluid)
                                 : nlohmann::json{{"density_kg_m3", q.density_kg_m3.value_or(0)},
                                                  {"viscosity_pa_s", q.viscosity_pa_s.value_or(0)}};
  nlohmann::json request{{"format",
                          {{"container", container},
                           {"fill_height_mm", q.fill_mm},
                           {"fluid", fluid},
                           {"stroke_mm", q.stroke_mm},
                           {"motion_time_s", q.time_s}}},
                         {"strategy", q.strategy}};
  if (std::optional<nlohmann::json> motion = motion_of_flags(q.motion)) {
    request["format"].erase("stroke_mm");
    request["format"]["motion"] = std::move(*motion);
  }
  return request;
}

std::string plan_reply_of(const nlohmann::json& request, PlanView view) {
  const PlanRequest parsed = parse_plan_request(request);
  require_no_series(view, parsed.sample_period);
  const nlohmann::json plan = run_plan(parsed);
  return pretty(view == PlanView::kCompact ? compact_plan(plan) : plan);
}

}  // namespace

std::string simulate_reply(std::string_view request) {
  return pretty(simulate_response(parse_json_body(request)));
}

std::string calibration_reply(std::string_view request) {
  return pretty(run_calibration(parse_calibration_request(parse_json_body(request))));
}

std::string min_time_reply(std::string_view request) {
  return pretty(
      run_min_time(parse_min_time_request(parse_json_body(request), plan_ranges::kTimeLimit.hi)));
}

std::string min_time_reply(std::string_view request, const QuickMotion& flags) {
  nlohmann::json body = parse_json_body(request);
  std::optional<nlohmann::json> motion = motion_of_flags(flags);
  if (motion && body.is_object() && body.contains("format") && body["format"].is_object()) {
    const std::string flag = flags.motion_text ? "--motion" : "--arc-radius/--arc-angle";
    for (const char* key : {"stroke_mm", "motion"}) {
      if (body["format"].contains(key)) {
        const std::string field = std::string("format.") + key;
        throw ApiError(ErrorCode::kInvalidValue, field,
                       field + " cannot be combined with " + flag +
                           ": the flags give the motion; leave " + field + " out of the request");
      }
    }
    body["format"]["motion"] = std::move(*motion);
  }
  return pretty(run_min_time(parse_min_time_request(body, plan_ranges::kTimeLimit.hi)));
}

std::string plan_reply(std::string_view request, PlanView view) {
  return plan_reply_of(parse_json_body(request), view);
}

std::string plan_reply(const QuickPlan& quick, PlanView view) {
  return plan_reply_of(quick_request(quick), view);
}

std::string plan_summary_reply(std::string_view request) {
  return plan_summary_text(run_plan(parse_plan_request(parse_json_body(request))));
}

std::string plan_summary_reply(const QuickPlan& quick) {
  return plan_summary_text(run_plan(parse_plan_request(quick_request(quick))));
}

std::string fluids_reply(bool as_table) {
  const nlohmann::json fluids = fluids_json();
  return as_table ? fluids_table_text(fluids) : pretty(fluids);
}

std::string error_envelope_text(const ApiError& error) {
  return pretty(error_envelope(error));
}

}  // namespace slosh::api
