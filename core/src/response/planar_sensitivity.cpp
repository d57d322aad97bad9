#include "response/planar_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "response/planar_scheme.hpp"
#include "response/sincos.hpp"

// One clone of the integration for AVX (a D8 is two AVX vectors of doubles), chosen at load time
// where the CPU has it. No FMA and no reassociation, so both clones compute the same numbers bit
// for bit.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SLOSH_PLANAR_CLONES __attribute__((target_clones("avx", "default")))
#else
#define SLOSH_PLANAR_CLONES
#endif

namespace slosh::detail {

PlanarSensitivity::PlanarSensitivity(const SloshingModel& model, const PlanarPath& path,
                                     double rest_time, double steps_per_period)
    : model_(model),
      path_(path),
      rest_time_(rest_time),
      h_max_(std::min(0.05, 2.0 * std::numbers::pi / model.omega1() / steps_per_period)),
      steps_per_period_(steps_per_period) {}

/// The integration of compute() (a friend: it reads the law's duals and writes the steps).
struct PlanarSensitivityPass {
  static void run(PlanarSensitivity& s, const std::vector<DualPiece>& list);
};

// flatten: every helper is inlined, so the AVX clone's lane loops are AVX as well.
SLOSH_PLANAR_CLONES [[gnu::flatten]] void PlanarSensitivityPass::run(
    PlanarSensitivity& s, const std::vector<DualPiece>& list) {
  const SloshingModel& m = s.model_;
  const PlanarPath& path = s.path_;
  const PlanarTangentRhs rhs{m.omega1() * m.omega1(), 2.0 * m.zeta * m.omega1(), m.C * m.C, m.alpha,
                             1.0 / m.radius};
  const std::vector<std::size_t> counts =
      s.frozen_.steps(list, piece_steps(s.law_, path, list, s.h_max_, s.steps_per_period_));
  s.steps_.clear();
  s.t0_values_.clear();
  DualPair x(0.0), v(0.0);
  DopStep<DualPair> step;
  for (std::size_t p = 0; p < list.size(); ++p) {
    const DualPiece& piece = list[p];
    const Dual7 length = piece.t_end - piece.t_begin;
    const std::size_t n = counts[p];
    const Dual7 h = length * (1.0 / static_cast<double>(n));
    const PieceDrive drive(path, s.law_, piece);
    auto force = [&drive](const D8& t) { return drive.world(t); };
    const D8 tb(piece.t_begin);
    const D8 hd(h);
    const DualPair hh(hd);
    DualPair f0 = rhs(x, v, force(tb));
    for (std::size_t j = 0; j < n; ++j) {
      const D8 t0 = tb + static_cast<double>(j) * hd;
      auto acc = [&](std::size_t i) { return force(t0 + kDopC[i] * hd); };
      dop853_step(rhs, acc, x, v, f0, hh, true, step, false);
      s.steps_.push_back({t0, hd, step.x_poly});
      s.t0_values_.push_back(t0.value());
      if (t0.value() + hd.value() >= s.until_) return;
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
    }
  }
}

void PlanarSensitivity::compute(const double* d, double until) {
  until_ = until;
  const std::vector<DualPiece> list = law_.pieces(path_, rest_time_, dual_durations(d, true));
  motion_time_ = law_.t_start[kSegments].v;
  PlanarSensitivityPass::run(*this, list);
}

void PlanarSensitivity::freeze_steps(const double* d) {
  const std::vector<DualPiece> list = law_.pieces(path_, rest_time_, dual_durations(d, false));
  frozen_.freeze(list, piece_steps(law_, path_, list, h_max_, steps_per_period_));
}

std::size_t PlanarSensitivity::step_at(double t) const {
  return step_index(t0_values_, t);
}

void PlanarSensitivity::eta_at(const std::vector<double>& t, std::vector<double>& values,
                               std::vector<std::array<double, kSegments>>& gradients) const {
  values.resize(t.size());
  gradients.resize(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Stored& s = steps_[step_at(t[i])];
    const D8 theta = (D8(t[i]) - s.t0) / s.h;
    const DualPair q = dense_value(s.q, theta);
    const double r = std::hypot(q.c[0].x[0], q.c[1].x[0]);
    values[i] = model_.K * r;
    for (std::size_t k = 0; k < kSegments; ++k) {
      gradients[i][k] =
          r > 0.0 ? model_.K * (q.c[0].x[0] * q.c[0].x[1 + k] + q.c[1].x[0] * q.c[1].x[1 + k]) / r
                  : 0.0;
    }
  }
}

namespace {

/// q and dq/dtheta of a step's interpolant at theta (values only).
struct QJet {
  double x{}, y{}, dx{}, dy{};
};
QJet q_jet(const DensePoly<DualPair>& q, double theta) {
  QJet j;
  for (std::size_t k = kDenseTerms; k-- > 0;) {
    j.dx = j.dx * theta + j.x;
    j.dy = j.dy * theta + j.y;
    j.x = j.x * theta + q[k].c[0].x[0];
    j.y = j.y * theta + q[k].c[1].x[0];
  }
  return j;
}

}  // namespace

double PlanarSensitivity::peak_time(double lo, double hi) const {
  auto jet = [this](double t) {
    const Stored& s = steps_[step_at(t)];
    return q_jet(s.q, (t - s.t0.value()) / s.h.value());
  };
  // The slope of |q|^2 / 2 over theta (the step's positive length scales it, not its sign).
  auto slope = [&jet](double t) {
    const QJet j = jet(t);
    return j.x * j.dx + j.y * j.dy;
  };
  auto height = [&jet](double t) {
    const QJet j = jet(t);
    return std::hypot(j.x, j.y);
  };
  const double g_lo = slope(lo), g_hi = slope(hi);
  if (!(g_lo > 0.0 && g_hi < 0.0)) return height(lo) >= height(hi) ? lo : hi;
  // Bisection on the sign of the slope: its bracket always holds a maximum, and the count of
  // halvings is fixed by the bracket, so the time is a deterministic function of the response.
  double a = lo, b = hi;
  while (b - a > 1e-12) {
    const double m = 0.5 * (a + b);
    if (m <= a || m >= b) break;
    (slope(m) > 0.0 ? a : b) = m;
  }
  return 0.5 * (a + b);
}

std::vector<PlanarWindowPeak> PlanarSensitivity::window_peaks(double t_begin, double t_end,
                                                              double window) const {
  std::vector<PlanarWindowPeak> out;
  const Poly none{};
  std::size_t current = static_cast<std::size_t>(-1);
  for (const Stored& s : steps_) {
    const double t0 = s.t0.value();
    if (t0 < t_begin - 1e-12 || t0 >= t_end - 1e-12) continue;
    Poly ex{}, ey{};
    for (std::size_t k = 0; k < kDenseTerms; ++k) {
      ex[k] = model_.K * s.q[k].c[0].x[0];
      ey[k] = model_.K * s.q[k].c[1].x[0];
    }
    const StepMax m = step_max(ex, ey, none, 0.0);
    const double t = t0 + m.s * s.h.value();
    const auto w = static_cast<std::size_t>(std::max(0.0, (t - t_begin) / window));
    if (w != current) {
      out.push_back({m.value, t});
      current = w;
    } else if (m.value > out.back().value) {
      out.back() = {m.value, t};
    }
  }
  return out;
}

}  // namespace slosh::detail
