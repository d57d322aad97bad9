#include "solve/admissible_starts.hpp"

#include <algorithm>
#include <array>

namespace slosh::detail {

namespace {

/// A limit that is not reachable is raised to its least reachable value times (1 + kRaise), so
/// the point that reaches it is inside to the solvers' tolerance [-].
constexpr double kRaise{1e-8};

/// One machine limit: its rows in DurationSpace::limit_constraints and its value in `limits`.
struct LimitRows {
  int first;
  int count;
  std::optional<double> MachineLimits::*value;
};

std::vector<LimitRows> limit_rows(const MachineLimits& l) {
  std::vector<LimitRows> rows;
  int first = 0;
  if (l.a_max) rows.push_back({first, 2, &MachineLimits::a_max}), first += 2;
  if (l.v_max) rows.push_back({first, 1, &MachineLimits::v_max}), first += 1;
  if (l.j_max) rows.push_back({first, 4, &MachineLimits::j_max});
  return rows;
}

/// The context with `limits` in its space (the solvers of least_limit_scale and the projection
/// read them there).
StrategyContext with_limits(const StrategyContext& c, const MachineLimits& limits) {
  StrategyContext out = c;
  out.space.limits = limits;
  return out;
}

/// Every limit of `l` times `factor`.
MachineLimits scaled(MachineLimits l, double factor) {
  for (std::optional<double>* v : {&l.a_max, &l.v_max, &l.j_max}) {
    if (*v) *v = **v * factor;
  }
  return l;
}

/// The nearest point to x0 (least sum of squared duration changes, relative to T) that keeps the
/// context's limits, solved from `inside` (a point that keeps them, so SLSQP starts feasible and
/// stays near the admissible set); `inside` when the solver ends outside.
Durations project(const StrategyContext& c, const Durations& x0, const Durations& inside) {
  NlpProblem p = c.space.problem(0);
  const double T = c.format.motion_time;
  p.objective = [x0, T](const double* d, double* grad) {
    double f = 0.0;
    for (std::size_t i = 0; i < kSegments; ++i) {
      const double r = (d[i] - x0[i]) / T;
      f += r * r;
      if (grad != nullptr) grad[i] = 2.0 * r / T;
    }
    return f;
  };
  p.inequality_count = c.space.limit_count();
  const DurationSpace* space = &c.space;
  p.inequalities = [space](const double* x, double* g, double* jac) {
    space->limit_constraints(x, g, jac, kSegments);
  };
  const MultiStartResult m = multi_start(p, as_vectors({inside}), c, NlpOptions{});
  if (m.best.x.empty() || !m.feasible) return inside;
  const Durations d = c.space.polish(m.best.x.data());
  return keeps_limits(c.space, c.space.limits, d, kLimitSlack) ? d : inside;
}

}  // namespace

bool keeps_limits(const DurationSpace& space, const MachineLimits& limits, const Durations& d,
                  double slack) {
  DurationSpace s = space;
  s.limits = limits;
  std::array<double, kSegments> g{};
  s.limit_constraints(d.data(), g.data(), nullptr, kSegments);
  const int rows = s.limit_count();
  return std::all_of(g.begin(), g.begin() + rows, [slack](double v) { return v <= slack; });
}

AdmissibleStarts admissible_starts(const StrategyContext& c, const std::vector<Durations>& starts) {
  AdmissibleStarts out{c.space.limits, false, starts};
  const int rows = c.space.limit_count();
  const bool all_inside = std::all_of(starts.begin(), starts.end(), [&](const Durations& d) {
    return keeps_limits(c.space, c.space.limits, d, kLimitSlack);
  });
  if (rows == 0 || all_inside) return out;
  // A point that keeps the limits: the least common scale of every limit, <= 1 when they are
  // reachable together.
  MultiStartResult joint = least_limit_scale(c, 0, rows);
  if (joint.best.x.empty() || !joint.feasible) return out;  // time ran out: the starts as given
  if (joint.best.objective > 1.0) {
    // A limit that cannot be met alone is raised to its least reachable value; the others keep
    // the options' values unless they cannot be met together with it (then all are scaled up by
    // the least common factor).
    MachineLimits raised = c.space.limits;
    for (const LimitRows& q : limit_rows(c.space.limits)) {
      const MultiStartResult alone = least_limit_scale(c, q.first, q.count);
      if (alone.feasible && alone.best.objective > 1.0) {
        raised.*q.value = *(raised.*q.value) * alone.best.objective * (1.0 + kRaise);
      }
    }
    joint = least_limit_scale(with_limits(c, raised), 0, rows);
    if (joint.best.x.empty() || !joint.feasible) return out;
    if (joint.best.objective > 1.0) raised = scaled(raised, joint.best.objective * (1.0 + kRaise));
    out.limits = raised;
    out.relaxed = true;
  }
  const StrategyContext limited = with_limits(c, out.limits);
  const Durations inside = c.space.polish(joint.best.x.data());
  out.starts.clear();
  for (const Durations& d : starts) {
    const Durations p =
        keeps_limits(c.space, out.limits, d, kLimitSlack) ? d : project(limited, d, inside);
    if (std::find(out.starts.begin(), out.starts.end(), p) == out.starts.end()) {
      out.starts.push_back(p);
    }
  }
  return out;
}

std::vector<Durations> with_families(const StrategyContext& c, std::vector<Durations> starts,
                                     int random) {
  if (c.space.warm_start) return starts;
  for (const Durations& d : admissible_starts(c, c.space.starts(random)).starts) {
    if (std::find(starts.begin(), starts.end(), d) == starts.end()) starts.push_back(d);
  }
  return starts;
}

}  // namespace slosh::detail
