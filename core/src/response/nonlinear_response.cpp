#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "slosh/core/response/response.hpp"

#include "response/nonlinear_scheme.hpp"

namespace slosh {

double nonlinear_acceleration(const SloshingModel& m, double x, double v, double a) {
  return detail::nonlinear_rhs(m, x, v, a);
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
      detail::rk4_step(model, x, v, h, a0, a_mid, a1);
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
  return {detail::hermite(x_[i], v_[i], x_[i + 1], v_[i + 1], h, s),
          detail::hermite(v_[i], acc_[i], v_[i + 1], acc_[i + 1], h, s)};
}

double NonlinearResponse::eta(double t) const {
  // Position only: the peak search's hot path.
  if (t <= 0.0) return 0.0;
  if (t >= time_.back()) return K_ * x_.back();
  auto it = std::upper_bound(time_.begin(), time_.end(), t);
  const std::size_t i = static_cast<std::size_t>(it - time_.begin()) - 1;
  const double h = time_[i + 1] - time_[i];
  return K_ * detail::hermite(x_[i], v_[i], x_[i + 1], v_[i + 1], h, (t - time_[i]) / h);
}

SloshPeaks NonlinearResponse::peaks() const {
  auto abs_eta = [this](double t) { return std::abs(eta(t)); };
  SloshPeaks p{find_max(abs_eta, 0.0, motion_time_, peak_step_),
               find_max(abs_eta, motion_time_, end_time_, peak_step_)};
  // A diverged integration stays non-finite to its end, and the scan skips NaN samples (they
  // compare false): the peaks say so instead of showing the values before the divergence.
  if (!std::isfinite(eta(end_time_))) {
    p.motion.value = std::numeric_limits<double>::quiet_NaN();
    p.rest.value = std::numeric_limits<double>::quiet_NaN();
  }
  return p;
}

}  // namespace slosh
