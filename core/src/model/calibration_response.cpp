#include "model/calibration_response.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "response/law_pieces_dop.hpp"

namespace slosh::detail {

namespace {

// xbar'' of eq. 2.35 with omega_1, zeta and alpha as dual numbers (the expression of
// nonlinear_rhs, term for term, so the values agree with NonlinearResponse).
Dual3 rhs(const Dual3& w, const Dual3& zeta, const Dual3& alpha, const SloshingModel& m,
          const Dual3& x, const Dual3& v, double a) {
  const double c2 = m.C * m.C;
  const Dual3 c2x2 = c2 * x * x;
  const Dual3 num = 2.0 * w * zeta * v * (1.0 + c2x2) + c2 * x * v * v +
                    w * w * x * (1.0 + alpha * x * x) + a / m.radius;
  return -num / (1.0 + c2x2);
}

struct Params {
  Dual3 w, zeta, alpha;
};

}  // namespace

CalibrationResponse::CalibrationResponse(SloshingModel base, MotionLaw law, double rest_time,
                                         const NonlinearOptions& options)
    : base_(std::move(base)), law_(std::move(law)), rest_time_(rest_time), options_(options) {}

void CalibrationResponse::compute(const MotionParameters& p, double height_gain) {
  gain_ = height_gain;
  const Params params{Dual3::variable(p[0], 0) * base_.omega1(), Dual3::variable(p[1], 1),
                      Dual3::variable(p[2], 2)};
  // The grid of NonlinearResponse for the applied model (omega_1 scaled).
  const double period = 2.0 * std::numbers::pi / params.w.v;
  const double h_max = std::min(options_.max_step, period / options_.steps_per_period);
  std::vector<LawPiece> pieces = law_.pieces();
  const double T = law_.duration();
  pieces.push_back(LawPiece{T, T + rest_time_});
  t_.clear();
  h_.clear();
  x_.clear();
  auto f = [&](const Dual3& x, const Dual3& v, double a) {
    return rhs(params.w, params.zeta, params.alpha, base_, x, v, a);
  };
  integrate_law_pieces<Dual3>(pieces, h_max, options_.steps_per_period, f, false,
                              [&](double t0, double h, const DopStep<Dual3>& step) {
                                t_.push_back(t0);
                                h_.push_back(h);
                                x_.push_back(step.x_poly);
                              });
  end_ = T + rest_time_;
}

EtaSample CalibrationResponse::sample(std::size_t i, double t) const {
  const double H = h_[i];
  const double s = std::clamp((t - t_[i]) / H, 0.0, 1.0);
  const Dual3 xs = dense_value(x_[i], s);
  // d/dt of the same interpolant (the rate of the value returned, not the integrated xbar').
  double rate = 7.0 * x_[i][7].v;
  for (std::size_t k = 6; k >= 1; --k) rate = rate * s + static_cast<double>(k) * x_[i][k].v;
  const double k = base_.K * gain_;
  EtaSample out;
  out.value = k * xs.v;
  for (std::size_t j = 0; j < 3; ++j) out.gradient[j] = k * xs.d[j];
  out.rate = k * rate / H;
  return out;
}

EtaSample CalibrationResponse::eta_at(double t) const {
  const double tc = std::clamp(t, 0.0, end_);
  auto it = std::upper_bound(t_.begin(), t_.end(), tc);
  const std::size_t i = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  EtaSample out = sample(i, tc);
  if (tc != t) out.rate = 0.0;  // held beyond the computed window
  return out;
}

EtaSample CalibrationResponse::abs_peak(double t_begin, double t_end) const {
  t_begin = std::max(t_begin, 0.0);
  t_end = std::min(t_end, end_);
  auto it = std::upper_bound(t_.begin(), t_.end(), t_begin);
  std::size_t i = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  double best = -1.0, best_time = t_begin;
  std::size_t best_step = i;
  for (; i < t_.size() && t_[i] <= t_end; ++i) {
    const double H = h_[i];
    const double s_lo = std::max(0.0, (t_begin - t_[i]) / H);
    const double s_hi = std::min(1.0, (t_end - t_[i]) / H);
    DensePoly<double> values;
    for (std::size_t k = 0; k < kDenseTerms; ++k) values[k] = x_[i][k].v;
    const PolyMax m = dense_max_abs(values, s_lo, s_hi);
    if (m.value > best) {
      best = m.value;
      best_time = t_[i] + m.s * H;
      best_step = i;
    }
  }
  EtaSample out = sample(best_step, best_time);
  if (out.value < 0.0) {
    out.value = -out.value;
    for (double& g : out.gradient) g = -g;
    out.rate = -out.rate;
  }
  return out;
}

}  // namespace slosh::detail
