#include "slosh/api/option_registry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;
using namespace plan_ranges;  // NOLINT: the option ranges of plan.hpp

// ---- reading one value -----------------------------------------------------------------------

json number_array(const json& object, const std::string& path, std::string_view key,
                  const Range& range, std::size_t n) {
  const json& value = *given_member(object, key);
  const std::string field = join_path(path, key);
  if (!value.is_array() || value.size() != n) {
    invalid(field,
            field + " must be an array of " + std::to_string(n) + " numbers, got " + show(value));
  }
  json out = json::array();
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(checked_number(&value[i], field + "[" + std::to_string(i) + "]", range));
  }
  return out;
}

std::string choice(const json& object, const std::string& path, std::string_view key,
                   const std::vector<std::string>& allowed) {
  const json& value = *given_member(object, key);
  if (value.is_string()) {
    const auto text = value.get<std::string>();
    if (std::find(allowed.begin(), allowed.end(), text) != allowed.end()) return text;
  }
  const std::string field = join_path(path, key);
  invalid(field, field + " = " + show(value) + " is not allowed: one of " + quoted_names(allowed));
}

// options.model.alpha (zeta) and options.alpha (damping) set the same value: one of them only.
void reject_model_conflicts(const json& options) {
  const json* model = given_member(options, "model");
  if (model == nullptr || !model->is_object()) return;
  for (const auto& [member, top] :
       {std::pair<std::string_view, std::string_view>{"alpha", "alpha"}, {"zeta", "damping"}}) {
    if (given_member(*model, member) != nullptr && given_member(options, top) != nullptr) {
      const std::string field = "options.model." + std::string(member);
      invalid(field,
              field + " and options." + std::string(top) + " both set the model: give one of them");
    }
  }
}

json damping_value(const json& object, const std::string& path) {
  ModelOptions model;
  parse_damping(object, path, model);
  if (model.damping == DampingCorrelation::kExplicit) return model.explicit_zeta;
  return name_of(model.damping);
}

// `user` x option.scale; a non-zero value whose SI value is not a normal double (it underflows to
// 0 or a denormal) is refused rather than read as 0 ("none").
double si_of(const OptionSpec& option, double user, const std::string& field) {
  const double si = user * option.scale;
  if (user != 0.0 && !std::isnormal(si)) {
    invalid(field, field + " = " + number_text(user) + " " + std::string(option.range.unit) +
                       " is too small to be told from 0: give 0 or at least " +
                       number_text(std::numeric_limits<double>::min() / option.scale) + " " +
                       std::string(option.range.unit));
  }
  return si;
}

// User units -> SI.
json to_si(const OptionSpec& option, json value, const std::string& field) {
  if (option.scale == 1.0) return value;
  if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      value[i] = si_of(option, value[i].get<double>(), field + "[" + std::to_string(i) + "]");
    }
    return value;
  }
  return value.is_number() ? json(si_of(option, value.get<double>(), field)) : value;
}

// SI -> user units (the OpenAPI defaults).
json to_user(const OptionSpec& option, json value) {
  if (option.scale == 1.0 || !value.is_number()) return value;
  return value.get<double>() / option.scale;
}

// ---- the built-in options --------------------------------------------------------------------

template <class T>
using Field = T& (*)(PlanOptions&);

// Reads through a field accessor of a const PlanOptions (the accessor only selects the member).
template <class T>
const T& read(const PlanOptions& options, Field<T> field) {
  return field(const_cast<PlanOptions&>(options));  // NOLINT: read only
}

OptionSpec spec(std::string_view name, OptionKind kind, std::string doc) {
  OptionSpec s;
  s.name = name;
  s.recipe_name = name;
  s.kind = kind;
  s.doc = std::move(doc);
  return s;
}

template <class T>
OptionSpec plain(std::string_view name, OptionKind kind, const Range& range, Field<T> field,
                 std::string doc) {
  OptionSpec s = spec(name, kind, std::move(doc));
  s.range = range;
  s.get = [field](const PlanOptions& o) { return json(read(o, field)); };
  s.set = [field](PlanOptions& o, const json& v) { field(o) = v.get<T>(); };
  return s;
}

OptionSpec number(std::string_view name, const Range& range, Field<double> field, std::string doc) {
  return plain(name, OptionKind::kNumber, range, field, std::move(doc));
}

OptionSpec integer(std::string_view name, int lo, int hi, Field<int> field, std::string doc) {
  return plain(name, OptionKind::kInteger, Range{double(lo), double(hi), ""}, field,
               std::move(doc));
}

OptionSpec nullable_number(std::string_view name, const Range& range,
                           Field<std::optional<double>> field, std::string doc) {
  OptionSpec s = spec(name, OptionKind::kOptionalNumber, std::move(doc));
  s.range = range;
  s.get = [field](const PlanOptions& o) {
    const std::optional<double>& v = read(o, field);
    return v ? json(*v) : json(nullptr);
  };
  s.set = [field](PlanOptions& o, const json& v) { field(o) = v.get<double>(); };
  return s;
}

template <std::size_t N>
OptionSpec array(std::string_view name, const Range& range, Field<std::array<double, N>> field,
                 std::string doc) {
  OptionSpec s = plain(name, OptionKind::kNumberArray, range, field, std::move(doc));
  s.size = N;
  return s;
}

OptionSpec optional_pair(std::string_view name, const Range& range,
                         Field<std::optional<std::array<double, 2>>> field, std::string doc) {
  OptionSpec s = spec(name, OptionKind::kNumberArray, std::move(doc));
  s.range = range;
  s.size = 2;
  s.get = [field](const PlanOptions& o) {
    const std::optional<std::array<double, 2>>& v = read(o, field);
    return v ? json(*v) : json(nullptr);
  };
  s.set = [field](PlanOptions& o, const json& v) { field(o) = v.get<std::array<double, 2>>(); };
  return s;
}

template <class E>
OptionSpec enumeration(std::string_view name, Field<E> field, std::string doc) {
  OptionSpec s = spec(name, OptionKind::kEnum, std::move(doc));
  s.names = enum_names<E>();
  s.get = [field](const PlanOptions& o) { return json(name_of(read(o, field))); };
  s.set = [field](PlanOptions& o, const json& v) {
    field(o) = enum_from_name<E>(v.get<std::string>()).value_or(field(o));
  };
  return s;
}

OptionSpec damping() {
  OptionSpec s = spec("damping", OptionKind::kDamping,
                      "Damping correlation (thesis, paper, eq227, eq228) or a measured zeta");
  s.range = ranges::kZeta;
  s.get = [](const PlanOptions& o) {
    if (o.model.damping == DampingCorrelation::kExplicit) return json(o.model.explicit_zeta);
    return json(name_of(o.model.damping));
  };
  s.set = [](PlanOptions& o, const json& v) {
    if (v.is_number()) {
      o.model.damping = DampingCorrelation::kExplicit;
      o.model.explicit_zeta = v.get<double>();
    } else {
      o.model.damping = enum_from_name<DampingCorrelation>(v.get<std::string>()).value();
    }
  };
  return s;
}

void check_weights(const json& weights) {
  double sum = 0.0;
  for (const json& w : weights) sum += w.get<double>();
  if (sum <= 0.0) {
    invalid("options.weights", "options.weights = [0, 0, 0]: at least one weight must be > 0");
  }
}

OptionSpec in_mm(OptionSpec s, std::string_view recipe_name) {
  s.scale = 1e-3;
  s.recipe_name = recipe_name;
  return s;
}

OptionSpec in_group(OptionSpec s, std::string_view group) {
  s.group = group;
  return s;
}

// The time budget: how long to search, not what to plan (same recipe, same key).
OptionSpec not_keyed(OptionSpec s) {
  s.recipe_name = {};
  return s;
}

OptionSpec ranked(OptionSpec s, int rank) {
  s.parse_rank = rank;
  return s;
}

OptionSpec min_ramp() {
  OptionSpec s = number(
      "min_ramp_s", Range{ranges::kMinRampS.lo, ranges::kMotionTimeS.hi / 4.0, "s"},
      [](PlanOptions& o) -> double& { return o.min_ramp; },
      "Minimum duration of the jerk ramps 1, 3, 5, 7");
  s.range_for = [](const Format& f) {
    return Range{ranges::kMinRampS.lo, f.motion_time / 4.0, "s"};
  };
  s.message_note = " (the upper bound is format.motion_time_s / 4: four ramps must fit)";
  s.allowed_text =
      number_text(ranges::kMinRampS.lo) + " s to format.motion_time_s / 4 (four ramps must fit)";
  return s;
}

OptionSpec plateau_min() {
  OptionSpec s = array<2>(
      "plateau_min_s", Range{0.0, ranges::kMotionTimeS.hi, "s"},
      [](PlanOptions& o) -> std::array<double, 2>& { return o.plateau_min; },
      "Lower bounds on the plateau durations dT2 and dT6 [s], each 0 to format.motion_time_s; "
      "4 min_ramp_s + both must not exceed format.motion_time_s.");
  s.range_for = [](const Format& f) { return Range{0.0, f.motion_time, "s"}; };
  return s;
}

OptionSpec iir_sample_period() {
  OptionSpec s = number(
      "iir_sample_period_s", kIirSamplePeriod,
      [](PlanOptions& o) -> double& { return o.iir_sample_period; },
      "iir: sample period of the difference equation and of the returned law "
      "(the controller cycle); also <= format.motion_time_s / " +
          std::to_string(kIirMinSamples));
  s.range_for = [](const Format& f) {
    return Range{kIirSamplePeriod.lo, std::min(kIirSamplePeriod.hi, f.motion_time / kIirMinSamples),
                 "s"};
  };
  s.message_note = " (the upper bound is min(0.01 s, format.motion_time_s / " +
                   std::to_string(kIirMinSamples) + "))";
  return s;
}

OptionSpec iir_order() {
  OptionSpec s = spec("iir_order", OptionKind::kInteger,
                      "iir: order of the critically damped target (2: eq. 8, 11; 3: eq. 9, 12, no "
                      "initial peak).");
  s.range = Range{2.0, 3.0, ""};
  s.get = [](const PlanOptions& o) { return json(static_cast<int>(o.iir_order)); };
  s.set = [](PlanOptions& o, const json& v) { o.iir_order = static_cast<IirOrder>(v.get<int>()); };
  return s;
}

std::vector<OptionSpec> multi_notch_and_band_options() {
  OptionSpec weights = array<3>(
      "weights", kWeight, [](PlanOptions& o) -> std::array<double, 3>& { return o.weights; },
      "multi_notch: weights b1, b2, b3 of |X(w-)|², |X(w1)|², |X(w+)|²; at least one > 0.");
  weights.item_doc = "Weight";
  weights.check = check_weights;
  return {
      number(
          "p_notch", kPNotch, [](PlanOptions& o) -> double& { return o.p_notch; },
          "multi_notch: side notches at (1 ± p) omega_1"),
      weights,
      number(
          "band", kBand, [](PlanOptions& o) -> double& { return o.band; },
          "min_jerk_band: half width of the band [(1 - band) w1, (1 + band) w1]"),
      integer(
          "n_band", 1, kMaxBandPoints, [](PlanOptions& o) -> int& { return o.n_band; },
          "min_jerk_band: evenly spaced band frequencies."),
      number(
          "tol_rel", kTolRel, [](PlanOptions& o) -> double& { return o.tol_rel; },
          "min_jerk_band: band limit relative to X_ref, the uniform law's largest |X| on the "
          "band"),
  };
}

std::vector<OptionSpec> time_domain_options() {
  return {
      in_mm(number(
                "eta_rest_max_mm", kEtaMm, [](PlanOptions& o) -> double& { return o.eta_rest_max; },
                "time_domain (objective motion): largest residual wave eta_rest; auto's "
                "too (an auto plan above it is infeasible, never optimal)"),
            "eta_rest_max_m"),
      in_mm(nullable_number(
                "eta_motion_max_mm", kEtaMm,
                [](PlanOptions& o) -> std::optional<double>& { return o.eta_motion_max; },
                "time_domain (objective rest): largest eta_motion; default the "
                "uniform law's nonlinear eta_motion"),
            "eta_motion_max_m"),
      enumeration<TimeDomainObjective>(
          "objective", [](PlanOptions& o) -> TimeDomainObjective& { return o.objective; },
          "time_domain: minimise eta_motion subject to eta_rest <= eta_rest_max_mm (motion) or "
          "eta_rest subject to eta_motion <= eta_motion_max_mm (rest)."),
  };
}

OptionSpec drive_profile() {
  OptionSpec s = enumeration<DriveProfile>(
      "drive_profile", [](PlanOptions& o) -> DriveProfile& { return o.drive_profile; },
      "What the drive runs: free (any 7-segment law, four ramp jerks of their own; a cam table "
      "runs it) or move_absolute (one jerk for the four ramps: what a PLCopen MC_MoveAbsolute "
      "block with a jerk limit runs; the optimisers search that family and the plan carries "
      "move_absolute: distance, velocity, acceleration, deceleration and jerk in mm units; "
      "shaper and iir are refused).");
  s.keyed_when_set = true;
  return s;
}

std::vector<OptionSpec> law_shape_options() {
  return {
      number(
          "rest_time_s", kRestTime, [](PlanOptions& o) -> double& { return o.rest_time; },
          "Rest window after the motion"),
      min_ramp(),
      plain<bool>(
          "fix_constant_velocity_zero", OptionKind::kBool, Range{0.0, 0.0, ""},
          [](PlanOptions& o) -> bool& { return o.fix_constant_velocity_zero; },
          "Force the constant-velocity segment 4 to zero (thesis campaign)."),
      plateau_min(),
      in_group(nullable_number(
                   "a_max", kAMax,
                   [](PlanOptions& o) -> std::optional<double>& { return o.limits.a_max; },
                   "Peak |acceleration| max(A, B); along an arc or a path the total horizontal "
                   "acceleration sqrt(s''^2 + (s'^2/rho)^2)"),
               "limits"),
      in_group(nullable_number(
                   "v_max", kVMax,
                   [](PlanOptions& o) -> std::optional<double>& { return o.limits.v_max; },
                   "Peak velocity (along a path: of s)"),
               "limits"),
      in_group(nullable_number(
                   "j_max", kJMax,
                   [](PlanOptions& o) -> std::optional<double>& { return o.limits.j_max; },
                   "Peak |jerk| over the four ramps (along a path: the tangential jerk)"),
               "limits"),
      drive_profile(),
  };
}

std::vector<OptionSpec> model_and_solver_options() {
  return {
      ranked(damping(), -1),
      ranked(number(
                 "alpha", ranges::kAlpha, [](PlanOptions& o) -> double& { return o.model.alpha; },
                 "Nonlinear stiffening coefficient alpha (eq. 2.35)"),
             -2),
      ranked(integer(
                 "modes", 1, static_cast<int>(kMaxModes),
                 [](PlanOptions& o) -> int& { return o.model.modes; },
                 "Radial modes of the linear model."),
             -3),
      enumeration<SolverChoice>(
          "solver", [](PlanOptions& o) -> SolverChoice& { return o.solver; },
          "NLP solver: auto (NLopt SLSQP, measured best), nlopt, ipopt."),
      not_keyed(number(
          "time_limit_s", kTimeLimit, [](PlanOptions& o) -> double& { return o.time_limit; },
          "Wall-clock budget of the whole plan; on expiry the best admissible point is "
          "returned with status time_limit. The service defaults it to, and caps it at, its "
          "solve budget (setting solve_budget_s, default 10 s); the CLI default is 5 s")),
  };
}

// Naming the shaper chooses its family: with an uncertainty range, shaper then keeps it instead
// of taking the shortest family that holds over the range.
OptionSpec shaper() {
  OptionSpec s = enumeration<ShaperType>(
      "shaper", [](PlanOptions& o) -> ShaperType& { return o.shaper; },
      "shaper: the input shaper on mode 1, by delay in damped periods: zv 1/2, mzv 3/4, "
      "zvd 1, zvdd 3/2, ei 1, ei2 ~3/2, ei3 ~2. zv, mzv, zvd and zvdd cancel omega_1 exactly; "
      "ei, ei2 and ei3 keep the residual below `residual` (V, the height of their humps) over "
      "a band around omega_1 that widens with the shaper: at V = 5 % without damping "
      "omega / omega_1 in 0.968-1.032 (zv), 0.951-1.055 (mzv), 0.856-1.144 (zvd), "
      "0.800-1.200 (ei), 0.638-1.362 (ei2), 0.518-1.482 (ei3). Named, it is used as given "
      "also under options.uncertainty; not named, shaper takes the shortest family whose "
      "residual stays <= residual over the uncertainty range (zv without one).");
  s.set = [](PlanOptions& o, const json& v) {
    o.shaper = enum_from_name<ShaperType>(v.get<std::string>()).value_or(o.shaper);
    o.shaper_for_range = false;
  };
  return s;
}

std::vector<OptionSpec> filter_options() {
  return {
      enumeration<BaseLaw>(
          "base", [](PlanOptions& o) -> BaseLaw& { return o.base; },
          "shaper and iir: the base law, planned over T minus the filter's delay."),
      shaper(),
      number(
          "residual", kResidual, [](PlanOptions& o) -> double& { return o.residual; },
          "shaper ei, ei2, ei3: V, the height of the residual humps around omega_1 (0.05 = 5 %); "
          "under options.uncertainty also the residual a range-chosen shaper may keep"),
      iir_order(),
      number(
          "iir_tau", kIirTau, [](PlanOptions& o) -> double& { return o.iir_tau; },
          "iir: pole tau of the target (s + tau)^n; larger is less delay"),
      iir_sample_period(),
  };
}

OptionSpec robustness() {
  OptionSpec s = plain<bool>(
      "robustness", OptionKind::kBool, Range{0.0, 0.0, ""},
      [](PlanOptions& o) -> bool& { return o.robustness; },
      "Attach the robustness report (SPEC §10): the returned law re-simulated on both models "
      "with every mode frequency scaled by (1 + delta), delta evenly over +-10 % (over the "
      "uncertainty's range when given), and the interval of delta around 0 where "
      "eta_rest_max_mm (and eta_motion_max_mm when given) hold. false leaves it out.");
  s.keyed_when_set = true;
  return s;
}

// A member of options.uncertainty: keyed only when given a value other than its default, so
// the keys of the requests without it stay as they were.
OptionSpec in_uncertainty(OptionSpec s, std::string_view recipe_name) {
  s.group = "uncertainty";
  s.recipe_name = recipe_name;
  s.keyed_when_set = true;
  return s;
}

/// The fill heights options.uncertainty.fill_height_mm allows for `format`: the format's own
/// (1 to 5000 mm, below the container height when given).
Range uncertainty_fill_range(const Format& format) {
  const Range& fill = ranges::kFillHeightMm;
  if (!format.container.height) return fill;
  const double height_mm = mm_of(*format.container.height);
  if (height_mm > fill.hi) return fill;
  return Range{fill.lo, height_mm, fill.unit, false, true};
}

std::vector<OptionSpec> uncertainty_options() {
  OptionSpec omega = number(
      "omega_error_pct", kOmegaErrorPct,
      [](PlanOptions& o) -> double& { return o.uncertainty.omega_error; },
      "Relative error of every mode frequency the plan must hold over: omega_n (1 + delta), "
      "|delta| <= omega_error_pct (0: none)");
  omega.scale = 0.01;
  OptionSpec fill = optional_pair(
      "fill_height_mm", ranges::kFillHeightMm,
      [](PlanOptions& o) -> std::optional<std::array<double, 2>>& {
        return o.uncertainty.fill_height;
      },
      "Fill heights [min, max] the format may have [mm], mapped through the model to the "
      "omega_1 (and zeta) range they imply: each 1 to 5000 mm and below "
      "format.container.height_mm when given, min <= format.fill_height_mm <= max.");
  fill.scale = 1e-3;
  fill.range_for = uncertainty_fill_range;
  OptionSpec viscosity = optional_pair(
      "viscosity_pa_s", kViscosityRangePaS,
      [](PlanOptions& o) -> std::optional<std::array<double, 2>>& {
        return o.uncertainty.viscosity;
      },
      "Dynamic viscosities [min, max] the fluid may have [Pa·s], mapped through the damping "
      "correlation to the zeta range: each 0 to 1e6, min <= the fluid's viscosity <= max; not "
      "with an explicit zeta (options.damping {\"zeta\": z}).");
  OptionSpec samples = integer(
      "sample_points", kMinUncertaintySamples, kMaxUncertaintySamples,
      [](PlanOptions& o) -> int& { return o.uncertainty.sample_points; },
      "time_domain: models evenly over the frequency range (both ends included) whose worst "
      "eta_motion it minimises with eta_rest <= eta_rest_max_mm at every one.");
  samples.keyed_only_if = [](const PlanOptions& o) { return o.uncertainty.active(); };
  samples.read_by = {Strategy::kTimeDomain, Strategy::kAuto};
  return {in_uncertainty(std::move(omega), "omega_error"),
          in_uncertainty(std::move(fill), "uncertainty_fill_height_m"),
          in_uncertainty(std::move(viscosity), "uncertainty_viscosity_pa_s"),
          in_uncertainty(std::move(samples), "uncertainty_sample_points")};
}

// A member of options.model (a calibrated model). omega_scale and height_gain are keyed
// only when they differ from 1, so the keys of requests without a model stay as they were;
// model.alpha and model.zeta write the options alpha and damping write, and are keyed by them.
OptionSpec in_model(OptionSpec s, std::string_view recipe_name) {
  s.group = "model";
  s.recipe_name = recipe_name;
  s.keyed_when_set = true;
  return s;
}

std::vector<OptionSpec> calibrated_model_options() {
  OptionSpec zeta = spec("zeta", OptionKind::kOptionalNumber,
                         "Calibrated damping ratio of the modes (POST /v1/calibrations); "
                         "overrides options.damping");
  zeta.range = ranges::kZeta;
  zeta.get = [](const PlanOptions& o) {
    return o.model.damping == DampingCorrelation::kExplicit ? json(o.model.explicit_zeta)
                                                            : json(nullptr);
  };
  zeta.set = [](PlanOptions& o, const json& v) {
    o.model.damping = DampingCorrelation::kExplicit;
    o.model.explicit_zeta = v.get<double>();
  };
  return {
      in_model(number(
                   "omega_scale", ranges::kModelScale,
                   [](PlanOptions& o) -> double& { return o.model.omega_scale; },
                   "Calibrated scale of every natural frequency omega_n (1: eq. 2.14)"),
               "model_omega_scale"),
      in_model(std::move(zeta), ""),
      in_model(number(
                   "alpha", ranges::kAlpha, [](PlanOptions& o) -> double& { return o.model.alpha; },
                   "Calibrated nonlinear stiffening alpha (eq. 2.35); overrides options.alpha"),
               ""),
      in_model(number(
                   "height_gain", ranges::kModelScale,
                   [](PlanOptions& o) -> double& { return o.model.height_gain; },
                   "Calibrated gain on the predicted wall height, linear and nonlinear (1: none)"),
               "model_height_gain"),
      in_model(
          nullable_number(
              "width_omega_scale", ranges::kModelScale,
              [](PlanOptions& o) -> std::optional<double>& { return o.model.width_omega_scale; },
              "A rectangular container calibrated in both directions (a turned tank): the "
              "scale of the natural frequencies of its modes along the width; omega_scale "
              "is then the length's (absent: omega_scale holds for both)"),
          "model_width_omega_scale"),
      in_model(nullable_number(
                   "width_zeta", ranges::kZeta,
                   [](PlanOptions& o) -> std::optional<double>& { return o.model.width_zeta; },
                   "A rectangular container calibrated in both directions: the damping ratio of "
                   "its modes along the width; zeta is then the length's (absent: the damping of "
                   "the length holds for both)"),
               "model_width_zeta"),
  };
}

OptionRegistry built_in_registry() {
  std::vector<OptionSpec> options;
  for (auto part :
       {multi_notch_and_band_options(), time_domain_options(), law_shape_options(),
        model_and_solver_options(), filter_options(), std::vector<OptionSpec>{robustness()},
        uncertainty_options(), calibrated_model_options()}) {
    for (OptionSpec& o : part) options.push_back(std::move(o));
  }
  return OptionRegistry(
      std::move(options),
      {OptionGroup{"limits", "MachineLimits", "Machine limits; an absent limit is not enforced."},
       OptionGroup{"uncertainty", "Uncertainty",
                   "What the model does not know exactly (SPEC §10); every member optional. "
                   "With omega_error_pct > 0 or a range, the optimising strategies plan for the "
                   "whole omega_1 (and zeta) range it implies, auto compares its candidates by "
                   "their worst case, and the plan carries uncertainty and worst_case.",
                   "uncertainty_"},
       OptionGroup{"model", "CalibratedModel",
                   "A calibrated model (POST /v1/calibrations returns one): each member optional; "
                   "zeta and alpha override options.damping and options.alpha (giving both is "
                   "refused).",
                   "model_"}});
}

// ---- OpenAPI ---------------------------------------------------------------------------------

json number_schema(const Range& range, const std::string& doc, const std::string& allowed_text) {
  json s{{"type", "number"}, {"minimum", range.lo}, {"maximum", range.hi}};
  if (range.lo_open) s["exclusiveMinimum"] = true;
  if (range.hi_open) s["exclusiveMaximum"] = true;
  std::string text = doc;
  if (!range.unit.empty()) text += " [" + std::string(range.unit) + "]";
  text += ". Allowed: " + (allowed_text.empty() ? range.describe() : allowed_text) + ".";
  s["description"] = text;
  return s;
}

json array_schema(const OptionSpec& option) {
  json items =
      option.item_doc.empty()
          ? json{{"type", "number"}, {"minimum", option.range.lo}, {"maximum", option.range.hi}}
          : number_schema(option.range, option.item_doc, "");
  const auto n = static_cast<int>(option.size);
  return {{"type", "array"},
          {"items", items},
          {"minItems", n},
          {"maxItems", n},
          {"description", option.doc}};
}

json kind_schema(const OptionSpec& option) {
  switch (option.kind) {
    case OptionKind::kNumber:
    case OptionKind::kOptionalNumber:
      return number_schema(option.range, option.doc, option.allowed_text);
    case OptionKind::kInteger:
      return {{"type", "integer"},
              {"minimum", static_cast<int>(option.range.lo)},
              {"maximum", static_cast<int>(option.range.hi)},
              {"description", option.doc}};
    case OptionKind::kBool:
      return {{"type", "boolean"}, {"description", option.doc}};
    case OptionKind::kEnum:
      return {{"type", "string"}, {"enum", option.names}, {"description", option.doc}};
    case OptionKind::kNumberArray:
      return array_schema(option);
    case OptionKind::kDamping:
      return {{"$ref", "#/components/schemas/Damping"}};
  }
  return json::object();
}

}  // namespace

// ---- OptionRegistry ----------------------------------------------------------------------------

OptionRegistry::OptionRegistry(std::vector<OptionSpec> options, std::vector<OptionGroup> groups)
    : options_(std::move(options)), groups_(std::move(groups)) {}

void OptionRegistry::add(OptionSpec option) {
  options_.push_back(std::move(option));
}

const OptionSpec* OptionRegistry::find(std::string_view name) const {
  const auto it = std::find_if(options_.begin(), options_.end(),
                               [&](const OptionSpec& o) { return o.name == name; });
  return it == options_.end() ? nullptr : &*it;
}

const OptionGroup* OptionRegistry::group(std::string_view name) const {
  const auto it = std::find_if(groups_.begin(), groups_.end(),
                               [&](const OptionGroup& g) { return g.name == name; });
  return it == groups_.end() ? nullptr : &*it;
}

std::vector<std::string_view> OptionRegistry::option_keys() const {
  std::vector<std::string_view> keys;
  for (const OptionSpec& o : options_) {
    const std::string_view key = o.group.empty() ? o.name : o.group;
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  return keys;
}

std::vector<std::string_view> OptionRegistry::group_keys(std::string_view group_name) const {
  std::vector<std::string_view> keys;
  for (const OptionSpec& o : options_) {
    if (o.group == group_name) keys.push_back(o.name);
  }
  return keys;
}

void OptionRegistry::parse(const json& object, const Format& format, PlanOptions& out) const {
  reject_model_conflicts(object);
  std::vector<const OptionSpec*> order;
  for (const OptionSpec& o : options_) order.push_back(&o);
  std::stable_sort(order.begin(), order.end(), [](const OptionSpec* a, const OptionSpec* b) {
    return a->parse_rank < b->parse_rank;
  });
  std::vector<std::string_view> checked_groups;
  for (const OptionSpec* o : order) {
    const json* container = &object;
    std::string path = "options";
    if (!o->group.empty()) {
      container = given_member(object, o->group);
      if (container == nullptr) continue;
      path = join_path(path, o->group);
      if (std::find(checked_groups.begin(), checked_groups.end(), o->group) ==
          checked_groups.end()) {
        require_object(*container, path);
        reject_unknown_fields(*container, path, group_keys(o->group));
        checked_groups.push_back(o->group);
      }
    }
    const Range range = o->range_for ? o->range_for(format) : o->range;
    std::optional<json> value;
    try {
      value = parse_option(*o, *container, path, range);
      if (value && o->check) o->check(*value);
    } catch (const ApiError& e) {
      if (o->message_note.empty()) throw;
      invalid(e.field(), std::string(e.what()) + o->message_note);
    }
    if (value) o->set(out, to_si(*o, std::move(*value), join_path(path, o->name)));
  }
}

bool OptionSpec::read_by_any(std::span<const Strategy> strategies) const {
  if (read_by.empty()) return true;
  return std::any_of(strategies.begin(), strategies.end(), [this](Strategy s) {
    return std::find(read_by.begin(), read_by.end(), s) != read_by.end();
  });
}

json OptionRegistry::recipe(const PlanOptions& options,
                            std::span<const Strategy> strategies) const {
  json out = json::object();
  const PlanOptions defaults;
  for (const OptionSpec& o : options_) {
    if (o.recipe_name.empty()) continue;
    if (!o.read_by_any(strategies)) continue;
    nlohmann::json value = o.get(options);
    if (o.keyed_when_set && value == o.get(defaults)) continue;
    if (o.keyed_only_if && !o.keyed_only_if(options)) continue;
    out[std::string(o.recipe_name)] = std::move(value);
  }
  return out;
}

const OptionRegistry& plan_option_registry() {
  static const OptionRegistry registry = built_in_registry();
  return registry;
}

std::optional<json> parse_option(const OptionSpec& option, const json& options,
                                 const std::string& path, const Range& range) {
  const json* value = given_member(options, option.name);
  if (value == nullptr) return std::nullopt;
  switch (option.kind) {
    case OptionKind::kNumber:
    case OptionKind::kOptionalNumber:
      return checked_number(value, join_path(path, option.name), range);
    case OptionKind::kInteger:
      return api::optional_integer(options, path, option.name, static_cast<int>(range.lo),
                                   static_cast<int>(range.hi), 0);
    case OptionKind::kBool:
      return optional_bool(options, path, option.name, false);
    case OptionKind::kEnum:
      return choice(options, path, option.name, option.names);
    case OptionKind::kNumberArray:
      return number_array(options, path, option.name, range, option.size);
    case OptionKind::kDamping:
      return damping_value(options, path);
  }
  return std::nullopt;
}

json option_schema(const OptionSpec& option) {
  json s = kind_schema(option);
  if (option.kind == OptionKind::kDamping || !option.get) return s;
  json fallback = option.get(PlanOptions{});
  if (!fallback.is_null()) s["default"] = to_user(option, std::move(fallback));
  return s;
}

}  // namespace slosh::api
