#pragma once
// Structured refusal of a core input (like Ceres' Solver::Options::IsValid and Ruckig's
// validate_input): which input, which element, its value and the allowed range, and a sentence in
// core names and SI units. The API maps each input to its request field and words its own message
// (api/core_input.hpp); the core never names an API field.

#include <array>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "slosh/core/enum_names.hpp"

namespace slosh {

/// An input of plan() or simulate() that the core checks, by its core name (SI quantities).
enum class PlanInput {
  kContainerRadius,   ///< Container::radius [m]
  kContainerHeight,   ///< Container::height [m]
  kFillHeight,        ///< Format::fill_height [m]
  kFluidDensity,      ///< Fluid::density [kg/m^3]
  kFluidViscosity,    ///< Fluid::viscosity [Pa s]
  kStroke,            ///< Format::stroke [m]
  kMotionTime,        ///< Format::motion_time [s]
  kModes,             ///< ModelOptions::modes [-]
  kAlpha,             ///< ModelOptions::alpha [-]
  kZeta,              ///< ModelOptions::explicit_zeta [-]
  kMinRamp,           ///< PlanOptions::min_ramp [s]
  kRampsAndPlateaus,  ///< the relation 4 min_ramp + plateau_min[0] + plateau_min[1] <= T [s]
  kPlateauMin,        ///< PlanOptions::plateau_min[index] [s]
  kWeights,           ///< PlanOptions::weights[index]; index -1: their sum [-]
  kPNotch,            ///< PlanOptions::p_notch [-]
  kBand,              ///< PlanOptions::band [-]
  kNBand,             ///< PlanOptions::n_band [-]
  kTolRel,            ///< PlanOptions::tol_rel [-]
  kEtaRestMax,        ///< PlanOptions::eta_rest_max [m]
  kEtaMotionMax,      ///< PlanOptions::eta_motion_max [m]
  kRestTime,          ///< PlanOptions::rest_time, SimulationOptions::rest_time [s]
  kAMax,              ///< MachineLimits::a_max [m/s^2]
  kVMax,              ///< MachineLimits::v_max [m/s]
  kJMax,              ///< MachineLimits::j_max [m/s^3]
  kTimeLimit,         ///< PlanOptions::time_limit [s]
  kResidual,          ///< PlanOptions::residual [-]
  kIirTau,            ///< PlanOptions::iir_tau [1/s]
  kIirSamplePeriod,   ///< PlanOptions::iir_sample_period [s]
  kSloshingModel,     ///< the model built from the format (finite omega1, zeta, K) [rad/s]
  kUniformResponse,   ///< the uniform law's predicted sloshing (finite) [m]
  kReferenceLevels,   ///< X_ref and the uniform jerk integral (finite, > 0) [m/s]
  kLaw,               ///< simulate()'s law: pieces, finite duration and stroke [s]
  kSamplePeriod,      ///< SimulationOptions::sample_period [s]
  kMotionTimeMax,     ///< MinTimeOptions::motion_time_max [s]
  kFreeBoardMargin,   ///< MinTimeOptions::free_board_margin [m]
  kScanStep,          ///< MinTimeOptions::scan_step [s]
  kMaxPlans,          ///< MinTimeOptions::max_plans [-]
  kCurveFactor,       ///< MinTimeOptions::curve_factor [-]
  kRefineExcess,      ///< MinTimeOptions::refine_excess [-]
  kWarmStart,         ///< PlanOptions::warm_start[index]; index -1: their sum [s]
  kLawResponse,       ///< the planned law's predicted sloshing (finite: the models describe it) [m]
  kDriveProfile,      ///< PlanOptions::drive_profile with the strategy and the bounds; value: T [s]
  kOmegaError,        ///< Uncertainty::omega_error [-]
  kFillHeightRange,   ///< Uncertainty::fill_height[index] [m]; index -1: the pair
  kViscosityRange,    ///< Uncertainty::viscosity[index] [Pa s]; index -1: the pair
  kUncertaintySamples,    ///< Uncertainty::sample_points [-]
  kOmegaScale,            ///< ModelOptions::omega_scale [-]
  kHeightGain,            ///< ModelOptions::height_gain [-]
  kContainerLength,       ///< RectangularTank::length [m]
  kContainerWidth,        ///< RectangularTank::width [m]
  kContainerOrientation,  ///< RectangularTank::orientation_deg [deg]
  kWidthOmegaScale,       ///< ModelOptions::width_omega_scale [-]
  kWidthZeta,             ///< ModelOptions::width_zeta [-]
};

template <>
struct EnumNames<PlanInput> {
  static constexpr std::array<EnumName<PlanInput>, 53> table{{
      {PlanInput::kContainerRadius, "container_radius"},
      {PlanInput::kContainerHeight, "container_height"},
      {PlanInput::kFillHeight, "fill_height"},
      {PlanInput::kFluidDensity, "fluid_density"},
      {PlanInput::kFluidViscosity, "fluid_viscosity"},
      {PlanInput::kStroke, "stroke"},
      {PlanInput::kMotionTime, "motion_time"},
      {PlanInput::kModes, "modes"},
      {PlanInput::kAlpha, "alpha"},
      {PlanInput::kZeta, "zeta"},
      {PlanInput::kMinRamp, "min_ramp"},
      {PlanInput::kRampsAndPlateaus, "ramps_and_plateaus"},
      {PlanInput::kPlateauMin, "plateau_min"},
      {PlanInput::kWeights, "weights"},
      {PlanInput::kPNotch, "p_notch"},
      {PlanInput::kBand, "band"},
      {PlanInput::kNBand, "n_band"},
      {PlanInput::kTolRel, "tol_rel"},
      {PlanInput::kEtaRestMax, "eta_rest_max"},
      {PlanInput::kEtaMotionMax, "eta_motion_max"},
      {PlanInput::kRestTime, "rest_time"},
      {PlanInput::kAMax, "a_max"},
      {PlanInput::kVMax, "v_max"},
      {PlanInput::kJMax, "j_max"},
      {PlanInput::kTimeLimit, "time_limit"},
      {PlanInput::kResidual, "residual"},
      {PlanInput::kIirTau, "iir_tau"},
      {PlanInput::kIirSamplePeriod, "iir_sample_period"},
      {PlanInput::kSloshingModel, "sloshing_model"},
      {PlanInput::kUniformResponse, "uniform_response"},
      {PlanInput::kReferenceLevels, "reference_levels"},
      {PlanInput::kLaw, "law"},
      {PlanInput::kSamplePeriod, "sample_period"},
      {PlanInput::kMotionTimeMax, "motion_time_max"},
      {PlanInput::kFreeBoardMargin, "free_board_margin"},
      {PlanInput::kScanStep, "scan_step"},
      {PlanInput::kMaxPlans, "max_plans"},
      {PlanInput::kCurveFactor, "curve_factor"},
      {PlanInput::kRefineExcess, "refine_excess"},
      {PlanInput::kWarmStart, "warm_start"},
      {PlanInput::kLawResponse, "law_response"},
      {PlanInput::kDriveProfile, "drive_profile"},
      {PlanInput::kOmegaError, "omega_error"},
      {PlanInput::kFillHeightRange, "fill_height_range"},
      {PlanInput::kViscosityRange, "viscosity_range"},
      {PlanInput::kUncertaintySamples, "uncertainty_samples"},
      {PlanInput::kOmegaScale, "omega_scale"},
      {PlanInput::kHeightGain, "height_gain"},
      {PlanInput::kContainerLength, "container_length"},
      {PlanInput::kContainerWidth, "container_width"},
      {PlanInput::kContainerOrientation, "container_orientation"},
      {PlanInput::kWidthOmegaScale, "width_omega_scale"},
      {PlanInput::kWidthZeta, "width_zeta"},
  }};
};

/// SI unit of an input as the core's messages write it ("m", "s", "1/s"; empty when
/// dimensionless).
[[nodiscard]] std::string_view input_unit(PlanInput input);

/// The allowed set of an input: [lo, hi] with open ends where flagged; an infinite end is
/// unbounded. NaN and infinity are never allowed. SI units of the input.
struct InputBounds {
  double lo{-std::numeric_limits<double>::infinity()};  ///< lower bound [SI]
  double hi{std::numeric_limits<double>::infinity()};   ///< upper bound [SI]
  bool lo_open{false};                                  ///< lo itself is not allowed
  bool hi_open{false};                                  ///< hi itself is not allowed

  /// True when `value` is finite and in the set.
  [[nodiscard]] bool contains(double value) const;
};

/// The set as text with `number` writing its ends, without unit: "[0, 360)", "(30, 360]", "> 0",
/// "<= 1"; "finite" when both ends are infinite.
[[nodiscard]] std::string bounds_text(const InputBounds& bounds,
                                      const std::function<std::string(double)>& number);

/// Why the core refuses an input: which input, which element, its value and the allowed set.
struct InvalidInput {
  PlanInput input{};
  /// The element of an array input (plateau_min, weights), -1 for the input as a whole.
  int index{-1};
  /// The refused value [SI unit of the input]; for kRampsAndPlateaus the sum 4 min_ramp +
  /// plateau minimums [s]. NaN when the input has no single value (kLaw without pieces).
  double value{std::numeric_limits<double>::quiet_NaN()};
  /// What the input may be (for kRampsAndPlateaus: the sum, hi = the motion time).
  InputBounds bounds;
  /// One sentence in core names and SI units ("n_band = 0 must be finite and in [1, 2001]").
  std::string message;

  /// The allowed set as text with the input's unit: "> 0 s", ">= 0", "in [1, 2001]",
  /// "in (0, 1)", "<= 0.05 s".
  [[nodiscard]] std::string allowed() const;
};

/// The refusal of `input` (element `index`, -1 for none) whose `value` is outside `bounds`, with
/// the core's sentence "name[index] = value unit must be finite and <allowed>" (integer inputs,
/// modes and n_band, printed without exponent).
[[nodiscard]] InvalidInput out_of_range(PlanInput input, int index, double value,
                                        const InputBounds& bounds);

/// The refusal of an input judged as a whole (a relation or a derived quantity): `message` is the
/// core's sentence, `value` and `bounds` what it compares.
[[nodiscard]] InvalidInput refused(PlanInput input, double value, const InputBounds& bounds,
                                   std::string message);

/// One checked quantity: an input, its value and what it may be.
struct BoundedValue {
  PlanInput input{};
  double value{};
  InputBounds bounds;
};

/// The refusal (out_of_range) of the first value outside its bounds, in order; nullopt when all
/// hold.
[[nodiscard]] std::optional<InvalidInput> first_out_of_range(
    std::initializer_list<BoundedValue> values);

/// Bounds shorthands: (0, inf), [0, inf), [lo, hi], (lo, hi).
[[nodiscard]] inline InputBounds positive() {
  return {0.0, std::numeric_limits<double>::infinity(), true, false};
}
[[nodiscard]] inline InputBounds non_negative() {
  return {0.0, std::numeric_limits<double>::infinity(), false, false};
}
[[nodiscard]] inline InputBounds closed_range(double lo, double hi) {
  return {lo, hi, false, false};
}
[[nodiscard]] inline InputBounds open_range(double lo, double hi) {
  return {lo, hi, true, true};
}
/// Allowed calibrated scales (omega_scale, height_gain): (0, 10].
[[nodiscard]] inline InputBounds calibration_scale_range() {
  return {0.0, 10.0, true, false};
}

}  // namespace slosh
