#include "model/rectangular_direction_dual.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "response/law_pieces_dop.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/rectangular_nonlinear_direction.hpp"

namespace slosh::detail {

namespace {

/// RK4 steps per period of the second mode, as RectangularNonlinearDirection.
constexpr double kStepsPerSecondModePeriod{128.0};

/// xbar'' of eq. 2.35 with omega_1 and zeta as dual numbers (nonlinear_rhs term for term).
Dual2 dominant_rhs(const Dual2& w, const Dual2& zeta, const SloshingModel& m, double alpha,
                   const Dual2& x, const Dual2& v, double a) {
  const double c2 = m.C * m.C;
  const Dual2 c2x2 = c2 * x * x;
  const Dual2 num = 2.0 * w * zeta * v * (1.0 + c2x2) + c2 * x * v * v +
                    w * w * x * (1.0 + alpha * x * x) + a / m.radius;
  return -num / (1.0 + c2x2);
}

/// One oscillator x'' = f(x, x', a) from rest over the law's pieces and the rest window, by
/// DOP853 on NonlinearResponse's grid for the frequency w (steps of at most min(max_step,
/// period / steps_per_period), equal within a piece, harmonic pieces resolved).
template <typename Rhs>
RectangularDirectionDual::Trajectory integrate(const Rhs& f, double w, const MotionLaw& law,
                                               double rest_time, const NonlinearOptions& options,
                                               double gain) {
  RectangularDirectionDual::Trajectory tr;
  tr.gain = gain;
  const double period = 2.0 * std::numbers::pi / w;
  const double h_max = std::min(options.max_step, period / options.steps_per_period);
  std::vector<LawPiece> pieces = law.pieces();
  const double T = law.duration();
  pieces.push_back(LawPiece{T, T + rest_time});
  integrate_law_pieces<Dual2>(pieces, h_max, options.steps_per_period, f, true,
                              [&](double t0, double h, const DopStep<Dual2>& step) {
                                tr.t0.push_back(t0);
                                tr.h.push_back(h);
                                tr.x.push_back(step.x_poly);
                                tr.v.push_back(step.v_poly);
                              });
  return tr;
}

DirectionSample sample_of(const Dual2& value, double rate) {
  return {value.v, {value.d[0], value.d[1]}, rate};
}

}  // namespace

RectangularDirectionDual::RectangularDirectionDual(SloshingModel base, MotionLaw law,
                                                   double rest_time,
                                                   const NonlinearOptions& options, bool nonlinear)
    : base_(std::move(base)),
      law_(std::move(law)),
      rest_time_(rest_time),
      options_(options),
      nonlinear_(nonlinear) {}

void RectangularDirectionDual::compute(double omega_scale, double zeta_value) {
  const Dual2 scale = Dual2::variable(omega_scale, 0);
  const Dual2 zeta = Dual2::variable(zeta_value, 1);
  modes_.clear();
  // The dominant mode in xbar (eta = K xbar): the third-order oscillator, or linear (alpha 0).
  const Dual2 w1 = scale * base_.omega1();
  const double alpha = nonlinear_ ? base_.alpha : 0.0;
  modes_.push_back(
      integrate([&](const Dual2& x, const Dual2& v,
                    double a) { return dominant_rhs(w1, zeta, base_, alpha, x, v, a); },
                w1.v, law_, rest_time_, options_, base_.K));
  // The higher modes in x_n (eta = G_n x_n): x'' + 2 zeta w x' + w^2 x = -a.
  double fastest = w1.v;
  for (std::size_t n = 1; n < base_.omega.size(); ++n) {
    const Dual2 w = scale * base_.omega[n];
    fastest = std::max(fastest, w.v);
    modes_.push_back(integrate([&](const Dual2& x, const Dual2& v,
                                   double a) { return -(2.0 * zeta * w * v + w * w * x + a); },
                               w.v, law_, rest_time_, options_, base_.eta_gain[n]));
  }
  t2_.clear();
  b_.clear();
  b_dot_.clear();
  if (nonlinear_) {
    integrate_second_mode(w1, zeta, omega_scale);
    fastest = std::max(fastest, omega_scale * rectangular_second_mode(base_).sigma2);
  }
  peak_step_ = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / fastest / kSamplesPerPeriod);
}

RectangularDirectionDual::State RectangularDirectionDual::state_at(const Trajectory& tr, double t) {
  if (t <= 0.0 || tr.t0.empty()) return {};
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(tr.t0.begin(), tr.t0.end(), t) - tr.t0.begin()) - 1;
  const double s = std::min((t - tr.t0[i]) / tr.h[i], 1.0);
  return {dense_value(tr.x[i], s), dense_value(tr.v[i], s)};
}

void RectangularDirectionDual::integrate_second_mode(const Dual2& w1, const Dual2& zeta,
                                                     double scale) {
  // RectangularNonlinearDirection::integrate_second_mode, step for step, in dual numbers: the
  // second mode's frequency scales with the first (sigma_2 = scale sigma_2 of the theory).
  const RectangularSecondMode m2 = rectangular_second_mode(base_);
  const Dual2 s2 = w1 * (m2.sigma2 / base_.omega1());
  const double k_raw = base_.K;
  const Trajectory& first = modes_.front();
  auto forcing = [&](double t, double a) {
    const State s = state_at(first, t);
    const Dual2 x_dd = dominant_rhs(w1, zeta, base_, base_.alpha, s.x, s.v, a);
    const Dual2 beta = k_raw * s.x, beta_dot = k_raw * s.v, beta_dd = k_raw * x_dd;
    return -m2.d4 * beta * beta_dd - m2.d5 * beta_dot * beta_dot;
  };
  auto rhs = [&](const Dual2& b, const Dual2& v, const Dual2& f) {
    return -2.0 * zeta * s2 * v - s2 * s2 * b + f;
  };
  const double h_max = 2.0 * std::numbers::pi / (scale * m2.sigma2) / kStepsPerSecondModePeriod;
  Dual2 b(0.0), v(0.0);
  t2_.assign(1, 0.0);
  b_.assign(1, Dual2(0.0));
  b_dot_.assign(1, Dual2(0.0));
  auto stretch = [&](double t0, double length, const auto& acc) {
    const std::size_t n = step_count(length, h_max, 1);
    const double h = length / static_cast<double>(n);
    Dual2 f0 = forcing(t0, acc(t0));
    for (std::size_t i = 0; i < n; ++i) {
      const double t = t0 + h * static_cast<double>(i);
      const Dual2 fm = forcing(t + 0.5 * h, acc(t + 0.5 * h));
      const Dual2 f1 = forcing(t + h, acc(t + h));
      const Dual2 k1b = v, k1v = rhs(b, v, f0);
      const Dual2 k2b = v + 0.5 * h * k1v, k2v = rhs(b + 0.5 * h * k1b, k2b, fm);
      const Dual2 k3b = v + 0.5 * h * k2v, k3v = rhs(b + 0.5 * h * k2b, k3b, fm);
      const Dual2 k4b = v + h * k3v, k4v = rhs(b + h * k3b, k4b, f1);
      b = b + h / 6.0 * (k1b + 2.0 * k2b + 2.0 * k3b + k4b);
      v = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      t2_.push_back(t0 + h * static_cast<double>(i + 1));
      b_.push_back(b);
      b_dot_.push_back(v);
      f0 = f1;
    }
  };
  for (const LawPiece& p : law_.pieces()) {
    if (p.duration() <= 0.0) continue;
    stretch(p.t_begin, p.duration(), [&p](double t) {
      return p.at(std::clamp(t - p.t_begin, 0.0, p.duration())).acceleration;
    });
  }
  if (rest_time_ > 0.0) stretch(law_.duration(), rest_time_, [](double) { return 0.0; });
}

DirectionSample RectangularDirectionDual::odd(double t) const {
  Dual2 eta(0.0);
  double rate = 0.0;
  for (const Trajectory& tr : modes_) {
    const State s = state_at(tr, t);
    eta = eta + tr.gain * s.x;
    rate += tr.gain * s.v.v;
  }
  return sample_of(eta, rate);
}

DirectionSample RectangularDirectionDual::even(double t) const {
  if (b_.empty()) return {};
  if (t <= t2_.front()) return sample_of(b_.front(), 0.0);
  if (t >= t2_.back()) return sample_of(b_.back(), 0.0);
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(t2_.begin(), t2_.end(), t) - t2_.begin()) - 1;
  const double h = t2_[i + 1] - t2_[i];
  const double s = (t - t2_[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  // The cubic Hermite interpolant and its time derivative.
  const double rate =
      ((6.0 * s2 - 6.0 * s) * b_[i].v + (3.0 * s2 - 4.0 * s + 1.0) * h * b_dot_[i].v +
       (6.0 * s - 6.0 * s2) * b_[i + 1].v + (3.0 * s2 - 2.0 * s) * h * b_dot_[i + 1].v) /
      h;
  return sample_of((2.0 * s3 - 3.0 * s2 + 1.0) * b_[i] + (s3 - 2.0 * s2 + s) * h * b_dot_[i] +
                       (-2.0 * s3 + 3.0 * s2) * b_[i + 1] + (s3 - s2) * h * b_dot_[i + 1],
                   rate);
}

}  // namespace slosh::detail
