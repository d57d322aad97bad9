#include "slosh/core/strategy/rectangular_plan.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh {

RectangularPrediction rectangular_prediction(const RectangularModel& model, const MotionLaw& law,
                                             double rest_time) {
  RectangularPrediction p;
  p.linear = RectangularLinearResponse(model, law, rest_time).peaks().highest;
  RectangularNonlinearPeaks nonlinear = rectangular_nonlinear_peaks(model, law, rest_time);
  p.nonlinear = nonlinear.peaks.highest;
  p.length = nonlinear.peaks.along_length;
  p.width = nonlinear.peaks.along_width;
  p.warning = std::move(nonlinear.warning);
  return p;
}

std::string motion_too_short_for_mode(const RectangularModel& model, double motion_time) {
  const AxisComponents c = axis_components(model.orientation_deg);
  double period = 0.0;
  const char* name = "length";
  if (c.along_length != 0.0) period = 2.0 * std::numbers::pi / model.along_length.omega1();
  if (c.along_width != 0.0) {
    const double w = 2.0 * std::numbers::pi / model.along_width.omega1();
    if (w > period) {
      period = w;
      name = "width";
    }
  }
  if (!(motion_time < kMinMotionPeriodShare * period)) return {};
  return "motion too short for the tank: motion time " + detail::sig3(motion_time) +
         " s is below " + detail::fixed(kMinMotionPeriodShare, 1) +
         " of the first sloshing period " + detail::sig3(period) + " s along the " + name +
         "; the move is an impulse to that mode, every law of this duration leaves about the "
         "same sloshing, and no plan can reduce it (a longer motion time can)";
}

bool both_directions_excited(double orientation_deg) {
  const AxisComponents c = axis_components(orientation_deg);
  return c.along_length != 0.0 && c.along_width != 0.0;
}

namespace {

/// Both directions' frequencies scaled; with `common`, both at the damping ratio `zeta`.
RectangularModel scaled(const RectangularModel& m, double scale, bool common, double zeta) {
  RectangularModel out = m;
  out.along_length = scaled_model(m.along_length, scale, common ? zeta : m.along_length.zeta);
  out.along_width = scaled_model(m.along_width, scale, common ? zeta : m.along_width.zeta);
  return out;
}

}  // namespace

RobustnessReport rectangular_robustness_report(
    const RectangularModel& model, const MotionLaw& law, const RobustnessSweep& sweep,
    const std::optional<std::pair<SloshPeaks, SloshPeaks>>& at_zero) {
  const bool common = sweep.zeta != driven_directions(model).front().model.zeta;
  std::vector<RobustnessPoint> points;
  for (double delta : robustness_deltas(sweep)) {
    RobustnessPoint p;
    p.delta = delta;
    if (delta == 0.0 && at_zero && !common) {
      p.linear = at_zero->first;
      p.nonlinear = at_zero->second;
    } else {
      const RectangularPrediction q = rectangular_prediction(
          scaled(model, 1.0 + delta, common, sweep.zeta), law, sweep.rest_time);
      p.linear = q.linear;
      p.nonlinear = q.nonlinear;
    }
    points.push_back(p);
  }
  return judged_report(sweep, std::move(points));
}

namespace {

/// A direction whose static wall height is below this share of the other's is not designed for
/// (the law is still verified on both): a tank turned a hair off an axis, e.g. 89.9999999 degrees
/// from a PLC's float, plans as on the axis instead of jumping to the two-mode design.
constexpr double kMinDesignShare{0.05};

double static_wall_height(const DrivenDirection& d) {
  return d.model.eta_gain.front() / (d.model.omega1() * d.model.omega1());
}

}  // namespace

std::optional<RectangularModel> rectangular_axis_tank(const RectangularModel& model) {
  const std::vector<DrivenDirection> directions = driven_directions(model);
  // driven_directions puts the direction of the higher static wall height first.
  if (directions.size() < 2 || !(static_wall_height(directions[1]) <
                                 kNegligibleDirectionShare * static_wall_height(directions[0]))) {
    return std::nullopt;
  }
  RectangularModel axis = model;
  axis.orientation_deg = 90.0 * std::round(model.orientation_deg / 90.0);
  return axis;
}

namespace detail {

void set_directions(StrategyContext& c) {
  if (c.rectangular == nullptr) return;
  const std::vector<DrivenDirection> directions = driven_directions(*c.rectangular);
  if (directions.size() < 2) return;
  // driven_directions puts the direction of the higher static wall height first.
  if (static_wall_height(directions[1]) < kMinDesignShare * static_wall_height(directions[0])) {
    return;
  }
  // Both directions excited: the spectral strategies design over the range of the two first
  // frequencies (multi_notch's side notches at its ends, min_jerk_band's band over both, notch
  // and the filters at its middle), as they do over an uncertainty range; with one, over the
  // union of both directions' ranges (uncertainty_range's factors cover each direction's own).
  const double s_lo = c.range ? c.range->scale_lo : 1.0;
  const double s_hi = c.range ? c.range->scale_hi : 1.0;
  const double w_a = directions[0].model.omega1(), w_b = directions[1].model.omega1();
  const double lo = std::min(w_a, w_b) * s_lo, hi = std::max(w_a, w_b) * s_hi;
  const double mid = 0.5 * (lo + hi);
  double zeta = std::min(directions[0].model.zeta, directions[1].model.zeta);
  if (c.range) zeta = std::min(zeta, c.range->zeta_lo);
  c.design_model = scaled_model(c.model, mid / c.model.omega1(), zeta);
  c.over_directions = true;
  c.direction_omega = {w_a, w_b};
  c.direction_zeta = {directions[0].model.zeta, directions[1].model.zeta};
  const double band = c.options.band;
  c.band = std::max((1.0 + band) * hi / mid - 1.0, 1.0 - (1.0 - band) * lo / mid);
  c.p_notch = std::max(c.options.p_notch, (hi - lo) / (hi + lo));
  // time_domain bounds the corners, |eta_L| + |eta_W| <= 2 max(|eta_L|, |eta_W|): each driven
  // direction at twice its wall height (exact for a square tank at 45 degrees, where both are
  // equal; conservative otherwise, and the plan is verified on the corners themselves); over a
  // range, each direction at the range's sample points and checked at the sweep's points.
  c.sample_models.clear();
  c.check_models.clear();
  for (const DrivenDirection& d : directions) {
    const SloshingModel doubled = with_height_factor(d.model, 2.0);
    if (!c.range) {
      c.sample_models.push_back(doubled);
      c.check_models.push_back(doubled);
      continue;
    }
    for (const SloshingModel& m :
         sample_models(doubled, *c.range, c.options.uncertainty.sample_points)) {
      c.sample_models.push_back(m);
    }
    for (double delta : robustness_deltas(c.sweep)) {
      c.check_models.push_back(scaled_model(doubled, 1.0 + delta, c.sweep.zeta));
    }
  }
}

}  // namespace detail

}  // namespace slosh
