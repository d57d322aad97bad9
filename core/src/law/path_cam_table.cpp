#include "slosh/core/law/path_cam_table.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "slosh/core/constants.hpp"

namespace slosh {

std::vector<PathCamSample> cam_along_path(const std::vector<CamSample>& cam,
                                          const PlanarPath& path) {
  std::vector<PathCamSample> out;
  out.reserve(cam.size());
  for (const CamSample& c : cam) {
    const PlanarKinematics k = path.at(c.position, c.velocity, c.acceleration, c.jerk);
    // The world heading, in the frame of x and y (theta counts from the path's start heading).
    out.push_back({c.t, c.position, c.velocity, c.acceleration, c.jerk, k.x, k.y,
                   path.start_heading() + k.theta});
  }
  return out;
}

std::optional<double> table_rotation_deg(const PlanarPath& path) {
  const std::vector<PathElement>& e = path.elements();
  if (e.size() != 1 || e.front().kind != PathElement::Kind::kArc) return std::nullopt;
  // The degrees the angle was given in: the shortest decimal whose conversion deg * pi / 180 (the
  // request's) gives the radians back, so -120 deg ends the table at -120, not at
  // -119.99999999999999 (radians * 180 / pi).
  const double radians = e.front().angle;
  const double degrees = radians / kRadPerDeg;
  for (int digits = 1; digits <= 17; ++digits) {
    std::array<char, 40> text{};
    std::snprintf(text.data(), text.size(), "%.*g", digits, degrees);
    const double candidate = std::strtod(text.data(), nullptr);
    if (candidate * kRadPerDeg == radians) return candidate;
  }
  return degrees;
}

std::vector<MasterCamSample> table_rotation_rows(const std::vector<MasterCamSample>& rows,
                                                 const PlanarPath& path) {
  const std::optional<double> angle = table_rotation_deg(path);
  if (!angle) throw std::invalid_argument("a table rotation cam needs a path of one arc");
  const double length = path.length();
  std::vector<MasterCamSample> out = rows;
  // value / length * angle: at the end, position == length exactly, the row holds the angle
  // exactly (a precomputed factor angle / length would round it).
  for (MasterCamSample& r : out) {
    r.position = r.position / length * *angle;
    r.velocity = r.velocity / length * *angle;
    r.acceleration = r.acceleration / length * *angle;
    r.jerk = r.jerk / length * *angle;
  }
  return out;
}

}  // namespace slosh
