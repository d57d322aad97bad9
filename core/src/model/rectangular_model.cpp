#include "slosh/core/model/rectangular_model.hpp"

#include <cmath>
#include <numbers>

namespace slosh {

double rectangular_wavenumber(double side, int n) {
  return (2.0 * n - 1.0) * std::numbers::pi / side;
}

double rectangular_frequency(double side, double fill_height, int n) {
  const double k = rectangular_wavenumber(side, n);
  return std::sqrt(kGravity * k * std::tanh(k * fill_height));
}

double rectangular_sloshing_mass(double fluid_mass, double side, double fill_height, int n) {
  const double odd = 2.0 * n - 1.0;
  const double k = rectangular_wavenumber(side, n);
  const double pi3 = std::numbers::pi * std::numbers::pi * std::numbers::pi;
  return fluid_mass * 8.0 * std::tanh(k * fill_height) * side /
         (odd * odd * odd * pi3 * fill_height);
}

double rectangular_wall_gain(double side, double fill_height, int n) {
  const double k = rectangular_wavenumber(side, n);
  return 4.0 * std::tanh(k * fill_height) / ((2.0 * n - 1.0) * std::numbers::pi);
}

double rectangular_damping_ratio(double side, double across, double fill_height,
                                 double kinematic_viscosity, int n) {
  const double k = rectangular_wavenumber(side, n);
  const double w = rectangular_frequency(side, fill_height, n);
  // Bottom and end walls together: k (1 - 2h/side) / sinh(2kh) + 1/side (docs/models.md); in
  // deep fill the bracket's first term vanishes with 1/sinh, in shallow fill it tends to
  // 1/(2h) - 1/side.
  const double bracket = k * (1.0 - 2.0 * fill_height / side) / std::sinh(2.0 * k * fill_height) +
                         1.0 / side + 1.0 / across;
  return std::sqrt(kinematic_viscosity / (2.0 * w)) * bracket;
}

double rectangular_frequency_correction(double side, double fill_height) {
  const double t = std::tanh(rectangular_wavenumber(side, 1) * fill_height);
  const double t2 = t * t;
  return (9.0 / (t2 * t2) - 12.0 / t2 - 3.0 - 2.0 * t2) / 64.0;
}

SloshingModel make_rectangular_direction_model(const RectangularTank& tank, double fill_height,
                                               const Fluid& fluid, TankAxis axis,
                                               const RectangularModelOptions& options) {
  const double side = axis == TankAxis::kLength ? tank.length : tank.width;
  const double across = axis == TankAxis::kLength ? tank.width : tank.length;
  const double h = fill_height;
  SloshingModel m;
  m.radius = side;
  m.fill_height = h;
  m.density = fluid.density;
  m.fluid_mass = fluid.density * tank.length * tank.width * h;
  m.zeta = options.explicit_zeta.has_value()
               ? *options.explicit_zeta
               : rectangular_damping_ratio(side, across, h, fluid.kinematic_viscosity(), 1);
  for (int n = 1; n <= options.modes; ++n) {
    m.omega.push_back(rectangular_frequency(side, h, n) * options.omega_scale);
    m.mass.push_back(rectangular_sloshing_mass(m.fluid_mass, side, h, n));
    m.eta_gain.push_back(rectangular_wall_gain(side, h, n) * options.height_gain);
  }
  // Dominant-mode nonlinear oscillator in xbar = x_1 / side: with C = 0 the equation of
  // SloshingModel reads xbar'' + 2 zeta w xbar' + w^2 xbar (1 + alpha xbar^2) + a / side = 0,
  // whose backbone w (1 + 3 alpha A^2 / 8) equals the third-order standing-wave frequency
  // w (1 + c (k_1 G_1 side A)^2) when alpha = 8/3 c pi^2 G_1^2 (k_1 side = pi).
  const double g1 = rectangular_wall_gain(side, h, 1);
  m.C = 0.0;
  m.alpha = 8.0 / 3.0 * rectangular_frequency_correction(side, h) * std::numbers::pi *
            std::numbers::pi * g1 * g1;
  m.K = g1 * side * options.height_gain;
  return m;
}

RectangularModel make_rectangular_model(const RectangularTank& tank, double fill_height,
                                        const Fluid& fluid,
                                        const RectangularModelOptions& options) {
  return {make_rectangular_direction_model(tank, fill_height, fluid, TankAxis::kLength, options),
          make_rectangular_direction_model(tank, fill_height, fluid, TankAxis::kWidth, options),
          tank.orientation_deg};
}

}  // namespace slosh
