#include "response/nonlinear_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace slosh::detail {

NonlinearSensitivity::NonlinearSensitivity(const SloshingModel& model, double stroke,
                                           double rest_time, const NonlinearOptions& options)
    : model_(model), stroke_(stroke), rest_time_(rest_time) {
  const double period = 2.0 * std::numbers::pi / model.omega1();
  h_max_ = std::min(options.max_step, period / options.steps_per_period);
}

bool NonlinearSensitivity::freeze_steps(const double* d) {
  std::array<std::size_t, kSegments> n{};
  for (std::size_t k = 0; k < kSegments; ++k) n[k] = step_count(d[k], h_max_, 1) + 1;
  const bool changed = !frozen_ || n != steps_;
  steps_ = n;
  frozen_ = true;
  return changed;
}

namespace {

/// Acceleration on segment k at the fraction f of it: ramps interpolate linearly (exact for the
/// constant-jerk law), plateaus hold A or -B. Inlined: the DOP853 stages call it on every step.
[[gnu::always_inline]] inline Dual7 segment_acceleration(const PlateauLevelsT<Dual7>& lv,
                                                         std::size_t k, double f) {
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
}

/// The rest window from the state (x_end, v_end) at t_end, n_rest steps of h_rest, each step
/// handed to store(t0, h, x_poly). It has no forcing: its states depend on the durations only
/// through the state at T, so it is integrated with derivatives with respect to (x_T, v_T) and
/// chained (a quarter of the work of carrying all 7 directions).
template <typename Store>
void integrate_rest(const SloshingModel& model, const Dual7& t_end, const Dual7& x_end,
                    const Dual7& v_end, std::size_t n_rest, double h_rest, const Store& store) {
  using Dual2 = Dual<2>;
  Dual2 xr = Dual2::variable(x_end.v, 0), vr = Dual2::variable(v_end.v, 1);
  auto chain = [&](const Dual2& r) {
    Dual7 out(r.v);
    for (std::size_t i = 0; i < kSegments; ++i)
      out.d[i] = r.d[0] * x_end.d[i] + r.d[1] * v_end.d[i];
    return out;
  };
  auto rhs2 = [&model](const Dual2& xx, const Dual2& vv, double a) {
    return nonlinear_rhs(model, xx, vv, a);
  };
  Dual2 f0 = rhs2(xr, vr, 0.0);
  DopStep<Dual2> rest_step;
  for (std::size_t j = 0; j < n_rest; ++j) {
    dop853_step(
        rhs2, [](std::size_t) { return 0.0; }, xr, vr, f0, Dual2(h_rest), true, rest_step, false);
    DensePoly<Dual7> x_poly;
    for (std::size_t k = 0; k < kDenseTerms; ++k) x_poly[k] = chain(rest_step.x_poly[k]);
    store(t_end + h_rest * static_cast<double>(j), Dual7(h_rest), x_poly);
    xr = rest_step.x1;
    vr = rest_step.v1;
    f0 = rest_step.f1;
  }
}

}  // namespace

void NonlinearSensitivity::compute(const double* d) {
  std::array<Dual7, kSegments> dd;
  for (std::size_t i = 0; i < kSegments; ++i) dd[i] = Dual7::variable(d[i], i);
  const auto lv = plateau_levels(dd, Dual7(stroke_));
  tv_.clear();
  hv_.clear();
  xv_.clear();
  t_.clear();
  h_.clear();
  x_.clear();
  auto store = [&](const Dual7& t0, const Dual7& h, const DensePoly<Dual7>& x_poly) {
    tv_.push_back(t0.v);
    hv_.push_back(h.v);
    DensePoly<double> values;
    for (std::size_t k = 0; k < kDenseTerms; ++k) values[k] = x_poly[k].v;
    xv_.push_back(values);
    t_.push_back(t0);
    h_.push_back(h);
    x_.push_back(x_poly);
  };
  auto accel = [&lv](std::size_t k, double f) { return segment_acceleration(lv, k, f); };
  auto rhs7 = [this](const Dual7& x, const Dual7& v, const Dual7& a) {
    return nonlinear_rhs(model_, x, v, a);
  };
  Dual7 t(0.0), x(0.0), v(0.0);
  DopStep<Dual7> step;
  for (std::size_t k = 0; k < kSegments; ++k) {
    // A segment of zero length still takes one (empty) step so that its derivatives (the flow
    // of the state over dT_k) are carried; NonlinearResponse skips it, the values agree.
    const std::size_t own = step_count(d[k], h_max_, 1);
    const std::size_t n = frozen_ ? std::max(own, steps_[k]) : own;
    const double inv_n = 1.0 / static_cast<double>(n);
    const Dual7 h = dd[k] * inv_n;
    const Dual7 t_begin = t;
    // As NonlinearResponse: the first stage of a segment is evaluated on that segment.
    Dual7 f0 = rhs7(x, v, accel(k, 0.0));
    for (std::size_t j = 0; j < n; ++j) {
      const double jd = static_cast<double>(j);
      const Dual7 t0 = t_begin + h * jd;
      dop853_step(
          rhs7, [&](std::size_t i) { return accel(k, (jd + kDopC[i]) * inv_n); }, x, v, f0, h, true,
          step, false);
      store(t0, h, step.x_poly);
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
    }
    t = t_begin + dd[k];
  }
  motion_time_ = t.v;
  const auto n_rest = step_count(rest_time_, h_max_, 1);
  const double h_rest = rest_time_ / static_cast<double>(n_rest);
  integrate_rest(model_, t, x, v, n_rest, h_rest, store);
}

Dual7 NonlinearSensitivity::x_at(std::size_t i, double t) const {
  const Dual7 s = h_[i].v > 0.0 ? (Dual7(t) - t_[i]) / h_[i] : Dual7(1.0);
  return dense_value(x_[i], s);
}

void NonlinearSensitivity::abs_eta_at(const std::vector<double>& t, std::vector<double>* values,
                                      std::vector<std::array<double, kSegments>>* gradients) const {
  values->resize(t.size());
  if (gradients != nullptr) gradients->resize(t.size());
  const double t_last = tv_.back() + hv_.back();
  std::size_t i = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double tk = std::clamp(t[k], 0.0, t_last);
    // The step holding tk (the later of two at a shared end; empty steps are passed over).
    while (i + 1 < tv_.size() && (tv_[i] + hv_[i] < tk || hv_[i] <= 0.0)) ++i;
    Dual7 xs = x_at(i, tk);
    if (xs.v < 0.0) xs = -xs;
    (*values)[k] = model_.K * xs.v;
    if (gradients != nullptr) {
      for (std::size_t j = 0; j < kSegments; ++j) (*gradients)[k][j] = model_.K * xs.d[j];
    }
  }
}

WindowPeak NonlinearSensitivity::window_peak(double t_begin, double t_end) const {
  t_begin = std::max(t_begin, 0.0);
  t_end = std::min(t_end, tv_.back() + hv_.back());
  double best = -1.0;
  double best_time = t_begin;
  std::size_t best_step = 0;
  // First step that can hold t_begin.
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(tv_.begin(), tv_.end(), t_begin) - tv_.begin());
  i = i == 0 ? 0 : i - 1;
  for (; i < tv_.size() && tv_[i] <= t_end; ++i) {
    const double H = hv_[i];
    if (H <= 0.0 || !(dense_abs_bound(xv_[i]) > best)) continue;
    const double s_lo = std::max(0.0, (t_begin - tv_[i]) / H);
    const double s_hi = std::min(1.0, (t_end - tv_[i]) / H);
    const PolyMax m = dense_max_abs(xv_[i], s_lo, s_hi);
    if (m.value > best) {
      best = m.value;
      best_time = tv_[i] + m.s * H;
      best_step = i;
    }
  }
  WindowPeak out;
  Dual7 xs = x_at(best_step, best_time);
  if (xs.v < 0.0) xs = -xs;
  out.value = model_.K * xs.v;
  out.time = best_time;
  for (std::size_t k = 0; k < kSegments; ++k) out.gradient[k] = model_.K * xs.d[k];
  return out;
}

}  // namespace slosh::detail
