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

namespace {

/// cos x and sin x of a dual x (one kernel call for both).
void dual_cos_sin(const D8& x, D8& c, D8& s) {
  const SinCos v = fast_sincos(x.x[0]);
  c = (-v.sin) * x;
  c.x[0] = v.cos;
  s = v.cos * x;
  s.x[0] = v.sin;
}

using Accel = std::array<D8, 2>;

/// The time where s(t) = target on a segment starting at t0 with (s0, v0, a0) and jerk J, by
/// bisection then Newton's method on tau in [0, len] (s is increasing there).
double crossing_tau(double s0, double v0, double a0, double J, double len, double target) {
  auto s = [&](double tau) { return s0 + tau * (v0 + tau * (0.5 * a0 + tau * J / 6.0)); };
  double lo = 0.0, hi = len;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * std::max(1.0, len); ++it) {
    const double m = 0.5 * (lo + hi);
    (s(m) < target ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

PlanarSensitivity::PlanarSensitivity(const SloshingModel& model, const PlanarPath& path,
                                     double rest_time, double steps_per_period)
    : model_(model),
      path_(path),
      rest_time_(rest_time),
      h_max_(std::min(0.05, 2.0 * std::numbers::pi / model.omega1() / steps_per_period)) {}

std::vector<PlanarSensitivity::Piece> PlanarSensitivity::pieces(
    const std::array<Dual7, kSegments>& d) {
  const auto lv = plateau_levels(d, Dual7(path_.length()));
  jerk_ = {lv.A / d[0],  Dual7(0.0), -lv.A / d[2], Dual7(0.0),
           -lv.B / d[4], Dual7(0.0), lv.B / d[6]};
  t_start_[0] = s_start_[0] = v_start_[0] = a_start_[0] = Dual7(0.0);
  for (std::size_t k = 0; k < kSegments; ++k) {
    const Dual7& tau = d[k];
    const Dual7& J = jerk_[k];
    const Dual7& a = a_start_[k];
    const Dual7& v = v_start_[k];
    t_start_[k + 1] = t_start_[k] + tau;
    s_start_[k + 1] = s_start_[k] + tau * (v + tau * (0.5 * a + tau * J * (1.0 / 6.0)));
    v_start_[k + 1] = v + tau * (a + 0.5 * tau * J);
    a_start_[k + 1] = a + J * tau;
  }
  // Boundaries: the switch times, then the joins' crossing times, each with its segment.
  struct Cut {
    Dual7 t;
    std::size_t segment;
  };
  std::vector<Cut> cuts;
  for (std::size_t k = 0; k <= kSegments; ++k) cuts.push_back({t_start_[k], k});
  const std::vector<double>& starts = path_.element_starts();
  for (std::size_t e = 1; e + 1 < starts.size(); ++e) {
    const double target = starts[e];
    for (std::size_t k = 0; k < kSegments; ++k) {
      if (!(s_start_[k].v < target && target < s_start_[k + 1].v) || !(d[k].v > 0.0)) continue;
      const double tau =
          crossing_tau(s_start_[k].v, v_start_[k].v, a_start_[k].v, jerk_[k].v, d[k].v, target);
      // s at the fixed time t_start + tau, as the durations move: tau shifts with t_start.
      const Dual7 t_fixed = Dual7(t_start_[k].v + tau);
      const Dual7 u = t_fixed - t_start_[k];
      const Dual7 s =
          s_start_[k] + u * (v_start_[k] + u * (0.5 * a_start_[k] + u * jerk_[k] * (1.0 / 6.0)));
      const double speed = v_start_[k].v + tau * (a_start_[k].v + 0.5 * tau * jerk_[k].v);
      Dual7 t = t_fixed;
      for (std::size_t i = 0; i < kSegments; ++i) t.d[i] = -s.d[i] / speed;
      cuts.push_back({t, k});
    }
  }
  std::stable_sort(cuts.begin(), cuts.end(),
                   [](const Cut& a, const Cut& b) { return a.t.v < b.t.v; });
  std::vector<Piece> out;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1].t.v > cuts[i].t.v)) continue;
    Piece p;
    p.t_begin = cuts[i].t;
    p.t_end = cuts[i + 1].t;
    // The segment holding the middle of the piece: the last switch at or before its start.
    p.segment = 0;
    for (std::size_t k = 0; k < kSegments; ++k) {
      if (t_start_[k].v <= cuts[i].t.v) p.segment = k;
    }
    const double mid = 0.5 * (p.t_begin.v + p.t_end.v) - t_start_[p.segment].v;
    const std::size_t k = p.segment;
    const double s_mid =
        s_start_[k].v +
        mid * (v_start_[k].v + mid * (0.5 * a_start_[k].v + mid * jerk_[k].v / 6.0));
    p.element = path_.element_at(s_mid);
    out.push_back(p);
  }
  Piece rest;
  rest.t_begin = t_start_[kSegments];
  rest.t_end = t_start_[kSegments] + rest_time_;
  rest.rest = true;
  out.push_back(rest);
  return out;
}

/// The integration of compute() (a friend: it reads the law's duals and writes the steps).
struct PlanarSensitivityPass {
  static void run(PlanarSensitivity& s, const std::vector<PlanarSensitivity::Piece>& list);
};

// flatten: every helper is inlined, so the AVX clone's lane loops are AVX as well.
SLOSH_PLANAR_CLONES [[gnu::flatten]] void PlanarSensitivityPass::run(
    PlanarSensitivity& s, const std::vector<PlanarSensitivity::Piece>& list) {
  const SloshingModel& m = s.model_;
  const PlanarPath& path = s.path_;
  const PlanarTangentRhs rhs{m.omega1() * m.omega1(), 2.0 * m.zeta * m.omega1(), m.C * m.C, m.alpha,
                             1.0 / m.radius};
  bool same_pieces = s.frozen_.size() == list.size();
  for (std::size_t i = 0; same_pieces && i < list.size(); ++i) {
    same_pieces = s.frozen_key_[i] == list[i].segment * 1000 + list[i].element;
  }
  s.steps_.clear();
  s.t0_values_.clear();
  DualPair x(0.0), v(0.0);
  DopStep<DualPair> step;
  for (std::size_t p = 0; p < list.size(); ++p) {
    const PlanarSensitivity::Piece& piece = list[p];
    const Dual7 length = piece.t_end - piece.t_begin;
    std::size_t n = step_count(length.v, s.h_max_, 1);
    if (same_pieces) n = std::max(n, s.frozen_[p]);
    const Dual7 h = length * (1.0 / static_cast<double>(n));
    const std::size_t k = piece.segment;
    const std::size_t e = piece.element;
    const PlanarKinematics start = path.at(e, path.element_starts()[e], 1.0, 0.0, 0.0);
    const double psi0 = std::atan2(start.vy, start.vx);
    const double kappa = path.curvature(e);
    const double s_e = path.element_starts()[e];
    const D8 T_k(s.t_start_[k]), s_k(s.s_start_[k]), v_k(s.v_start_[k]), a_k(s.a_start_[k]),
        J_k(s.jerk_[k]);
    const D8 half_J = 0.5 * J_k, sixth_J = (1.0 / 6.0) * J_k, half_a = 0.5 * a_k;
    const double cos0 = std::cos(psi0), sin0 = std::sin(psi0);
    auto force = [&](const D8& t) {
      Accel a{};
      if (piece.rest) return a;
      const D8 u = t - T_k;
      const D8 acc = a_k + J_k * u;
      if (kappa == 0.0) {
        a[0] = cos0 * acc;
        a[1] = sin0 * acc;
        return a;
      }
      const D8 vel = v_k + u * (a_k + u * half_J);
      const D8 pos = s_k + u * (v_k + u * (half_a + u * sixth_J));
      const D8 psi = psi0 + kappa * (pos - s_e);
      D8 c, sn;
      dual_cos_sin(psi, c, sn);
      const D8 normal = kappa * (vel * vel);
      a[0] = acc * c - normal * sn;
      a[1] = acc * sn + normal * c;
      return a;
    };
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
  std::array<Dual7, kSegments> D;
  for (std::size_t i = 0; i < kSegments; ++i) D[i] = Dual7::variable(d[i], i);
  const std::vector<Piece> list = pieces(D);
  motion_time_ = t_start_[kSegments].v;
  PlanarSensitivityPass::run(*this, list);
}

void PlanarSensitivity::freeze_steps(const double* d) {
  std::array<Dual7, kSegments> D;
  for (std::size_t i = 0; i < kSegments; ++i) D[i] = Dual7(d[i]);
  const std::vector<Piece> list = pieces(D);
  frozen_.clear();
  frozen_key_.clear();
  for (const Piece& p : list) {
    frozen_.push_back(step_count(p.t_end.v - p.t_begin.v, h_max_, 1) + 1);
    frozen_key_.push_back(p.segment * 1000 + p.element);
  }
}

std::size_t PlanarSensitivity::step_at(double t) const {
  const auto it = std::upper_bound(t0_values_.begin(), t0_values_.end(), t);
  if (it == t0_values_.begin()) return 0;
  return static_cast<std::size_t>(it - t0_values_.begin()) - 1;
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
