#pragma once
// The feasible set every optimising strategy shares: bounds on the 7 durations, their sum, the
// machine limits as smooth inequalities, the jerk integral, deterministic starts and the final
// polish onto the exact admissible set (internal to the core).

#include <optional>
#include <random>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/solve/nlp_solver.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "solve/one_jerk_chart.hpp"

namespace slosh::detail {

/// Bounds of the 7 durations and the motion time they sum to.
struct DurationSpace {
  Durations lower{};
  Durations upper{};
  double motion_time{};
  double stroke{};
  MachineLimits limits;
  /// PlanOptions::warm_start, when given: starts() is it (mapped) and the uniform law.
  std::optional<Durations> warm_start;
  /// PlanOptions::drive_profile kMoveAbsolute: the one-jerk family's coordinates. multi_start()
  /// then solves every problem in them, and polish() and starts() land in the family.
  std::optional<OneJerkChart> one_jerk;

  DurationSpace(const Format& format, const PlanOptions& options);

  /// Number of limit inequalities (0..7).
  [[nodiscard]] int limit_count() const;
  /// Writes the scaled limit inequalities g <= 0 (value / limit - 1) and, when `jac` is not null,
  /// their gradients into rows of length `stride` (the first 7 columns; the rest untouched).
  void limit_constraints(const double* d, double* g, double* jac, int stride) const;

  /// An NlpProblem over `extra` variables after the 7 durations (bounds [0, extra_upper]) with
  /// the bounds and the sum equality set; inequalities left to the caller. With extra > 0 the
  /// objective is the first extra variable (epigraph form: min z s.t. g(x) <= z), else unset.
  [[nodiscard]] NlpProblem problem(int extra = 0, double extra_upper = 1e6) const;

  /// Deterministic starts: the uniform law (when inside the bounds), symmetric families and
  /// `random_count` points of a seeded Dirichlet spread, all inside the bounds and summing to T.
  /// With a warm start: that start scaled to T and polished, then the uniform law (no others).
  [[nodiscard]] std::vector<Durations> starts(int random_count) const;
  /// starts() with the duplicates the one-jerk family's projection can make.
  [[nodiscard]] std::vector<Durations> general_starts(int random_count) const;

  /// Maps a solver point onto the exact admissible set (bounds hold, the sum equals T to the
  /// last bit, a segment within kZeroDuration of its bound is on it): the residual of the sum is
  /// spread over the segments with room. In the one-jerk family the point is first restated in
  /// its coordinates (repaired into their bounds), so the result is in the family.
  [[nodiscard]] Durations polish(const double* x) const;

  /// Whether the uniform law T/7 lies inside the bounds (min_ramp <= T/7, the plateau minimums,
  /// a cruise allowed), to within kZeroDuration.
  [[nodiscard]] bool uniform_inside() const;
  /// The admissible law nearest the uniform one: the uniform law when inside the bounds, else
  /// every segment at its lower bound plus an equal share of the remaining time (the baseline
  /// strategy's law, and the fallback of a method that has no law of its own).
  [[nodiscard]] Durations nearest_uniform() const;

  /// The point with free-weight fractions w (>= 0) of the room above the lower bounds.
  [[nodiscard]] Durations from_weights(const Durations& w) const;

  /// The only admissible point when the lower bounds fill the motion time (to kZeroDuration:
  /// e.g. T = 4 min_ramp without plateau minimums, where a min-time search starts), else nullopt.
  [[nodiscard]] std::optional<Durations> only_point() const;
};

/// Jerk integral sum J_i^2 dT_i [m^2/s^5] and its gradient.
[[nodiscard]] double jerk_integral(const double* d, double stroke, double* grad);

/// max(A, B) of a set of durations [m/s^2].
[[nodiscard]] double peak_acceleration(const Durations& d, double stroke);

}  // namespace slosh::detail
