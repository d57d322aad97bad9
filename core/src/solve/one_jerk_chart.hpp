#pragma once
// The one-jerk family of the 7-segment law (what a PLCopen MC_MoveAbsolute block with a jerk limit
// runs, SPEC §11) as its own coordinates: the solvers optimise these 3 numbers instead of the 7
// durations, so every point they visit is in the family (internal to the core).
//
// Coordinates p = (ta, tb, c): the acceleration ramps dT1 = dT3 = ta, the deceleration ramps
// dT5 = dT7 = tb and the cruise dT4 = c. With M = T - c and s = ta + tb the plateaus are
//   dT2 = tb M / s - s,   dT6 = ta M / s - s,
// so that the durations sum to T and ta (ta + dT2) = tb (tb + dT6) for every p: rest-to-rest then
// gives A / ta = B / tb, one jerk J for the four ramps.

#include <array>
#include <optional>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh::detail {

struct OneJerkChart {
  static constexpr int kDimension{3};
  using Point = std::array<double, kDimension>;

  double motion_time{};  ///< T [s]
  double min_ramp{};     ///< lower bound of ta and tb [s]
  double cruise_max{};   ///< upper bound of c (0 with fix_constant_velocity_zero, else T) [s]
  std::array<double, 2> plateau_min{};  ///< lower bounds of dT2, dT6 [s]
  /// A point of the family inside every bound, or nullopt when the family has none.
  std::optional<Point> anchor;

  OneJerkChart(double T, double min_ramp, double cruise_max, std::array<double, 2> plateau_min);

  /// The durations of p; with `jacobian` not null also d(durations)/dp, 7 x 3 row-major.
  [[nodiscard]] Durations durations(const double* p, double* jacobian) const;
  /// The family point nearest in spirit to any 7 durations: the mean of each pair of ramps and
  /// the cruise (exact for a point of the family).
  [[nodiscard]] Point coordinates(const double* d) const;
  /// Lower and upper bounds of the coordinates.
  [[nodiscard]] Point lower() const;
  [[nodiscard]] Point upper() const;
  /// True when p is inside the bounds and its plateaus are >= their minimums - `slack`.
  [[nodiscard]] bool admissible(const Point& p, double slack) const;
  /// p clamped into the bounds, then moved towards the anchor until its plateaus are admissible.
  [[nodiscard]] Point repair(Point p) const;

  /// The problem `full` over 7 durations + e extra variables, restated over the 3 coordinates + the
  /// same extra variables: the sum equality (the only equality `full` may have) holds by
  /// construction, two inequalities keep the plateaus above their minimums (relative to T), and
  /// every gradient is the exact chain rule through durations(). Throws std::logic_error when
  /// `full` has an equality other than the sum.
  [[nodiscard]] NlpProblem reduce(const NlpProblem& full) const;
  /// The point of the full problem (n variables) that reduce()'s functions evaluate at p: the 7
  /// durations, then p's extra variables. Outside the family's admissible set (a plateau below 0,
  /// which only the solver's trial points and an infeasible last point reach) that plateau is held
  /// at 0 with a zero row in `jac`, so the functions of the full problem only ever see durations
  /// >= 0 (a negative one makes the time-domain response meaningless); the plateau rows, on the
  /// durations as charted, push the solver back. `jac` (7 x 3, may be null) gets the Jacobian of
  /// the evaluated durations, `charted_jac` and `charted` (may be null) those as charted.
  [[nodiscard]] std::vector<double> evaluation_point(const double* p, std::size_t n, double* jac,
                                                     double* charted_jac, Durations* charted) const;
  /// A point of reduce(full) as a point of full: evaluation_point() of it.
  [[nodiscard]] std::vector<double> lift(const std::vector<double>& reduced) const;
  /// A point of full as a point of reduce(full).
  [[nodiscard]] std::vector<double> restrict(const std::vector<double>& full) const;
};

}  // namespace slosh::detail
