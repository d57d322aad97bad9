#pragma once
// The cam table of a law along a planar path (format.motion of type arc or path, SPEC §14) as
// `slosh export` and GET /v1/plans/{key}/cam.csv and cam.st write it: s along the path with its
// derivatives plus the container's pose x, y and heading theta at every row; for a rotary table
// (a motion of one arc) the table's rotation in degrees too, and its master-axis table gives
// that rotation as the slave. CSV or IEC 61131-3 structured text with the same columns.

#include <string>

#include "export/cam_export.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh::service {

/// The file of `table` (sample_cam(law, path.length(), ...)) along `path` in the format of
/// `spec`, its columns:
/// - time-based: `t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg`,
///   and for one arc a last column `table_deg` (the table's rotation, s / length * angle); ST
///   type SLOSH_PATH_CAM_POINT, or SLOSH_TABLE_CAM_POINT with table_deg;
/// - master-axis, one arc: `master,table_deg,velocity_deg_per_unit,acceleration_deg_per_unit2,
///   jerk_deg_per_unit3` (table_rotation_rows); ST type SLOSH_TABLE_MASTER_CAM_POINT;
/// - master-axis, any other path: `master,s_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,
///   jerk_mm_per_unit3,x_mm,y_mm,theta_deg`; ST type SLOSH_PATH_MASTER_CAM_POINT.
/// Positions in mm of the world frame (the path starts at the origin), theta the heading in
/// degrees from the start (0 throughout when the container keeps its orientation). CSV numbers
/// csv_number, ST literals st_real_literal under cam_table_st's header (`source`) with a line
/// naming the path; a row at the end of the path holds its length as api::mm_of gives it.
[[nodiscard]] std::string path_cam_file(const CamTable& table, const PlanarPath& path,
                                        const CamSource& source, const CamTableSpec& spec);

/// The CSV of path_cam_file.
[[nodiscard]] std::string path_cam_csv(const CamTable& table, const PlanarPath& path);

/// Columns of the widest path table over those of the straight-line one (9 against 5), for
/// bounding an export's bytes (cam_export_bytes counts the straight-line columns).
inline constexpr std::size_t kPathCamWidthFactor{2};

}  // namespace slosh::service
