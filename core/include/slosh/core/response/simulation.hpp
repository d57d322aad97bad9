#pragma once
// One-call simulation of a law on a format: model, kinematics, both responses, warnings.

#include <optional>
#include <string>
#include <vector>

#include "slosh/core/invalid_input.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/rectangular_model.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/rectangular_response.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/warning.hpp"

namespace slosh {

/// Options of simulate().
struct SimulationOptions {
  ModelOptions model;
  /// Length of the rest window after the motion [s]. Default 1 s.
  double rest_time{kDefaultRestTime};
  /// When set, time series are sampled at this period [s] over [0, T + rest_time].
  std::optional<double> sample_period;
  NonlinearOptions nonlinear;
};

/// Sampled time series (SI: s, m/s^2, m/s, m, m).
/// For a rectangular tank square to the motion the wave heights are signed (at the wall ahead in
/// the tank's axis); turned, they are the highest corner's |eta_L| + |eta_W| (>= 0).
struct TimeSeries {
  std::vector<double> t, a, v, s, eta_linear, eta_nonlinear;
};

/// Everything a simulation reports.
struct SimulationResult {
  /// The model (a rectangular tank's: its most excited direction driven by the motion).
  SloshingModel model;
  KinematicSummary kinematics;
  SloshPeaks linear;     ///< a rectangular tank's: the highest wall or corner
  SloshPeaks nonlinear;  ///< a rectangular tank's: outside its range, the linear model's
  /// A rectangular tank's model (SPEC §15); nullopt for the cylinder.
  std::optional<RectangularModel> rectangular;
  /// A rectangular tank's nonlinear peaks per direction (along_length, along_width; zero for a
  /// direction the motion does not drive) and the corners' (highest).
  std::optional<RectangularPeaks> rectangular_peaks;
  std::optional<TimeSeries> series;
  std::vector<Warning> warnings;
  /// Set when simulate() refused its inputs (validate_simulation_input); nothing else is filled.
  std::optional<InvalidInput> invalid_input;
};

/// Validity thresholds of SPEC §2 (warnings, not errors).
constexpr double kLinearModelMaxAcceleration{10.0};  ///< [m/s^2], JDSMC sec. 5/7
constexpr double kMinModelledRadius{0.015};          ///< [m], surface tension below
constexpr double kMinFillRatio{0.3};                 ///< h/R below: shallow-liquid regime

/// Validity warnings of SPEC §2 for a format, a law's peak |a| and predicted eta_motion values.
/// `nonlinear_in_range` false says the nonlinear figures are the linear model's (a rectangular
/// tank outside its nonlinear model's range): the sentences then neither send the user to the
/// nonlinear prediction nor call a figure nonlinear. `eta_rest_linear` [m], the linear wave left
/// after the motion: a rectangular tank's linear-theory check judges the larger of eta_motion and
/// eta_rest (a shallow fill rings on after the motion, and its wave there can exceed the one
/// during it) and quotes both when the rest one is larger. A wave (eta_motion of either model,
/// eta_rest_linear) deeper than the fill height is a warning of its own (kWaveExceedsFill).
/// `linear_directions`, a rectangular tank's linear waves of each direction alone: the steepness
/// of each is judged on its own side (a corner's height is their sum, which no single standing
/// wave carries); without them the corner's height stands for both, an upper bound.
[[nodiscard]] std::vector<Warning> validity_warnings(
    const Format& format, double peak_abs_acceleration, double eta_motion_linear,
    double eta_motion_nonlinear, bool nonlinear_in_range = true, double eta_rest_linear = 0.0,
    const DirectionWaves* linear_directions = nullptr);

/// The first input simulate() refuses, or nullopt: the format (radius, fill height, density
/// finite and > 0; viscosity, stroke finite and >= 0; motion time and the container height when
/// set finite and > 0), the model options (validate_model_options), the law (at least one piece,
/// finite duration > 0 and finite stroke), the rest window (finite, >= 0) and the sample period
/// when set (finite, > 0).
[[nodiscard]] std::optional<InvalidInput> validate_simulation_input(
    const Format& format, const MotionLaw& law, const SimulationOptions& options);

/// Simulates `law` on `format`. Invalid inputs (validate_simulation_input) give a result with
/// only `invalid_input` set, never a throw or a non-finite number.
[[nodiscard]] SimulationResult simulate(const Format& format, const MotionLaw& law,
                                        const SimulationOptions& options);

}  // namespace slosh
