#include "solve/one_jerk_chart.hpp"

#include <algorithm>
#include <stdexcept>

namespace slosh::detail {

namespace {

/// Points per family of the anchor scan [-].
constexpr int kAnchorScan{400};
/// Bisection steps of repair() towards the anchor [-].
constexpr int kRepairSteps{60};

}  // namespace

OneJerkChart::OneJerkChart(double T, double ramp, double cruise, std::array<double, 2> plateaus)
    : motion_time(T), min_ramp(ramp), cruise_max(cruise), plateau_min(plateaus) {
  // The uniform law is in the family; else a scan with no cruise over symmetric ramps, then
  // over one ramp at its minimum and the other longer (unequal plateau minimums need it).
  std::vector<Point> candidates{{T / 7.0, T / 7.0, std::min(T / 7.0, cruise_max)}};
  for (int k = 0; k <= kAnchorScan; ++k) {
    const double x = min_ramp + (0.5 * T - min_ramp) * k / kAnchorScan;
    candidates.push_back({x, x, 0.0});
    candidates.push_back({min_ramp, x, 0.0});
    candidates.push_back({x, min_ramp, 0.0});
  }
  for (const Point& p : candidates) {
    if (admissible(p, 0.0)) {
      anchor = p;
      break;
    }
  }
}

Durations OneJerkChart::durations(const double* p, double* jac) const {
  const double ta = p[0], tb = p[1], c = p[2];
  const double M = motion_time - c, s = ta + tb;
  const Durations d{ta, tb * M / s - s, ta, c, tb, ta * M / s - s, tb};
  if (jac != nullptr) {
    const double q = M / (s * s);
    const double rows[kSegments][kDimension] = {
        {1.0, 0.0, 0.0}, {-tb * q - 1.0, ta * q - 1.0, -tb / s}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0},
        {0.0, 1.0, 0.0}, {tb * q - 1.0, -ta * q - 1.0, -ta / s}, {0.0, 1.0, 0.0}};
    for (std::size_t i = 0; i < kSegments; ++i) {
      for (int k = 0; k < kDimension; ++k) jac[i * kDimension + k] = rows[i][k];
    }
  }
  return d;
}

OneJerkChart::Point OneJerkChart::coordinates(const double* d) const {
  return {0.5 * (d[0] + d[2]), 0.5 * (d[4] + d[6]), d[3]};
}

OneJerkChart::Point OneJerkChart::lower() const {
  return {min_ramp, min_ramp, 0.0};
}

OneJerkChart::Point OneJerkChart::upper() const {
  return {0.5 * motion_time, 0.5 * motion_time, cruise_max};
}

bool OneJerkChart::admissible(const Point& p, double slack) const {
  const Point lo = lower(), hi = upper();
  for (int k = 0; k < kDimension; ++k) {
    if (!(p[k] >= lo[k] && p[k] <= hi[k])) return false;
  }
  const Durations d = durations(p.data(), nullptr);
  return d[1] >= plateau_min[0] - slack && d[5] >= plateau_min[1] - slack;
}

OneJerkChart::Point OneJerkChart::repair(Point p) const {
  const Point lo = lower(), hi = upper();
  for (int k = 0; k < kDimension; ++k) p[k] = std::clamp(p[k], lo[k], hi[k]);
  if (admissible(p, 0.0) || !anchor) return p;
  auto at = [&](double lambda) {
    Point q;
    for (int k = 0; k < kDimension; ++k) q[k] = p[k] + lambda * ((*anchor)[k] - p[k]);
    return q;
  };
  double infeasible = 0.0, feasible = 1.0;
  for (int step = 0; step < kRepairSteps; ++step) {
    const double mid = 0.5 * (infeasible + feasible);
    (admissible(at(mid), 0.0) ? feasible : infeasible) = mid;
  }
  return at(feasible);
}

std::vector<double> OneJerkChart::evaluation_point(const double* p, std::size_t n, double* jac,
                                                   double* charted_jac, Durations* charted) const {
  std::vector<double> x(n);
  const Durations d = durations(p, jac);
  if (charted != nullptr) *charted = d;
  if (charted_jac != nullptr && jac != nullptr) {
    std::copy(jac, jac + kSegments * kDimension, charted_jac);
  }
  std::copy(d.begin(), d.end(), x.begin());
  for (std::size_t i : {std::size_t{1}, std::size_t{5}}) {
    if (x[i] >= 0.0) continue;
    x[i] = 0.0;
    if (jac != nullptr) std::fill(jac + i * kDimension, jac + (i + 1) * kDimension, 0.0);
  }
  std::copy(p + kDimension, p + kDimension + (n - kSegments), x.begin() + kSegments);
  return x;
}

std::vector<double> OneJerkChart::lift(const std::vector<double>& reduced) const {
  return evaluation_point(reduced.data(), reduced.size() - kDimension + kSegments, nullptr, nullptr,
                          nullptr);
}

std::vector<double> OneJerkChart::restrict(const std::vector<double>& full) const {
  const Point p = repair(coordinates(full.data()));
  std::vector<double> reduced(p.begin(), p.end());
  reduced.insert(reduced.end(), full.begin() + kSegments, full.end());
  return reduced;
}

NlpProblem OneJerkChart::reduce(const NlpProblem& full) const {
  const auto n = static_cast<std::size_t>(full.size());
  const std::size_t extra = n - kSegments;
  const std::size_t nr = kDimension + extra;
  for (const auto& eq : full.equalities) {
    bool sum = eq.b == motion_time;
    for (std::size_t i = 0; i < n; ++i) sum = sum && eq.a[i] == (i < kSegments ? 1.0 : 0.0);
    if (!sum) throw std::logic_error("the one-jerk chart only restates the sum equality");
  }
  NlpProblem q;
  const Point lo = lower(), hi = upper();
  q.lower.assign(lo.begin(), lo.end());
  q.upper.assign(hi.begin(), hi.end());
  q.lower.insert(q.lower.end(), full.lower.begin() + kSegments, full.lower.end());
  q.upper.insert(q.upper.end(), full.upper.begin() + kSegments, full.upper.end());
  const OneJerkChart chart = *this;
  // Row r of a full Jacobian (or gradient) `gx` through the chain rule into `out`.
  auto chain = [n, nr](const double* gx, const double* jac, double* out) {
    for (int k = 0; k < kDimension; ++k) {
      double v = 0.0;
      for (std::size_t i = 0; i < kSegments; ++i) v += gx[i] * jac[i * kDimension + k];
      out[k] = v;
    }
    for (std::size_t j = kDimension; j < nr; ++j) out[j] = gx[kSegments + j - kDimension];
  };
  q.objective = [f = full.objective, chart, chain, n](const double* p, double* grad) {
    double jac[kSegments * kDimension];
    const std::vector<double> x =
        chart.evaluation_point(p, n, grad != nullptr ? jac : nullptr, nullptr, nullptr);
    if (grad == nullptr) return f(x.data(), nullptr);
    std::vector<double> gx(n);
    const double value = f(x.data(), gx.data());
    chain(gx.data(), jac, grad);
    return value;
  };
  if (full.before_start) {
    q.before_start = [h = full.before_start, chart, n](const double* p) {
      h(chart.evaluation_point(p, n, nullptr, nullptr, nullptr).data());
    };
  }
  const int m = full.inequality_count;
  q.inequality_count = m + 2;
  q.inequalities = [g_full = full.inequalities, chain, m, n, nr, chart](const double* p, double* g,
                                                                        double* jac_out) {
    double jac[kSegments * kDimension];
    double charted_jac[kSegments * kDimension];
    Durations d{};
    const std::vector<double> x = chart.evaluation_point(p, n, jac, charted_jac, &d);
    std::vector<double> jx(jac_out != nullptr ? static_cast<std::size_t>(m) * n : 0);
    if (m > 0) g_full(x.data(), g, jac_out != nullptr ? jx.data() : nullptr);
    const double T = chart.motion_time;
    g[m] = (chart.plateau_min[0] - d[1]) / T;
    g[m + 1] = (chart.plateau_min[1] - d[5]) / T;
    if (jac_out == nullptr) return;
    for (int r = 0; r < m; ++r) chain(jx.data() + r * n, jac, jac_out + r * nr);
    for (int r = 0; r < 2; ++r) {
      double* row = jac_out + (m + r) * nr;
      std::fill(row, row + nr, 0.0);
      for (int k = 0; k < kDimension; ++k) {
        row[k] = -charted_jac[(r == 0 ? 1 : 5) * kDimension + k] / T;
      }
    }
  };
  return q;
}

}  // namespace slosh::detail
