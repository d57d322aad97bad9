// Both solver wrappers on problems with known solutions, and their status translation.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <string>

#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh {
namespace test_nlp_solver {

using Solver = NlpResult (*)(const NlpProblem&, const std::vector<double>&, const NlpOptions&);

struct SolverCase {
  const char* name;
  Solver solve;
};

void PrintTo(const SolverCase& c, std::ostream* os) {
  *os << c.name;
}

class NlpSolvers : public ::testing::TestWithParam<SolverCase> {};

// The tests of an answer run without a wall-clock budget: a slow machine (a sanitizer build under
// load takes over a second for Ipopt's first solve) must not turn a right answer into a time
// limit. The budget has its own test, StopsAtTheTimeBudget.
NlpOptions untimed() {
  NlpOptions options;
  options.time_limit = 0.0;
  return options;
}

// min (x0 - 1)^2 + 100 (x1 - x0^2)^2 + (x2 - x0)^2  s.t.  x0 + x1 + x2 = 3, -5 <= x <= 5.
// (With tight bounds the corner (-1, 2, 2) is a second KKT point: start inside the basin.)
NlpProblem rosenbrock_with_equality() {
  NlpProblem p;
  p.lower = {-5, -5, -5};
  p.upper = {5, 5, 5};
  p.objective = [](const double* x, double* g) {
    const double r = x[1] - x[0] * x[0];
    if (g != nullptr) {
      g[0] = 2 * (x[0] - 1) - 400 * x[0] * r - 2 * (x[2] - x[0]);
      g[1] = 200 * r;
      g[2] = 2 * (x[2] - x[0]);
    }
    return (x[0] - 1) * (x[0] - 1) + 100 * r * r + (x[2] - x[0]) * (x[2] - x[0]);
  };
  p.equalities.push_back({{1, 1, 1}, 3.0});
  return p;
}

TEST_P(NlpSolvers, ReachesTheKnownOptimumWithALinearEquality) {
  const NlpResult r = GetParam().solve(rosenbrock_with_equality(), {0.3, 1.2, 1.5}, untimed());
  ASSERT_TRUE(r.usable()) << to_string(r.status) << " " << r.message;
  for (double xi : r.x) EXPECT_NEAR(xi, 1.0, 1e-5);
  EXPECT_LT(r.objective, 1e-10);
  EXPECT_LT(r.max_violation, 1e-9);
  EXPECT_GT(r.evaluations, 0);
}

TEST_P(NlpSolvers, ActiveNonlinearInequality) {
  // min x0 + x1  s.t.  x0^2 + x1^2 - 1 <= 0: optimum -(1, 1)/sqrt 2.
  NlpProblem p;
  p.lower = {-5, -5};
  p.upper = {5, 5};
  p.objective = [](const double* x, double* g) {
    if (g != nullptr) g[0] = g[1] = 1.0;
    return x[0] + x[1];
  };
  p.inequality_count = 1;
  p.inequalities = [](const double* x, double* g, double* jac) {
    g[0] = x[0] * x[0] + x[1] * x[1] - 1.0;
    if (jac != nullptr) {
      jac[0] = 2 * x[0];
      jac[1] = 2 * x[1];
    }
  };
  const NlpResult r = GetParam().solve(p, {0.3, -0.2}, untimed());
  ASSERT_TRUE(r.usable()) << to_string(r.status) << " " << r.message;
  EXPECT_NEAR(r.x[0], -std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(r.x[1], -std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(r.objective, -std::sqrt(2.0), 1e-8);
}

TEST_P(NlpSolvers, ReportsInfeasibleConstraints) {
  // x0 + x1 = 3 with both in [0, 1].
  NlpProblem p;
  p.lower = {0, 0};
  p.upper = {1, 1};
  p.objective = [](const double* x, double* g) {
    if (g != nullptr) g[0] = g[1] = 0.0;
    return 0.0 * x[0];
  };
  p.equalities.push_back({{1, 1}, 3.0});
  const NlpResult r = GetParam().solve(p, {0.5, 0.5}, untimed());
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  EXPECT_NEAR(r.max_violation, 1.0, 1e-6);
}

TEST_P(NlpSolvers, StopsAtTheTimeBudget) {
  NlpProblem p = rosenbrock_with_equality();
  const auto slow = p.objective;
  p.objective = [slow](const double* x, double* g) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2);
    while (std::chrono::steady_clock::now() < until) {
    }
    return slow(x, g);
  };
  NlpOptions options;
  options.time_limit = 0.01;
  options.tolerance = 1e-15;
  const NlpResult r = GetParam().solve(p, {-1.9, 1.9, 3.0}, options);
  EXPECT_EQ(r.status, SolveStatus::kTimeLimit) << r.message;
  EXPECT_LT(r.evaluations, 40);
}

// The stop flag (a client that hung up) ends a run within it, not at its end: NLopt at the next
// evaluation, Ipopt at the end of the iteration under way. Set here by the objective itself at its
// third call, so the count of calls after it is exact, whatever the machine's speed.
TEST_P(NlpSolvers, StopsWithinTheRunWhenTheStopFlagIsSet) {
  std::atomic<bool> stop{false};
  int calls = 0;
  int calls_when_set = -1;
  NlpProblem p = rosenbrock_with_equality();
  const auto plain = p.objective;
  p.objective = [&](const double* x, double* g) {
    if (++calls == 3) {
      stop = true;
      calls_when_set = calls;
    }
    return plain(x, g);
  };
  NlpOptions options;
  options.tolerance = 1e-15;
  options.time_limit = 0.0;
  options.stop = &stop;
  const NlpResult r = GetParam().solve(p, {-1.9, 1.9, 3.0}, options);
  EXPECT_EQ(r.status, SolveStatus::kTimeLimit) << r.message;
  EXPECT_FALSE(r.abandoned);
  ASSERT_EQ(calls_when_set, 3);
  // NLopt: none in the run after the flag, one for the returned point's objective; Ipopt: the
  // rest of the iteration's line search as well.
  const bool nlopt = std::string(GetParam().name) == "nlopt";
  EXPECT_LE(calls - calls_when_set, nlopt ? 1 : 8);
  // Without the flag the same run goes on well past that.
  calls = 0;
  stop = false;
  options.stop = nullptr;
  const NlpResult full = GetParam().solve(p, {-1.9, 1.9, 3.0}, options);
  EXPECT_TRUE(full.usable()) << full.message;
  EXPECT_GT(calls, 12);
}

INSTANTIATE_TEST_SUITE_P(Solvers, NlpSolvers,
                         ::testing::Values(SolverCase{"nlopt", solve_with_nlopt},
                                           SolverCase{"ipopt", solve_with_ipopt}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(SolveStatus, Names) {
  EXPECT_EQ(to_string(SolveStatus::kOptimal), "optimal");
  EXPECT_EQ(to_string(SolveStatus::kAcceptable), "acceptable");
  EXPECT_EQ(to_string(SolveStatus::kInfeasible), "infeasible");
  EXPECT_EQ(to_string(SolveStatus::kTimeLimit), "time_limit");
  EXPECT_EQ(to_string(SolveStatus::kFailed), "failed");
}

}  // namespace test_nlp_solver
}  // namespace slosh
