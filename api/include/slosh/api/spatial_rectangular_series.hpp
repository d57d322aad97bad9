#pragma once
// The series of a rectangular tank's simulation along a spatial motion (SPEC §14 with §15): the
// same columns as spatial_series_json, the heights being the tank's highest corner (or wall)
// and the directions the world angle from the tank's centre to that corner.

#include <nlohmann/json.hpp>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"

namespace slosh::api {

/// Columns and units as spatial_series_json; "eta_linear_mm" and "eta_nonlinear_mm" the highest
/// corner of RectangularPlanarResponse's linear and nonlinear models (the linear one in both
/// columns when `nonlinear_holds` is false: the nonlinear model is outside its range), the
/// liquid's spin rise included. `frame_angle` [rad] as RectangularPlanarResponse takes it.
[[nodiscard]] nlohmann::json rectangular_spatial_series_json(const RectangularModel& model,
                                                             const PlanarDrive& drive,
                                                             double frame_angle,
                                                             const MotionLaw* law, double rest_time,
                                                             double dt, bool nonlinear_holds,
                                                             double theta_origin = 0.0);

}  // namespace slosh::api
