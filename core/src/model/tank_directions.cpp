#include "slosh/core/model/tank_directions.hpp"

#include <cmath>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh {

RectangularModelOptions rectangular_model_options(const ModelOptions& options) {
  RectangularModelOptions r;
  r.modes = options.modes;
  if (options.damping == DampingCorrelation::kExplicit) r.explicit_zeta = options.explicit_zeta;
  r.omega_scale = options.omega_scale;
  r.height_gain = options.height_gain;
  return r;
}

RectangularModel rectangular_model_of(const Format& format, const ModelOptions& options) {
  const RectangularTank& tank = *format.container.rectangular;
  RectangularModel m = make_rectangular_model(tank, format.fill_height, format.fluid,
                                              rectangular_model_options(options));
  // A calibration of both directions gives the width's modes their own scale and damping.
  if (options.width_omega_scale || options.width_zeta) {
    RectangularModelOptions width = rectangular_model_options(options);
    if (options.width_omega_scale) width.omega_scale = *options.width_omega_scale;
    if (options.width_zeta) width.explicit_zeta = *options.width_zeta;
    m.along_width = make_rectangular_direction_model(tank, format.fill_height, format.fluid,
                                                     TankAxis::kWidth, width);
  }
  return m;
}

SloshingModel with_height_factor(const SloshingModel& model, double factor) {
  SloshingModel m = model;
  for (double& g : m.eta_gain) g *= factor;
  m.K *= factor;
  return m;
}

namespace {

DrivenDirection driven(const SloshingModel& direction, TankAxis axis, double component) {
  DrivenDirection d{with_height_factor(direction, std::abs(component)), axis, component};
  const bool nonlinear_holds =
      !below_limit(direction.fill_height / direction.radius, kRectangularMinDepthRatio);
  d.model.alpha = nonlinear_holds ? direction.alpha * component * component : 0.0;
  return d;
}

double static_height(const DrivenDirection& d) {
  return d.model.eta_gain.front() / (d.model.omega1() * d.model.omega1());
}

}  // namespace

std::vector<DrivenDirection> driven_directions(const RectangularModel& model) {
  const AxisComponents c = axis_components(model.orientation_deg);
  std::vector<DrivenDirection> out;
  if (c.along_length != 0.0) {
    out.push_back(driven(model.along_length, TankAxis::kLength, c.along_length));
  }
  if (c.along_width != 0.0) {
    out.push_back(driven(model.along_width, TankAxis::kWidth, c.along_width));
  }
  if (out.size() == 2 && static_height(out[1]) > static_height(out[0])) std::swap(out[0], out[1]);
  return out;
}

}  // namespace slosh
