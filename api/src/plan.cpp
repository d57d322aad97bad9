#include "slosh/api/plan.hpp"

#include <openssl/evp.h>

#include <array>
#include <cmath>
#include <numbers>

#include "slosh/api/core_input.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/law_json.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/api/plan_warnings.hpp"
#include "slosh/api/robustness_json.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/api/spatial_simulate.hpp"
#include "slosh/core/response/spectrum.hpp"
#include "slosh/core/strategy/path_plan.hpp"

namespace slosh::api {

namespace {

/// Version of the planner's numerics; part of every recipe key, bumped when results change.
/// plan-v14: when a rectangular tank's nonlinear model holds for some of the laws compared and not
/// for others, worse_than_baseline compares the linear figures alone and auto ranks its
/// candidates on the linear model. plan-v15: a rectangular tank's steepness warning judges each
/// direction's wave on its own side, a fill height range reaching a fill the models do not
/// describe is said (fill_range_beyond_models), and an acceptable plan says why. plan-v16: a
/// bound met on a rectangular tank's linear figures standing in for its nonlinear model keeps
/// time_domain and auto from optimal, the modal sum's convergence is said
/// (modal_sum_not_converged), and a plan past its budget is time_limit. plan-v17: a turned
/// tank's design over both directions that is not usable, or sloshes more than the uniform law,
/// gives way to a direction's own design that is neither, and two first modes within 0.1 % of
/// each other are notched double. plan-v18: a turned tank's design over both directions that
/// rests above the uniform law gives way to a direction's own design that rests lower, an
/// unusable one to an unusable own design that rests lower, a spectral law on a turned tank is
/// weighed against its mirror, and auto's candidates that slosh more than the uniform law are
/// not optimal.
constexpr const char* kPlannerVersion = "plan-v18";
/// Version of the numerics of plans along an arc or a path (in their keys only). path-v6: the
/// reductions on one model and the uniform law's out-of-range warning along a path, as plan-v13;
/// path-v7: objective rest's runs again from the solver's nearest evaluation, and a budget that
/// ends returns only admissible laws as such; path-v8: worse_than_baseline and auto's ranking on
/// one model, as plan-v14; path-v9: the steepness warning per direction, as plan-v15; path-v10:
/// the spectral strategies keep a_max on the total acceleration, and the yaw warning finds the
/// peak inside a smooth law's piece; path-v11: as plan-v17; path-v12: as plan-v18, a spectral
/// law's speed held where the normal acceleration alone breaks a_max, and no law verified once
/// the budget is spent (the uniform law stands in).
constexpr const char* kPathPlannerVersion = "path-v12";
/// Spectrum grid of the response: 0 .. kSpectrumMaxF1 f1 in kSpectrumPoints points (SPEC §6).
constexpr double kSpectrumMaxF1 = 5.0;
constexpr int kSpectrumPoints = 512;

Strategy parse_request_strategy(const nlohmann::json& body) {
  const nlohmann::json* s = given_member(body, "strategy");
  if (s == nullptr) return Strategy::kAuto;
  std::optional<Strategy> strategy;
  if (s->is_string()) strategy = parse_strategy(s->get<std::string>());
  if (!strategy) {
    invalid("strategy", "strategy = " + show(*s) + " is not allowed: one of " +
                            quoted_names(enum_names<Strategy>()));
  }
  return *strategy;
}

/// The "options" object of a request (an empty one when absent or null).
nlohmann::json request_options(const nlohmann::json& body) {
  nlohmann::json options = body.value("options", nlohmann::json::object());
  if (options.is_null()) options = nlohmann::json::object();
  require_object(options, "options");
  return options;
}

nlohmann::json prediction_json(const LawPrediction& p) {
  return api::prediction_json(p.nonlinear, p.linear);
}

/// The worst case over an uncertainty range: each model's peaks, null for a model that diverges
/// somewhere in the range (the nonlinear one can, far outside its validity: no bound to give).
nlohmann::json worst_case_json(const LawPrediction& p) {
  auto model = [](const SloshPeaks& peaks) {
    if (!std::isfinite(peaks.motion.value) || !std::isfinite(peaks.rest.value)) {
      return nlohmann::json(nullptr);
    }
    return peaks_json(peaks);
  };
  return {{"nonlinear", model(p.nonlinear)}, {"linear", model(p.linear)}};
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

/// The options a plan along an arc or a path does not apply yet: refused rather than ignored.
void refuse_path_options(const PlanOptions& o) {
  if (!o.uncertainty.active()) return;
  // The range given is named (a recipe table then names its column).
  const std::string field = uncertainty_range_field(o.uncertainty);
  invalid(field, field +
                     " is not available along an arc or a path yet: a plan along a path is "
                     "verified at the nominal model (leave options.uncertainty out, or plan on "
                     "a straight line)");
}

}  // namespace

PlanRequest parse_plan_request(const nlohmann::json& given, const OptionRegistry& registry) {
  // A line motion is the stroke (motion_json.hpp): the same request, key and answer; an arc or a
  // path plans along it.
  std::optional<SpatialFormat> spatial = planned_path_format(given);
  const std::optional<nlohmann::json> line = spatial ? std::nullopt : straight_line_body(given);
  const nlohmann::json& body = line ? *line : given;
  require_object(body, "");
  reject_unknown_fields(body, "", {"format", "strategy", "options", "sample_period_s"});
  PlanRequest r;
  if (spatial) {
    r.format = spatial->format;
    r.motion = std::move(spatial->motion);
  } else {
    r.format = parse_request_format(body);
  }
  r.strategy = parse_request_strategy(body);
  const nlohmann::json options = request_options(body);
  reject_unknown_fields(options, "options", registry.option_keys());
  refuse_cylinder_model_options(r.format, options, "options");
  PlanOptions& o = r.options;
  registry.parse(options, r.format, o);
  // Relations between options (e.g. ramps + plateau minimums longer than T).
  InvalidInput error;
  if (!o.is_valid(r.format, &error)) {
    invalid(options_field(error, o), "options." + input_sentence(error, r.format, o));
  }
  if (std::optional<InvalidInput> why = drive_profile_refusal(r.strategy, o.drive_profile)) {
    invalid("options.drive_profile", "options." + why->message);
  }
  if (std::optional<InvalidInput> why = band_refusal(r.strategy, r.format, o)) {
    invalid(options_field(*why, o), "options." + input_sentence(*why, r.format, o));
  }

  if (r.motion) refuse_path_options(o);
  r.sample_period = parse_sample_period(body, r.format.motion_time + o.rest_time);
  return r;
}

nlohmann::json canonical_recipe(const PlanRequest& r, const OptionRegistry& registry,
                                std::string_view version, std::span<const Strategy> read_by) {
  const Format& f = r.format;
  auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  const std::array<Strategy, 1> own{r.strategy};
  nlohmann::json options =
      registry.recipe(r.options, read_by.empty() ? std::span<const Strategy>(own) : read_by);
  // A warm start (min-time searches) is part of the answer; absent, the keys stay as they were.
  if (r.options.warm_start) options["warm_start_s"] = *r.options.warm_start;
  // A shaper named under an uncertainty range is used as given (not the family for the range):
  // another answer. Without a range naming the shaper changes nothing, nor the key.
  if (r.options.uncertainty.active() && !r.options.shaper_for_range) {
    options["shaper_for_range"] = false;
  }
  // "version" names the numerics (bumped with them, as before the slosh version was part of the
  // key); "slosh_version" the release that plans: an upgrade never answers with an older plan.
  nlohmann::json recipe = {{"version", kPlannerVersion},
                           {"slosh_version", version},
                           {"format",
                            {{"radius_m", f.container.radius},
                             {"height_m", optional(f.container.height)},
                             {"fill_height_m", f.fill_height},
                             {"density_kg_m3", f.fluid.density},
                             {"viscosity_pa_s", f.fluid.viscosity},
                             // The plan echoes the fluid's name: two names are two answers (a
                             // cached plan never shows one client's fluid name to another).
                             {"fluid_name", f.fluid.name},
                             {"stroke_m", f.stroke},
                             {"motion_time_s", f.motion_time}}},
                           {"strategy", to_string(r.strategy)},
                           {"options", std::move(options)}};
  // Only a plan along an arc or a path has the member: every other key stays as it was.
  // Plans along a path have numerics of their own (plan_on_path), versioned beside the
  // planner's: bumped with them, the straight line's keys unchanged.
  if (r.motion) {
    recipe["motion"] = canonical_motion(*r.motion);
    recipe["path_planner"] = kPathPlannerVersion;
  }
  // A rectangular container is another answer; the cylinder's keys stay as they were.
  if (const auto& t = f.container.rectangular) {
    nlohmann::json& format = recipe["format"];
    format.erase("radius_m");
    format["shape"] = "rectangular";
    format["length_m"] = t->length;
    format["width_m"] = t->width;
    format["orientation_deg"] = t->orientation_deg;
  }
  return recipe;
}

std::string recipe_key(const PlanRequest& request, const OptionRegistry& registry,
                       std::string_view version) {
  return sha256_key(canonical_recipe(request, registry, version).dump());
}

std::string sha256_key(const std::string& text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256 of the recipe failed");
  }
  return to_hex(digest, 16);
}

namespace {

/// Amplitude spectrum |X_a| of the plan and of the uniform law, 0 .. 5 f1: closed form for the
/// 7-segment laws, piece by piece for the general ones.
nlohmann::json spectrum_json(const PlanRequest& request, const PlanResult& r) {
  const Format& f = request.format;
  const double f1 = r.model.omega1() / (2.0 * std::numbers::pi);
  const Durations uniform = uniform_durations(f.motion_time);
  std::vector<double> f_hz(kSpectrumPoints), amp(kSpectrumPoints), amp_base(kSpectrumPoints);
  for (int k = 0; k < kSpectrumPoints; ++k) {
    const double fk = kSpectrumMaxF1 * f1 * k / (kSpectrumPoints - 1);
    const double w = 2.0 * std::numbers::pi * fk;
    f_hz[k] = fk;
    amp[k] = std::abs(r.durations ? seven_segment_spectrum(*r.durations, f.stroke, w)
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
  // Where the returned law notches (notch, multi_notch, or auto's choice of either): on a turned
  // tank around each excited direction's first mode, under an uncertainty range at its middle
  // with the side notches at its ends.
  if (const std::vector<double> notched = notched_frequencies(f, request.options, r);
      !notched.empty()) {
    nlohmann::json notch = nlohmann::json::array();
    for (double w : notched) notch.push_back(w / (2.0 * std::numbers::pi));
    markers["notch_hz"] = std::move(notch);
  }
  return {{"f_hz", f_hz},
          {"amplitude", amp},
          {"baseline_amplitude", amp_base},
          {"units", {{"f_hz", "Hz"}, {"amplitude", "m/s (|X_a|)"}}},
          {"markers", markers}};
}

/// durations_s, durations_pct, switch_times_s and kinematics: of the 7-segment law, or null
/// (SPEC §7 keeps the fields) with the general law's peaks.
void add_kinematics(const PlanRequest& request, const PlanResult& r, nlohmann::json& out) {
  const double T = request.format.motion_time;
  if (r.durations) {
    const SevenSegmentLaw seven(*r.durations, request.format.stroke);
    nlohmann::json pct = nlohmann::json::array();
    for (double d : *r.durations) pct.push_back(100.0 * d / T);
    double j_peak = 0.0;
    for (double j : seven.jerks()) j_peak = std::max(j_peak, std::abs(j));
    out["durations_s"] = *r.durations;
    out["durations_pct"] = pct;
    out["switch_times_s"] = seven.switch_times();
    out["kinematics"] = {{"a_max", r.A},
                         {"a_min", r.B},
                         {"v_peak", seven.v_peak()},
                         {"j_peak", j_peak},
                         {"jerks_m_s3", seven.jerks()}};
    return;
  }
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

/// The reductions against the uniform law: on the nonlinear model, or on the linear one when
/// both laws' nonlinear figures do not come from one model (`one_model`, the warning
/// reductions_on_linear_model: a rectangular tank's nonlinear model holds for one law only).
nlohmann::json reduction_json(const LawPrediction& baseline, const LawPrediction& plan,
                              bool one_model) {
  auto pair = [](const SloshPeaks& base, const SloshPeaks& p) {
    return nlohmann::json{{"motion", reduction_percent(base.motion.value, p.motion.value)},
                          {"rest", reduction_percent(base.rest.value, p.rest.value)}};
  };
  nlohmann::json out =
      one_model ? pair(baseline.linear, plan.linear) : pair(baseline.nonlinear, plan.nonlinear);
  out["model"] = one_model ? "linear" : "nonlinear";
  out["linear"] = pair(baseline.linear, plan.linear);
  return out;
}

/// The MC_MoveAbsolute inputs in the units a PLC axis in millimetres takes.
nlohmann::json move_absolute_json(const MoveAbsoluteProfile& m) {
  return {{"distance_mm", m.distance * 1e3},
          {"velocity_mm_s", m.velocity * 1e3},
          {"acceleration_mm_s2", m.acceleration * 1e3},
          {"deceleration_mm_s2", m.deceleration * 1e3},
          {"jerk_mm_s3", m.jerk * 1e3}};
}

nlohmann::json candidates_json(const std::vector<PlanCandidate>& candidates) {
  nlohmann::json list = nlohmann::json::array();
  for (const PlanCandidate& c : candidates) {
    nlohmann::json item{{"strategy", to_string(c.strategy)},
                        {"status", to_string(c.status)},
                        {"durations_s", c.durations ? nlohmann::json(*c.durations) : nullptr},
                        {"law_type", to_string(law_type_of(c.law, c.durations))},
                        {"prediction", prediction_json(c.prediction)},
                        {"a_peak", std::max(c.prediction.kinematics.a_peak_positive,
                                            c.prediction.kinematics.a_peak_negative)},
                        {"chosen", c.chosen}};
    // Why auto did not return it: the rule's reason code and the figures that decided it.
    const bool lost = c.lost != CandidateLoss::kNone;
    item["reason"] = lost ? nlohmann::json(std::string(name_of(c.lost))) : nlohmann::json();
    item["reason_detail"] = lost ? nlohmann::json(c.lost_detail) : nlohmann::json();
    item["warnings"] = c.worse_than_baseline.empty()
                           ? nlohmann::json::array()
                           : nlohmann::json::array({c.worse_than_baseline});
    if (c.worst_case) item["worst_case"] = worst_case_json(*c.worst_case);
    list.push_back(std::move(item));
  }
  return list;
}

/// The blocks of SPEC §10: the uncertainty range and the worst case over it (when the request
/// gives one), the robustness report (unless the request opts out).
void add_robustness(const PlanRequest& request, const PlanResult& r, nlohmann::json& out) {
  if (r.uncertainty) {
    // An option the strategy does not read stays out of the key, so the plan answers requests
    // that differ there: its echo is null.
    const OptionSpec* samples = plan_option_registry().find("sample_points");
    const std::array<Strategy, 1> own{request.strategy};
    out["uncertainty"] = uncertainty_json(*r.uncertainty, request.options.uncertainty,
                                          samples == nullptr || samples->read_by_any(own));
  }
  if (r.worst_case) out["worst_case"] = worst_case_json(*r.worst_case);
  if (r.robustness) out["robustness"] = robustness_json(*r.robustness, r.model);
}

/// The figures of the planar models along the path, with the wall direction of each peak.
nlohmann::json path_prediction_json(const PathPrediction& p) {
  return {{"nonlinear", planar_peaks_json(p.nonlinear)},
          {"linear", planar_peaks_json(p.linear)},
          {"kinematics",
           {{"a_total_peak", p.a_total_peak},
            {"t_a_total_peak_s", p.a_total_time},
            {"a_normal_peak", p.a_normal_peak},
            {"v_peak", p.v_peak},
            {"j_peak", p.j_peak}}}};
}

/// A plan along an arc or a path: format.motion as given (format.stroke_mm is the length the law
/// moves along it) and the "path" block.
void add_path(const SpatialMotion& motion, const PathPlanReport& report, nlohmann::json& out) {
  out["format"]["motion"] = motion.echo;
  nlohmann::json path{{"type", motion.type == MotionType::kArc ? "arc" : "path"},
                      {"length_mm", report.length * 1e3},
                      {"container_turns", motion.path->container_turns()},
                      {"prediction", path_prediction_json(report.prediction)},
                      {"baseline", path_prediction_json(report.baseline)}};
  out["path"] = std::move(path);
}

}  // namespace

nlohmann::json plan_json(const PlanRequest& request, const PlanResult& r) {
  nlohmann::json out;
  out["key"] = recipe_key(request);
  out["cached"] = false;
  out["version"] = kVersion;
  out["strategy"] = to_string(r.strategy);
  out["status"] = to_string(r.status);
  out["message"] = r.message;
  add_kinematics(request, r, out);
  out["law"] = law_json(r.law, r.durations);
  if (r.design) out["design"] = design_json(*r.design);
  out["model"] = model_json(r.model, request.options.model);
  if (r.rectangular) add_rectangular_model(out["model"], *r.rectangular, request.options.model);
  out["prediction"] = prediction_json(r.prediction);
  out["baseline"] = prediction_json(r.baseline);
  out["baseline"]["durations_s"] = uniform_durations(request.format.motion_time);
  out["reduction_pct"] =
      reduction_json(r.baseline, r.prediction, compares_on_linear_model(r.warnings));
  out["spectrum"] = spectrum_json(request, r);
  out["solver"] = {{"name", r.solver.name},
                   {"iterations", r.solver.iterations},
                   {"starts", r.solver.starts},
                   {"objective", r.solver.objective},
                   {"solve_ms", r.solver.solve_ms}};
  if (!r.candidates.empty()) out["candidates"] = candidates_json(r.candidates);
  if (r.move_absolute) out["move_absolute"] = move_absolute_json(*r.move_absolute);
  add_robustness(request, r, out);
  out["format"] = format_json(request.format);
  if (request.motion) {
    // The plan's own verification along the path; a result made otherwise is verified here.
    add_path(*request.motion,
             r.path ? *r.path
                    : path_plan_report(r, *request.motion->path, request.format.motion_time,
                                       request.options.rest_time),
             out);
  }
  out["rest_time_s"] = request.options.rest_time;
  out["warnings"] = warning_texts(r.warnings);
  out["warning_codes"] = warning_codes(r.warnings);
  if (std::string budget = budget_warning(r); !budget.empty()) {
    out["warnings"].push_back(std::move(budget));
    out["warning_codes"].push_back(std::string(kTimeLimitedCandidates));
  }
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
  if (request.motion) {
    // Along the path, simulate's own series of the container's models (a tank's highest corner,
    // a cylinder's wall maximum), the ones the plan's figures come from.
    plan["series"] = run_spatial_simulate({std::move(s), *request.motion})["series"];
    return;
  }
  plan["series"] = run_simulate(s)["series"];
}

PlanResult plan_request(const PlanRequest& request) {
  PlanResult result = request.motion ? plan_on_path(request.format, *request.motion->path,
                                                    request.strategy, request.options)
                                     : plan(request.format, request.strategy, request.options);
  if (result.invalid_input) {
    // The request passed the API's ranges but not the planner's own checks (e.g. a format whose
    // uniform law already drives the model out of its range): a 422, not a plan of zeros.
    throw ApiError(ErrorCode::kInvalidValue, "format",
                   plan_refusal(*result.invalid_input, request.format, request.options));
  }
  return result;
}

nlohmann::json run_plan(const PlanRequest& request) {
  const PlanResult result = plan_request(request);
  nlohmann::json out = plan_json(request, result);
  add_series(request, out);
  return out;
}

}  // namespace slosh::api
