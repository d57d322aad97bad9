#pragma once
// Cam tables of a law along a planar path (SPEC §14): the law's s(t) along the path sampled at
// the controller cycle as sample_cam_table() does (cam_table.hpp), with the container's world
// position x, y and heading theta at each sample from the path's closed forms (planar_path.hpp),
// so a track mover or a robot is fed s and the pose together. For a rotary table (a single arc,
// the table turning about the arc's centre) the slave of a master-axis table is the table's
// rotation in degrees instead of the distance along the arc.

#include <optional>
#include <vector>

#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh {

/// One row of a time-based cam table along a path (SI units).
struct PathCamSample {
  double t{};             ///< [s]
  double s{};             ///< distance along the path [m]
  double velocity{};      ///< ds/dt [m/s]
  double acceleration{};  ///< d2s/dt2 (tangential) [m/s^2]
  double jerk{};          ///< d3s/dt3 [m/s^3]
  double x{}, y{};        ///< the container's position, world frame [m]
  /// The container's heading about the vertical axis, world frame as x and y: the path's start
  /// heading at the start [rad].
  double theta{};
};

/// The rows of a time-based cam table of a law along `path` (sample_cam_table(law,
/// path.length(), period)) with the pose at each: x, y and theta from PlanarPath::at.
[[nodiscard]] std::vector<PathCamSample> cam_along_path(const std::vector<CamSample>& cam,
                                                        const PlanarPath& path);

/// The table's rotation of a rotary table: the signed angle of a path that is one arc [deg]
/// (left positive, as the arc's angle); nullopt for any other path (lines, several elements).
[[nodiscard]] std::optional<double> table_rotation_deg(const PlanarPath& path);

/// The rows of a master-axis cam table of a law along the one-arc `path`
/// (sample_master_cam_table(law, path.length(), axis)) with the slave in degrees of table
/// rotation: every slave column scaled by angle / length (position [deg], derivatives [deg per
/// master unit^k]); rows at the end (position == length) hold the arc's angle exactly. Throws
/// std::invalid_argument when the path is not one arc.
[[nodiscard]] std::vector<MasterCamSample> table_rotation_rows(
    const std::vector<MasterCamSample>& rows, const PlanarPath& path);

}  // namespace slosh
