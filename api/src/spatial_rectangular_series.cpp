#include "slosh/api/spatial_rectangular_series.hpp"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <vector>

#include "slosh/core/response/rectangular_planar.hpp"

namespace slosh::api {

namespace {

constexpr double kDegPerRad{180.0 / std::numbers::pi};

struct Columns {
  std::vector<double> t, x, y, theta, a_h, eta_lin, eta_non, dir_lin, dir_non, s, v, a;
};

}  // namespace

nlohmann::json rectangular_spatial_series_json(const RectangularModel& model,
                                               const PlanarDrive& drive, double frame_angle,
                                               const MotionLaw* law, double rest_time, double dt,
                                               bool nonlinear_holds) {
  const double span = drive.duration() + rest_time;
  // Samples at 0, dt, ..., both ends included (as the straight line's series).
  const auto n = static_cast<std::size_t>(std::floor(span / dt + 1e-9)) + 1;
  const RectangularPlanarResponse linear(model, drive, frame_angle, rest_time,
                                         RectangularPlanarModel::kLinear);
  std::optional<RectangularPlanarResponse> own;
  if (nonlinear_holds) {
    own.emplace(model, drive, frame_angle, rest_time, RectangularPlanarModel::kNonlinear);
  }
  const RectangularPlanarResponse& nonlinear = own ? *own : linear;
  Columns c;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    const PlanarKinematics p = drive.kinematics(t);
    const double heading = frame_angle + p.theta;
    c.t.push_back(t);
    c.x.push_back(p.x * 1e3);
    c.y.push_back(p.y * 1e3);
    c.theta.push_back(p.theta * kDegPerRad);
    c.a_h.push_back(std::hypot(p.ax, p.ay));
    c.eta_lin.push_back(linear.eta_highest(t) * 1e3);
    c.eta_non.push_back(nonlinear.eta_highest(t) * 1e3);
    c.dir_lin.push_back((heading + linear.corner_angle(t)) * kDegPerRad);
    c.dir_non.push_back((heading + nonlinear.corner_angle(t)) * kDegPerRad);
    if (law != nullptr) {
      const KinematicState s = law->at(t);
      c.s.push_back(s.position);
      c.v.push_back(s.velocity);
      c.a.push_back(s.acceleration);
    }
  }
  nlohmann::json out{{"t_s", c.t},
                     {"x_mm", c.x},
                     {"y_mm", c.y},
                     {"theta_deg", c.theta},
                     {"a_h", c.a_h},
                     {"eta_linear_mm", c.eta_lin},
                     {"eta_nonlinear_mm", c.eta_non},
                     {"direction_linear_deg", c.dir_lin},
                     {"direction_nonlinear_deg", c.dir_non}};
  nlohmann::json units{{"t_s", "s"},
                       {"x_mm", "mm"},
                       {"y_mm", "mm"},
                       {"theta_deg", "deg"},
                       {"a_h", "m/s^2"},
                       {"eta_linear_mm", "mm"},
                       {"eta_nonlinear_mm", "mm"},
                       {"direction_linear_deg", "deg"},
                       {"direction_nonlinear_deg", "deg"}};
  if (law != nullptr) {
    out["s"] = c.s;
    out["v"] = c.v;
    out["a"] = c.a;
    units["s"] = "m";
    units["v"] = "m/s";
    units["a"] = "m/s^2";
  }
  out["units"] = units;
  return out;
}

}  // namespace slosh::api
