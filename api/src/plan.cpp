#include "slosh/api/plan.hpp"

#include <openssl/evp.h>

#include <cmath>
#include <numbers>

#include "slosh/api/core_input.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/law_json.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/response/spectrum.hpp"

namespace slosh::api {

namespace {

/// Version of the planner's numerics; part of every recipe key, bumped when results change.
constexpr const char* kPlannerVersion = "plan-v2";
/// Spectrum grid of the response: 0 .. kSpectrumMaxF1 f1 in kSpectrumPoints points (SPEC §6).
constexpr double kSpectrumMaxF1 = 5.0;
constexpr int kSpectrumPoints = 512;

using namespace plan_ranges;  // NOLINT: the option ranges of plan.hpp

const char* kStrategies =
    "\"baseline\", \"notch\", \"multi_notch\", \"min_jerk_band\", "
    "\"time_domain\", \"fir_chain\", \"shaper\", \"iir\", \"auto\"";

const nlohmann::json* member(const nlohmann::json& object, std::string_view key) {
  auto it = object.find(key);
  return it == object.end() || it->is_null() ? nullptr : &*it;
}

template <std::size_t N>
std::array<double, N> number_array(const nlohmann::json& object, const std::string& path,
                                   std::string_view key, const Range& range,
                                   std::array<double, N> fallback) {
  const nlohmann::json* value = member(object, key);
  if (value == nullptr) return fallback;
  const std::string field = join_path(path, key);
  if (!value->is_array() || value->size() != N) {
    invalid(field,
            field + " must be an array of " + std::to_string(N) + " numbers, got " + show(*value));
  }
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    out[i] = checked_number(&(*value)[i], field + "[" + std::to_string(i) + "]", range);
  }
  return out;
}

std::string choice(const nlohmann::json& object, const std::string& path, std::string_view key,
                   const std::vector<std::string>& allowed, const std::string& fallback) {
  const nlohmann::json* value = member(object, key);
  if (value == nullptr) return fallback;
  if (value->is_string()) {
    const auto text = value->get<std::string>();
    for (const auto& a : allowed) {
      if (a == text) return text;
    }
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
  const std::string field = join_path(path, key);
  invalid(field, field + " = " + show(*value) + " is not allowed: one of " + list);
}

/// An option naming a value of E (its EnumNames table); `fallback` when absent.
template <typename E>
E enum_choice(const nlohmann::json& options, std::string_view key, E fallback) {
  const std::string name =
      choice(options, "options", key, enum_names<E>(), std::string(name_of(fallback)));
  return enum_from_name<E>(name).value_or(fallback);
}

void parse_limits(const nlohmann::json& options, MachineLimits& limits) {
  const nlohmann::json* value = member(options, "limits");
  if (value == nullptr) return;
  require_object(*value, "options.limits");
  reject_unknown_fields(*value, "options.limits", {"a_max", "v_max", "j_max"});
  auto one = [&](std::string_view key, const Range& range) -> std::optional<double> {
    const nlohmann::json* v = member(*value, key);
    if (v == nullptr) return std::nullopt;
    return checked_number(v, join_path("options.limits", key), range);
  };
  limits.a_max = one("a_max", kAMax);
  limits.v_max = one("v_max", kVMax);
  limits.j_max = one("j_max", kJMax);
}

nlohmann::json prediction(const LawPrediction& p) {
  return {{"nonlinear", peaks_json(p.nonlinear)}, {"linear", peaks_json(p.linear)}};
}

double reduction(double baseline, double value) {
  return baseline > 0.0 ? 100.0 * (1.0 - value / baseline) : 0.0;
}

nlohmann::json design_json(const FilterDesign& design) {
  struct Visitor {
    nlohmann::json operator()(const FirChainDesign& d) const {
      return {{"method", "fir_chain"},
              {"t1_s", d.t1},
              {"t2_s", d.t2},
              {"t3_s", d.t3},
              {"conditions_14", d.trapezoidal}};
    }
    nlohmann::json operator()(const ShaperDesign& d) const {
      nlohmann::json impulses = nlohmann::json::array();
      for (const Impulse& i : d.shaper.impulses) {
        impulses.push_back({{"t_s", i.time}, {"amplitude", i.amplitude}});
      }
      return {{"method", "shaper"},          {"shaper", to_string(d.shaper.type)},
              {"base", to_string(d.base)},   {"base_duration_s", d.base_duration},
              {"delay_s", d.shaper.delay()}, {"impulses", impulses},
              {"residual_at_f1", d.residual}};
    }
    nlohmann::json operator()(const IirDesign& d) const {
      nlohmann::json a = nlohmann::json::array(), b = nlohmann::json::array();
      for (long double v : d.filter.a) a.push_back(static_cast<double>(v));
      for (long double v : d.filter.b) b.push_back(static_cast<double>(v));
      return {{"method", "iir"},
              {"order", static_cast<int>(d.filter.order)},
              {"tau", d.filter.tau},
              {"sample_period_s", d.filter.sample_period},
              {"base", to_string(d.base)},
              {"base_duration_s", d.base_duration},
              {"delay_s", d.delay},
              {"filtered_duration_s", d.filtered_duration},
              {"iterations", d.iterations},
              {"correction_pct", 100.0 * d.correction},
              {"a", a},
              {"b", b}};
    }
  };
  return std::visit(Visitor{}, design);
}

std::string to_hex(const unsigned char* data, std::size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < n; ++i) {
    out += digits[data[i] >> 4];
    out += digits[data[i] & 15];
  }
  return out;
}

}  // namespace

PlanRequest parse_plan_request(const nlohmann::json& body) {
  require_object(body, "");
  reject_unknown_fields(body, "", {"format", "strategy", "options", "sample_period_s"});
  PlanRequest r;
  r.format = parse_request_format(body);
  if (const nlohmann::json* s = member(body, "strategy")) {
    std::optional<Strategy> strategy;
    if (s->is_string()) strategy = parse_strategy(s->get<std::string>());
    if (!strategy) {
      invalid("strategy", "strategy = " + show(*s) + " is not allowed: one of " + kStrategies);
    }
    r.strategy = *strategy;
  }

  nlohmann::json options = body.value("options", nlohmann::json::object());
  if (options.is_null()) options = nlohmann::json::object();
  require_object(options, "options");
  reject_unknown_fields(options, "options",
                        {"p_notch",
                         "weights",
                         "band",
                         "n_band",
                         "tol_rel",
                         "eta_rest_max_mm",
                         "eta_motion_max_mm",
                         "objective",
                         "rest_time_s",
                         "min_ramp_s",
                         "fix_constant_velocity_zero",
                         "plateau_min_s",
                         "limits",
                         "damping",
                         "alpha",
                         "modes",
                         "solver",
                         "time_limit_s",
                         "base",
                         "shaper",
                         "residual",
                         "iir_order",
                         "iir_tau",
                         "iir_sample_period_s"});
  PlanOptions& o = r.options;
  const double T = r.format.motion_time;
  parse_model_options(options, "options", o.model);
  o.p_notch = optional_number(options, "options", "p_notch", kPNotch, o.p_notch);
  o.weights = number_array<3>(options, "options", "weights", kWeight, o.weights);
  if (o.weights[0] + o.weights[1] + o.weights[2] <= 0.0) {
    invalid("options.weights", "options.weights = [0, 0, 0]: at least one weight must be > 0");
  }
  o.band = optional_number(options, "options", "band", kBand, o.band);
  o.n_band = optional_integer(options, "options", "n_band", 1, kMaxBandPoints, o.n_band);
  o.tol_rel = optional_number(options, "options", "tol_rel", kTolRel, o.tol_rel);
  o.eta_rest_max =
      optional_number(options, "options", "eta_rest_max_mm", kEtaMm, o.eta_rest_max * 1e3) * 1e-3;
  if (const nlohmann::json* v = member(options, "eta_motion_max_mm")) {
    o.eta_motion_max = checked_number(v, "options.eta_motion_max_mm", kEtaMm) * 1e-3;
  }
  o.objective = choice(options, "options", "objective", {"motion", "rest"}, "motion") == "rest"
                    ? TimeDomainObjective::kRest
                    : TimeDomainObjective::kMotion;
  o.rest_time = optional_number(options, "options", "rest_time_s", kRestTime, o.rest_time);
  const Range min_ramp{ranges::kMinRampS.lo, T / 4.0, "s"};
  try {
    o.min_ramp = optional_number(options, "options", "min_ramp_s", min_ramp, o.min_ramp);
  } catch (const ApiError& e) {
    invalid(e.field(), std::string(e.what()) +
                           " (the upper bound is format.motion_time_s / 4: four ramps must fit)");
  }
  o.fix_constant_velocity_zero =
      optional_bool(options, "options", "fix_constant_velocity_zero", o.fix_constant_velocity_zero);
  o.plateau_min =
      number_array<2>(options, "options", "plateau_min_s", Range{0.0, T, "s"}, o.plateau_min);
  parse_limits(options, o.limits);
  const std::string solver =
      choice(options, "options", "solver", {"auto", "nlopt", "ipopt"}, "auto");
  o.solver = solver == "nlopt"   ? SolverChoice::kNlopt
             : solver == "ipopt" ? SolverChoice::kIpopt
                                 : SolverChoice::kAuto;
  o.time_limit = optional_number(options, "options", "time_limit_s", kTimeLimit, o.time_limit);
  o.base = enum_choice(options, "base", o.base);
  o.shaper = enum_choice(options, "shaper", o.shaper);
  o.residual = optional_number(options, "options", "residual", kResidual, o.residual);
  o.iir_order = static_cast<IirOrder>(
      optional_integer(options, "options", "iir_order", 2, 3, static_cast<int>(o.iir_order)));
  o.iir_tau = optional_number(options, "options", "iir_tau", kIirTau, o.iir_tau);
  const Range iir_period{kIirSamplePeriod.lo, std::min(kIirSamplePeriod.hi, T / kIirMinSamples),
                         "s"};
  try {
    o.iir_sample_period =
        optional_number(options, "options", "iir_sample_period_s", iir_period, o.iir_sample_period);
  } catch (const ApiError& e) {
    invalid(e.field(), std::string(e.what()) +
                           " (the upper bound is min(0.01 s, format.motion_time_s / " +
                           std::to_string(kIirMinSamples) + "))");
  }
  // Relations between options (e.g. ramps + plateau minimums longer than T).
  InvalidInput error;
  if (!o.is_valid(r.format, &error)) {
    invalid("options", "options." + input_sentence(error, r.format, o));
  }

  r.sample_period = parse_sample_period(body, T + o.rest_time);
  return r;
}

nlohmann::json canonical_recipe(const PlanRequest& r) {
  const Format& f = r.format;
  const PlanOptions& o = r.options;
  auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  nlohmann::json damping = to_string(o.model.damping);
  if (o.model.damping == DampingCorrelation::kExplicit) damping = o.model.explicit_zeta;
  return {{"version", kPlannerVersion},
          {"format",
           {{"radius_m", f.container.radius},
            {"height_m", optional(f.container.height)},
            {"fill_height_m", f.fill_height},
            {"density_kg_m3", f.fluid.density},
            {"viscosity_pa_s", f.fluid.viscosity},
            // The plan echoes the fluid's name: two names are two answers (a cached plan never
            // shows one client's fluid name to another).
            {"fluid_name", f.fluid.name},
            {"stroke_m", f.stroke},
            {"motion_time_s", f.motion_time}}},
          {"strategy", to_string(r.strategy)},
          {"options",
           {{"p_notch", o.p_notch},
            {"weights", o.weights},
            {"band", o.band},
            {"n_band", o.n_band},
            {"tol_rel", o.tol_rel},
            {"eta_rest_max_m", o.eta_rest_max},
            {"eta_motion_max_m", optional(o.eta_motion_max)},
            {"objective", o.objective == TimeDomainObjective::kRest ? "rest" : "motion"},
            {"rest_time_s", o.rest_time},
            {"min_ramp_s", o.min_ramp},
            {"fix_constant_velocity_zero", o.fix_constant_velocity_zero},
            {"plateau_min_s", o.plateau_min},
            {"a_max", optional(o.limits.a_max)},
            {"v_max", optional(o.limits.v_max)},
            {"j_max", optional(o.limits.j_max)},
            {"damping", damping},
            {"alpha", o.model.alpha},
            {"modes", o.model.modes},
            {"solver", to_string(o.solver)},
            {"base", to_string(o.base)},
            {"shaper", to_string(o.shaper)},
            {"residual", o.residual},
            {"iir_order", static_cast<int>(o.iir_order)},
            {"iir_tau", o.iir_tau},
            {"iir_sample_period_s", o.iir_sample_period}}}};
}

std::string recipe_key(const PlanRequest& request) {
  const std::string text = canonical_recipe(request).dump();
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256 of the recipe failed");
  }
  return to_hex(digest, 16);
}

nlohmann::json plan_json(const PlanRequest& request, const PlanResult& r) {
  const Format& f = request.format;
  const double T = f.motion_time;
  const std::optional<SevenSegmentLaw> seven =
      r.durations ? std::optional<SevenSegmentLaw>(SevenSegmentLaw(*r.durations, f.stroke))
                  : std::nullopt;

  // Amplitude spectrum |X_a| of the plan and of the uniform law, 0 .. 5 f1: closed form for the
  // 7-segment laws, piece by piece for the general ones.
  const double f1 = r.model.omega1() / (2.0 * std::numbers::pi);
  const Durations uniform = uniform_durations(T);
  std::vector<double> f_hz(kSpectrumPoints), amp(kSpectrumPoints), amp_base(kSpectrumPoints);
  for (int k = 0; k < kSpectrumPoints; ++k) {
    const double fk = kSpectrumMaxF1 * f1 * k / (kSpectrumPoints - 1);
    const double w = 2.0 * std::numbers::pi * fk;
    f_hz[k] = fk;
    amp[k] = std::abs(seven ? seven_segment_spectrum(*r.durations, f.stroke, w)
                            : acceleration_spectrum(r.law, w));
    amp_base[k] = std::abs(seven_segment_spectrum(uniform, f.stroke, w));
  }
  nlohmann::json f_modes = nlohmann::json::array();
  for (double w : r.model.omega) f_modes.push_back(w / (2.0 * std::numbers::pi));
  nlohmann::json markers{
      {"f1_hz", f1},
      {"band_hz",
       {r.band_omega[0] / (2.0 * std::numbers::pi), r.band_omega[1] / (2.0 * std::numbers::pi)}},
      {"f_modes_hz", f_modes}};
  if (r.strategy == Strategy::kMultiNotch) {
    const double p = request.options.p_notch;
    markers["notch_hz"] = {(1.0 - p) * f1, f1, (1.0 + p) * f1};
  }

  nlohmann::json out;
  out["key"] = recipe_key(request);
  out["cached"] = false;
  out["strategy"] = to_string(r.strategy);
  out["status"] = to_string(r.status);
  out["message"] = r.message;
  if (seven) {
    nlohmann::json pct = nlohmann::json::array();
    for (double d : *r.durations) pct.push_back(100.0 * d / T);
    double j_peak = 0.0;
    for (double j : seven->jerks()) j_peak = std::max(j_peak, std::abs(j));
    out["durations_s"] = *r.durations;
    out["durations_pct"] = pct;
    out["switch_times_s"] = seven->switch_times();
    out["kinematics"] = {{"a_max", r.A},
                         {"a_min", r.B},
                         {"v_peak", seven->v_peak()},
                         {"j_peak", j_peak},
                         {"jerks_m_s3", seven->jerks()}};
  } else {
    // A general law (SPEC §7 keeps the fields; they are null): its shape is in `law`.
    out["durations_s"] = nullptr;
    out["durations_pct"] = nullptr;
    out["switch_times_s"] = nullptr;
    const KinematicSummary& k = r.prediction.kinematics;
    out["kinematics"] = {{"a_max", r.A},
                         {"a_min", r.B},
                         {"v_peak", k.v_peak},
                         {"j_peak", k.j_peak},
                         {"jerks_m_s3", nullptr}};
  }
  out["law"] = law_json(r.law, r.durations);
  if (r.design) out["design"] = design_json(*r.design);
  out["model"] = model_json(r.model, request.options.model);
  out["prediction"] = prediction(r.prediction);
  out["baseline"] = prediction(r.baseline);
  out["baseline"]["durations_s"] = uniform;
  out["reduction_pct"] = {
      {"motion", reduction(r.baseline.nonlinear.motion.value, r.prediction.nonlinear.motion.value)},
      {"rest", reduction(r.baseline.nonlinear.rest.value, r.prediction.nonlinear.rest.value)},
      {"linear",
       {{"motion", reduction(r.baseline.linear.motion.value, r.prediction.linear.motion.value)},
        {"rest", reduction(r.baseline.linear.rest.value, r.prediction.linear.rest.value)}}}};
  out["spectrum"] = {{"f_hz", f_hz},
                     {"amplitude", amp},
                     {"baseline_amplitude", amp_base},
                     {"units", {{"f_hz", "Hz"}, {"amplitude", "m/s (|X_a|)"}}},
                     {"markers", markers}};
  out["solver"] = {{"name", r.solver.name},
                   {"iterations", r.solver.iterations},
                   {"starts", r.solver.starts},
                   {"objective", r.solver.objective},
                   {"solve_ms", r.solver.solve_ms}};
  if (!r.candidates.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const PlanCandidate& c : r.candidates) {
      list.push_back({{"strategy", to_string(c.strategy)},
                      {"status", to_string(c.status)},
                      {"durations_s", c.durations ? nlohmann::json(*c.durations) : nullptr},
                      {"law_type", to_string(law_type_of(c.law, c.durations))},
                      {"prediction", prediction(c.prediction)},
                      {"a_peak", std::max(c.prediction.kinematics.a_peak_positive,
                                          c.prediction.kinematics.a_peak_negative)},
                      {"chosen", c.chosen}});
    }
    out["candidates"] = list;
  }
  out["format"] = format_json(f);
  out["rest_time_s"] = request.options.rest_time;
  out["warnings"] = r.warnings;
  require_finite(out);
  return out;
}

void add_series(const PlanRequest& request, nlohmann::json& plan) {
  if (!request.sample_period) return;
  const auto law = plan.find("law");
  if (law == plan.end() || law->is_null()) return;  // a design without a law has no series
  // The plan's law in exactly the form simulate accepts (its ramps were checked by the planner).
  ParsedLaw parsed = parse_law(*law, "law", request.format, ranges::kMinRampS.lo);
  SimulateRequest s;
  s.format = request.format;
  s.law_type = parsed.type;
  s.durations = parsed.durations;
  s.law = std::move(parsed.law);
  s.options.model = request.options.model;
  s.options.rest_time = request.options.rest_time;
  s.options.sample_period = request.sample_period;
  plan["series"] = run_simulate(s)["series"];
}

nlohmann::json run_plan(const PlanRequest& request) {
  const PlanResult result = plan(request.format, request.strategy, request.options);
  if (result.invalid_input) {
    // The request passed the API's ranges but not the planner's own checks (e.g. a format whose
    // uniform law already drives the model out of its range): a 422, not a plan of zeros.
    throw ApiError(ErrorCode::kInvalidValue, "format",
                   plan_refusal(*result.invalid_input, request.format, request.options));
  }
  nlohmann::json out = plan_json(request, result);
  add_series(request, out);
  return out;
}

}  // namespace slosh::api
