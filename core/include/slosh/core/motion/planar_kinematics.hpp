#pragma once
// The container's pose in the world frame (x, y horizontal, z up) and its time derivatives.

namespace slosh {

/// Pose and derivatives of the container at one instant, world frame, SI.
struct PlanarKinematics {
  double x{}, y{}, z{};     ///< position [m]
  double vx{}, vy{}, vz{};  ///< velocity [m/s]
  double ax{}, ay{}, az{};  ///< acceleration [m/s^2]
  double jx{}, jy{}, jz{};  ///< jerk [m/s^3]
  double theta{};           ///< heading about the vertical axis [rad]
  double theta_dot{};       ///< [rad/s]
  double theta_ddot{};      ///< [rad/s^2]
  double theta_dddot{};     ///< [rad/s^3]
};

}  // namespace slosh
