#include <algorithm>
#include <cmath>
#include <numbers>

#include "slosh/core/response.hpp"

namespace slosh {

double nonlinear_acceleration(const SloshingModel& m, double x, double v, double a) {
  const double w = m.omega1();
  const double c2x2 = m.C * m.C * x * x;
  const double rhs = 2.0 * w * m.zeta * v * (1.0 + c2x2) + m.C * m.C * x * v * v +
                     w * w * x * (1.0 + m.alpha * x * x) + a / m.radius;
  return -rhs / (1.0 + c2x2);
}

NonlinearResponse::NonlinearResponse(const SloshingModel& model, const MotionLaw& law,
                                     double rest_time, const NonlinearOptions& options)
    : K_(model.K), motion_time_(law.duration()), end_time_(law.duration() + rest_time) {
  const double period = 2.0 * std::numbers::pi / model.omega1();
  const double h_max = std::min(options.max_step, period / options.steps_per_period);
  std::vector<LawPiece> pieces = law.pieces();
  pieces.push_back(LawPiece{motion_time_, end_time_});

  std::size_t total = 1;
  for (const LawPiece& p : pieces) {
    total += step_count(p.duration(), h_max);
  }
  time_.reserve(total);
  x_.reserve(total);
  v_.reserve(total);
  acc_.reserve(total);

  double x = 0.0;
  double v = 0.0;
  time_.push_back(0.0);
  x_.push_back(0.0);
  v_.push_back(0.0);
  acc_.push_back(nonlinear_acceleration(model, 0.0, 0.0, law.at(0.0).acceleration));
  for (const LawPiece& p : pieces) {
    const double L = p.duration();
    if (L <= 0.0) continue;
    const auto n = step_count(L, h_max, 1);
    const double h = L / static_cast<double>(n);
    auto accel = [&](double tau) { return p.at(tau).acceleration; };
    double a0 = accel(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double tau = h * static_cast<double>(i);
      const double a_mid = accel(tau + 0.5 * h);
      const double a1 = accel(tau + h);
      const double k1x = v;
      const double k1v = nonlinear_acceleration(model, x, v, a0);
      const double k2x = v + 0.5 * h * k1v;
      const double k2v = nonlinear_acceleration(model, x + 0.5 * h * k1x, k2x, a_mid);
      const double k3x = v + 0.5 * h * k2v;
      const double k3v = nonlinear_acceleration(model, x + 0.5 * h * k2x, k3x, a_mid);
      const double k4x = v + h * k3v;
      const double k4v = nonlinear_acceleration(model, x + h * k3x, k4x, a1);
      x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
      v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      time_.push_back(i + 1 == n ? p.t_end : p.t_begin + tau + h);
      x_.push_back(x);
      v_.push_back(v);
      acc_.push_back(nonlinear_acceleration(model, x, v, a1));
      a0 = a1;
    }
  }
  peak_step_ = h_max;
}

ModeState NonlinearResponse::state(double t) const {
  if (t <= 0.0) return {};
  if (t >= time_.back()) return {x_.back(), v_.back()};
  auto it = std::upper_bound(time_.begin(), time_.end(), t);
  const std::size_t i = static_cast<std::size_t>(it - time_.begin()) - 1;
  const double h = time_[i + 1] - time_[i];
  const double s = (t - time_[i]) / h;
  // Cubic Hermite on (x, v) for the position and on (v, acc) for the rate.
  const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
  const double h10 = s * (1.0 - s) * (1.0 - s);
  const double h01 = s * s * (3.0 - 2.0 * s);
  const double h11 = s * s * (s - 1.0);
  return {h00 * x_[i] + h10 * h * v_[i] + h01 * x_[i + 1] + h11 * h * v_[i + 1],
          h00 * v_[i] + h10 * h * acc_[i] + h01 * v_[i + 1] + h11 * h * acc_[i + 1]};
}

double NonlinearResponse::eta(double t) const {
  return K_ * state(t).x;
}

SloshPeaks NonlinearResponse::peaks() const {
  auto abs_eta = [this](double t) { return std::abs(eta(t)); };
  return {find_max(abs_eta, 0.0, motion_time_, peak_step_),
          find_max(abs_eta, motion_time_, end_time_, peak_step_)};
}

}  // namespace slosh
