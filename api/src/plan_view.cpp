#include "slosh/api/plan_view.hpp"

#include <algorithm>
#include <cmath>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/plan_warnings.hpp"
#include "slosh/api/robustness_json.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

constexpr std::string_view kField = "view";

// The compact kinematics' resolutions (per m/s^2, per m/s, per m/s^3).
constexpr double kAccelerationPer{1e4};
constexpr double kSpeedPer{1e5};
constexpr double kJerkPer{1e3};

[[noreturn]] void not_a_view(const json& value) {
  invalid(std::string(kField), std::string(kField) + " = " + show(value) +
                                   " is not allowed: one of " + quoted_names(plan_view_names()));
}

/// A value rounded to 1 / `per` (the compact view's figures that need no more), divided by the
/// integer count so that it prints as the short decimal (130.7, not 130.70000000000002).
double rounded(double value, double per) {
  return std::round(value * per) / per;
}

/// A figure of the full plan rounded as above; anything but a number (none is expected) as it is.
json rounded_figure(const json& value, double per) {
  return value.is_number() ? json(rounded(value.get<double>(), per)) : value;
}

/// A figure to 7 significant digits: what the REAL (32-bit) inputs of an MC_MoveAbsolute block
/// hold; anything but a number as it is.
json real_figure(const json& value) {
  if (!value.is_number()) return value;
  const double x = value.get<double>();
  if (x == 0.0 || !std::isfinite(x)) return value;
  // An exact power of ten, multiplied or divided by once, rounds as the decimal text would.
  const double digits = 6.0 - std::floor(std::log10(std::abs(x)));
  if (digits >= 0.0) {
    const double scale = std::pow(10.0, digits);
    return std::round(x * scale) / scale;
  }
  const double step = std::pow(10.0, -digits);
  return std::round(x / step) * step;
}

/// The two figures of one model's peaks, to 1 um (a wave height an HMI shows; the full plan has
/// them to the last digit).
json compact_peaks(const json& peaks) {
  return {{"eta_motion_mm", rounded_figure(peaks.at("eta_motion_mm"), 1e3)},
          {"eta_rest_mm", rounded_figure(peaks.at("eta_rest_mm"), 1e3)}};
}

}  // namespace

std::vector<std::string> plan_view_names() {
  return {"full", "compact"};
}

PlanView parse_plan_view(std::string_view value) {
  if (value == "full") return PlanView::kFull;
  if (value == "compact") return PlanView::kCompact;
  not_a_view(json(std::string(value)));
}

PlanView parse_view_query(const std::vector<std::string>& values) {
  if (values.empty()) return PlanView::kFull;
  if (values.size() > 1) {
    // The wording of every other repeated query parameter (the cam tables'): "view is given
    // twice (full and full): give each query parameter once".
    const std::string count =
        values.size() == 2 ? "twice" : std::to_string(values.size()) + " times";
    std::string given;
    for (std::size_t i = 0; i < values.size() && i < 3; ++i) {
      if (i > 0) given += i + 1 == values.size() ? " and " : ", ";
      given += values[i].substr(0, 32);
    }
    if (values.size() > 3) given += ", ...";
    invalid(std::string(kField), std::string(kField) + " is given " + count + " (" + given +
                                     "): give each query parameter once, one of " +
                                     quoted_names(plan_view_names()));
  }
  return parse_plan_view(values.front());
}

PlanView batch_view(const std::vector<std::string>& query_values,
                    const std::optional<json>& body_view) {
  const PlanView query = parse_view_query(query_values);
  if (!body_view) return query;
  if (!body_view->is_string()) not_a_view(*body_view);
  const PlanView body = parse_plan_view(body_view->get<std::string>());
  if (!query_values.empty() && body != query) {
    invalid(std::string(kField), "view is " + show(json(query_values.front())) +
                                     " in the query but " + show(*body_view) +
                                     " in the body: give one view");
  }
  return body;
}

void require_no_series(PlanView view, const std::optional<double>& sample_period) {
  if (view == PlanView::kCompact && sample_period) {
    invalid("sample_period_s",
            "sample_period_s is not allowed with view \"compact\" (a compact plan carries no "
            "series): ask the full view for the series");
  }
}

std::span<const PlanWarningKind> plan_warning_kinds() {
  return warning_kinds();
}

std::vector<std::string> plan_warning_codes(const json& plan) {
  // One code per finding: two sentences of one kind (e.g. both models beyond their theory) would
  // read as the same warning twice.
  std::vector<std::string> out;
  auto add = [&out](std::string code) {
    if (std::find(out.begin(), out.end(), code) == out.end()) out.push_back(std::move(code));
  };
  if (const auto codes = plan.find("warning_codes"); codes != plan.end() && codes->is_array()) {
    for (const json& c : *codes) {
      if (c.is_string()) add(c.get<std::string>());
    }
    return out;
  }
  // A plan stored before its warnings carried their kinds: each sentence's finding (the text up
  // to the first ": "), the only thing known of it.
  if (const auto warnings = plan.find("warnings"); warnings != plan.end() && warnings->is_array()) {
    for (const json& w : *warnings) {
      if (!w.is_string()) continue;
      const std::string text = w.get<std::string>();
      add(text.substr(0, text.find(": ")));
    }
  }
  return out;
}

namespace {

/// Along an arc or a path: the peak horizontal acceleration, tangential and normal together (to
/// 1 mm/s^2), the figure limits.a_max bounds there. The path's length is the law's stroke_mm; the
/// peaks' wall directions are in the full plan of the same key (with them, a tank's plan along a
/// path with move_absolute and every warning took 1099 B).
json compact_path(const json& path) {
  const json& p = path.at("prediction");
  return {{"a_total_peak", rounded(p.at("kinematics").at("a_total_peak").get<double>(), 1e3)}};
}

/// The motion in a compact plan: its type, and a path's segment count. Its length is the law's
/// stroke_mm; the rest (an arc's radius and angle, a path's segments, the start heading,
/// container_turns) is in the full plan of the same key: echoed as given, those numbers took a
/// tank's compact plan along an arc with move_absolute past 1 kB (1098 B).
json compact_motion(const json& motion) {
  json out{{"type", motion.value("type", "line")}};
  if (const auto segments = motion.find("segments"); segments != motion.end()) {
    out["segment_count"] = segments->size();
  }
  return out;
}

}  // namespace

json compact_plan(const json& plan) {
  json out;
  out["view"] = "compact";
  for (const char* member : {"key", "cached", "version", "strategy", "status"}) {
    out[member] = plan.at(member);
  }
  json law = plan.at("law");
  if (law.is_object()) {
    const json& format = plan.at("format");
    law["stroke_mm"] = format.at("stroke_mm");
    law["motion_time_s"] = format.at("motion_time_s");
    // Along an arc or a path the law's stroke is the length along it: the motion says where.
    if (const auto m = format.find("motion"); m != format.end()) law["motion"] = compact_motion(*m);
  }
  out["law"] = std::move(law);
  const auto move_absolute = plan.find("move_absolute");
  if (move_absolute == plan.end()) {
    const json& k = plan.at("kinematics");
    // The law's peaks as an HMI shows them, to 0.1 mm/s^2, 0.01 mm/s and 1 mm/s^3 (the law
    // itself, its durations or pieces, is exact: a drive runs it).
    out["kinematics"] = {{"a_max", rounded_figure(k.at("a_max"), kAccelerationPer)},
                         {"a_min", rounded_figure(k.at("a_min"), kAccelerationPer)},
                         {"v_peak", rounded_figure(k.at("v_peak"), kSpeedPer)},
                         {"j_peak", rounded_figure(k.at("j_peak"), kJerkPer)}};
  } else {
    // The MC_MoveAbsolute inputs are what a drive needs of a one-jerk plan, as its REAL inputs
    // hold them; they are the law's peaks too (acceleration, deceleration, velocity, jerk), so
    // the kinematics are not repeated: a path plan with every warning took 1105 B with both.
    json block = json::object();
    for (const auto& [name, value] : move_absolute->items()) block[name] = real_figure(value);
    out["move_absolute"] = std::move(block);
  }
  const json& p = plan.at("prediction");
  out["prediction"] = {{"nonlinear", compact_peaks(p.at("nonlinear"))},
                       {"linear", compact_peaks(p.at("linear"))}};
  if (const auto path = plan.find("path"); path != plan.end()) out["path"] = compact_path(*path);
  out["warnings"] = plan_warning_codes(plan);
  // How far the tank's frequencies may be off (SPEC §10): the interval and the worst case.
  if (const auto r = plan.find("robustness"); r != plan.end()) {
    out["robustness"] = compact_robustness(*r);
  }
  return out;
}

std::string compact_plan_text(std::string_view plan) {
  return dump_json(compact_plan(json::parse(plan)));
}

}  // namespace slosh::api
