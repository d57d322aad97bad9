#include "slosh/api/spatial_series.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace slosh::api {

namespace {

struct Columns {
  std::vector<double> t, x, y, theta, a_h, eta_lin, eta_non, dir_lin, dir_non, s, v, a;
};

}  // namespace

nlohmann::json spatial_series_columns(const PlanarDrive& drive, const MotionLaw* law,
                                      double rest_time, double dt,
                                      const SpatialSeriesSample& sample, double theta_origin) {
  const double span = drive.duration() + rest_time;
  // Samples at 0, dt, ..., both ends included (as the straight line's series).
  const auto n = static_cast<std::size_t>(std::floor(span / dt + 1e-9)) + 1;
  Columns c;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    const PlanarKinematics p = drive.kinematics(t);
    const std::array<double, 4> w = sample(t, p);
    c.t.push_back(t);
    c.x.push_back(p.x * 1e3);
    c.y.push_back(p.y * 1e3);
    c.theta.push_back((theta_origin + p.theta) * kDegPerRad);
    c.a_h.push_back(std::hypot(p.ax, p.ay));
    c.eta_lin.push_back(w[0] * 1e3);
    c.eta_non.push_back(w[1] * 1e3);
    c.dir_lin.push_back(w[2] * kDegPerRad);
    c.dir_non.push_back(w[3] * kDegPerRad);
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

nlohmann::json spatial_series_json(const SloshingModel& model, const PlanarDrive& drive,
                                   const MotionLaw* law, double rest_time, double dt,
                                   double theta_origin) {
  const PlanarLinearResponse linear(model, drive, rest_time);
  const PlanarNonlinearResponse nonlinear(model, drive, rest_time);
  return spatial_series_columns(
      drive, law, rest_time, dt,
      [&](double t, const PlanarKinematics&) {
        return std::array<double, 4>{linear.eta(t), nonlinear.eta(t), linear.direction(t),
                                     nonlinear.direction(t)};
      },
      theta_origin);
}

}  // namespace slosh::api
