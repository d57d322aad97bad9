#pragma once
// Sloshing responses of a rectangular tank (SPEC §15) moved along a straight path, its axes
// turned by orientation_deg from the motion: the acceleration a(t) along the motion drives the
// modes along L with a cos(phi) and those along W with a sin(phi); each direction is the exact
// response of its own model (LinearResponse, NonlinearResponse), and the wall height reported is
// the highest over the tank's walls and corners (docs/models.md, "Rectangular containers").

#include <optional>
#include <string>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// Components of a unit vector along the motion in the tank's axes: {cos phi, sin phi}, exact
/// (0, ±1) at multiples of 90 degrees so that a tank square to the motion leaves the other
/// direction exactly at rest.
struct AxisComponents {
  double along_length{};  ///< cos(phi) [-]
  double along_width{};   ///< sin(phi) [-]
};
[[nodiscard]] AxisComponents axis_components(double orientation_deg);

/// Peaks of a rectangular tank's response.
struct RectangularPeaks {
  /// Highest wall height over the walls and corners: max over t of |eta_L(t)| + |eta_W(t)|
  /// (at the corner where both directions' waves are crests, or both troughs) [m].
  SloshPeaks highest;
  SloshPeaks along_length;  ///< wall height of the L modes alone (the walls normal to L) [m]
  SloshPeaks along_width;   ///< wall height of the W modes alone (the walls normal to W) [m]
};

/// The exact linear response of both directions (each a LinearResponse of its components'
/// forcing, closed form on every law piece).
class RectangularLinearResponse {
 public:
  RectangularLinearResponse(const RectangularModel& model, const MotionLaw& law, double rest_time);

  /// Signed wall height at the wall x = +L/2 from the L modes [m] (0 when not excited).
  [[nodiscard]] double eta_length(double t) const;
  /// Signed wall height at the wall y = +W/2 from the W modes [m].
  [[nodiscard]] double eta_width(double t) const;
  /// Highest wall height over the corners at t: |eta_length| + |eta_width| [m].
  [[nodiscard]] double eta_highest(double t) const {
    return std::abs(eta_length(t)) + std::abs(eta_width(t));
  }
  /// Peaks located on the continuous response: each direction's by LinearResponse::peaks(); the
  /// corners' (when both directions move) sampled at <= 1 ms and <= 1/64 of the fastest period
  /// of either direction, every candidate refined by golden section to 1e-10 s.
  [[nodiscard]] RectangularPeaks peaks() const;

 private:
  std::optional<LinearResponse> length_;
  std::optional<LinearResponse> width_;
  double motion_time_{};
  double end_time_{};
  double peak_step_{};
};

/// Where the rectangular nonlinear model holds (rectangular_nonlinear_validity, docs/models.md):
/// the Moiseev-type asymptotics of the dominant mode need a finite depth, h / side >=
/// kRectangularMinDepthRatio for every excited direction (Faltinsen et al. 2000; shallower fill
/// needs the adaptive and small-depth modal systems of Faltinsen & Timokha, 2001 and 2002), and
/// a small wave: the third-order theory is an expansion in the steepness k_1 A of the wall
/// amplitude A, trusted here up to kRectangularMaxSteepness, about half the steepest standing
/// wave (Penney & Price 1952: crest height H / lambda = 0.218, i.e. k A = 0.68).
inline constexpr double kRectangularMinDepthRatio{0.24};
inline constexpr double kRectangularMaxSteepness{0.3};

/// Peaks of the rectangular nonlinear model, or of the linear one with the reason.
struct RectangularNonlinearPeaks {
  RectangularPeaks peaks;
  /// True when the peaks are the nonlinear model's; false when the format or the response lies
  /// outside its range and the peaks are the linear model's.
  bool nonlinear{true};
  /// Empty, or why the linear model answers (names the direction, the quantity, its value and
  /// the range).
  std::string warning;
};

/// Each excited direction by RectangularNonlinearDirection (the dominant mode's third-order
/// oscillator with the direction's forcing component, the second mode it drives, the higher
/// modes linear); the corners' peak on the sum of the continuous responses. Outside the range of
/// rectangular_nonlinear_validity (checked on the format first, then on the directions' peak
/// wall heights) the linear peaks are returned with its reason, never an extrapolation.
[[nodiscard]] RectangularNonlinearPeaks rectangular_nonlinear_peaks(
    const RectangularModel& model, const MotionLaw& law, double rest_time,
    const NonlinearOptions& options = {});

}  // namespace slosh
