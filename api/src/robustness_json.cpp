#include "slosh/api/robustness_json.hpp"

#include <cmath>
#include <numbers>

#include "slosh/api/fields.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The two peaks in mm; null when the model diverged (not finite: the nonlinear model can, on
/// formats far outside its range, at some delta).
json eta_pair(const SloshPeaks& p) {
  if (!std::isfinite(p.motion.value) || !std::isfinite(p.rest.value)) return nullptr;
  return {{"eta_motion_mm", p.motion.value * 1e3}, {"eta_rest_mm", p.rest.value * 1e3}};
}

/// The largest peaks of one model over the sweep; null when it diverged at some point (the
/// report's worst value is then NaN: no bound).
json worst_json(const RobustnessReport& r, bool nonlinear) {
  return eta_pair(nonlinear ? r.worst_nonlinear : r.worst_linear);
}

json interval_json(const std::optional<DeltaInterval>& d) {
  if (!d) return nullptr;
  return {{"from_pct", 100.0 * d->lo},
          {"to_pct", 100.0 * d->hi},
          {"from_is_sweep_end", d->lo_is_sweep_end},
          {"to_is_sweep_end", d->hi_is_sweep_end}};
}

json sweep_json(const RobustnessSweep& s) {
  return {{"delta_pct", {100.0 * s.delta_lo, 100.0 * s.delta_hi}},
          {"points", s.points},
          {"zeta", s.zeta},
          {"rest_time_s", s.rest_time},
          {"eta_rest_max_mm", mm_of(s.eta_rest_max)},
          {"eta_motion_max_mm", s.eta_motion_max ? json(mm_of(*s.eta_motion_max)) : json(nullptr)}};
}

json pair_or_null(const std::optional<std::array<double, 2>>& pair, bool in_mm) {
  if (!pair) return nullptr;
  if (!in_mm) return *pair;
  return {mm_of((*pair)[0]), mm_of((*pair)[1])};
}

}  // namespace

json robustness_json(const RobustnessReport& report, const SloshingModel& model) {
  const double f1 = model.omega1() / kTwoPi;
  json points = json::array();
  for (const RobustnessPoint& p : report.points) {
    points.push_back({{"delta_pct", 100.0 * p.delta},
                      {"f1_hz", f1 * (1.0 + p.delta)},
                      {"linear", eta_pair(p.linear)},
                      {"nonlinear", eta_pair(p.nonlinear)},
                      {"holds_linear", p.holds_linear},
                      {"holds_nonlinear", p.holds_nonlinear}});
  }
  return {
      {"sweep", sweep_json(report.sweep)},
      {"points", std::move(points)},
      {"holds",
       {{"linear", interval_json(report.linear)}, {"nonlinear", interval_json(report.nonlinear)}}},
      {"worst", {{"linear", worst_json(report, false)}, {"nonlinear", worst_json(report, true)}}}};
}

json uncertainty_json(const UncertaintyRange& range, const Uncertainty& given, bool samples_read) {
  return {{"omega_error_pct", pct_of(given.omega_error)},
          {"fill_height_mm", pair_or_null(given.fill_height, true)},
          {"viscosity_pa_s", pair_or_null(given.viscosity, false)},
          {"sample_points", samples_read ? json(given.sample_points) : json(nullptr)},
          {"omega1_rad_s", {range.omega_lo, range.omega_hi}},
          {"f1_hz", {range.omega_lo / kTwoPi, range.omega_hi / kTwoPi}},
          {"scale", {range.scale_lo, range.scale_hi}},
          {"zeta", {range.zeta_lo, range.zeta_hi}}};
}

json compact_robustness(const json& robustness) {
  // Hundredths of a percent and of a millimetre: the compact plan stays under 1 kB.
  auto hundredths = [](const json& v) { return std::round(v.get<double>() * 100.0) / 100.0; };
  const json& holds = robustness.at("holds").at("nonlinear");
  const json& worst = robustness.at("worst").at("nonlinear");
  return {{"holds_pct", holds.is_null() ? json(nullptr)
                                        : json::array({hundredths(holds.at("from_pct")),
                                                       hundredths(holds.at("to_pct"))})},
          {"worst_mm", worst.is_null() ? json(nullptr)
                                       : json::array({hundredths(worst.at("eta_motion_mm")),
                                                      hundredths(worst.at("eta_rest_mm"))})}};
}

json robustness_row_figures(const json* robustness) {
  json row{{"holds_from_pct", nullptr}, {"holds_to_pct", nullptr}, {"worst_eta_rest_mm", nullptr}};
  if (robustness == nullptr || !robustness->is_object()) return row;
  const json& holds = robustness->at("holds").at("nonlinear");
  if (!holds.is_null()) {
    row["holds_from_pct"] = holds.at("from_pct");
    row["holds_to_pct"] = holds.at("to_pct");
  }
  const json& worst = robustness->at("worst").at("nonlinear");
  if (!worst.is_null()) row["worst_eta_rest_mm"] = worst.at("eta_rest_mm");
  return row;
}

}  // namespace slosh::api
