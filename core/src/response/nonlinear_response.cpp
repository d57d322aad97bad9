#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>

#include "slosh/core/response/response.hpp"

#include "response/nonlinear_scheme.hpp"

namespace slosh {

double nonlinear_acceleration(const SloshingModel& m, double x, double v, double a) {
  return detail::nonlinear_rhs(m, x, v, a);
}

namespace detail {

/// Where the rest window's integration stopped once its peak was proved found: the state after
/// step j - 1 of the window's n steps of length h from t_begin.
struct RestResume {
  double x{}, v{}, f0{}, h{}, t_begin{};
  std::size_t j{}, n{};
};

}  // namespace detail

namespace {

using detail::RestResume;

/// The trajectory kept by NonlinearResponse (null for nonlinear_peaks).
struct Keep {
  std::vector<double>* t0;
  std::vector<double>* h;
  std::vector<NonlinearResponse::StepPoly>* x_poly;
  std::vector<NonlinearResponse::StepPoly>* v_poly;
};

/// One classical RK4 step with the cubic Hermite interpolants of x (from x, v) and v (from v,
/// x''), in the DopStep layout: the scheme of the divergence fallback (integrate_or_refine).
template <typename Rhs, typename Acc>
void rk4_step(const Rhs& rhs, const Acc& acc, double x, double v, double f0, double h,
              detail::DopStep<double>& out) {
  const double a_mid = acc(0.5), a1 = acc(1.0);
  const double half_h = 0.5 * h;
  const double k2x = v + half_h * f0;
  const double k2v = rhs(x + half_h * v, k2x, a_mid);
  const double k3x = v + half_h * k2v;
  const double k3v = rhs(x + half_h * k2x, k3x, a_mid);
  const double k4x = v + h * k3v;
  const double k4v = rhs(x + h * k3x, k4x, a1);
  const double sixth_h = h * (1.0 / 6.0);
  out.x1 = x + sixth_h * (v + 2.0 * (k2x + k3x) + k4x);
  out.v1 = v + sixth_h * (f0 + 2.0 * (k2v + k3v) + k4v);
  out.f1 = rhs(out.x1, out.v1, a1);
  auto hermite = [h](double y0, double d0, double y1, double d1) {
    detail::DensePoly<double> p{};
    p[0] = y0;
    p[1] = h * d0;
    p[2] = -3.0 * y0 - 2.0 * h * d0 + 3.0 * y1 - h * d1;
    p[3] = 2.0 * y0 + h * d0 - 2.0 * y1 + h * d1;
    return p;
  };
  out.x_poly = hermite(x, v, out.x1, out.v1);
  out.v_poly = hermite(v, f0, out.v1, out.f1);
}

/// Raises `window` to the step's maximum of K |xbar| when it exceeds it; the cheap bound of the
/// step's polynomial skips the search on the (many) steps that cannot hold a new peak.
[[gnu::always_inline]] inline void raise_window_peak(Peak& window, double K,
                                                     const detail::DensePoly<double>& x_poly,
                                                     double t0, double h) {
  if (K * detail::dense_abs_bound(x_poly) > window.value) {
    const detail::PolyMax m = detail::dense_max_abs(x_poly, 0.0, 1.0);
    if (K * m.value > window.value) window = {K * m.value, t0 + m.s * h};
  }
}

/// K times the largest |xbar| the free motion from (x, v) can reach (docs/models.md): its energy
/// never increases, and bounds |xbar| by V^-1(E): alpha/4 y^2 + y/2 = E / w^2 with y = xbar^2.
[[gnu::always_inline]] inline double free_motion_bound(double K, double w, double c2, double alpha,
                                                       double x, double v) {
  const double e =
      (0.5 * (1.0 + c2 * x * x) * v * v + w * w * x * x * (0.5 + 0.25 * alpha * x * x)) / (w * w);
  return K * std::sqrt(2.0 * e / (0.5 + std::sqrt(0.25 + alpha * e)));
}

/// Appends one step to the kept trajectory.
[[gnu::always_inline]] inline void keep_step(const Keep& keep, double t0, double h,
                                             const detail::DopStep<double>& step) {
  keep.t0->push_back(t0);
  keep.h->push_back(h);
  keep.x_poly->push_back(step.x_poly);
  keep.v_poly->push_back(step.v_poly);
}

/// A diverged integration stays non-finite to its end, and the search skips NaN values (they
/// compare false): the peaks say so instead of showing the values before the divergence.
void mark_if_diverged(double x, double v, SloshPeaks& peaks) {
  if (!std::isfinite(x) || !std::isfinite(v)) {
    peaks.motion.value = std::numeric_limits<double>::quiet_NaN();
    peaks.rest.value = std::numeric_limits<double>::quiet_NaN();
  }
}

/// Integrates eq. 2.35 over the law and the rest window and returns the peaks; with `keep` the
/// whole rest window is integrated and every step stored, else the integration ends where the
/// rest window's search does. `last` receives the final state.
SloshPeaks integrate(const SloshingModel& model, const MotionLaw& law, double rest_time,
                     const NonlinearOptions& options, const Keep* keep, ModeState* last,
                     bool rk4 = false, std::optional<RestResume>* resume = nullptr) {
  const double w = model.omega1();
  const double period = 2.0 * std::numbers::pi / w;
  const double h_max = std::min(options.max_step, period / options.steps_per_period);
  const double T = law.duration();
  const double K = model.K;
  const double c2 = model.C * model.C;
  const std::vector<LawPiece>& pieces = law.pieces();
  const std::size_t n_pieces = pieces.size() + 1;  // the law's pieces, then the rest window
  const LawPiece rest{T, T + rest_time};
  auto rhs = [&model](double x, double v, double a) {
    return detail::nonlinear_rhs(model, x, v, a);
  };

  SloshPeaks peaks;  // motion: eta(0) = 0 at t = 0
  bool rest_found = false;
  double x = 0.0, v = 0.0;
  detail::DopStep<double> step;
  for (std::size_t k = 0; k < n_pieces && !(rest_found && keep == nullptr); ++k) {
    const bool in_rest = k + 1 == n_pieces;
    const LawPiece& p = in_rest ? rest : pieces[k];
    const double L = p.duration();
    if (!(L > 0.0)) continue;
    const double hp = detail::piece_max_step(h_max, p.harmonic_omega, options.steps_per_period);
    const std::size_t n = step_count(L, hp, 1);
    const double h = L / static_cast<double>(n);
    // The acceleration may jump at a piece start: the first stage is evaluated on this piece.
    double f0 = rhs(x, v, in_rest ? 0.0 : p.acceleration(0.0));
    Peak& window = in_rest ? peaks.rest : peaks.motion;
    for (std::size_t j = 0; j < n; ++j) {
      const double tau = h * static_cast<double>(j);
      if (rk4) {
        rk4_step(
            rhs, [&](double c) { return in_rest ? 0.0 : p.acceleration(tau + c * h); }, x, v, f0, h,
            step);
      } else if (in_rest) {
        detail::dop853_step(
            rhs, [](std::size_t) { return 0.0; }, x, v, f0, h, true, step, keep != nullptr);
      } else {
        detail::dop853_step(
            rhs, [&](std::size_t i) { return p.acceleration(tau + detail::kDopC[i] * h); }, x, v,
            f0, h, true, step, keep != nullptr);
      }
      const double t0 = p.t_begin + tau;
      if (!(in_rest && rest_found)) raise_window_peak(window, K, step.x_poly, t0, h);
      if (keep != nullptr) keep_step(*keep, t0, h, step);
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
      // Once the free motion cannot exceed the rest window's peak found, the window is done.
      if (in_rest && !rest_found && !rk4) {
        const double bound = free_motion_bound(K, w, c2, model.alpha, x, v);
        if (bound * (1.0 + detail::kEnergyStopMargin) <= peaks.rest.value) {
          rest_found = true;
          if (keep == nullptr) break;
          if (resume != nullptr) {
            *resume = RestResume{x, v, f0, h, p.t_begin, j + 1, n};
            break;
          }
        }
      }
      if (!std::isfinite(x) && keep == nullptr) break;
    }
    if (!std::isfinite(x) && keep == nullptr) break;
  }
  if (last != nullptr) *last = {x, v};
  mark_if_diverged(x, v, peaks);
  return peaks;
}

/// integrate(), and when the response diverges on the period-based grid, or leaves the model's
/// range (|xbar| > kModelRange), once more over the whole window (no early end of the rest
/// window) by classical RK4 with steps of at most min(1 ms, period / 100) (cubic Hermite dense
/// output): far outside
/// the model's range (peak accelerations of thousands of m/s^2) the motion is stiff on the scale
/// of the period and the order-8 stages leave the region where the model is defined; the
/// product's verdict there (a response, or "diverges") stays that of the fine low-order grid.
constexpr double kDivergenceRetryStep{1e-3};
constexpr double kDivergenceRetryStepsPerPeriod{100.0};

SloshPeaks integrate_or_refine(const SloshingModel& model, const MotionLaw& law, double rest_time,
                               const NonlinearOptions& options, const Keep* keep, ModeState* last,
                               std::optional<RestResume>* resume = nullptr) {
  SloshPeaks p = integrate(model, law, rest_time, options, keep, last, false, resume);
  if (std::max(p.motion.value, p.rest.value) <= detail::kModelRange * model.K) return p;
  NonlinearOptions fine = options;
  fine.max_step = std::min(options.max_step, kDivergenceRetryStep);
  fine.steps_per_period = std::max(options.steps_per_period, kDivergenceRetryStepsPerPeriod);
  if (keep != nullptr) {
    keep->t0->clear();
    keep->h->clear();
    keep->x_poly->clear();
    keep->v_poly->clear();
  }
  if (resume != nullptr) resume->reset();
  return integrate(model, law, rest_time, fine, keep, last, true);
}

/// The rest of the rest window from `r`, step for step what integrate() does there once the
/// peak is found (the forcing is zero; nothing is searched).
void resume_rest(const SloshingModel& model, const RestResume& r, const Keep& keep,
                 ModeState& last) {
  auto rhs = [&model](double x, double v, double a) {
    return detail::nonlinear_rhs(model, x, v, a);
  };
  double x = r.x, v = r.v, f0 = r.f0;
  detail::DopStep<double> step;
  for (std::size_t j = r.j; j < r.n; ++j) {
    const double tau = r.h * static_cast<double>(j);
    detail::dop853_step(
        rhs, [](std::size_t) { return 0.0; }, x, v, f0, r.h, true, step, true);
    keep.t0->push_back(r.t_begin + tau);
    keep.h->push_back(r.h);
    keep.x_poly->push_back(step.x_poly);
    keep.v_poly->push_back(step.v_poly);
    x = step.x1;
    v = step.v1;
    f0 = step.f1;
  }
  last = {x, v};
}

}  // namespace

struct NonlinearResponse::Trajectory {
  std::vector<double> t0, h;             // start and length of every step [s]
  std::vector<StepPoly> x_poly, v_poly;  // xbar, xbar' over each step
  ModeState last{};                      // state at the end of the rest window
  SloshingModel model;                   // for the rest window's remaining steps
  std::optional<RestResume> resume;      // set while the rest window is not complete
  std::once_flag completed;
};

NonlinearResponse::NonlinearResponse(const SloshingModel& model, const MotionLaw& law,
                                     double rest_time, const NonlinearOptions& options)
    : trajectory_(std::make_shared<Trajectory>()), K_(model.K), motion_time_(law.duration()) {
  Trajectory& tr = *trajectory_;
  // Room for the whole grid (every piece rounds its step count up by at most one), so the
  // vectors are not regrown while integrating.
  const double h_max = std::min(options.max_step,
                                2.0 * std::numbers::pi / model.omega1() / options.steps_per_period);
  const double estimate =
      (law.duration() + rest_time) / h_max + static_cast<double>(law.pieces().size()) + 2.0;
  if (estimate > 0.0 && estimate < 1e6) {
    const auto n = static_cast<std::size_t>(estimate);
    tr.t0.reserve(n);
    tr.h.reserve(n);
    tr.x_poly.reserve(n);
    tr.v_poly.reserve(n);
  }
  const Keep keep{&tr.t0, &tr.h, &tr.x_poly, &tr.v_poly};
  peaks_ = integrate_or_refine(model, law, rest_time, options, &keep, &tr.last, &tr.resume);
  if (tr.resume) tr.model = model;
}

const NonlinearResponse::Trajectory& NonlinearResponse::trajectory() const {
  Trajectory& tr = *trajectory_;
  std::call_once(tr.completed, [&tr] {
    if (!tr.resume) return;
    const Keep keep{&tr.t0, &tr.h, &tr.x_poly, &tr.v_poly};
    resume_rest(tr.model, *tr.resume, keep, tr.last);
    tr.resume.reset();
  });
  return tr;
}

std::size_t NonlinearResponse::steps() const {
  return trajectory().t0.size();
}

SloshPeaks nonlinear_peaks(const SloshingModel& model, const MotionLaw& law, double rest_time,
                           const NonlinearOptions& options) {
  return integrate_or_refine(model, law, rest_time, options, nullptr, nullptr);
}

ModeState NonlinearResponse::state(double t) const {
  const Trajectory& tr = trajectory();
  if (t <= 0.0 || tr.t0.empty()) return {};
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(tr.t0.begin(), tr.t0.end(), t) - tr.t0.begin()) - 1;
  const double s = (t - tr.t0[i]) / tr.h[i];
  if (s >= 1.0 && i + 1 == tr.t0.size()) return tr.last;
  return {detail::dense_value(tr.x_poly[i], s), detail::dense_value(tr.v_poly[i], s)};
}

double NonlinearResponse::eta(double t) const {
  return K_ * state(t).x;
}

}  // namespace slosh
