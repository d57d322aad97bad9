#pragma once
// What a plan along a path verifies a rectangular tank's law by (SPEC §14 with §15): the tank's
// own models along the path (rectangular_planar.hpp, its modes in its own frame, the highest
// corner), in the figures the path planner judges every law by.

#include <string>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/strategy/path_report.hpp"
#include "slosh/core/strategy/robustness.hpp"

namespace slosh {

/// The world angle of the tank's L axis at the path's start [rad]: orientation_deg from the
/// path's start tangent (counter-clockwise, as the arcs' angles).
[[nodiscard]] double tank_frame_angle(const PlanarPath& path, double orientation_deg);

/// The verified figures of `law` along `path` for the tank (tank.orientation_deg from the start
/// tangent): `linear` the linear model's highest corner, `nonlinear` the nonlinear model's, or
/// the linear one's outside its range, the reason then in `*warning` when given; the path's
/// kinematics as predict_on_path.
[[nodiscard]] PathPrediction predict_tank_on_path(const RectangularModel& tank,
                                                  const PlanarPath& path, const MotionLaw& law,
                                                  double rest_time, std::string* warning = nullptr);

/// robustness_report_on_path for the tank: both directions' frequencies scaled by (1 + delta),
/// each direction keeping its own damping ratio unless `sweep.zeta` differs from the most
/// excited direction's on the line (driven_directions; then both take it), every point from the
/// tank's models along the path.
[[nodiscard]] std::optional<RobustnessReport> rectangular_robustness_report_on_path(
    const RectangularModel& tank, const PlanarPath& path, const MotionLaw& law,
    const RobustnessSweep& sweep, const std::function<bool()>& out_of_time = {});

}  // namespace slosh
