#pragma once
// time_domain along a planar path (internal to the core): min eta_motion s.t. eta_rest <= bound
// (or the reverse) on a model along the path, with exact gradients from its PathSensitivity (the
// cylinder's planar nonlinear model, the height maximised over the wall: PlanarSensitivity; a
// rectangular tank's models, the highest corner: TankPlanarSensitivity); the machine limit on
// the total horizontal acceleration as sampled constraints closed by exchange.

#include <functional>
#include <memory>
#include <vector>

#include "response/path_sensitivity.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "strategy/strategies.hpp"

namespace slosh::detail {

/// What time_domain optimises along the path: the model's sensitivity, and the verified peaks a
/// law is judged by.
struct PathTarget {
  const PlanarPath* path{};
  /// The rows' time scale [rad/s]: the starting samples, the dense check's windows and the span
  /// a peak's row follows are fractions of 2 pi / omega.
  double omega{};
  /// A sensitivity with `steps_per_period` steps per period of its fastest modelled mode.
  std::function<std::unique_ptr<PathSensitivity>(double steps_per_period)> sensitivity;
  /// The verified peak of the law `d` in the motion window (`motion`) or the rest window [m].
  std::function<double(const Durations& d, bool motion)> verified_peak;
};

/// The cylinder's target: c.model's planar nonlinear model along `path`.
[[nodiscard]] PathTarget planar_target(const StrategyContext& c, const PlanarPath& path);

/// `c` is the context of the format whose stroke is the path length (its eta_ref the uniform
/// law's verified eta_motion); `seeds` extra starts after the uniform law.
[[nodiscard]] StrategyOutcome solve_path_time_domain(const StrategyContext& c,
                                                     const PathTarget& target,
                                                     const std::vector<Durations>& seeds);

}  // namespace slosh::detail
