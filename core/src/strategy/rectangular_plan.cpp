#include "slosh/core/strategy/rectangular_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <vector>

#include "slosh/core/model/tank_directions.hpp"
#include "slosh/core/model/uncertainty.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh {

RectangularPrediction rectangular_prediction(const RectangularModel& model, const MotionLaw& law,
                                             double rest_time) {
  RectangularPrediction p;
  const RectangularPeaks linear = RectangularLinearResponse(model, law, rest_time).peaks();
  p.linear = linear.highest;
  p.linear_directions = {linear.along_length, linear.along_width};
  RectangularNonlinearPeaks nonlinear = rectangular_nonlinear_peaks(model, law, rest_time);
  p.nonlinear = nonlinear.peaks.highest;
  p.length = nonlinear.peaks.along_length;
  p.width = nonlinear.peaks.along_width;
  p.warning = std::move(nonlinear.warning);
  return p;
}

namespace {

/// The driven direction's wall height u >= 0 seconds after a unit step of the position (the
/// velocity an impulse of unit area): each mode's coordinate x'' + 2 zeta w x' + w^2 x = -a
/// then moves as -e^{-zeta w u} (cos w_d u - zeta w / w_d sin w_d u) [m per m].
double step_wall_height(const SloshingModel& m, double u) {
  double eta = 0.0;
  for (int n = 0; n < m.modes(); ++n) {
    const double w = m.omega[n];
    const double wd = w * std::sqrt(1.0 - m.zeta * m.zeta);
    const double decay = std::exp(-m.zeta * w * u);
    eta -= m.eta_gain[n] * decay * (std::cos(wd * u) - m.zeta * w / wd * std::sin(wd * u));
  }
  return eta;
}

/// A bound of |d/du step_wall_height| over u >= 0: each mode's w^2 / w_d times |eta_gain| [1/s].
double step_slope_bound(const SloshingModel& m) {
  double slope = 0.0;
  for (int n = 0; n < m.modes(); ++n) {
    slope += std::abs(m.eta_gain[n]) * m.omega[n] / std::sqrt(1.0 - m.zeta * m.zeta);
  }
  return slope;
}

/// The least of `values` over every window of `width` + 1 consecutive samples, the largest of
/// those least values over the windows that end at or after sample `width`.
double best_window_minimum(const std::vector<double>& values, std::size_t width) {
  std::deque<std::size_t> at;  // indices of increasing values: the window's minimum in front
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < values.size(); ++i) {
    while (!at.empty() && values[at.back()] >= values[i]) at.pop_back();
    at.push_back(i);
    if (at.front() + width < i) at.pop_front();
    if (i >= width) best = std::max(best, values[at.front()]);
  }
  return best;
}

}  // namespace

double one_way_rest_floor(const RectangularModel& model, double stroke, double motion_time,
                          double rest_time) {
  // The linear wall heights are convolutions of the velocity v with the step responses s_d:
  // eta_d(t) = int_0^T v(tau) s_d(t - tau) dtau. With v >= 0 and int v = stroke, at any t in the
  // rest window eta_L(t) + sigma eta_W(t) >= stroke min over u in [t - T, t] of
  // (s_L + sigma s_W)(u), and a corner's |eta_L| + |eta_W| is at least |eta_L + sigma eta_W| for
  // both signs sigma: the largest such minimum over t, over sigma and over the wave's sign is a
  // floor of eta_rest for every such law (for one mode undamped it is the impulse residual's
  // cos(omega T / 2)). The minima are taken on samples h apart, less the slope bound times h / 2
  // (every point of a window is within h / 2 of a sample); t runs over the samples of the rest
  // window's first four periods of the slowest mode (a max over fewer t is still a floor).
  const std::vector<DrivenDirection> directions = driven_directions(model);
  double slowest = 0.0, fastest = 0.0, slope = 0.0;
  for (const DrivenDirection& d : directions) {
    const SloshingModel& m = d.model;
    if (!(m.zeta >= 0.0 && m.zeta < 1.0) || m.modes() == 0) return 0.0;
    slowest = std::max(slowest, 2.0 * std::numbers::pi / m.omega1());
    fastest = std::max(fastest, m.omega.back());
    slope += step_slope_bound(m);
  }
  // A motion longer than half the slowest period lets a law cancel a first mode: no floor.
  if (directions.empty() || !(motion_time > 0.0) || motion_time >= 0.5 * slowest) return 0.0;
  constexpr std::size_t kLeastSamples{64};        // per motion time
  constexpr double kFloorSamplesPerPeriod{64.0};  // of the fastest mode
  const std::size_t width = std::max(
      kLeastSamples, static_cast<std::size_t>(std::ceil(kFloorSamplesPerPeriod * fastest *
                                                        motion_time / (2.0 * std::numbers::pi))));
  const double h = motion_time / static_cast<double>(width);
  const double window = std::min(rest_time, 4.0 * slowest);
  const std::size_t samples = width + static_cast<std::size_t>(std::floor(window / h)) + 1;
  std::vector<double> s_length(samples, 0.0), s_width(samples, 0.0);
  for (const DrivenDirection& d : directions) {
    std::vector<double>& s = d.axis == TankAxis::kLength ? s_length : s_width;
    for (std::size_t i = 0; i < samples; ++i)
      s[i] = step_wall_height(d.model, h * static_cast<double>(i));
  }
  double best = -std::numeric_limits<double>::infinity();
  std::vector<double> combined(samples);
  for (double sigma : {1.0, -1.0}) {
    for (double sign : {1.0, -1.0}) {
      for (std::size_t i = 0; i < samples; ++i) {
        combined[i] = sign * (s_length[i] + sigma * s_width[i]);
      }
      best = std::max(best, best_window_minimum(combined, width));
    }
  }
  return std::max(0.0, stroke * (best - 0.5 * slope * h));
}

std::string motion_too_short_for_mode(const RectangularModel& model, double stroke,
                                      double motion_time, double rest_time, double uniform_rest) {
  const double floor = one_way_rest_floor(model, stroke, motion_time, rest_time);
  if (!(uniform_rest > 0.0) || !(floor >= kMotionTooShortShare * uniform_rest)) return {};
  double period = 0.0;
  const char* name = "length";
  for (const DrivenDirection& d : driven_directions(model)) {
    const double own = 2.0 * std::numbers::pi / d.model.omega1();
    if (own > period) {
      period = own;
      name = d.axis == TankAxis::kLength ? "length" : "width";
    }
  }
  // Rounded down, so that the share quoted is a floor too.
  const double share = std::floor(100.0 * std::min(1.0, floor / uniform_rest)) / 100.0;
  return "motion too short for the tank: motion time " + detail::sig3(motion_time) + " s is " +
         detail::sig3(motion_time / period) + " of the first sloshing period " +
         detail::sig3(period) + " s along the " + name +
         "; the move is an impulse to the tank's modes: on the linear model every law of this "
         "duration that moves one way leaves an eta_rest of at least " +
         detail::fixed(share, 2) + " of the uniform law's (" +
         detail::fixed(std::floor(1e4 * floor) / 10.0, 1) + " of " +
         detail::fixed(uniform_rest * 1e3, 1) +
         " mm), so no such plan can reduce it by more than " +
         detail::fixed(100.0 * (1.0 - share), 0) + " % (a longer motion time can)";
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

std::optional<RobustnessReport> rectangular_robustness_report(
    const RectangularModel& model, const MotionLaw& law, const RobustnessSweep& sweep,
    const std::optional<std::pair<SloshPeaks, SloshPeaks>>& at_zero,
    const std::function<bool()>& out_of_time) {
  const bool common = sweep.zeta != driven_directions(model).front().model.zeta;
  std::vector<RobustnessPoint> points;
  for (double delta : robustness_deltas(sweep)) {
    RobustnessPoint p;
    p.delta = delta;
    if (delta == 0.0 && at_zero && !common) {
      p.linear = at_zero->first;
      p.nonlinear = at_zero->second;
    } else {
      if (out_of_time && out_of_time()) return std::nullopt;
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

double static_wall_height(const DrivenDirection& d) {
  return d.model.eta_gain.front() / (d.model.omega1() * d.model.omega1());
}

/// The residual wave a unit |X_a(omega_1)| leaves on the direction's walls: its first mode's
/// gain over omega_1 (the undamped residual amplitude is |X_a(omega_1)| / omega_1 of the modal
/// coordinate) [s].
double residual_gain(const DrivenDirection& d) {
  return d.model.eta_gain.front() / d.model.omega1();
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

double direction_engagement(double share) {
  return std::min(1.0, share / kFullDirectionShare);
}

namespace detail {

void set_directions(StrategyContext& c) {
  if (c.rectangular == nullptr || c.one_direction) return;
  const std::vector<DrivenDirection> directions = driven_directions(*c.rectangular);
  if (directions.size() < 2) return;
  // Both directions excited (rectangular_axis_tank has put a tank a hair off an axis onto it).
  // notch and multi_notch weigh each direction's first mode by its residual wave (a share that
  // goes to 0 with the orientation, so the law moves continuously with it). fir_chain, iir, the
  // shaper and min_jerk_band's band take the second direction in by its engagement
  // (kFullDirectionShare): fully above that share of the residual wave (both modes cancelled,
  // the band over both), and below it on a path that reaches the most excited direction's own
  // design as the share goes to 0, so that none of them changes in kind at an orientation.
  const double axis_zeta = c.design_model.zeta;
  const double axis_lo = (1.0 - c.band) * c.design_model.omega1();
  const double axis_hi = (1.0 + c.band) * c.design_model.omega1();
  const double s_lo = c.range ? c.range->scale_lo : 1.0;
  const double s_hi = c.range ? c.range->scale_hi : 1.0;
  const double w_a = directions[0].model.omega1(), w_b = directions[1].model.omega1();
  c.over_directions = true;
  c.direction_omega = {w_a, w_b};
  c.direction_zeta = {directions[0].model.zeta, directions[1].model.zeta};
  c.direction_weight = {1.0, residual_gain(directions[1]) / residual_gain(directions[0])};
  c.direction_engagement = direction_engagement(c.direction_weight[1]);
  for (std::size_t k = 0; k < 2; ++k) {
    c.direction_name[k] = directions[k].axis == TankAxis::kLength ? "length" : "width";
  }
  // The band over both directions: around the middle of their first modes (with a range, the
  // union of both directions' ranges: uncertainty_range's factors cover each direction's own),
  // reaching the option's band beyond each; its edges, and the damping the design takes (the
  // least of both), are met from the most excited direction's by the engagement.
  const double lo = std::min(w_a, w_b) * s_lo, hi = std::max(w_a, w_b) * s_hi;
  const double mid = 0.5 * (lo + hi);
  const double band = c.options.band;
  const double both_band = std::max((1.0 + band) * hi / mid - 1.0, 1.0 - (1.0 - band) * lo / mid);
  double both_zeta = std::min(directions[0].model.zeta, directions[1].model.zeta);
  if (c.range) both_zeta = std::min(both_zeta, c.range->zeta_lo);
  const double e = c.direction_engagement;
  if (e >= 1.0) {
    c.design_model = scaled_model(c.model, mid / c.model.omega1(), both_zeta);
    c.band = both_band;
  } else {
    const double edge_lo = (1.0 - e) * axis_lo + e * (1.0 - both_band) * mid;
    const double edge_hi = (1.0 - e) * axis_hi + e * (1.0 + both_band) * mid;
    c.design_model = scaled_model(c.model, 0.5 * (edge_lo + edge_hi) / c.model.omega1(),
                                  (1.0 - e) * axis_zeta + e * both_zeta);
    c.band = (edge_hi - edge_lo) / (edge_hi + edge_lo);
  }
  // time_domain bounds the corners, |eta_A| + |eta_B| <= max((1 + rho) |eta_A|,
  // (1 + 1/rho) |eta_B|) for every rho > 0 (if rho |eta_A| >= |eta_B| the first term holds the
  // sum, else the second): each driven direction at its height times its factor. rho, the square
  // root of the ratio of the static wall heights (B the less excited), is 1 for a square tank at
  // 45 degrees (both at twice their height, exact where both are equal) and takes both factors'
  // bounds continuously to the one-direction bound as the orientation nears an axis: A's factor
  // 1 + rho -> 1, and B's bounded height (1 + 1/rho) h_B = h_B + sqrt(h_A h_B) -> 0. The plan is
  // verified on the corners themselves. Over a range, each direction at the range's sample
  // points and checked at the sweep's points.
  const double rho =
      std::sqrt(static_wall_height(directions[1]) / static_wall_height(directions[0]));
  const std::array<double, 2> factors{1.0 + rho, 1.0 + 1.0 / rho};
  c.sample_models.clear();
  c.check_models.clear();
  for (std::size_t k = 0; k < directions.size(); ++k) {
    const SloshingModel bounded = with_height_factor(directions[k].model, factors[k]);
    if (!c.range) {
      c.sample_models.push_back(bounded);
      c.check_models.push_back(bounded);
      continue;
    }
    for (const SloshingModel& m :
         sample_models(bounded, *c.range, c.options.uncertainty.sample_points)) {
      c.sample_models.push_back(m);
    }
    for (double delta : robustness_deltas(c.sweep)) {
      c.check_models.push_back(scaled_model(bounded, 1.0 + delta, c.sweep.zeta));
    }
  }
}

std::vector<NotchTarget> notch_targets(const StrategyContext& c) {
  if (!c.over_directions) return {{c.design_model.omega1(), 1.0, nullptr}};
  const double scale = c.range ? c.range->scale_mid() : 1.0;
  std::vector<NotchTarget> out;
  for (std::size_t k = 0; k < 2; ++k) {
    out.push_back({c.direction_omega[k] * scale, c.direction_weight[k], c.direction_name[k]});
  }
  return out;
}

std::vector<double> notched_frequencies(const StrategyContext& c, Strategy strategy) {
  std::vector<double> out;
  if (strategy != Strategy::kNotch && strategy != Strategy::kMultiNotch) return out;
  for (const NotchTarget& t : notch_targets(c)) {
    if (strategy == Strategy::kMultiNotch) out.push_back((1.0 - c.p_notch) * t.omega);
    out.push_back(t.omega);
    if (strategy == Strategy::kMultiNotch) out.push_back((1.0 + c.p_notch) * t.omega);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace detail

}  // namespace slosh
