#pragma once
// The one bounded nonlinear least-squares solver of the core (internal): Levenberg-Marquardt with
// Marquardt's diagonal scaling and box bounds by projection. The caller supplies the residuals
// and their exact Jacobian; nothing here differentiates numerically.
//
// Why our own: Ceres is not in the design card; Eigen's unsupported LevenbergMarquardt (MINPACK
// lmder) has no bounds, and Ipopt/NLopt would see only the scalar sum of squares (losing the
// Gauss-Newton structure). This is ~80 lines on Eigen, bounded by projection, and every
// calibration goes through this function only.

#include <functional>

#include <Eigen/Dense>

namespace slosh::detail {

/// Minimise 0.5 |r(x)|^2 subject to lower <= x <= upper.
struct BoundedLeastSquares {
  /// Fills the residuals r (m) and the Jacobian J (m x n) at x; false when x cannot be evaluated.
  std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& J)> evaluate;
  Eigen::VectorXd lower;  ///< n lower bounds
  Eigen::VectorXd upper;  ///< n upper bounds
};

struct LeastSquaresOptions {
  int max_iterations{100};     ///< accepted or rejected steps, at most
  double tolerance{1e-10};     ///< relative change of the cost or of x that ends the search
  std::function<bool()> stop;  ///< polled before every step; true ends with kStopped
};

enum class LeastSquaresStatus { kConverged, kMaxIterations, kStopped, kFailed };

struct LeastSquaresOutcome {
  Eigen::VectorXd x;  ///< the solution (within the bounds)
  double cost{};      ///< 0.5 |r|^2 at x
  int iterations{};   ///< steps tried
  LeastSquaresStatus status{LeastSquaresStatus::kFailed};
};

[[nodiscard]] LeastSquaresOutcome solve_bounded_least_squares(const BoundedLeastSquares& problem,
                                                              Eigen::VectorXd x0,
                                                              const LeastSquaresOptions& options);

}  // namespace slosh::detail
