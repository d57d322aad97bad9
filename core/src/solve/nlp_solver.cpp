#include "slosh/core/solve/nlp_solver.hpp"

#include <algorithm>
#include <cmath>

namespace slosh {

double max_violation(const NlpProblem& problem, const std::vector<double>& x) {
  double worst = 0.0;
  const int n = problem.size();
  for (int i = 0; i < n; ++i) {
    worst = std::max({worst, problem.lower[i] - x[i], x[i] - problem.upper[i]});
  }
  for (const auto& e : problem.equalities) {
    double ax = 0.0;
    for (int i = 0; i < n; ++i) ax += e.a[i] * x[i];
    worst = std::max(worst, std::abs(ax - e.b));
  }
  if (problem.inequality_count > 0) {
    std::vector<double> g(problem.inequality_count);
    problem.inequalities(x.data(), g.data(), nullptr);
    for (double gj : g) worst = std::max(worst, gj);
  }
  return worst;
}

}  // namespace slosh
