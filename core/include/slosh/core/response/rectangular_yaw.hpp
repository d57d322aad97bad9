#pragma once
// The limit of a rectangular tank's models along a turning motion (docs/models.md "A rectangular
// tank along a path"): the tank's yaw acceleration drives the modes odd in both directions, which
// the models leave out, so where it is large against the horizontal acceleration the predicted
// heights are a lower bound.

#include <string>

#include "slosh/core/model/rectangular_tank.hpp"
#include "slosh/core/motion/planar_drive.hpp"

namespace slosh {

/// The warning of a tank (`fill_height` [m]) whose yaw acceleration along `drive` drives the
/// modes the models leave out: its largest |theta''| times the half diagonal (the corners'
/// tangential acceleration) above half the peak horizontal acceleration `horizontal_peak`
/// [m/s^2]; empty when it is not.
[[nodiscard]] std::string yaw_mode_warning(const RectangularTank& tank, double fill_height,
                                           const PlanarDrive& drive, double horizontal_peak);

}  // namespace slosh
