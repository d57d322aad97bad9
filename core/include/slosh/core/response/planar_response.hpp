#pragma once
// Sloshing under planar and spatial motions (SPEC §14), in the world frame (x, y horizontal,
// z up), driven by a PlanarDrive (a law along a path, or a sampled trajectory):
//
// - the linear multi-mode model as isotropic 2-D oscillators, one per mode n,
//     r_n'' + 2 zeta w_n r_n' + w_n^2 (1 + a_z / g) r_n = -a_h   (r_n = (x_n, y_n), a_h = (a_x,
//     a_y)),
//   with the wall height eta(phi) = sum_n eta_gain_n (x_n cos phi + y_n sin phi), whose maximum
//   over the wall angle phi is |sum_n eta_gain_n r_n| in the direction of that vector;
// - the nonlinear fundamental-mode model of eq. 2.35 made planar: the mass of the thesis'
//   model moves on the paraboloid zbar = C |q|^2 / 2 (q = r_1 / R), so with
//   M(q) = I + C^2 q q^T,
//     M q'' + C^2 |q'|^2 q + 2 zeta w (M q') + w^2 (1 + a_z / g)(1 + alpha |q|^2) q + a_h / R = 0,
//   which on a straight line (q = (xbar, 0)) is eq. 2.35 term for term; eta = K |q| at the wall
//   in the direction of q;
// - for a container turning about its own axis, the forced-vortex rise of the free surface at
//   the wall, R^2 w_l^2 / (4 g), where w_l is the liquid's spin, which follows the container's
//   turning rate theta' through the Ekman layer on the bottom (spin-up time h / sqrt(nu Omega),
//   Greenspan and Howard 1963): w_l' = sqrt(nu Omega) / h (theta' - w_l), Omega = max(|theta'|,
//   |w_l|). The rise adds to the wave's height (it is the same around the wall).
//
// The stored responses of both models are integrated as the straight-line nonlinear model is
// (nonlinear_response.cpp): DOP853 in equal steps on every smooth piece of the drive (never
// across a piece boundary), steps of at most 1/steps_per_period of the fastest modelled period
// and, on an arc, of a turn of the heading (the world-frame acceleration turns with it);
// between steps the order-7 dense output, on which the maximum over the wall is located exactly
// on every step (the roots of its derivative). planar_linear_peaks() solves the linear model
// exactly piece by piece instead (planar_linear_exact.cpp). The liquid's spin depends on the
// turning alone and is integrated once per drive (planar_spin.hpp). docs/models.md derives the
// models and compares them with measurements.

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"

namespace slosh {

/// How the liquid's spin follows the container's turning.
enum class SpinLag {
  kEkman,  ///< spin-up through the bottom Ekman layer (default; see the file comment)
  kNone,   ///< the liquid does not spin: no vortex term
};

/// Options of the planar integration.
struct PlanarOptions {
  /// Largest step [s]. Default 50 ms (the period bound governs).
  double max_step{0.05};
  /// Minimum steps per period of the fastest modelled mode [-]. Default 40 (as the straight-line
  /// nonlinear model: the order-8 scheme's error is below 1e-6 of the peak).
  double steps_per_period{40.0};
  /// The liquid's spin model. Default kEkman.
  SpinLag spin{SpinLag::kEkman};
  /// Kinematic viscosity nu = mu / rho of the liquid [m^2/s] (the spin-up rate). Default
  /// 1.0e-6 (water at 20 degrees C); > 0.
  double kinematic_viscosity{1.0e-6};
};

/// A peak of the wall height maximised over the wall.
struct PlanarPeak {
  double value{};      ///< [m]
  double time{};       ///< [s]
  double direction{};  ///< wall angle where the wave peaks, world frame, from +x [rad]
};

struct PlanarPeaks {
  PlanarPeak motion;  ///< on [0, T]
  PlanarPeak rest;    ///< on (T, T + rest_time]
};

/// One stored step of a planar response: the wave vector E (its length the height, its
/// direction the peak's wall angle) and the liquid's spin over the step, as polynomials in
/// theta = (t - t0) / h.
struct PlanarStep {
  double t0{}, h{};
  std::array<double, 8> ex{}, ey{}, spin{};
};

/// A computed planar response (either model): peaks and the height at any time.
class PlanarResponse {
 public:
  /// Wall height maximised over the wall at t [m] (0 before the start, held after the end).
  [[nodiscard]] double eta(double t) const;
  /// The wall angle of the maximum at t [rad].
  [[nodiscard]] double direction(double t) const;
  /// The liquid's spin rate at t [rad/s].
  [[nodiscard]] double liquid_spin(double t) const;
  [[nodiscard]] const PlanarPeaks& peaks() const { return peaks_; }
  [[nodiscard]] std::size_t steps() const { return steps_.size(); }
  [[nodiscard]] double motion_time() const { return motion_time_; }

 protected:
  PlanarResponse() = default;
  friend struct PlanarBuilder;
  std::vector<PlanarStep> steps_;
  PlanarPeaks peaks_;
  double vortex_gain_{};  ///< R^2 / (4 g) [s^2 m]
  double motion_time_{};

 private:
  [[nodiscard]] const PlanarStep* step_at(double t, double& s) const;
};

/// The linear multi-mode model on the drive, integrated over [0, T + rest_time].
class PlanarLinearResponse : public PlanarResponse {
 public:
  PlanarLinearResponse(const SloshingModel& model, const PlanarDrive& drive, double rest_time,
                       const PlanarOptions& options = {});
};

/// The planar nonlinear fundamental-mode model on the drive, over [0, T + rest_time].
class PlanarNonlinearResponse : public PlanarResponse {
 public:
  PlanarNonlinearResponse(const SloshingModel& model, const PlanarDrive& drive, double rest_time,
                          const PlanarOptions& options = {});
};

/// The peaks of the planar linear model without storing the response, from the piecewise exact
/// solution (the forcing interpolated at degree 7 on sub-steps, the modes in closed form, the
/// height sampled at min(1 ms, fastest period / 64) and refined by Newton's method); they agree
/// with PlanarLinearResponse's to about 1e-8 of the peak. With vertical motion or a mode that is
/// not under-damped, PlanarLinearResponse's integration (its peaks exactly). The rest window
/// ends where the modes' energy bound proves its maximum found.
[[nodiscard]] PlanarPeaks planar_linear_peaks(const SloshingModel& model, const PlanarDrive& drive,
                                              double rest_time, const PlanarOptions& options = {});
/// The peaks of PlanarNonlinearResponse, equal to them bit for bit, without storing the response
/// (the rest window ends by the energy bound).
[[nodiscard]] PlanarPeaks planar_nonlinear_peaks(const SloshingModel& model,
                                                 const PlanarDrive& drive, double rest_time,
                                                 const PlanarOptions& options = {});

}  // namespace slosh
