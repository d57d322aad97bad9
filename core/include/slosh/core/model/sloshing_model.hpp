#pragma once
// Equivalent mechanical models of sloshing in a cylindrical container (thesis ch. 2, SPEC §2).

#include <optional>
#include <string>
#include <vector>
#include "slosh/core/enum_names.hpp"

#include "slosh/core/constants.hpp"
#include "slosh/core/invalid_input.hpp"
#include "slosh/core/model/format.hpp"

namespace slosh {

/// How the damping ratio zeta is obtained.
enum class DampingCorrelation {
  kThesis,    ///< thesis eq. 2.26, coefficient 0.79 (default)
  kPaper,     ///< JDSMC 2022 eq. 2, coefficient 0.92
  kEq227,     ///< thesis eq. 2.27, 0.83 sqrt(Re1) tanh(1.84 h/R)[1 + 2(1 - h/R)/cosh(3.68 h/R)]
  kEq228,     ///< thesis eq. 2.28, coefficient 2.89/pi
  kExplicit,  ///< zeta given by the caller (e.g. measured by logarithmic decrement)
};

/// Options of the sloshing model.
struct ModelOptions {
  /// Number of radial modes of the linear model, 1..kMaxModes. Default 3.
  int modes{3};
  /// Damping correlation. Default: thesis eq. 2.26.
  DampingCorrelation damping{DampingCorrelation::kThesis};
  /// Damping ratio used when damping == kExplicit [-], 0 <= zeta < 0.5.
  double explicit_zeta{0.0};
  /// Nonlinear stiffening coefficient alpha of eq. 2.35 [-]. Default 0.58.
  double alpha{kDefaultAlpha};
  /// Calibrated scale of every natural frequency omega_n [-] (1 = the potential-flow
  /// frequencies of eq. 2.14). Default 1, allowed (0, 10].
  double omega_scale{1.0};
  /// Calibrated gain on the predicted wall height (linear eta_gain_n and nonlinear K) [-].
  /// Default 1, allowed (0, 10].
  double height_gain{1.0};
  /// A rectangular tank calibrated in both of its directions (calibrate_rectangular): the scale
  /// of the natural frequencies of its modes along the width [-], (0, 10]; nullopt (default):
  /// omega_scale holds for both directions. Not used by the cylinder.
  std::optional<double> width_omega_scale;
  /// Likewise the damping ratio of the modes along the width [-], 0 <= zeta < 0.5; nullopt
  /// (default): the damping above (explicit, or the tank's own) holds for both directions.
  std::optional<double> width_zeta;
};

/// Immutable model parameters of one format. All SI.
struct SloshingModel {
  double radius{};            ///< R [m]
  double fill_height{};       ///< h [m]
  double density{};           ///< rho [kg/m^3]
  double fluid_mass{};        ///< m_f = pi R^2 h rho [kg]
  double zeta{};              ///< damping ratio, shared by all modes [-]
  double alpha{};             ///< nonlinear stiffening [-]
  double C{};                 ///< C = xi_1 tanh(xi_1 h/R) = omega_1^2 R / g [-]
  double K{};                 ///< nonlinear height gain eta = K xbar, K = 2 R C / (xi_1^2 - 1) [m]
  std::vector<double> omega;  ///< natural circular frequencies omega_n [rad/s]
  std::vector<double> mass;   ///< sloshing masses m_n [kg]
  std::vector<double> eta_gain;  ///< linear wall height eta = sum eta_gain_n x_n [-]

  [[nodiscard]] int modes() const { return static_cast<int>(omega.size()); }
  [[nodiscard]] double omega1() const { return omega.front(); }
};

/// Damping ratio of a format from a correlation of SPEC §2 (not kExplicit).
[[nodiscard]] double damping_ratio(const Format& format, DampingCorrelation correlation);

/// Natural circular frequency of radial mode n (1-based) [rad/s].
[[nodiscard]] double natural_frequency(double radius, double fill_height, int n);

/// Builds the model parameters. Inputs are assumed validated (see api/validation). A rectangular
/// container (Container::rectangular) gives its most excited direction driven by the motion
/// (driven_directions in tank_directions.hpp): the whole model when the tank is square to the
/// motion, one of its two directions when it is turned.
[[nodiscard]] SloshingModel make_sloshing_model(const Format& format, const ModelOptions& options);

/// The first model option outside what the model accepts (modes in [1, kMaxModes], alpha >= 0,
/// explicit zeta >= 0, all finite), or nullopt.
[[nodiscard]] std::optional<InvalidInput> validate_model_options(const ModelOptions& options);

/// Human name of a correlation as used on the API ("thesis", "paper", "eq227", "eq228",
/// "explicit").
template <>
struct EnumNames<DampingCorrelation> {
  static constexpr std::array<EnumName<DampingCorrelation>, 5> table{{
      {DampingCorrelation::kThesis, "thesis"},
      {DampingCorrelation::kPaper, "paper"},
      {DampingCorrelation::kEq227, "eq227"},
      {DampingCorrelation::kEq228, "eq228"},
      {DampingCorrelation::kExplicit, "explicit"},
  }};
};
[[nodiscard]] inline std::string to_string(DampingCorrelation value) {
  return std::string(name_of(value));
}

}  // namespace slosh
