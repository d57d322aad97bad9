#pragma once
// One small interface over the two nonlinear-programming solvers of the planner (NLopt SLSQP and
// Ipopt). Each library is wrapped in exactly one source file and its status is translated into
// SolveStatus here; nothing else in the product includes a solver header.

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>
#include "slosh/core/enum_names.hpp"

namespace slosh {

/// Outcome of a solve, shared by every solver and strategy.
enum class SolveStatus {
  kOptimal,     ///< converged to the requested tolerance, constraints satisfied
  kAcceptable,  ///< constraints satisfied, optimality not certified to the requested tolerance
                ///< (Ipopt's acceptable level, a stall on round-off; for a plan also a law that
                ///< meets its constraints but whose objective was not minimised)
  kInfeasible,  ///< the constraints could not be satisfied
  kTimeLimit,   ///< the time budget ran out; x is the last iterate
  kFailed,      ///< anything else (numerical failure, the iteration limit before convergence,
                ///< invalid problem or input); x may still be a usable point
};

template <>
struct EnumNames<SolveStatus> {
  static constexpr std::array<EnumName<SolveStatus>, 5> table{{
      {SolveStatus::kOptimal, "optimal"},
      {SolveStatus::kAcceptable, "acceptable"},
      {SolveStatus::kInfeasible, "infeasible"},
      {SolveStatus::kTimeLimit, "time_limit"},
      {SolveStatus::kFailed, "failed"},
  }};
};
[[nodiscard]] inline std::string to_string(SolveStatus value) {
  return std::string(name_of(value));
}

/// min f(x)  s.t.  lower <= x <= upper,  a_k . x = b_k (linear equalities),  g_j(x) <= 0.
/// Derivatives are exact (given by the caller); the solvers never difference.
struct NlpProblem {
  struct LinearEquality {
    std::vector<double> a;  ///< coefficients, size n
    double b{};             ///< right-hand side
  };
  std::vector<double> lower;  ///< size n
  std::vector<double> upper;  ///< size n
  /// f(x); writes the gradient to `grad` (size n) when it is not null.
  std::function<double(const double* x, double* grad)> objective;
  std::vector<LinearEquality> equalities;
  /// Number of nonlinear inequalities g(x) <= 0.
  int inequality_count{0};
  /// Writes g(x) (size m) and, when `jacobian` is not null, dg/dx row-major (m x n).
  std::function<void(const double* x, double* g, double* jacobian)> inequalities;
  /// Called by multi_start() with each start x0 before the solver runs from it (may be empty):
  /// lets a problem fix, for the whole run from x0, the discretisation its functions use, so
  /// they stay smooth in x during that run (time_domain's step counts per law piece).
  std::function<void(const double* x0)> before_start;

  [[nodiscard]] int size() const { return static_cast<int>(lower.size()); }
};

/// The violation an Ipopt point may keep and still be feasible [units of the constraints]:
/// Ipopt relaxes bounds and equalities by about 1e-8 (bound_relax_factor), and the durations are
/// polished onto the exact admissible set afterwards, so that much is not an infeasibility.
inline constexpr double kIpoptRelaxedViolation{1e-7};

/// Solver settings with safe defaults.
struct NlpOptions {
  /// Relative tolerance on the objective / optimality error [-]. Default 1e-10.
  double tolerance{1e-10};
  /// Allowed constraint violation [units of the constraints]. Default 1e-9.
  double constraint_tolerance{1e-9};
  /// Iteration (NLopt: evaluation) limit. Default 1000.
  int max_iterations{1000};
  /// Wall-clock budget [s]; <= 0 means none. Default 1 s.
  double time_limit{1.0};
  /// Stop as soon as a feasible point with f <= stop_value is found (NLopt only; Ipopt solves
  /// to optimality). Default: none.
  std::optional<double> stop_value;
  /// Called with every point the objective is evaluated at (NLopt only; may be empty): true
  /// abandons the run there (NlpResult::abandoned). A multi-start leaves a run this way once it
  /// has reached an optimum an earlier start found. Default: none.
  std::function<bool(const double* x)> abandon;
  /// Set true (a client hung up, the service shuts down), it ends the run at its next evaluation
  /// (NLopt) or iteration (Ipopt) with status kTimeLimit: a run can take seconds, far longer than
  /// a caller should wait for work nobody reads. May be null. Default: none.
  const std::atomic<bool>* stop{nullptr};
};

/// Result of one solve.
struct NlpResult {
  SolveStatus status{SolveStatus::kFailed};
  std::vector<double> x;   ///< final (best admissible when time-limited) point
  double objective{};      ///< f(x)
  double max_violation{};  ///< largest bound / equality / inequality violation at x
  int evaluations{};       ///< objective evaluations
  std::string message;     ///< the solver's own words, for the report
  /// NlpOptions::abandon stopped the run (status kFailed; x is where it stopped).
  bool abandoned{false};

  [[nodiscard]] bool usable() const {
    return status == SolveStatus::kOptimal || status == SolveStatus::kAcceptable;
  }
};

/// Largest violation of the bounds and constraints of `problem` at x.
[[nodiscard]] double max_violation(const NlpProblem& problem, const std::vector<double>& x);

/// NLopt's SLSQP (sequential quadratic programming with BFGS), from x0.
[[nodiscard]] NlpResult solve_with_nlopt(const NlpProblem& problem, const std::vector<double>& x0,
                                         const NlpOptions& options);

/// Ipopt (interior point, limited-memory BFGS Hessian), from x0.
[[nodiscard]] NlpResult solve_with_ipopt(const NlpProblem& problem, const std::vector<double>& x0,
                                         const NlpOptions& options);

}  // namespace slosh
