// One direction of the rectangular nonlinear model: the dominant mode's oscillator, the linear
// higher modes, and the second mode the dominant one drives, integrated by classical RK4 on steps
// that never cross a law piece (where the acceleration, hence beta_1'', jumps) and interpolated by
// cubic Hermite for the peak search.

#include "slosh/core/response/rectangular_nonlinear_direction.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slosh/core/constants.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/peak_finder.hpp"

namespace slosh {

namespace {

/// RK4 steps per period of the second mode: the local error (sigma_2 h)^5 / 120 per step is
/// 1e-9 of the mode's amplitude, far below the second-order theory's own O(k A) error.
constexpr double kStepsPerSecondModePeriod{128.0};

}  // namespace

RectangularSecondMode rectangular_second_mode(const SloshingModel& model) {
  const double side = model.radius;
  const double h = model.fill_height;
  const double k = rectangular_wavenumber(side, 1);
  const double t = std::tanh(k * h);
  // The model's first frequency carries the calibrated omega_scale; the second scales alike.
  const double scale = model.omega1() / rectangular_frequency(side, h, 1);
  const double sigma2 = scale * std::sqrt(kGravity * 2.0 * k * std::tanh(2.0 * k * h));
  return {sigma2, k * (t * t - 1.0) / (t * (1.0 + t * t)), -2.0 * k / (t * (1.0 + t * t))};
}

RectangularNonlinearDirection::RectangularNonlinearDirection(const SloshingModel& model,
                                                             const MotionLaw& law, double rest_time,
                                                             const NonlinearOptions& options)
    : first_(model, law, rest_time, options),
      mode2_(rectangular_second_mode(model)),
      zeta_(model.zeta),
      gain_(model.K / (rectangular_wall_gain(model.radius, model.fill_height, 1) * model.radius)) {
  if (model.modes() > 1) {
    SloshingModel higher = model;
    higher.omega.erase(higher.omega.begin());
    higher.mass.erase(higher.mass.begin());
    higher.eta_gain.erase(higher.eta_gain.begin());
    higher_.emplace(higher, law, rest_time);
  }
  integrate_second_mode(model, law, rest_time);
  // The fastest of the model's modes and the second mode sets the sampling.
  const double fastest =
      std::max(*std::max_element(model.omega.begin(), model.omega.end()), mode2_.sigma2);
  const double period = 2.0 * std::numbers::pi / fastest;
  peak_step_ = std::min(kMaxPeakStep, period / kSamplesPerPeriod);
  const double T = law.duration();
  auto wall_at = [this](double t) { return wall(t); };
  peaks_ = {find_max(wall_at, 0.0, T, peak_step_), find_max(wall_at, T, T + rest_time, peak_step_)};
}

void RectangularNonlinearDirection::integrate_second_mode(const SloshingModel& model,
                                                          const MotionLaw& law, double rest_time) {
  const double s2 = mode2_.sigma2;
  const double k_raw = model.K / gain_;  // beta_1 = k_raw xbar without the height gain
  // The right-hand side's forcing -d4 beta_1 beta_1'' - d5 beta_1'^2 at t, for the acceleration
  // a of the piece holding t (it does not depend on b_2: three evaluations a step, the last one
  // the next step's first within a stretch).
  auto forcing = [&](double t, double a) {
    const ModeState s = first_.state(t);
    const double x_dd = nonlinear_acceleration(model, s.x, s.x_dot, a);
    const double beta = k_raw * s.x, beta_dot = k_raw * s.x_dot, beta_dd = k_raw * x_dd;
    return -mode2_.d4 * beta * beta_dd - mode2_.d5 * beta_dot * beta_dot;
  };
  auto rhs = [&](double b, double v, double f) { return -2.0 * zeta_ * s2 * v - s2 * s2 * b + f; };
  const double h_max = 2.0 * std::numbers::pi / s2 / kStepsPerSecondModePeriod;
  double b = 0.0, v = 0.0;
  t_.assign(1, 0.0);
  b_.assign(1, 0.0);
  b_dot_.assign(1, 0.0);
  // One stretch [t0, t0 + length] of smooth acceleration acc(t) in equal RK4 steps.
  auto stretch = [&](double t0, double length, const auto& acc) {
    const std::size_t n = step_count(length, h_max, 1);
    const double h = length / static_cast<double>(n);
    double f0 = forcing(t0, acc(t0));
    for (std::size_t i = 0; i < n; ++i) {
      const double t = t0 + h * static_cast<double>(i);
      const double fm = forcing(t + 0.5 * h, acc(t + 0.5 * h));
      const double f1 = forcing(t + h, acc(t + h));
      const double k1b = v, k1v = rhs(b, v, f0);
      const double k2b = v + 0.5 * h * k1v, k2v = rhs(b + 0.5 * h * k1b, k2b, fm);
      const double k3b = v + 0.5 * h * k2v, k3v = rhs(b + 0.5 * h * k2b, k3b, fm);
      const double k4b = v + h * k3v, k4v = rhs(b + h * k3b, k4b, f1);
      b += h / 6.0 * (k1b + 2.0 * k2b + 2.0 * k3b + k4b);
      v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      t_.push_back(t0 + h * static_cast<double>(i + 1));
      b_.push_back(b);
      b_dot_.push_back(v);
      f0 = f1;
    }
  };
  for (const LawPiece& p : law.pieces()) {
    if (p.duration() <= 0.0) continue;
    stretch(p.t_begin, p.duration(), [&p](double t) {
      return p.at(std::clamp(t - p.t_begin, 0.0, p.duration())).acceleration;
    });
  }
  if (rest_time > 0.0) stretch(law.duration(), rest_time, [](double) { return 0.0; });
}

double RectangularNonlinearDirection::eta_even(double t) const {
  if (t <= t_.front()) return gain_ * b_.front();
  if (t >= t_.back()) return gain_ * b_.back();
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  const double h = t_[i + 1] - t_[i];
  const double s = (t - t_[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  const double value = (2.0 * s3 - 3.0 * s2 + 1.0) * b_[i] + (s3 - 2.0 * s2 + s) * h * b_dot_[i] +
                       (-2.0 * s3 + 3.0 * s2) * b_[i + 1] + (s3 - s2) * h * b_dot_[i + 1];
  return gain_ * value;
}

double RectangularNonlinearDirection::wall(double t) const {
  return std::abs(eta_odd(t)) + std::abs(eta_even(t));
}

}  // namespace slosh
