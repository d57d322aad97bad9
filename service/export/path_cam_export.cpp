#include "export/path_cam_export.hpp"

#include <numbers>
#include <optional>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/core/law/path_cam_table.hpp"

namespace slosh::service {

namespace {

constexpr double kMmPerM = 1e3;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A distance along the path in mm: the path's end as the request gave it (api::mm_of).
double s_mm(double s, double length) {
  return s == length ? api::mm_of(length) : s * kMmPerM;
}

std::string line_of(std::initializer_list<double> values) {
  std::string out;
  for (const double v : values) {
    if (!out.empty()) out += ',';
    out += csv_number(v);
  }
  out += '\n';
  return out;
}

std::string time_csv(const CamTable& table, const PlanarPath& path) {
  const std::optional<double> table_deg = table_rotation_deg(path);
  const double length = path.length();
  std::string out = "t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg";
  out += table_deg ? ",table_deg\n" : "\n";
  for (const PathCamSample& r : cam_along_path(table.time, path)) {
    std::string row =
        line_of({r.t, s_mm(r.s, length), r.velocity * kMmPerM, r.acceleration * kMmPerM,
                 r.jerk * kMmPerM, r.x * kMmPerM, r.y * kMmPerM, r.theta * kDegPerRad});
    if (table_deg) {
      row.back() = ',';
      row += csv_number(r.s / length * *table_deg) + '\n';
    }
    out += row;
  }
  return out;
}

std::string master_csv(const CamTable& table, const PlanarPath& path) {
  if (table_rotation_deg(path)) {
    std::string out =
        "master,table_deg,velocity_deg_per_unit,acceleration_deg_per_unit2,jerk_deg_per_unit3\n";
    for (const MasterCamSample& r : table_rotation_rows(table.master, path)) {
      out += line_of({r.master, r.position, r.velocity, r.acceleration, r.jerk});
    }
    return out;
  }
  const double length = path.length();
  std::string out =
      "master,s_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3,x_mm,y_mm,"
      "theta_deg\n";
  for (const MasterCamSample& r : table.master) {
    const PlanarKinematics k = path.at(r.position, 0.0, 0.0, 0.0);
    out +=
        line_of({r.master, s_mm(r.position, length), r.velocity * kMmPerM, r.acceleration * kMmPerM,
                 r.jerk * kMmPerM, k.x * kMmPerM, k.y * kMmPerM, k.theta * kDegPerRad});
  }
  return out;
}

}  // namespace

std::string path_cam_csv(const CamTable& table, const PlanarPath& path) {
  return table.axis ? master_csv(table, path) : time_csv(table, path);
}

void check_path_cam_format(CamFileFormat format, const std::string& format_field) {
  if (format == CamFileFormat::kCsv) return;
  throw api::ApiError(api::ErrorCode::kInvalidValue, format_field,
                      format_field +
                          " st: the structured-text cam table of a motion along an arc or a path "
                          "is not available (its type holds the straight-line columns); use " +
                          format_field + " csv");
}

}  // namespace slosh::service
