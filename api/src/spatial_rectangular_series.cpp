#include "slosh/api/spatial_rectangular_series.hpp"

#include <array>
#include <optional>

#include "slosh/api/spatial_series.hpp"
#include "slosh/core/response/rectangular_planar.hpp"

namespace slosh::api {

nlohmann::json rectangular_spatial_series_json(const RectangularModel& model,
                                               const PlanarDrive& drive, double frame_angle,
                                               const MotionLaw* law, double rest_time, double dt,
                                               bool nonlinear_holds, double theta_origin) {
  const RectangularPlanarResponse linear(model, drive, frame_angle, rest_time,
                                         RectangularPlanarModel::kLinear);
  std::optional<RectangularPlanarResponse> own;
  if (nonlinear_holds) {
    own.emplace(model, drive, frame_angle, rest_time, RectangularPlanarModel::kNonlinear);
  }
  const RectangularPlanarResponse& nonlinear = own ? *own : linear;
  return spatial_series_columns(
      drive, law, rest_time, dt,
      [&](double t, const PlanarKinematics& p) {
        const double heading = frame_angle + p.theta;
        return std::array<double, 4>{linear.eta_highest(t), nonlinear.eta_highest(t),
                                     linear.world_corner_angle(heading, t),
                                     nonlinear.world_corner_angle(heading, t)};
      },
      theta_origin);
}

}  // namespace slosh::api
