#include "slosh/core/response/rectangular_yaw.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "slosh/core/constants.hpp"

namespace slosh {

namespace {

/// Share of the yaw modes' forcing (the yaw acceleration at the corners) in the peak horizontal
/// acceleration above which a tank's prediction is called a lower bound [-]. On a table of
/// radius R the share is about the half-diagonal over R (0.24 for the 120 x 80 mm cup on a
/// 300 mm table), which docs/models.md counts as small; a tank turned in place has no
/// horizontal acceleration at all.
constexpr double kYawShare{0.5};

std::string three_digits(double v) {
  std::array<char, 32> b{};
  std::snprintf(b.data(), b.size(), "%.3g", v);
  return b.data();
}

}  // namespace

std::string yaw_mode_warning(const RectangularTank& tank, double fill_height,
                             const PlanarDrive& drive, double horizontal_peak) {
  double yaw = 0.0;
  for (const DrivePiece& p : drive.pieces()) {
    const double span = p.t_end - p.t_begin;
    if (!(span > 0.0)) continue;
    for (const double u : {1e-9, 0.5, 1.0 - 1e-9}) {
      yaw = std::max(yaw, std::abs(drive.kinematics(p.t_begin + u * span).theta_ddot));
    }
  }
  const double half_diagonal = 0.5 * std::hypot(tank.length, tank.width);
  const double corner = yaw * half_diagonal;
  if (!(corner > kYawShare * horizontal_peak) || !(yaw > 0.0)) return {};
  const double k = std::numbers::pi * std::hypot(1.0 / tank.length, 1.0 / tank.width);
  const double f11 =
      std::sqrt(kGravity * k * std::tanh(k * fill_height)) / (2.0 * std::numbers::pi);
  return "yaw modes not modelled: the tank turns with an angular acceleration up to " +
         three_digits(yaw) + " rad/s^2 (" + three_digits(corner) +
         " m/s^2 at its corners, against a peak horizontal acceleration of " +
         three_digits(horizontal_peak) +
         " m/s^2), which drives the modes odd in both directions (the lowest at " +
         three_digits(f11) + " Hz) that the model leaves out: the prediction is a lower bound";
}

}  // namespace slosh
