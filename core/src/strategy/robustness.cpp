#include "slosh/core/strategy/robustness.hpp"

#include <algorithm>
#include <cmath>

#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace slosh {

namespace {

/// |delta| below this is the nominal point [-].
constexpr double kZeroDelta{1e-14};

/// The largest eta / limit minus 1 of one model's peaks (<= kRobustnessSlack: the limits hold).
double margin(const SloshPeaks& p, const RobustnessSweep& s) {
  double m = p.rest.value / s.eta_rest_max - 1.0;
  if (s.eta_motion_max) m = std::max(m, p.motion.value / *s.eta_motion_max - 1.0);
  return std::isnan(m) ? INFINITY : m;
}

/// w = max(w, p) by value, where a NaN (a model that diverged) sticks: the worst case is then
/// unknown.
void raise(Peak& w, const Peak& p) {
  if (std::isnan(w.value)) return;
  if (std::isnan(p.value) || p.value > w.value) w = p;
}

void raise(SloshPeaks& w, const SloshPeaks& p) {
  raise(w.motion, p.motion);
  raise(w.rest, p.rest);
}

}  // namespace

std::vector<double> robustness_deltas(const RobustnessSweep& s) {
  std::vector<double> deltas;
  const int n = std::max(2, s.points);
  for (int k = 0; k < n; ++k) {
    // Written as a weighted mean so a symmetric sweep hits 0 exactly at its middle.
    const double w = static_cast<double>(k) / (n - 1);
    double d = s.delta_lo * (1.0 - w) + s.delta_hi * w;
    if (std::abs(d) < kZeroDelta) d = 0.0;
    deltas.push_back(d);
  }
  if (std::find(deltas.begin(), deltas.end(), 0.0) == deltas.end()) {
    deltas.insert(std::upper_bound(deltas.begin(), deltas.end(), 0.0), 0.0);
  }
  return deltas;
}

namespace {

/// The interval around the point `zero` over which `margins` <= slack, its ends interpolated.
std::optional<DeltaInterval> holding_interval(const std::vector<double>& deltas,
                                              const std::vector<double>& margins,
                                              std::size_t zero) {
  if (margins[zero] > kRobustnessSlack) return std::nullopt;
  auto edge = [&](std::size_t in, std::size_t out) {
    const double m0 = margins[in], m1 = margins[out];
    if (!std::isfinite(m1)) return deltas[in];
    const double t = std::clamp((kRobustnessSlack - m0) / (m1 - m0), 0.0, 1.0);
    return deltas[in] + t * (deltas[out] - deltas[in]);
  };
  DeltaInterval r;
  std::size_t lo = zero;
  while (lo > 0 && margins[lo - 1] <= kRobustnessSlack) --lo;
  std::size_t hi = zero;
  while (hi + 1 < deltas.size() && margins[hi + 1] <= kRobustnessSlack) ++hi;
  r.lo_is_sweep_end = lo == 0;
  r.hi_is_sweep_end = hi + 1 == deltas.size();
  r.lo = r.lo_is_sweep_end ? deltas.front() : edge(lo, lo - 1);
  r.hi = r.hi_is_sweep_end ? deltas.back() : edge(hi, hi + 1);
  return r;
}

}  // namespace

RobustnessReport robustness_report(
    const SloshingModel& nominal, const MotionLaw& law, const RobustnessSweep& sweep,
    const std::optional<std::pair<SloshPeaks, SloshPeaks>>& at_zero) {
  const std::vector<double> deltas = robustness_deltas(sweep);
  const bool zero_given = at_zero && sweep.zeta == nominal.zeta;
  // The models to simulate, in delta order (neighbours have nearly the same step grid, so the
  // nonlinear lanes integrated side by side finish together).
  std::vector<SloshingModel> models;
  std::vector<std::size_t> simulated;  // index into deltas of models[i]
  for (std::size_t k = 0; k < deltas.size(); ++k) {
    if (deltas[k] == 0.0 && zero_given) continue;
    models.push_back(scaled_model(nominal, 1.0 + deltas[k], sweep.zeta));
    simulated.push_back(k);
  }
  const std::vector<SloshPeaks> nonlinear = nonlinear_peaks(models, law, sweep.rest_time);
  std::vector<LinearResponse> responses;
  responses.reserve(models.size());
  for (const SloshingModel& m : models) responses.emplace_back(m, law, sweep.rest_time);
  const std::vector<SloshPeaks> linear = LinearResponse::peaks_of(responses);
  std::vector<RobustnessPoint> points(deltas.size());
  for (std::size_t i = 0; i < models.size(); ++i) {
    RobustnessPoint& p = points[simulated[i]];
    p.linear = linear[i];
    p.nonlinear = nonlinear[i];
  }
  for (std::size_t k = 0; k < deltas.size(); ++k) {
    points[k].delta = deltas[k];
    if (deltas[k] == 0.0 && zero_given) {
      points[k].linear = at_zero->first;
      points[k].nonlinear = at_zero->second;
    }
  }
  return judged_report(sweep, std::move(points));
}

RobustnessReport judged_report(const RobustnessSweep& sweep, std::vector<RobustnessPoint> points) {
  RobustnessReport r;
  r.sweep = sweep;
  r.points = std::move(points);
  std::vector<double> deltas, lin_margin, nl_margin;
  std::size_t zero = 0;
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    RobustnessPoint& p = r.points[k];
    deltas.push_back(p.delta);
    if (p.delta == 0.0) zero = k;
    lin_margin.push_back(margin(p.linear, sweep));
    nl_margin.push_back(margin(p.nonlinear, sweep));
    p.holds_linear = lin_margin.back() <= kRobustnessSlack;
    p.holds_nonlinear = nl_margin.back() <= kRobustnessSlack;
    raise(r.worst_linear, p.linear);
    raise(r.worst_nonlinear, p.nonlinear);
  }
  r.linear = holding_interval(deltas, lin_margin, zero);
  r.nonlinear = holding_interval(deltas, nl_margin, zero);
  return r;
}

std::optional<RobustnessReport> robustness_report_on_path(
    const SloshingModel& nominal, const PlanarPath& path, const MotionLaw& law,
    const RobustnessSweep& sweep, const std::function<bool()>& out_of_time) {
  const PlanarDrive drive(path, law);
  auto peaks = [](const PlanarPeaks& p) {
    return SloshPeaks{{p.motion.value, p.motion.time}, {p.rest.value, p.rest.time}};
  };
  std::vector<RobustnessPoint> points;
  for (const double delta : robustness_deltas(sweep)) {
    if (out_of_time && out_of_time()) return std::nullopt;
    const SloshingModel model = scaled_model(nominal, 1.0 + delta, sweep.zeta);
    RobustnessPoint p;
    p.delta = delta;
    p.linear = peaks(planar_linear_peaks(model, drive, sweep.rest_time));
    p.nonlinear = peaks(planar_nonlinear_peaks(model, drive, sweep.rest_time));
    points.push_back(p);
  }
  return judged_report(sweep, std::move(points));
}

}  // namespace slosh
