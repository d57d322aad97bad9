#include "slosh/core/strategy/rectangular_plan.hpp"

#include <algorithm>
#include <cmath>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "strategy/strategies.hpp"

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
  // and the filters at its middle), as they do over an uncertainty range.
  const double w_a = directions[0].model.omega1(), w_b = directions[1].model.omega1();
  const double lo = std::min(w_a, w_b), hi = std::max(w_a, w_b), mid = 0.5 * (lo + hi);
  const double zeta = std::min(directions[0].model.zeta, directions[1].model.zeta);
  c.design_model = scaled_model(c.model, mid / c.model.omega1(), zeta);
  const double band = c.options.band;
  c.band = std::max((1.0 + band) * hi / mid - 1.0, 1.0 - (1.0 - band) * lo / mid);
  c.p_notch = std::max(c.options.p_notch, (hi - lo) / (hi + lo));
  // time_domain bounds the corners, |eta_L| + |eta_W| <= 2 max(|eta_L|, |eta_W|): each driven
  // direction at twice its wall height (exact for a square tank at 45 degrees, where both are
  // equal; conservative otherwise, and the plan is verified on the corners themselves).
  c.sample_models.clear();
  for (const DrivenDirection& d : directions) {
    c.sample_models.push_back(with_height_factor(d.model, 2.0));
  }
  c.check_models = c.sample_models;
}

}  // namespace detail

}  // namespace slosh
