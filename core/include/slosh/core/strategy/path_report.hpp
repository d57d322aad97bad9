#pragma once
// The figures of a law along a planar path (path_plan.hpp).

#include <optional>
#include <vector>

#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// A law's verified figures along a path.
struct PathPrediction {
  PlanarPeaks linear;     ///< the planar linear multi-mode model, maximised over the wall
  PlanarPeaks nonlinear;  ///< the planar nonlinear fundamental-mode model
  /// Largest horizontal acceleration sqrt(s''^2 + (s'^2 / rho)^2) [m/s^2] and where [s].
  double a_total_peak{};
  double a_total_time{};
  double a_normal_peak{};  ///< largest s'^2 / rho [m/s^2]
  double v_peak{};         ///< largest s' [m/s]
  double j_peak{};         ///< largest |s'''| (tangential jerk) [m/s^3]
  /// A rectangular tank's linear waves of each direction alone (no spin rise); nullopt for the
  /// cylinder.
  std::optional<DirectionWaves> linear_directions;
};

/// What a plan along a path reports beside its PlanResult (whose predictions, values and times,
/// are the planar models' along the path): the directions of the peaks and the path's kinematics.
struct PathPlanReport {
  double length{};            ///< path length the law moves along [m]
  PathPrediction prediction;  ///< of the returned law
  PathPrediction baseline;    ///< of the uniform law
};

}  // namespace slosh
