#include "export/path_cam_export.hpp"

#include <cmath>
#include <optional>
#include <vector>

#include "export/export_units.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/law/path_cam_table.hpp"

namespace slosh::service {

namespace {

// A distance along the path in mm: the path's end as the request gave it (api::mm_of).
double s_mm(double s, double length) {
  return s == length ? api::mm_of(length) : s * kMmPerM;
}

// A pose value in the file's units to 1e-10 of them: a heading of 37 + 90 deg
// reads 127, not the 126.99999999999999 its radians round to.
double pose_value(double v) {
  return std::round(v * 1e10) / 1e10;
}

// The rows of a path's table in the file's units, with its columns and ST type: one table
// written as CSV or ST, so the two formats cannot drift apart.
struct PathRows {
  std::string_view type;
  std::vector<CamColumn> columns;
  std::vector<std::vector<double>> rows;
};

const std::vector<CamColumn> kPoseColumns{
    {"x_mm", "container position x, world frame from the path's start [mm]"},
    {"y_mm", "container position y [mm]"},
    {"theta_deg",
     "container heading about the vertical, world frame as x_mm and y_mm (the path's start heading "
     "at the start) [deg]"}};

std::vector<CamColumn> with_pose(std::vector<CamColumn> columns) {
  columns.insert(columns.end(), kPoseColumns.begin(), kPoseColumns.end());
  return columns;
}

PathRows time_rows(const CamTable& table, const PlanarPath& path) {
  const std::optional<double> table_deg = table_rotation_deg(path);
  const double length = path.length();
  PathRows out;
  out.type = table_deg ? kStTablePointType : kStPathPointType;
  out.columns = with_pose({{"t_s", "time since the start of the motion [s]"},
                           {"s_mm", "distance along the path [mm]"},
                           {"velocity_mm_s", "ds/dt [mm/s]"},
                           {"acceleration_mm_s2", "tangential acceleration d2s/dt2 [mm/s^2]"},
                           {"jerk_mm_s3", "tangential jerk d3s/dt3 [mm/s^3]"}});
  if (table_deg) out.columns.push_back({"table_deg", "the table's rotation [deg]"});
  for (const PathCamSample& r : cam_along_path(table.time, path)) {
    std::vector<double> row{r.t,
                            s_mm(r.s, length),
                            r.velocity * kMmPerM,
                            r.acceleration * kMmPerM,
                            r.jerk * kMmPerM,
                            pose_value(r.x * kMmPerM),
                            pose_value(r.y * kMmPerM),
                            pose_value(r.theta * kDegPerRad)};
    if (table_deg) row.push_back(r.s / length * *table_deg);
    out.rows.push_back(std::move(row));
  }
  return out;
}

PathRows master_rows(const CamTable& table, const PlanarPath& path) {
  PathRows out;
  if (table_rotation_deg(path)) {
    out.type = kStTableMasterPointType;
    out.columns = {{"master", "master position [master units]"},
                   {"table_deg", "the table's rotation [deg]"},
                   {"velocity_deg_per_unit", "d rotation / d master [deg/master unit]"},
                   {"acceleration_deg_per_unit2", "d2 rotation / d master2 [deg/master unit^2]"},
                   {"jerk_deg_per_unit3", "d3 rotation / d master3 [deg/master unit^3]"}};
    for (const MasterCamSample& r : table_rotation_rows(table.master, path)) {
      out.rows.push_back({r.master, r.position, r.velocity, r.acceleration, r.jerk});
    }
    return out;
  }
  const double length = path.length();
  out.type = kStPathMasterPointType;
  out.columns = with_pose({{"master", "master position [master units]"},
                           {"s_mm", "distance along the path [mm]"},
                           {"velocity_mm_per_unit", "ds / d master [mm/master unit]"},
                           {"acceleration_mm_per_unit2", "d2s / d master2 [mm/master unit^2]"},
                           {"jerk_mm_per_unit3", "d3s / d master3 [mm/master unit^3]"}});
  for (const MasterCamSample& r : table.master) {
    const PlanarKinematics k = path.at(r.position, 0.0, 0.0, 0.0);
    out.rows.push_back({r.master, s_mm(r.position, length), r.velocity * kMmPerM,
                        r.acceleration * kMmPerM, r.jerk * kMmPerM, pose_value(k.x * kMmPerM),
                        pose_value(k.y * kMmPerM),
                        // The world heading, as the time table's (theta counts from the start).
                        pose_value((path.start_heading() + k.theta) * kDegPerRad)});
  }
  return out;
}

PathRows rows_of(const CamTable& table, const PlanarPath& path) {
  return table.axis ? master_rows(table, path) : time_rows(table, path);
}

std::string csv_of(const PathRows& t) {
  std::string out;
  for (const CamColumn& c : t.columns) {
    if (!out.empty()) out += ',';
    out += c.name;
  }
  out += '\n';
  for (const std::vector<double>& row : t.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i > 0) out += ',';
      out += csv_number(row[i]);
    }
    out += '\n';
  }
  return out;
}

// The header line naming the path the law moves along.
std::string path_line(const PlanarPath& path) {
  const std::optional<double> table_deg = table_rotation_deg(path);
  std::string line = "   path: ";
  const char* arc = path.container_turns() ? "one arc (a rotary table), rotation "
                                           : "one arc (a curved track), angle ";
  line += table_deg ? arc + api::number_text(*table_deg) + " deg"
                    : "a path of " + std::to_string(path.elements().size()) +
                          " segments (lines and arcs)";
  line += ", length " + api::number_text(api::mm_of(path.length())) + " mm; the container " +
          (path.container_turns() ? "turns with the path" : "keeps its heading") + "\n";
  return line;
}

}  // namespace

std::string path_cam_csv(const CamTable& table, const PlanarPath& path) {
  return csv_of(rows_of(table, path));
}

std::string path_cam_file(const CamTable& table, const PlanarPath& path, const CamSource& source,
                          const CamTableSpec& spec) {
  const PathRows t = rows_of(table, path);
  if (spec.format == CamFileFormat::kCsv) return csv_of(t);
  // The slave of a table's master cam is the table's rotation; of any other path, s along it.
  CamSource along = source;
  const std::optional<double> table_deg = table_rotation_deg(path);
  along.slave_dwell =
      table_deg
          ? "0 deg before the start and at " + api::number_text(*table_deg) +
                " deg (the table's rotation) from the end on"
          : "s = 0 mm before the start and at s = " + api::number_text(api::mm_of(path.length())) +
                " mm (the path's end) from the end on";
  return st_declaration(cam_st_header(table, along, t.type, path_line(path)), t.type, t.columns,
                        t.rows, spec.st_name);
}

}  // namespace slosh::service
