#include "slosh/api/core_input.hpp"

#include <cstdio>
#include <numbers>

#include "slosh/api/fields.hpp"
#include "slosh/core/model/uncertainty.hpp"

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

// ---- options.uncertainty ---------------------------------------------------------------------

/// A band the uncertainty range widens down to 0 Hz (the core refuses it as kBand with a band the
/// API's own range admits).
bool widened_band_refusal(const InvalidInput& e, const PlanOptions& o) {
  return e.input == PlanInput::kBand && o.uncertainty.active() && e.value > 0.0 && e.value < 1.0;
}

/// "[70, 90] mm": a (min, max) pair in the request's units.
std::string pair_text(const std::array<double, 2>& pair, const char* unit) {
  return "[" + number_text(pair[0]) + ", " + number_text(pair[1]) + "] " + unit;
}

std::array<double, 2> in_mm(const std::array<double, 2>& metres) {
  return {mm_of(metres[0]), mm_of(metres[1])};
}

/// The refusal of a (min, max) range given in the request's units: empty, without the nominal
/// value, or (not reached through the API, which checks the items first) an item out of range.
std::string pair_sentence(const char* member, const std::array<double, 2>& pair, double nominal,
                          const char* unit, const char* what, const InvalidInput& e, double scale) {
  const std::string head = std::string("uncertainty.") + member + " = " + pair_text(pair, unit);
  if (pair[0] > pair[1]) return head + " is empty: the maximum must be >= the minimum";
  if (nominal < pair[0] || nominal > pair[1]) {
    return head + " must contain the nominal " + what + " " + number_text(nominal) + " " + unit;
  }
  return std::string("uncertainty.") + member + "[" + std::to_string(e.index) +
         "] = " + sig3(e.value / scale) + " " + unit + " must be in [" + sig3(e.bounds.lo / scale) +
         ", " + sig3(e.bounds.hi / scale) + "] " + unit;
}

/// The member of options.uncertainty that spreads omega_1 (the one a too-wide band is refused at).
std::string spreading_member(const Uncertainty& u) {
  if (u.omega_error > 0.0)
    return "uncertainty.omega_error_pct = " + number_text(pct_of(u.omega_error)) + " %";
  return "uncertainty.fill_height_mm = " +
         pair_text(in_mm(u.fill_height.value_or(std::array<double, 2>{})), "mm");
}

/// The band widened to [f_lo - band f_hi, (1 + band) f_hi] over the range's f1 in [f_lo, f_hi]
/// reaches 0 Hz: allowed band < f_lo / f_hi.
std::string widened_band_sentence(const Format& format, const PlanOptions& o) {
  const UncertaintyRange r = uncertainty_range(format, o.model, o.uncertainty);
  const double f_lo = r.omega_lo / (2.0 * std::numbers::pi);
  const double f_hi = r.omega_hi / (2.0 * std::numbers::pi);
  return spreading_member(o.uncertainty) + " spreads f1 over " + sig3(f_lo) + " to " + sig3(f_hi) +
         " Hz: min_jerk_band's options.band = " + number_text(o.band) +
         " widened to cover it (centred on the range's middle) reaches 0 Hz at its lower edge (" +
         sig3(f_lo) + " - " + number_text(o.band) + " x " + sig3(f_hi) + " = " +
         sig3(f_lo - o.band * f_hi) + " Hz); allowed options.band < " +
         number_text(r.scale_lo / r.scale_hi) + " with this range: narrow the band or the range";
}

/// The sentence of a refused member of options.uncertainty (or of the band it widens), nullopt
/// for the other inputs.
std::optional<std::string> uncertainty_sentence(const InvalidInput& e, const Format& format,
                                                const PlanOptions& o) {
  const Uncertainty& u = o.uncertainty;
  const std::array<double, 2> none{};
  switch (e.input) {
    case PlanInput::kOmegaError:
      return "uncertainty.omega_error_pct = " + number_text(pct_of(e.value)) +
             " % must be in [0, " + number_text(pct_of(kMaxOmegaError)) + "] %";
    case PlanInput::kFillHeightRange:
      return pair_sentence("fill_height_mm", in_mm(u.fill_height.value_or(none)),
                           mm_of(format.fill_height), "mm", "fill height", e, 1e-3);
    case PlanInput::kViscosityRange:
      if (o.model.damping == DampingCorrelation::kExplicit) {
        return "uncertainty.viscosity_pa_s = " + pair_text(u.viscosity.value_or(none), "Pa·s") +
               " is not allowed with an explicit damping (options.damping = {\"zeta\": " +
               number_text(o.model.explicit_zeta) +
               "}): a viscosity range acts through the damping correlation; " +
               (format.container.rectangular
                    ? std::string("omit options.damping (the rectangular tank's boundary-layer "
                                  "damping, the one that takes the viscosity) or give no "
                                  "viscosity range")
                    : std::string("give a correlation (thesis, paper, eq227, eq228) or no "
                                  "viscosity range"));
      }
      return pair_sentence("viscosity_pa_s", u.viscosity.value_or(none), format.fluid.viscosity,
                           "Pa·s", "viscosity", e, 1.0);
    case PlanInput::kUncertaintySamples:
      return "uncertainty.sample_points = " + integer(e.value) + " must be in [" +
             std::to_string(kMinUncertaintySamples) + ", " +
             std::to_string(kMaxUncertaintySamples) + "]";
    default:
      if (widened_band_refusal(e, o)) return widened_band_sentence(format, o);
      return std::nullopt;
  }
}

/// The sentence of a plan option (without the "options." the parser puts in front).
std::string option_sentence(const InvalidInput& e, const Format& format, const PlanOptions& o) {
  if (std::optional<std::string> sentence = uncertainty_sentence(e, format, o)) return *sentence;
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
    {PlanInput::kOmegaScale, "options.model.omega_scale"},
    {PlanInput::kHeightGain, "options.model.height_gain"},
    {PlanInput::kFillHeightRange, "options.uncertainty.fill_height_mm"},
    {PlanInput::kViscosityRange, "options.uncertainty.viscosity_pa_s"},
    {PlanInput::kUncertaintySamples, "options.uncertainty.sample_points"},
    {PlanInput::kContainerLength, "format.container.length_mm"},
    {PlanInput::kContainerWidth, "format.container.width_mm"},
    {PlanInput::kContainerOrientation, "format.container.orientation_deg"},
    {PlanInput::kWidthOmegaScale, "options.model.width_omega_scale"},
    {PlanInput::kWidthZeta, "options.model.width_zeta"},
};

}  // namespace

std::string_view api_field_path(PlanInput input, Endpoint endpoint) {
  if (input == PlanInput::kRestTime && endpoint != Endpoint::kPlan) return "rest_time_s";
  for (const FieldOfInput& row : kFieldOfInput) {
    if (row.input == input) return row.path;
  }
  return "";
}

std::string uncertainty_range_field(const Uncertainty& uncertainty) {
  const char* member = uncertainty.omega_error > 0.0         ? "omega_error_pct"
                       : uncertainty.fill_height.has_value() ? "fill_height_mm"
                                                             : "viscosity_pa_s";
  return std::string("options.uncertainty.") + member;
}

std::string options_field(const InvalidInput& invalid, const PlanOptions& options) {
  switch (invalid.input) {
    case PlanInput::kDriveProfile:
    case PlanInput::kOmegaError:
    case PlanInput::kFillHeightRange:
    case PlanInput::kViscosityRange:
    case PlanInput::kUncertaintySamples:
      return std::string(api_field_path(invalid.input));
    case PlanInput::kContainerOrientation:
      // The one option refused for the tank's orientation: an uncertainty range.
      return "options.uncertainty";
    default:
      // The band is the value refused (its allowed maximum for the range is named).
      if (widened_band_refusal(invalid, options)) return "options.band";
      return "options";
  }
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
