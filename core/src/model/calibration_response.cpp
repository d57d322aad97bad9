#include "model/calibration_response.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

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

void rk4(const Params& p, const SloshingModel& m, Dual3& x, Dual3& v, double h, double a0,
         double a_mid, double a1) {
  const double half_h = 0.5 * h;
  const Dual3 k1x = v;
  const Dual3 k1v = rhs(p.w, p.zeta, p.alpha, m, x, v, a0);
  const Dual3 k2x = v + half_h * k1v;
  const Dual3 k2v = rhs(p.w, p.zeta, p.alpha, m, x + half_h * k1x, k2x, a_mid);
  const Dual3 k3x = v + half_h * k2v;
  const Dual3 k3v = rhs(p.w, p.zeta, p.alpha, m, x + half_h * k2x, k3x, a_mid);
  const Dual3 k4x = v + h * k3v;
  const Dual3 k4v = rhs(p.w, p.zeta, p.alpha, m, x + h * k3x, k4x, a1);
  const double sixth_h = h * (1.0 / 6.0);
  x = x + sixth_h * (k1x + 2.0 * (k2x + k3x) + k4x);
  v = v + sixth_h * (k1v + 2.0 * (k2v + k3v) + k4v);
}

}  // namespace

CalibrationResponse::CalibrationResponse(SloshingModel base, MotionLaw law, double rest_time,
                                         const NonlinearOptions& options)
    : base_(std::move(base)), law_(std::move(law)), rest_time_(rest_time), options_(options) {}

void CalibrationResponse::compute(const MotionParameters& p, double height_gain) {
  gain_ = height_gain;
  const Params params{Dual3::variable(p[0], 0) * base_.omega1(), Dual3::variable(p[1], 1),
                      Dual3::variable(p[2], 2)};
  const double period = 2.0 * std::numbers::pi / params.w.v;
  const double h_max = std::min(options_.max_step, period / options_.steps_per_period);
  std::vector<LawPiece> pieces = law_.pieces();
  const double T = law_.duration();
  pieces.push_back(LawPiece{T, T + rest_time_});
  t_.assign(1, 0.0);
  x_.assign(1, Dual3(0.0));
  v_.assign(1, Dual3(0.0));
  Dual3 x(0.0), v(0.0);
  for (const LawPiece& piece : pieces) {
    const double L = piece.duration();
    if (L <= 0.0) continue;
    const auto n = step_count(L, h_max, 1);
    const double h = L / static_cast<double>(n);
    double a0 = piece.at(0.0).acceleration;
    for (std::size_t i = 0; i < n; ++i) {
      const double tau = h * static_cast<double>(i);
      const double a_mid = piece.at(tau + 0.5 * h).acceleration;
      const double a1 = piece.at(tau + h).acceleration;
      rk4(params, base_, x, v, h, a0, a_mid, a1);
      t_.push_back(i + 1 == n ? piece.t_end : piece.t_begin + tau + h);
      x_.push_back(x);
      v_.push_back(v);
      a0 = a1;
    }
  }
}

EtaSample CalibrationResponse::sample(std::size_t i, double t) const {
  const double H = t_[i + 1] - t_[i];
  const double s = H > 0.0 ? std::clamp((t - t_[i]) / H, 0.0, 1.0) : 1.0;
  const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
  const double h10 = s * (1.0 - s) * (1.0 - s);
  const double h01 = s * s * (3.0 - 2.0 * s);
  const double h11 = s * s * (s - 1.0);
  const Dual3 xs = h00 * x_[i] + (h10 * H) * v_[i] + h01 * x_[i + 1] + (h11 * H) * v_[i + 1];
  // d/ds of the basis, divided by H for d/dt.
  const double d00 = 6.0 * s * s - 6.0 * s;
  const double d10 = 3.0 * s * s - 4.0 * s + 1.0;
  const double d11 = 3.0 * s * s - 2.0 * s;
  const double rate =
      H > 0.0 ? (d00 * x_[i].v - d00 * x_[i + 1].v) / H + d10 * v_[i].v + d11 * v_[i + 1].v
              : v_[i + 1].v;
  const double k = base_.K * gain_;
  EtaSample out;
  out.value = k * xs.v;
  for (std::size_t j = 0; j < 3; ++j) out.gradient[j] = k * xs.d[j];
  out.rate = k * rate;
  return out;
}

EtaSample CalibrationResponse::eta_at(double t) const {
  const double tc = std::clamp(t, t_.front(), t_.back());
  auto it = std::upper_bound(t_.begin(), t_.end(), tc);
  std::size_t i = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  i = std::min(i, t_.size() - 2);
  EtaSample out = sample(i, tc);
  if (tc != t) out.rate = 0.0;  // held beyond the computed window
  return out;
}

EtaSample CalibrationResponse::abs_peak(double t_begin, double t_end) const {
  t_begin = std::max(t_begin, t_.front());
  t_end = std::min(t_end, t_.back());
  auto it = std::upper_bound(t_.begin(), t_.end(), t_begin);
  std::size_t i = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  double best = -1.0, best_time = t_begin;
  std::size_t best_interval = std::min(i, t_.size() - 2);
  for (; i + 1 < t_.size() && t_[i] <= t_end; ++i) {
    const double H = t_[i + 1] - t_[i];
    if (H <= 0.0) continue;
    const double s_lo = std::max(0.0, (t_begin - t_[i]) / H);
    const double s_hi = std::min(1.0, (t_end - t_[i]) / H);
    if (s_lo > s_hi) continue;
    const double x0 = x_[i].v, v0 = H * v_[i].v, x1 = x_[i + 1].v, v1 = H * v_[i + 1].v;
    // p(s) = x0 + c1 s + c2 s^2 + c3 s^3; candidates: the ends and the roots of p'.
    const double c1 = v0;
    const double c2 = -3.0 * x0 - 2.0 * v0 + 3.0 * x1 - v1;
    const double c3 = 2.0 * x0 + v0 - 2.0 * x1 + v1;
    std::array<double, 4> cand{s_lo, s_hi, -1.0, -1.0};
    const double qa = 3.0 * c3, qb = 2.0 * c2, qc = c1;
    if (std::abs(qa) > 1e-300) {
      const double disc = qb * qb - 4.0 * qa * qc;
      if (disc >= 0.0) {
        const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
        cand[2] = q / qa;
        if (q != 0.0) cand[3] = qc / q;
      }
    } else if (std::abs(qb) > 1e-300) {
      cand[2] = -qc / qb;
    }
    for (double s : cand) {
      if (s < s_lo || s > s_hi) continue;
      const double val = std::abs(x0 + s * (c1 + s * (c2 + s * c3)));
      if (val > best) {
        best = val;
        best_time = t_[i] + s * H;
        best_interval = i;
      }
    }
  }
  EtaSample out = sample(best_interval, best_time);
  if (out.value < 0.0) {
    out.value = -out.value;
    for (double& g : out.gradient) g = -g;
    out.rate = -out.rate;
  }
  return out;
}

}  // namespace slosh::detail
