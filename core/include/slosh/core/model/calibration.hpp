#pragma once
// Calibration of the nonlinear sloshing model (eq. 2.35) from bench measurements:
// bounded nonlinear least squares on measured eta(t) series and/or measured peaks, with exact
// gradients (dual numbers through the integrator), standard errors from the Jacobian and an
// identifiability check that refuses to report values the data cannot separate.

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/enum_names.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh {

/// The calibrated parameters, in this order everywhere (arrays index them).
enum class CalibrationParameter {
  kOmegaScale,  ///< scale of every natural frequency [-], prior 1
  kZeta,        ///< damping ratio of the modes [-], prior: the chosen correlation's value
  kAlpha,       ///< nonlinear stiffening of eq. 2.35 [-], prior: ModelOptions::alpha
  kHeightGain,  ///< gain on the predicted wall height [-], prior 1
};
inline constexpr std::size_t kCalibrationParameters = 4;

template <>
struct EnumNames<CalibrationParameter> {
  static constexpr std::array<EnumName<CalibrationParameter>, 4> table{{
      {CalibrationParameter::kOmegaScale, "omega_scale"},
      {CalibrationParameter::kZeta, "zeta"},
      {CalibrationParameter::kAlpha, "alpha"},
      {CalibrationParameter::kHeightGain, "height_gain"},
  }};
};

/// How one parameter enters the fit.
struct ParameterSetting {
  bool fit{true};  ///< fitted (true) or held at `initial`
  /// Start value and prior (the value reported when the data cannot identify the parameter);
  /// nullopt: the model's own value (omega_scale 1, zeta of the correlation, alpha, gain 1).
  std::optional<double> initial;
  double lower{};  ///< bound, < upper
  double upper{};  ///< bound
};

/// Default settings: omega_scale in [0.5, 2], zeta in [0, 0.3], alpha in [0, 2], gain in
/// [0.2, 5]; all fitted.
[[nodiscard]] std::array<ParameterSetting, kCalibrationParameters> default_parameter_settings();

/// A measured eta(t) series: the wall height the model predicts (the sign of simulate's series).
struct MeasuredSeries {
  std::vector<double> t;    ///< sample times on the measurement clock [s], increasing
  std::vector<double> eta;  ///< measured wall height [m]
  /// Time of the move start on the measurement clock [s] (model time = t - offset).
  double offset{0.0};
  bool fit_offset{false};   ///< estimate the offset (within offset +- max_offset)
  double max_offset{0.25};  ///< [s], > 0
};

/// Measured peaks of one move.
struct MeasuredPeaks {
  std::optional<double> eta_motion;  ///< max |eta| during the motion [0, T] [m]
  std::optional<double> eta_rest;    ///< max |eta| over the rest window (T, T + rest_window] [m]
  double rest_window{1.0};           ///< [s], > 0
};

/// One measured move: the law the bench ran and what was measured.
struct MeasuredMove {
  std::string name;  ///< shown in the result
  MotionLaw law;     ///< its stroke is the format's (checked by the API)
  std::optional<MeasuredSeries> series;
  std::optional<MeasuredPeaks> peaks;
};

struct CalibrationSettings {
  std::array<ParameterSetting, kCalibrationParameters> parameters{default_parameter_settings()};
  int max_iterations{60};
  NonlinearOptions nonlinear;
  /// A direction of the (bound-scaled) parameters is unidentifiable when its standard deviation
  /// exceeds this fraction of the bound box, or J^T J is singular in it to 1e-12 relative.
  double identifiable_fraction{0.25};
  /// Polled between solver steps; true ends the fit with status kTimeLimit (unset: never).
  std::function<bool()> stop;
};

enum class CalibrationStatus { kConverged, kMaxIterations, kTimeLimit, kFailed };
template <>
struct EnumNames<CalibrationStatus> {
  static constexpr std::array<EnumName<CalibrationStatus>, 4> table{{
      {CalibrationStatus::kConverged, "converged"},
      {CalibrationStatus::kMaxIterations, "max_iterations"},
      {CalibrationStatus::kTimeLimit, "time_limit"},
      {CalibrationStatus::kFailed, "failed"},
  }};
};

/// How a parameter ended.
enum class ParameterState { kFitted, kFixed, kUnidentifiable };
template <>
struct EnumNames<ParameterState> {
  static constexpr std::array<EnumName<ParameterState>, 3> table{{
      {ParameterState::kFitted, "fitted"},
      {ParameterState::kFixed, "fixed"},
      {ParameterState::kUnidentifiable, "unidentifiable"},
  }};
};

struct FittedParameter {
  double prior{};                        ///< start value / prior
  double value{};                        ///< fitted value (the prior when not fitted)
  std::optional<double> standard_error;  ///< sigma sqrt((J^T J)^-1_ii), fitted only
  ParameterState state{ParameterState::kFitted};
  bool at_bound{false};  ///< the value sits on a bound
};

struct MoveFit {
  std::string name;
  std::size_t residuals{};                      ///< number of measured values
  double rms_before{};                          ///< RMS residual at the priors [m]
  double rms_after{};                           ///< RMS residual at the fitted values [m]
  std::optional<double> offset;                 ///< fitted series offset [s]
  std::optional<double> offset_standard_error;  ///< [s]
};

struct CalibrationResult {
  CalibrationStatus status{CalibrationStatus::kFailed};
  std::array<FittedParameter, kCalibrationParameters> parameters;
  std::vector<MoveFit> moves;
  double sigma{};    ///< residual standard deviation sqrt(SSR / (m - p)) [m]; 0 when m <= p
  int iterations{};  ///< LM steps over all refits
  /// One sentence per unidentifiable direction (which parameters, why, what was done).
  std::vector<std::string> identifiability;
  /// The calibrated model options (the base options with the fitted values).
  ModelOptions model;
};

/// Fits the parameters to the moves on `format` (inputs validated by the caller: at least one
/// move, each with a series of >= 2 increasing finite samples or at least one peak; bounds
/// lower < upper containing the start values).
[[nodiscard]] CalibrationResult calibrate(const Format& format, const ModelOptions& base,
                                          const std::vector<MeasuredMove>& moves,
                                          const CalibrationSettings& settings);

/// The residuals (model - measured) of `moves` for parameter values `p` [m], in move order:
/// series samples, then eta_motion, then eta_rest; with their exact Jacobian (columns: the 4
/// parameters, then one per move with a fitted offset, in move order). The model is the
/// nonlinear one of `format` with `base` (its omega_scale and height_gain ignored).
void calibration_residuals(const Format& format, const ModelOptions& base,
                           const std::vector<MeasuredMove>& moves,
                           const std::array<double, kCalibrationParameters>& p,
                           const std::vector<double>& offsets, const NonlinearOptions& nonlinear,
                           std::vector<double>* residuals,
                           std::vector<std::vector<double>>* jacobian);

}  // namespace slosh
