#pragma once
// The series of a simulation along a spatial motion (SPEC §14): the wall height maximised over
// the wall of both planar models, the wall direction of that maximum, and the container's pose,
// at equal steps from the motion's start to the end of the rest window.

#include <array>
#include <functional>

#include <nlohmann/json.hpp>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"

namespace slosh::api {

/// {"t_s", "x_mm", "y_mm", "theta_deg", "a_h" (the horizontal acceleration's magnitude [m/s^2],
/// normal part included), "eta_linear_mm", "eta_nonlinear_mm" (each model's height maximised
/// over the wall, the vortex rise of a turning container included), "direction_linear_deg",
/// "direction_nonlinear_deg" (the wall angle of that maximum, world frame, from +x), and with a
/// law along a path also "s", "v", "a" (distance, speed and tangential acceleration along the
/// path, SI as the straight line's series); "units"}. Samples at k dt, k = 0 .. floor(span / dt),
/// span = the drive's duration + rest_time; the heights from the stored planar responses
/// (PlanarLinearResponse, PlanarNonlinearResponse). `law` is null for a trajectory.
/// "theta_deg" is the container's world heading, the frame of x_mm and y_mm: the drive's theta
/// plus `theta_origin` [rad] (a path's start heading; 0 for a trajectory, whose theta is the
/// world heading already), so that the series fed back as a trajectory is the same motion.
[[nodiscard]] nlohmann::json spatial_series_json(const SloshingModel& model,
                                                 const PlanarDrive& drive, const MotionLaw* law,
                                                 double rest_time, double dt,
                                                 double theta_origin = 0.0);

/// One sample of a series' wall heights [m] and their wall directions [rad, world frame]:
/// {linear, nonlinear, linear direction, nonlinear direction}.
using SpatialSeriesSample = std::function<std::array<double, 4>(double t, const PlanarKinematics&)>;

/// The series' columns and units as spatial_series_json documents them, at the same samples,
/// with the heights and directions of `sample` (the one layout of the cylinder's and the
/// rectangular tank's series).
[[nodiscard]] nlohmann::json spatial_series_columns(const PlanarDrive& drive, const MotionLaw* law,
                                                    double rest_time, double dt,
                                                    const SpatialSeriesSample& sample,
                                                    double theta_origin = 0.0);

}  // namespace slosh::api
