#include "response/path_law_duals.hpp"

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/response/response.hpp"

#include <algorithm>
#include <cmath>

namespace slosh::detail {

namespace {

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

/// A piece's end: a switch or a join crossing, with the segment it lies on.
struct Cut {
  Dual7 t;
  std::size_t segment;
};

/// The times where s(t) crosses the path's joins, with their derivatives.
void add_join_crossings(const PathLawDuals& law, const PlanarPath& path,
                        const std::array<Dual7, kSegments>& d, std::vector<Cut>& cuts) {
  const std::vector<double>& starts = path.element_starts();
  for (std::size_t e = 1; e + 1 < starts.size(); ++e) {
    const double target = starts[e];
    for (std::size_t k = 0; k < kSegments; ++k) {
      if (!(law.s_start[k].v < target && target < law.s_start[k + 1].v) || !(d[k].v > 0.0)) {
        continue;
      }
      const double tau = crossing_tau(law.s_start[k].v, law.v_start[k].v, law.a_start[k].v,
                                      law.jerk[k].v, d[k].v, target);
      // s at the fixed time t_start + tau, as the durations move: tau shifts with t_start.
      const Dual7 t_fixed = Dual7(law.t_start[k].v + tau);
      const Dual7 u = t_fixed - law.t_start[k];
      const Dual7 s =
          law.s_start[k] +
          u * (law.v_start[k] + u * (0.5 * law.a_start[k] + u * law.jerk[k] * (1.0 / 6.0)));
      const double speed = law.v_start[k].v + tau * (law.a_start[k].v + 0.5 * tau * law.jerk[k].v);
      Dual7 t = t_fixed;
      for (std::size_t i = 0; i < kSegments; ++i) t.d[i] = -s.d[i] / speed;
      cuts.push_back({t, k});
    }
  }
}

}  // namespace

std::vector<DualPiece> PathLawDuals::pieces(const PlanarPath& path, double rest_time,
                                            const std::array<Dual7, kSegments>& d) {
  const auto lv = plateau_levels(d, Dual7(path.length()));
  jerk = {lv.A / d[0], Dual7(0.0), -lv.A / d[2], Dual7(0.0), -lv.B / d[4], Dual7(0.0), lv.B / d[6]};
  t_start[0] = s_start[0] = v_start[0] = a_start[0] = Dual7(0.0);
  for (std::size_t k = 0; k < kSegments; ++k) {
    const Dual7& tau = d[k];
    const Dual7& J = jerk[k];
    const Dual7& a = a_start[k];
    const Dual7& v = v_start[k];
    t_start[k + 1] = t_start[k] + tau;
    s_start[k + 1] = s_start[k] + tau * (v + tau * (0.5 * a + tau * J * (1.0 / 6.0)));
    v_start[k + 1] = v + tau * (a + 0.5 * tau * J);
    a_start[k + 1] = a + J * tau;
  }
  // Boundaries: the switch times, then the joins' crossing times, each with its segment.
  std::vector<Cut> cuts;
  for (std::size_t k = 0; k <= kSegments; ++k) cuts.push_back({t_start[k], k});
  add_join_crossings(*this, path, d, cuts);
  std::stable_sort(cuts.begin(), cuts.end(),
                   [](const Cut& a, const Cut& b) { return a.t.v < b.t.v; });
  std::vector<DualPiece> out;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1].t.v > cuts[i].t.v)) continue;
    DualPiece p;
    p.t_begin = cuts[i].t;
    p.t_end = cuts[i + 1].t;
    // The segment holding the middle of the piece: the last switch at or before its start.
    p.segment = 0;
    for (std::size_t k = 0; k < kSegments; ++k) {
      if (t_start[k].v <= cuts[i].t.v) p.segment = k;
    }
    const double mid = 0.5 * (p.t_begin.v + p.t_end.v) - t_start[p.segment].v;
    const std::size_t k = p.segment;
    const double s_mid =
        s_start[k].v + mid * (v_start[k].v + mid * (0.5 * a_start[k].v + mid * jerk[k].v / 6.0));
    p.element = path.element_at(s_mid);
    out.push_back(p);
  }
  DualPiece rest;
  rest.t_begin = t_start[kSegments];
  rest.t_end = t_start[kSegments] + rest_time;
  rest.rest = true;
  out.push_back(rest);
  return out;
}

std::array<Dual7, kSegments> dual_durations(const double* d, bool variables) {
  std::array<Dual7, kSegments> D;
  for (std::size_t i = 0; i < kSegments; ++i)
    D[i] = variables ? Dual7::variable(d[i], i) : Dual7(d[i]);
  return D;
}

std::vector<double> piece_steps(const PathLawDuals& law, const PlanarPath& path,
                                const std::vector<DualPiece>& pieces, double h_max,
                                double steps_per_period) {
  std::vector<double> h(pieces.size(), h_max);
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const DualPiece& p = pieces[i];
    const double kappa = p.rest ? 0.0 : std::abs(path.curvature(p.element));
    if (kappa == 0.0) continue;
    const std::size_t k = p.segment;
    const double v = law.v_start[k].v, a = law.a_start[k].v, J = law.jerk[k].v;
    auto speed = [&](double u) { return std::abs(v + u * (a + 0.5 * u * J)); };
    const double lo = p.t_begin.v - law.t_start[k].v, hi = p.t_end.v - law.t_start[k].v;
    double fastest = std::max(speed(lo), speed(hi));
    if (J != 0.0 && -a / J > lo && -a / J < hi) fastest = std::max(fastest, speed(-a / J));
    h[i] = piece_max_step(h_max, kappa * fastest, steps_per_period);
  }
  return h;
}

void FrozenSteps::freeze(const std::vector<DualPiece>& pieces, const std::vector<double>& h_max) {
  count.clear();
  key.clear();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const DualPiece& p = pieces[i];
    count.push_back(step_count(p.t_end.v - p.t_begin.v, h_max[i], 1) + 1);
    key.push_back(p.segment * 1000 + p.element);
  }
}

std::vector<std::size_t> FrozenSteps::steps(const std::vector<DualPiece>& pieces,
                                            const std::vector<double>& h_max) const {
  bool same = count.size() == pieces.size();
  for (std::size_t i = 0; same && i < pieces.size(); ++i) {
    same = key[i] == pieces[i].segment * 1000 + pieces[i].element;
  }
  std::vector<std::size_t> n(pieces.size());
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    n[p] = step_count(pieces[p].t_end.v - pieces[p].t_begin.v, h_max[p], 1);
    if (same) n[p] = std::max(n[p], count[p]);
  }
  return n;
}

std::size_t step_index(const std::vector<double>& t0, double t) {
  const auto it = std::upper_bound(t0.begin(), t0.end(), t);
  if (it == t0.begin()) return 0;
  return static_cast<std::size_t>(it - t0.begin()) - 1;
}

}  // namespace slosh::detail
