#include "response/nonlinear_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "response/nonlinear_scheme.hpp"

namespace slosh::detail {

NonlinearSensitivity::NonlinearSensitivity(const SloshingModel& model, double stroke,
                                           double rest_time, const NonlinearOptions& options)
    : model_(model), stroke_(stroke), rest_time_(rest_time) {
  const double period = 2.0 * std::numbers::pi / model.omega1();
  h_max_ = std::min(options.max_step, period / options.steps_per_period);
}

void NonlinearSensitivity::compute(const double* d) {
  std::array<Dual7, kSegments> dd;
  for (std::size_t i = 0; i < kSegments; ++i) dd[i] = Dual7::variable(d[i], i);
  const auto lv = plateau_levels(dd, Dual7(stroke_));
  tv_.clear();
  t_.clear();
  x_.clear();
  v_.clear();
  Dual7 t(0.0), x(0.0), v(0.0);
  tv_.push_back(0.0);
  t_.push_back(t);
  x_.push_back(x);
  v_.push_back(v);
  // Acceleration on segment k at the fraction f of it: ramps interpolate linearly (exact for the
  // constant-jerk law), plateaus hold A or -B.
  auto accel = [&](std::size_t k, double f) -> Dual7 {
    switch (k) {
      case 0:
        return lv.A * f;
      case 1:
        return lv.A;
      case 2:
        return lv.A * (1.0 - f);
      case 4:
        return -(lv.B * f);
      case 5:
        return -lv.B;
      case 6:
        return -(lv.B * (1.0 - f));
      default:
        return Dual7(0.0);
    }
  };
  for (std::size_t k = 0; k < kSegments; ++k) {
    // A segment of zero length still takes one (empty) step so that its derivatives (the flow
    // of the state over dT_k) are carried; NonlinearResponse skips it, the values agree.
    const auto n = step_count(d[k], h_max_, 1);
    const Dual7 h = dd[k] * (1.0 / static_cast<double>(n));
    const Dual7 t_begin = t;
    for (std::size_t j = 0; j < n; ++j) {
      const double f0 = static_cast<double>(j) / static_cast<double>(n);
      const double fm = (static_cast<double>(j) + 0.5) / static_cast<double>(n);
      const double f1 = static_cast<double>(j + 1) / static_cast<double>(n);
      rk4_step(model_, x, v, h, accel(k, f0), accel(k, fm), accel(k, f1));
      t = j + 1 == n ? t_begin + dd[k] : t_begin + h * static_cast<double>(j + 1);
      tv_.push_back(t.v);
      t_.push_back(t);
      x_.push_back(x);
      v_.push_back(v);
    }
  }
  motion_time_ = t.v;
  const auto n_rest = step_count(rest_time_, h_max_, 1);
  const double h_rest = rest_time_ / static_cast<double>(n_rest);
  // The rest window has no forcing: its states depend on the durations only through the state
  // at T, so it is integrated with derivatives with respect to (x_T, v_T) and chained (a quarter
  // of the work of carrying all 7 directions).
  const Dual7 t_end = t;
  const Dual7 x_end = x, v_end = v;
  using Dual2 = Dual<2>;
  Dual2 xr = Dual2::variable(x.v, 0), vr = Dual2::variable(v.v, 1);
  const Dual2 zero(0.0);
  auto chain = [&](const Dual2& r) {
    Dual7 out(r.v);
    for (std::size_t i = 0; i < kSegments; ++i)
      out.d[i] = r.d[0] * x_end.d[i] + r.d[1] * v_end.d[i];
    return out;
  };
  for (std::size_t j = 0; j < n_rest; ++j) {
    rk4_step(model_, xr, vr, Dual2(h_rest), zero, zero, zero);
    t = j + 1 == n_rest ? t_end + rest_time_ : t_end + h_rest * static_cast<double>(j + 1);
    tv_.push_back(t.v);
    t_.push_back(t);
    x_.push_back(chain(xr));
    v_.push_back(chain(vr));
  }
}

void NonlinearSensitivity::abs_eta_at(const std::vector<double>& t, std::vector<double>* values,
                                      std::vector<std::array<double, kSegments>>* gradients) const {
  values->resize(t.size());
  if (gradients != nullptr) gradients->resize(t.size());
  std::size_t i = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double tk = std::clamp(t[k], tv_.front(), tv_.back());
    while (i + 2 < tv_.size() && (tv_[i + 1] < tk || tv_[i + 1] <= tv_[i])) ++i;
    const Dual7 H = t_[i + 1] - t_[i];
    const Dual7 s = H.v > 0.0 ? (Dual7(tk) - t_[i]) / H : Dual7(1.0);
    Dual7 xs = hermite(x_[i], v_[i], x_[i + 1], v_[i + 1], H, s);
    if (xs.v < 0.0) xs = -xs;
    (*values)[k] = model_.K * xs.v;
    if (gradients != nullptr) {
      for (std::size_t j = 0; j < kSegments; ++j) (*gradients)[k][j] = model_.K * xs.d[j];
    }
  }
}

WindowPeak NonlinearSensitivity::window_peak(double t_begin, double t_end) const {
  t_begin = std::max(t_begin, tv_.front());
  t_end = std::min(t_end, tv_.back());
  // First interval holding t_begin.
  auto it = std::upper_bound(tv_.begin(), tv_.end(), t_begin);
  std::size_t i = it == tv_.begin() ? 0 : static_cast<std::size_t>(it - tv_.begin()) - 1;
  double best = -1.0;
  double best_time = t_begin;
  std::size_t best_interval = i;
  for (; i + 1 < tv_.size() && tv_[i] <= t_end; ++i) {
    const double H = tv_[i + 1] - tv_[i];
    if (H <= 0.0) continue;
    const double s_lo = std::max(0.0, (t_begin - tv_[i]) / H);
    const double s_hi = std::min(1.0, (t_end - tv_[i]) / H);
    if (s_lo > s_hi) continue;
    const double x0 = x_[i].v, v0 = H * v_[i].v, x1 = x_[i + 1].v, v1 = H * v_[i + 1].v;
    // p(s) = c0 + c1 s + c2 s^2 + c3 s^3; candidates: the ends and the roots of p'.
    const double c1 = v0;
    const double c2 = -3.0 * x0 - 2.0 * v0 + 3.0 * x1 - v1;
    const double c3 = 2.0 * x0 + v0 - 2.0 * x1 + v1;
    auto value = [&](double s) { return std::abs(x0 + s * (c1 + s * (c2 + s * c3))); };
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
      const double val = value(s);
      if (val > best) {
        best = val;
        best_time = tv_[i] + s * H;
        best_interval = i;
      }
    }
  }
  WindowPeak out;
  const std::size_t j = best_interval;
  const Dual7 H = t_[j + 1] - t_[j];
  const Dual7 s = (Dual7(best_time) - t_[j]) / H;
  Dual7 xs = hermite(x_[j], v_[j], x_[j + 1], v_[j + 1], H, s);
  if (xs.v < 0.0) xs = -xs;
  out.value = model_.K * xs.v;
  out.time = best_time;
  for (std::size_t k = 0; k < kSegments; ++k) out.gradient[k] = model_.K * xs.d[k];
  return out;
}

}  // namespace slosh::detail
