#pragma once
// The trajectory CSV of `slosh simulate --trajectory` (SPEC §14), either
// - the measured runs' poses: header `t_s,x_m,y_m,z_m,qx,qy,qz,qw` (metres and a unit quaternion,
//   read by the core's read_pose_csv), or
// - plain columns: header `t_s,x_mm,y_mm[,z_mm][,theta_deg]` (seconds, millimetres, degrees).
// One sample a line; blank lines are skipped; a trailing carriage return and a UTF-8 byte order
// mark before the header are allowed.

#include <istream>
#include <string>

#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh::api {

/// The samples in SI (m, rad). Throws InvalidMotion naming the line ("line 17") with `source`
/// in the message, for an unknown header, a wrong number of fields, or a field that is not a
/// finite number.
[[nodiscard]] TrajectorySamples read_trajectory_csv(std::istream& in, const std::string& source);

}  // namespace slosh::api
