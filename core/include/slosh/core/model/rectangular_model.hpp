#pragma once
// Equivalent mechanical models of sloshing in an open rectangular tank (SPEC §15): each horizontal
// direction of the tank on its own, as linear potential-flow theory has it (the modes along the
// length and along the width do not couple), derivations and sources in docs/models.md
// ("Rectangular containers").

#include <optional>

#include "slosh/core/model/fluid.hpp"
#include "slosh/core/model/rectangular_tank.hpp"
#include "slosh/core/model/sloshing_model.hpp"

namespace slosh {

/// One of the tank's two horizontal directions.
enum class TankAxis {
  kLength,  ///< modes along L (wave crests parallel to the side W)
  kWidth,   ///< modes along W
};

/// Options of the rectangular model (the cylinder's ModelOptions minus its damping correlations).
struct RectangularModelOptions {
  /// Modes per direction, 1..kMaxModes. Default 3.
  int modes{3};
  /// Damping ratio of every mode [-], 0 <= zeta < 0.5 (measured by logarithmic decrement);
  /// nullopt (default): the laminar boundary-layer damping of the direction's first mode
  /// (rectangular_damping_ratio).
  std::optional<double> explicit_zeta;
  /// Calibrated scale of every natural frequency [-]. Default 1 (potential flow), (0, 10].
  double omega_scale{1.0};
  /// Calibrated gain on the predicted wall height (linear gains and nonlinear K) [-]. Default 1,
  /// (0, 10].
  double height_gain{1.0};
};

/// The two directions' models of one tank. Each is a SloshingModel whose `radius` is the side
/// along that direction (the length scale of the nonlinear coordinate xbar = x / side) and whose
/// `C` is 0: with C = 0 the nonlinear equation of SloshingModel is the hardening/softening
/// (Duffing) oscillator of the rectangular dominant mode (docs/models.md).
struct RectangularModel {
  SloshingModel along_length;  ///< modes k_n = (2n - 1) pi / L
  SloshingModel along_width;   ///< modes k_n = (2n - 1) pi / W
  double orientation_deg{};    ///< as RectangularTank::orientation_deg
};

/// k_n = (2n - 1) pi / side [1/m], n 1-based.
[[nodiscard]] double rectangular_wavenumber(double side, int n);

/// omega_n = sqrt(g k_n tanh(k_n h)) [rad/s] of mode n (1-based) along a side.
[[nodiscard]] double rectangular_frequency(double side, double fill_height, int n);

/// Sloshing mass of mode n along `side` [kg] (the equivalent mechanical models of Abramson,
/// NASA SP-106, and of Ibrahim, Liquid Sloshing Dynamics): m_n = m_f 8 tanh(k_n h) /
/// ((2n - 1)^3 pi^3 h / side), with m_f = rho L W h the fluid mass.
[[nodiscard]] double rectangular_sloshing_mass(double fluid_mass, double side, double fill_height,
                                               int n);

/// Wall-height factor of mode n: the linear wall elevation at the wall normal to `side` is
/// eta = sum_n G_n x_n with G_n = 4 tanh(k_n h) / ((2n - 1) pi), x_n the displacement [m] of
/// the mode's sloshing mass (docs/models.md).
[[nodiscard]] double rectangular_wall_gain(double side, double fill_height, int n);

/// Laminar boundary-layer damping ratio of mode n along `side`, `across` the other side [m],
/// kinematic viscosity nu [m^2/s]: zeta_n = sqrt(nu / (2 omega_n)) [k_n (1 - 2h/side) /
/// sinh(2 k_n h) + 1/side + 1/across] (Stokes layers on the bottom, the two end walls and the
/// two side walls of a clean-surface basin; Keulegan 1959, Miles 1967; docs/models.md).
[[nodiscard]] double rectangular_damping_ratio(double side, double across, double fill_height,
                                               double kinematic_viscosity, int n);

/// Third-order amplitude correction of the first mode's frequency, omega = omega_1 (1 + c (k_1
/// A)^2) for a standing wave of wall amplitude A (Tadjbakhsh & Keller 1960; the steady state of
/// the Moiseev-type modal theory of Faltinsen 1974 and Faltinsen et al. 2000):
/// c = (9 T^-4 - 12 T^-2 - 3 - 2 T^2) / 64, T = tanh(k_1 h). Positive (hardening) below the
/// critical depth h/side = 0.3368, negative (softening) above it.
[[nodiscard]] double rectangular_frequency_correction(double side, double fill_height);

/// The model of one direction of the tank. Inputs are assumed validated (sides, fill height and
/// fluid positive and finite).
[[nodiscard]] SloshingModel make_rectangular_direction_model(
    const RectangularTank& tank, double fill_height, const Fluid& fluid, TankAxis axis,
    const RectangularModelOptions& options);

/// Both directions' models.
[[nodiscard]] RectangularModel make_rectangular_model(const RectangularTank& tank,
                                                      double fill_height, const Fluid& fluid,
                                                      const RectangularModelOptions& options = {});

}  // namespace slosh
