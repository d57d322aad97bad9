#pragma once
// A rectangular tank (SPEC §15) carried along a planar or spatial motion (SPEC §14: an arc, a
// path of lines and arcs, a sampled trajectory), docs/models.md "A rectangular tank along a
// path". The tank's modes live in its own frame: its L axis points at the world angle
//   Psi(t) = frame_angle + theta(t)
// (theta the drive's heading: psi - psi_0 on a path whose container turns, 0 on one whose
// container keeps its orientation, the samples' theta on a trajectory), and each direction's
// modes are driven by the tank-frame component of the centre's horizontal acceleration,
//   a_L = a_x cos Psi + a_y sin Psi,   a_W = -a_x sin Psi + a_y cos Psi,
// with the vertical acceleration scaling every stiffness by (1 + a_z / g) as in the planar
// cylinder models. The linear model is every mode of both directions as today on the line; the
// nonlinear one is each direction's model of RectangularNonlinearDirection (the dominant mode's
// third-order oscillator, the second mode it drives, the higher modes linear), all in one state.
// A turning tank adds the forced vortex's rise at the corners, w_l^2 (L^2 + W^2) / (12 g),
// relative to the mean level, w_l the liquid's spin lagging the tank's turning as the cylinder's
// (SpinTrack, planar_response.hpp). The yaw-excited modes odd in both x and y are left out.
//
// Integration as the planar models: DOP853 in equal steps on every smooth piece of the drive
// (never across a piece), at most 1/steps_per_period of the fastest modelled period (the
// second modes included); the dense output is kept and the peaks are located on it as the
// rectangular line responses locate theirs (samples at <= 1 ms and <= 1/64 of the fastest
// period, golden-section refinement, peak_finder.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/planar_response.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// Peaks of a rectangular tank along a motion.
struct RectangularPlanarPeaks {
  /// The highest corner (or wall) over the tank, with the liquid's spin rise; `direction` is the
  /// world angle from the tank's centre to that corner (to the wall's middle when one direction
  /// is at rest) [rad].
  PlanarPeaks highest;
  SloshPeaks along_length;  ///< the walls normal to L alone (no spin rise) [m]
  SloshPeaks along_width;   ///< the walls normal to W alone [m]
};

/// Which model a RectangularPlanarResponse integrates.
enum class RectangularPlanarModel {
  kLinear,     ///< every mode of both directions linear
  kNonlinear,  ///< each direction as RectangularNonlinearDirection
};

/// The response over [0, T + rest_time], stored (the dense output of every step).
class RectangularPlanarResponse {
 public:
  /// `frame_angle`: world angle of the tank's L axis when the drive's heading is 0 [rad].
  RectangularPlanarResponse(const RectangularModel& model, const PlanarDrive& drive,
                            double frame_angle, double rest_time, RectangularPlanarModel which,
                            const PlanarOptions& options = {});

  /// Signed antisymmetric wall height at the wall x = +L/2 (tank frame) [m].
  [[nodiscard]] double eta_length(double t) const { return value(t, 0); }
  /// Signed antisymmetric wall height at y = +W/2 [m].
  [[nodiscard]] double eta_width(double t) const { return value(t, 2); }
  /// The even (second) modes' rise, alike at both walls of each direction [m] (0 when linear).
  [[nodiscard]] double eta_even(double t) const { return value(t, 1) + value(t, 3); }
  /// The forced vortex's rise at the corners [m].
  [[nodiscard]] double spin_rise(double t) const;
  /// The highest corner at t: |eta_length| + |eta_width| + |eta_even| + spin_rise [m].
  [[nodiscard]] double eta_highest(double t) const;
  /// The angle of the highest corner in the tank's frame at t, from its L axis [rad] (of the
  /// wall's middle when one direction is at rest; 0 when both are).
  [[nodiscard]] double corner_angle(double t) const;
  /// The world angle of the highest corner at t for the tank's L axis at `heading` [rad], in
  /// (-pi, pi] as the cylinder's wall angles (a tank turned several times spells one direction
  /// once).
  [[nodiscard]] double world_corner_angle(double heading, double t) const {
    const double a = std::remainder(heading + corner_angle(t), 2.0 * std::numbers::pi);
    return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
  }
  [[nodiscard]] const RectangularPlanarPeaks& peaks() const { return peaks_; }
  [[nodiscard]] double motion_time() const { return motion_time_; }
  [[nodiscard]] std::size_t steps() const { return steps_.size(); }

  /// One stored step: the signals (odd L, even L, odd W, even W) and the liquid's spin as
  /// polynomials in the step fraction.
  struct Step {
    double t0{}, h{};
    std::array<std::array<double, 8>, 4> eta{};
    std::array<double, 8> spin{};
  };

 private:
  [[nodiscard]] double value(double t, std::size_t signal) const;
  [[nodiscard]] const Step* step_at(double t, double& s) const;

  std::vector<Step> steps_;
  RectangularPlanarPeaks peaks_;
  double spin_gain_{};  ///< (L^2 + W^2) / (12 g) [s^2 m]
  double half_length_{}, half_width_{};
  double motion_time_{};
};

/// The linear model's peaks.
[[nodiscard]] RectangularPlanarPeaks rectangular_planar_linear_peaks(
    const RectangularModel& model, const PlanarDrive& drive, double frame_angle, double rest_time,
    const PlanarOptions& options = {});

/// Peaks of the nonlinear model, or of the linear one with the reason.
struct RectangularPlanarNonlinearPeaks {
  RectangularPlanarPeaks peaks;
  /// True when the peaks are the nonlinear model's; false when the format or the response lies
  /// outside its range (rectangular_nonlinear_validity, checked on the directions the motion
  /// excites) and the peaks are the linear model's.
  bool nonlinear{true};
  std::string warning;  ///< empty, or why the linear model answers
};
[[nodiscard]] RectangularPlanarNonlinearPeaks rectangular_planar_nonlinear_peaks(
    const RectangularModel& model, const PlanarDrive& drive, double frame_angle, double rest_time,
    const PlanarOptions& options = {});

}  // namespace slosh
