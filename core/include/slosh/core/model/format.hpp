#pragma once
// A production format (recipe) in SI units.

#include <optional>

#include "slosh/core/model/fluid.hpp"
#include "slosh/core/model/rectangular_tank.hpp"

namespace slosh {

/// The container, translated along x: a cylinder of radius R, or a rectangular tank (SPEC §15).
struct Container {
  double radius{0.0485};         ///< R [m] of the cylinder (unused when `rectangular` is set)
  std::optional<double> height;  ///< total inner height [m]; enables the free-board warning
  /// The rectangular tank's sides and orientation; nullopt (default): the cylinder.
  std::optional<RectangularTank> rectangular;
};

/// One production format: container, liquid and the rest-to-rest move.
struct Format {
  Container container;
  double fill_height{0.082};  ///< h [m]
  Fluid fluid{"water", 998.2, 1.0016e-3, ""};
  double stroke{0.8};       ///< s [m]
  double motion_time{1.0};  ///< T [s]
};

/// The thesis bench format (thesis ch. 5, SPEC §2 reference values): R = 48.5 mm, h = 82 mm,
/// water with rho = 1000 kg/m^3 and mu = 1.0e-3 Pa·s, s = 800 mm, T = 1 s.
[[nodiscard]] inline Format thesis_format() {
  Format f;
  f.container.radius = 0.0485;
  f.fill_height = 0.082;
  f.fluid = Fluid{"thesis_water", 1000.0, 1.0e-3, "thesis sec. 2 (rounded water properties)"};
  f.stroke = 0.8;
  f.motion_time = 1.0;
  return f;
}

}  // namespace slosh
