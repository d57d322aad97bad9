#include "slosh/api/core_input.hpp"

#include <cstdio>

namespace slosh::api {

namespace {

/// 3 significant digits, as the core's sentences have always printed numbers ("0.195", "1e+03").
std::string sig3(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string integer(double v) {
  return std::to_string(static_cast<long long>(v));
}

std::string range(const InvalidInput& e, const char* unit) {
  return "[" + sig3(e.bounds.lo) + ", " + sig3(e.bounds.hi) + "] " + unit;
}

std::string element(const char* name, const InvalidInput& e) {
  return std::string(name) + "[" + std::to_string(e.index) + "] = " + sig3(e.value);
}

/// The sentence of an input of the format or the model.
std::string format_sentence(const InvalidInput& e) {
  const std::string v = sig3(e.value);
  switch (e.input) {
    case PlanInput::kContainerRadius:
      return "container radius " + v + " m must be finite and in " + range(e, "m");
    case PlanInput::kContainerHeight:
      return "container height " + v + " m must be finite and > 0";
    case PlanInput::kFillHeight:
      return "fill height " + v + " m must be finite and in " + range(e, "m");
    case PlanInput::kFluidDensity:
      return "fluid density " + v + " kg/m^3 must be finite and in [1, 1e5]";
    case PlanInput::kFluidViscosity:
      return "fluid viscosity " + v + " Pa·s must be finite and in [0, 1e6]";
    case PlanInput::kStroke:
      return "stroke " + v + " m must be finite and in " + range(e, "m");
    case PlanInput::kMotionTime:
      return "motion time " + v + " s must be finite and in " + range(e, "s");
    case PlanInput::kModes:
      return "modes = " + integer(e.value) + " must be in [1, " + integer(e.bounds.hi) + "]";
    case PlanInput::kAlpha:
      return "alpha = " + v + " must be finite and >= 0";
    case PlanInput::kZeta:
      return "zeta = " + v + " must be finite and >= 0";
    default:
      return e.message;
  }
}

/// The sentence of a plan option (without the "options." the parser puts in front).
std::string option_sentence(const InvalidInput& e, const Format& format, const PlanOptions& o) {
  const std::string v = sig3(e.value);
  switch (e.input) {
    case PlanInput::kMinRamp:
      return "min_ramp_s = " + v + " s must be > 0";
    case PlanInput::kRampsAndPlateaus: {
      const double T = format.motion_time;
      return "min_ramp_s = " + sig3(o.min_ramp) + " s and plateau_min_s = [" +
             sig3(o.plateau_min[0]) + ", " + sig3(o.plateau_min[1]) +
             "] s need 4 ramps + 2 plateaus = " + v + " s, more than the motion time " + sig3(T) +
             " s: allowed min_ramp_s <= (T - plateau minimums) / 4 = " +
             sig3((T - o.plateau_min[0] - o.plateau_min[1]) / 4.0) + " s";
    }
    case PlanInput::kPlateauMin:
      if (e.bounds.lo > 0.0) {
        return element("plateau_min_s", e) +
               " s must be 0 or >= 1e-09 s: durations below 1 ns are exactly 0";
      }
      return element("plateau_min_s", e) + " s must be >= 0";
    case PlanInput::kWeights:
      if (e.index < 0) return "weights = [0, 0, 0]: at least one weight must be > 0";
      return element("weights", e) + " must be finite and >= 0";
    case PlanInput::kPNotch:
      return "p_notch = " + v + " must be > 0 and < 1";
    case PlanInput::kBand:
      return "band = " + v + " must be > 0 and < 1";
    case PlanInput::kNBand:
      return "n_band = " + integer(e.value) + " must be in [1, " + integer(e.bounds.hi) + "]";
    case PlanInput::kTolRel:
      return "tol_rel = " + v + " must be finite and > 0";
    case PlanInput::kEtaRestMax:
      return "eta_rest_max_mm = " + sig3(e.value * 1e3) + " mm must be > 0";
    case PlanInput::kEtaMotionMax:
      return "eta_motion_max_mm = " + sig3(e.value * 1e3) + " mm must be > 0";
    case PlanInput::kRestTime:
      return "rest_time_s = " + v + " s must be > 0 and <= " + sig3(e.bounds.hi) + " s";
    case PlanInput::kAMax:
    case PlanInput::kVMax:
    case PlanInput::kJMax:
      return "limits." + std::string(name_of(e.input)) + " = " + v + " must be finite and > 0";
    case PlanInput::kTimeLimit:
      return "time_limit_s = " + v + " s must be > 0";
    case PlanInput::kResidual:
      return "residual = " + v + " must be >= 0 and < 1";
    case PlanInput::kIirTau:
      return "iir_tau = " + v + " 1/s must be finite and > 0";
    case PlanInput::kIirSamplePeriod:
      return "iir_sample_period_s = " + v + " s must be > 0 and <= T / " +
             std::to_string(kIirMinSamples) + " = " + sig3(e.bounds.hi) + " s";
    case PlanInput::kWarmStart:
      if (e.index < 0) return "warm_start_s sums to " + v + " s: it must be > 0";
      return element("warm_start_s", e) + " s must be finite and >= 0";
    default:
      return format_sentence(e);
  }
}

}  // namespace

namespace {

struct FieldOfInput {
  PlanInput input;
  std::string_view path;
};

// The request field of each core input (plan requests; simulate differs only for the rest window).
constexpr FieldOfInput kFieldOfInput[] = {
    {PlanInput::kContainerRadius, "format.container.radius_mm"},
    {PlanInput::kContainerHeight, "format.container.height_mm"},
    {PlanInput::kFillHeight, "format.fill_height_mm"},
    {PlanInput::kFluidDensity, "format.fluid.density_kg_m3"},
    {PlanInput::kFluidViscosity, "format.fluid.viscosity_pa_s"},
    {PlanInput::kStroke, "format.stroke_mm"},
    {PlanInput::kMotionTime, "format.motion_time_s"},
    {PlanInput::kModes, "options.modes"},
    {PlanInput::kAlpha, "options.alpha"},
    {PlanInput::kZeta, "options.damping.zeta"},
    {PlanInput::kMinRamp, "options.min_ramp_s"},
    {PlanInput::kRampsAndPlateaus, "options"},
    {PlanInput::kPlateauMin, "options.plateau_min_s"},
    {PlanInput::kWeights, "options.weights"},
    {PlanInput::kPNotch, "options.p_notch"},
    {PlanInput::kBand, "options.band"},
    {PlanInput::kNBand, "options.n_band"},
    {PlanInput::kTolRel, "options.tol_rel"},
    {PlanInput::kEtaRestMax, "options.eta_rest_max_mm"},
    {PlanInput::kEtaMotionMax, "options.eta_motion_max_mm"},
    {PlanInput::kRestTime, "options.rest_time_s"},
    {PlanInput::kAMax, "options.limits.a_max"},
    {PlanInput::kVMax, "options.limits.v_max"},
    {PlanInput::kJMax, "options.limits.j_max"},
    {PlanInput::kTimeLimit, "options.time_limit_s"},
    {PlanInput::kResidual, "options.residual"},
    {PlanInput::kIirTau, "options.iir_tau"},
    {PlanInput::kIirSamplePeriod, "options.iir_sample_period_s"},
    {PlanInput::kSloshingModel, "format"},
    {PlanInput::kUniformResponse, "format"},
    {PlanInput::kLawResponse, "format"},
    {PlanInput::kReferenceLevels, "format"},
    {PlanInput::kLaw, "law"},
    {PlanInput::kSamplePeriod, "sample_period_s"},
    {PlanInput::kMotionTimeMax, "motion_time_max_s"},
    {PlanInput::kFreeBoardMargin, "free_board_margin_mm"},
    {PlanInput::kScanStep, "scan_step_s"},
    {PlanInput::kMaxPlans, "max_plans"},
    {PlanInput::kCurveFactor, "curve_factor"},
    {PlanInput::kRefineExcess, "refine_excess"},
    {PlanInput::kWarmStart, "options.warm_start_s"},
    {PlanInput::kDriveProfile, "options.drive_profile"},
    {PlanInput::kOmegaError, "options.uncertainty.omega_error_pct"},
    {PlanInput::kFillHeightRange, "options.uncertainty.fill_height_mm"},
    {PlanInput::kViscosityRange, "options.uncertainty.viscosity_pa_s"},
    {PlanInput::kUncertaintySamples, "options.uncertainty.sample_points"},
};

}  // namespace

std::string_view api_field_path(PlanInput input, Endpoint endpoint) {
  if (input == PlanInput::kRestTime && endpoint != Endpoint::kPlan) return "rest_time_s";
  for (const FieldOfInput& row : kFieldOfInput) {
    if (row.input == input) return row.path;
  }
  return "";
}

std::string input_sentence(const InvalidInput& invalid, const Format& format,
                           const PlanOptions& options) {
  return option_sentence(invalid, format, options);
}

std::string plan_refusal(const InvalidInput& invalid, const Format& format,
                         const PlanOptions& options) {
  return "invalid input: " + input_sentence(invalid, format, options) + "; nothing was planned";
}

std::string simulate_refusal(const InvalidInput& invalid) {
  return std::string(api_field_path(invalid.input, Endpoint::kSimulate)) +
         " is refused by the simulation: " + invalid.message;
}

}  // namespace slosh::api
