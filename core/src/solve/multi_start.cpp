#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

namespace {

// Measured on the thesis format (bench_planner, BM_Optimise_*/1 vs /2): on these small dense
// problems (7-8 variables, up to ~200 constraints) NLopt's SLSQP converges in 10-40 evaluations
// per start; the notch, multi_notch and min_jerk_band solves with all starts take 0.7-1.8 ms with
// SLSQP and 0.24-1.8 s with Ipopt (L-BFGS Hessian) for the same objectives. SLSQP is therefore
// the default of every strategy; Ipopt stays selectable ("solver": "ipopt") and is tested.
SolverChoice effective(const StrategyContext& c) {
  return c.options.solver == SolverChoice::kIpopt ? SolverChoice::kIpopt : SolverChoice::kNlopt;
}

}  // namespace

std::string solver_name(const StrategyContext& context) {
  return effective(context) == SolverChoice::kIpopt ? "ipopt" : "nlopt-slsqp";
}

std::vector<std::vector<double>> as_vectors(const std::vector<Durations>& starts) {
  std::vector<std::vector<double>> out;
  out.reserve(starts.size());
  for (const auto& d : starts) out.emplace_back(d.begin(), d.end());
  return out;
}

namespace {

/// An optimum a run reached: its point and objective.
struct KnownOptimum {
  std::vector<double> x;
  double f{};
};

/// True when x is within kKnownOptimumBasin of the bounds' range of every duration of one of
/// `optima` (coordinates past the durations, such as an epigraph's level, follow them), or, with
/// an approach basin, within `approach` of the range of every duration of a poor one (at least
/// kPoorOptimum times the lowest held) whose objective f exceeds by at most kApproachRatio times.
bool near_known_optimum(const NlpProblem& problem, const std::vector<KnownOptimum>& optima,
                        const double* x, double f, double approach) {
  double lowest = INFINITY;
  for (const auto& y : optima) lowest = std::min(lowest, y.f);
  const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(problem.size()), kSegments);
  for (const auto& y : optima) {
    // Only the basins of optima far above the lowest one held: a run that ends in another
    // optimum next to such a one (twins a few 1e-4 apart occur) would not be the answer either.
    const bool poor = std::abs(y.f) >= kPoorOptimum * std::abs(lowest);
    const bool close_in_f = approach > 0.0 && poor && std::abs(f) <= kApproachRatio * std::abs(y.f);
    const double basin = close_in_f ? std::max(approach, kKnownOptimumBasin) : kKnownOptimumBasin;
    bool near = true;
    for (std::size_t i = 0; i < n && near; ++i) {
      const double range = problem.upper[i] - problem.lower[i];
      if (!(range > 0.0 && std::isfinite(range))) continue;
      near = std::abs(x[i] - y.x[i]) <= basin * range;
    }
    if (near) return true;
  }
  return false;
}

/// Whether the problem's variables start with the 7 durations themselves (not the one-jerk
/// family's coordinates) and their bounds are the same read backwards.
bool symmetric_durations(const NlpProblem& problem, const StrategyContext& context) {
  if (context.space.one_jerk || problem.size() < static_cast<int>(kSegments)) return false;
  for (std::size_t i = 0; i < kSegments; ++i) {
    const std::size_t j = kSegments - 1 - i;
    if (problem.lower[i] != problem.lower[j] || problem.upper[i] != problem.upper[j]) return false;
  }
  return true;
}

/// x with its 7 durations in reverse order (the coordinates after them unchanged).
std::vector<double> mirrored(std::vector<double> x) {
  std::reverse(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(kSegments));
  return x;
}

/// With an approach basin, `given` with an objective that records its last value in `last_f`:
/// the abandon test reads it (the solver evaluates the objective first); else nothing.
std::optional<NlpProblem> recording(const NlpProblem& given, const StartPolicy& policy,
                                    double* last_f) {
  if (!policy.leave_known_optima || policy.approach_basin <= 0.0) return std::nullopt;
  NlpProblem p = given;
  p.objective = [f = given.objective, last_f](const double* x, double* grad) {
    *last_f = f(x, grad);
    return *last_f;
  };
  return p;
}

NlpResult run_solver(const NlpProblem& problem, const StrategyContext& context,
                     const std::vector<double>& x0, const NlpOptions& o) {
  return effective(context) == SolverChoice::kIpopt ? solve_with_ipopt(problem, x0, o)
                                                    : solve_with_nlopt(problem, x0, o);
}

// A run that ended outside the constraints goes again from its repaired end point (up to
// policy.restarts times), kept while it comes closer to the feasible set.
void rerun_repaired(const NlpProblem& problem, const StrategyContext& context,
                    const StartPolicy& policy, double feasible_tol, NlpOptions& o, NlpResult& r,
                    MultiStartResult& out) {
  for (int again = 0; again < policy.restarts && policy.repair && !r.abandoned &&
                      r.status != SolveStatus::kTimeLimit && std::isfinite(r.objective) &&
                      r.max_violation > feasible_tol;
       ++again) {
    std::vector<double> x = r.x;
    if (problem.before_start) problem.before_start(x.data());
    if (!policy.repair(x)) break;
    o.time_limit = context.deadline.remaining();
    if (o.time_limit <= 0.0) break;
    NlpResult next = run_solver(problem, context, x, o);
    out.evaluations += next.evaluations;
    if (next.status == SolveStatus::kTimeLimit) out.timed_out = true;
    if (next.abandoned || !std::isfinite(next.objective)) break;
    if (next.max_violation >= r.max_violation && next.max_violation > feasible_tol) break;
    r = std::move(next);
  }
}

MultiStartResult solve_starts(const NlpProblem& given,
                              const std::vector<std::vector<double>>& starts,
                              const StrategyContext& context, const NlpOptions& options,
                              const StartPolicy& policy) {
  double last_f = 0.0;
  const std::optional<NlpProblem> recorded = recording(given, policy, &last_f);
  const NlpProblem& problem = recorded ? *recorded : given;
  MultiStartResult out;
  // Optima reached (feasible, converged or stopped by round-off) by the runs so far.
  std::vector<KnownOptimum> optima;
  int stale = 0;  // optional starts in a row that did not lower the best
  const double feasible_tol =
      effective(context) == SolverChoice::kIpopt
          ? std::max(kIpoptRelaxedViolation, 10.0 * options.constraint_tolerance)
          : 10.0 * options.constraint_tolerance;
  bool have = false;
  const bool mirror =
      policy.leave_known_optima && policy.mirror_symmetric && symmetric_durations(problem, context);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const auto& x0 = starts[k];
    const bool optional =
        policy.optional_from >= 0 && k >= static_cast<std::size_t>(policy.optional_from);
    if (optional && stale >= policy.patience) break;
    const double remaining = context.deadline.remaining();
    if (remaining <= 0.0) {
      out.timed_out = true;
      break;
    }
    if (problem.before_start) problem.before_start(x0.data());
    NlpOptions o = options;
    o.time_limit = remaining;
    // A stop request ends the run at its next evaluation, not after it (a path plan's run takes
    // seconds).
    if (o.stop == nullptr) o.stop = context.deadline.stop_flag();
    if (policy.leave_known_optima && !optima.empty()) {
      o.abandon = [&problem, &optima, &last_f, approach = policy.approach_basin](const double* x) {
        return near_known_optimum(problem, optima, x, last_f, approach);
      };
    }
    NlpResult r = run_solver(problem, context, x0, o);
    ++out.starts;
    out.evaluations += r.evaluations;
    if (r.status == SolveStatus::kTimeLimit) out.timed_out = true;
    // An abandoned run was ending at an optimum already held: nothing lower.
    if (r.abandoned || !std::isfinite(r.objective)) {
      if (optional) ++stale;
      continue;
    }
    rerun_repaired(problem, context, policy, feasible_tol, o, r, out);
    const bool feasible = r.max_violation <= feasible_tol;
    if (feasible && r.usable()) {
      optima.push_back({r.x, r.objective});
      if (mirror) optima.push_back({mirrored(r.x), r.objective});
    }
    const bool better =
        !have || (feasible && !out.feasible) ||
        (feasible == out.feasible &&
         (feasible ? r.objective < out.best.objective : r.max_violation < out.best.max_violation));
    if (optional) {
      // A tie with the best (the same optimum to the solver's tolerance) is no progress.
      const bool tie = have && feasible && out.feasible &&
                       r.objective >= out.best.objective - 1e-9 * std::abs(out.best.objective);
      stale = better && !tie ? 0 : stale + 1;
    }
    if (better) {
      out.best = std::move(r);
      out.best_start = static_cast<int>(k);
      out.feasible = feasible;
      have = true;
    }
    if (out.timed_out) break;
    // The caller's "good enough": a feasible point at or below stop_value ends the multi-start.
    if (out.feasible && options.stop_value && out.best.objective <= *options.stop_value) break;
  }
  if (!have) out.best.status = out.timed_out ? SolveStatus::kTimeLimit : SolveStatus::kFailed;
  return out;
}

}  // namespace

MultiStartResult multi_start(const NlpProblem& problem,
                             const std::vector<std::vector<double>>& starts,
                             const StrategyContext& context, const NlpOptions& options,
                             const StartPolicy& policy) {
  // Lower bounds that fill the motion time leave one admissible point: it is the optimum, and
  // every start is it (SLSQP spent its whole evaluation budget there on infeasible problems).
  if (problem.size() == static_cast<int>(kSegments) && !starts.empty()) {
    if (const std::optional<Durations> only = context.space.only_point()) {
      MultiStartResult out;
      NlpResult& r = out.best;
      r.x.assign(only->begin(), only->end());
      if (problem.before_start) problem.before_start(r.x.data());
      r.objective = problem.objective(r.x.data(), nullptr);
      r.max_violation = max_violation(problem, r.x);
      r.evaluations = 1;
      r.message = "the bounds leave one admissible point";
      out.feasible = r.max_violation <= 10.0 * options.constraint_tolerance;
      r.status = out.feasible ? SolveStatus::kOptimal : SolveStatus::kInfeasible;
      out.starts = 1;
      out.evaluations = 1;
      return out;
    }
  }
  const std::optional<OneJerkChart>& chart = context.space.one_jerk;
  if (!chart) return solve_starts(problem, starts, context, options, policy);
  // The one-jerk family: solved in its coordinates, the best point restated as durations.
  std::vector<std::vector<double>> reduced;
  reduced.reserve(starts.size());
  for (const auto& x0 : starts) reduced.push_back(chart->restrict(x0));
  // A repair is written for the full problem's points (7 durations, then the extra variables):
  // it sees the reduced point lifted, and its result goes back to the family's coordinates.
  StartPolicy in_chart = policy;
  if (policy.repair) {
    in_chart.repair = [&chart, repair = policy.repair](std::vector<double>& p) {
      std::vector<double> x = chart->lift(p);
      if (!repair(x)) return false;
      p = chart->restrict(x);
      return true;
    };
  }
  MultiStartResult out = solve_starts(chart->reduce(problem), reduced, context, options, in_chart);
  if (!out.best.x.empty()) out.best.x = chart->lift(out.best.x);
  return out;
}

std::string not_converged(const NlpResult& best) {
  const std::string words =
      best.message.empty() ? std::string("its iteration limit") : best.message;
  if (best.status == SolveStatus::kInfeasible) {
    // It ended (converged or not) outside its constraint tolerance; polished onto the
    // admissible set and verified, the point meets them.
    return "the solver ended " + sig3(best.max_violation) + " outside a constraint (" + words +
           "); polished onto the admissible set its point meets them, but the objective may not "
           "be minimal";
  }
  return "the solver stopped at a point that meets the constraints without converging (" + words +
         "), so the objective may not be minimal";
}

StrategyOutcome outcome_from(const MultiStartResult& m, const StrategyContext& c) {
  StrategyOutcome o;
  o.evaluations = m.evaluations;
  o.starts = m.starts;
  o.solver = solver_name(c);
  if (m.best.x.empty()) {
    o.status = m.timed_out ? SolveStatus::kTimeLimit : SolveStatus::kFailed;
    o.durations = c.space.starts(0).front();
    return o;
  }
  if (!m.feasible && m.timed_out) {
    // Out of time before any feasible point: the best admissible point is the first start.
    o.status = SolveStatus::kTimeLimit;
    o.durations = c.space.starts(0).front();
    return o;
  }
  o.durations = c.space.polish(m.best.x.data());
  o.objective = m.best.objective;
  if (!m.feasible) {
    o.status = SolveStatus::kInfeasible;
  } else if (m.timed_out) {
    o.status = SolveStatus::kTimeLimit;
  } else {
    // Optimal only when the solver converged; a feasible point it stopped at otherwise (round-off,
    // the iteration limit) meets the constraints without a certificate of optimality.
    o.status =
        m.best.status == SolveStatus::kOptimal ? SolveStatus::kOptimal : SolveStatus::kAcceptable;
    if (o.status == SolveStatus::kAcceptable) o.detail = not_converged(m.best);
  }
  return o;
}

}  // namespace slosh::detail
