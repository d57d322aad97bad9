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

/// The largest |theta''| of the drive [rad/s^2]. On a turning arc theta'' = kappa s'', which
/// peaks inside a piece of a smooth law (poly5's at 0.21 and 0.79 of the motion, where its one
/// piece's middle has none), so each piece is sampled and its largest sample refined by golden
/// section. A drive of many pieces (a sampled trajectory, a law along thousands of arcs) has
/// pieces on which theta'' is linear (the spline's, the 7-segment law's s''): their ends and
/// middle are sampled only.
double largest_yaw_acceleration(const PlanarDrive& drive) {
  constexpr std::size_t kManyPieces{2000};
  constexpr int kSamples{32}, kGoldenSteps{40};
  const bool few = drive.pieces().size() <= kManyPieces;
  double yaw = 0.0;
  for (const DrivePiece& p : drive.pieces()) {
    const double span = p.t_end - p.t_begin;
    if (!(span > 0.0)) continue;
    auto at = [&](double u) { return std::abs(drive.kinematics(p.t_begin + u * span).theta_ddot); };
    for (const double u : {1e-9, 0.5, 1.0 - 1e-9}) yaw = std::max(yaw, at(u));
    if (!few) continue;
    int best = 1;
    double best_value = -1.0;
    for (int i = 1; i < kSamples; ++i) {
      const double v = at(static_cast<double>(i) / kSamples);
      if (v > best_value) {
        best_value = v;
        best = i;
      }
    }
    double a = static_cast<double>(best - 1) / kSamples,
           b = static_cast<double>(best + 1) / kSamples;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int k = 0; k < kGoldenSteps; ++k) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      if (at(c) >= at(d)) {
        b = d;
      } else {
        a = c;
      }
    }
    yaw = std::max({yaw, best_value, at(0.5 * (a + b))});
  }
  return yaw;
}

}  // namespace

std::string yaw_mode_warning(const RectangularTank& tank, double fill_height,
                             const PlanarDrive& drive, double horizontal_peak) {
  const double yaw = largest_yaw_acceleration(drive);
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
