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
    default:
      return format_sentence(e);
  }
}

}  // namespace

std::string_view api_field_path(PlanInput input, Endpoint endpoint) {
  const bool plan = endpoint == Endpoint::kPlan;
  switch (input) {
    case PlanInput::kContainerRadius:
      return "format.container.radius_mm";
    case PlanInput::kContainerHeight:
      return "format.container.height_mm";
    case PlanInput::kFillHeight:
      return "format.fill_height_mm";
    case PlanInput::kFluidDensity:
      return "format.fluid.density_kg_m3";
    case PlanInput::kFluidViscosity:
      return "format.fluid.viscosity_pa_s";
    case PlanInput::kStroke:
      return "format.stroke_mm";
    case PlanInput::kMotionTime:
      return "format.motion_time_s";
    case PlanInput::kModes:
      return "options.modes";
    case PlanInput::kAlpha:
      return "options.alpha";
    case PlanInput::kZeta:
      return "options.damping.zeta";
    case PlanInput::kMinRamp:
      return "options.min_ramp_s";
    case PlanInput::kRampsAndPlateaus:
      return "options";
    case PlanInput::kPlateauMin:
      return "options.plateau_min_s";
    case PlanInput::kWeights:
      return "options.weights";
    case PlanInput::kPNotch:
      return "options.p_notch";
    case PlanInput::kBand:
      return "options.band";
    case PlanInput::kNBand:
      return "options.n_band";
    case PlanInput::kTolRel:
      return "options.tol_rel";
    case PlanInput::kEtaRestMax:
      return "options.eta_rest_max_mm";
    case PlanInput::kEtaMotionMax:
      return "options.eta_motion_max_mm";
    case PlanInput::kRestTime:
      return plan ? "options.rest_time_s" : "rest_time_s";
    case PlanInput::kAMax:
      return "options.limits.a_max";
    case PlanInput::kVMax:
      return "options.limits.v_max";
    case PlanInput::kJMax:
      return "options.limits.j_max";
    case PlanInput::kTimeLimit:
      return "options.time_limit_s";
    case PlanInput::kResidual:
      return "options.residual";
    case PlanInput::kIirTau:
      return "options.iir_tau";
    case PlanInput::kIirSamplePeriod:
      return "options.iir_sample_period_s";
    case PlanInput::kSloshingModel:
    case PlanInput::kUniformResponse:
    case PlanInput::kReferenceLevels:
      return "format";
    case PlanInput::kLaw:
      return "law";
    case PlanInput::kSamplePeriod:
      return "sample_period_s";
    case PlanInput::kMotionTimeMax:
      return "motion_time_max_s";
    case PlanInput::kFreeBoardMargin:
      return "free_board_margin_mm";
    case PlanInput::kScanStep:
      return "scan_step_s";
    case PlanInput::kMaxPlans:
      return "max_plans";
    case PlanInput::kCurveFactor:
      return "curve_factor";
    case PlanInput::kRefineExcess:
      return "refine_excess";
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
