#pragma once
// A production format (recipe) in SI units.

#include <optional>

#include "slosh/core/fluid.hpp"

namespace slosh {

/// Cylindrical container, translated along x.
struct Container {
  double radius{0.0485};         ///< R [m]
  std::optional<double> height;  ///< total inner height [m]; enables the free-board warning
};

/// One production format: container, liquid and the rest-to-rest move.
struct Format {
  Container container;
  double fill_height{0.082};  ///< h [m]
  Fluid fluid{"water", 998.2, 1.0016e-3, ""};
  double stroke{0.8};       ///< s [m]
  double motion_time{1.0};  ///< T [s]
};

}  // namespace slosh
