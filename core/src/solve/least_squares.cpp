#include "solve/least_squares.hpp"

#include <algorithm>
#include <cmath>

namespace slosh::detail {

LeastSquaresOutcome solve_bounded_least_squares(const BoundedLeastSquares& problem,
                                                Eigen::VectorXd x0,
                                                const LeastSquaresOptions& options) {
  LeastSquaresOutcome out;
  out.x = x0.cwiseMax(problem.lower).cwiseMin(problem.upper);
  Eigen::VectorXd r, r_new;
  Eigen::MatrixXd J, J_new;
  if (!problem.evaluate(out.x, r, J) || !r.allFinite() || !J.allFinite()) return out;
  out.cost = 0.5 * r.squaredNorm();
  double mu = 1e-3;
  double nu = 2.0;
  for (out.iterations = 1; out.iterations <= options.max_iterations; ++out.iterations) {
    if (options.stop && options.stop()) {
      out.status = LeastSquaresStatus::kStopped;
      return out;
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    const Eigen::VectorXd d = A.diagonal().cwiseMax(1e-300);
    Eigen::MatrixXd M = A;
    M.diagonal() += mu * d;
    const Eigen::VectorXd step = M.ldlt().solve(-g);
    const Eigen::VectorXd x_new = (out.x + step).cwiseMax(problem.lower).cwiseMin(problem.upper);
    const Eigen::VectorXd dx = x_new - out.x;
    const double tiny = options.tolerance * (out.x.norm() + options.tolerance);
    if (dx.norm() <= tiny) {
      out.status = LeastSquaresStatus::kConverged;
      return out;
    }
    const double predicted = -(g.dot(dx) + 0.5 * dx.dot(A * dx));
    const bool ok = problem.evaluate(x_new, r_new, J_new) && r_new.allFinite() && J_new.allFinite();
    const double cost_new = ok ? 0.5 * r_new.squaredNorm() : HUGE_VAL;
    const double rho = predicted > 0.0 ? (out.cost - cost_new) / predicted : -1.0;
    if (ok && cost_new < out.cost) {
      const double drop = out.cost - cost_new;
      out.x = x_new;
      r.swap(r_new);
      J.swap(J_new);
      out.cost = cost_new;
      mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * std::clamp(rho, 0.0, 1.0) - 1.0, 3));
      nu = 2.0;
      if (drop <= options.tolerance * cost_new || out.cost == 0.0) {
        out.status = LeastSquaresStatus::kConverged;
        return out;
      }
    } else {
      mu *= nu;
      nu *= 2.0;
      if (mu > 1e30) {
        out.status = LeastSquaresStatus::kConverged;  // no descent left at this precision
        return out;
      }
    }
  }
  out.iterations = options.max_iterations;
  out.status = LeastSquaresStatus::kMaxIterations;
  return out;
}

}  // namespace slosh::detail
