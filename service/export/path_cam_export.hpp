#pragma once
// The cam table of a law along a planar path (format.motion of type arc or path, SPEC §14) as
// `slosh export` writes it: s along the path with its derivatives plus the container's pose x, y
// and heading theta at every row; for a rotary table (a motion of one arc) the master-axis table
// gives the table's rotation in degrees. CSV only: the structured-text types hold the
// straight-line columns.

#include <string>

#include "export/cam_export.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh::service {

/// The CSV of `table` (sample_cam(law, path.length(), ...)) along `path`:
/// - time-based: `t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg`,
///   and for one arc a last column `table_deg` (the table's rotation, s / length * angle);
/// - master-axis, one arc: `master,table_deg,velocity_deg_per_unit,acceleration_deg_per_unit2,
///   jerk_deg_per_unit3` (table_rotation_rows);
/// - master-axis, any other path: `master,s_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,
///   jerk_mm_per_unit3,x_mm,y_mm,theta_deg`.
/// Positions in mm of the world frame (the path starts at the origin), theta the heading in
/// degrees from the start (0 throughout when the container keeps its orientation). Every number
/// csv_number; a row at the end of the path holds its length as api::mm_of gives it.
[[nodiscard]] std::string path_cam_csv(const CamTable& table, const PlanarPath& path);

/// Throws ApiError(kInvalidValue, `format_field`) unless `format` is CSV: the structured
/// text of a path's cam table is not available.
void check_path_cam_format(CamFileFormat format, const std::string& format_field);

}  // namespace slosh::service
