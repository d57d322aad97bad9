#include "slosh/api/openapi.hpp"

#include <algorithm>
#include <string_view>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/plan_warnings.hpp"
#include "slosh/api/routes.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/model/fluid.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

json ref(std::string_view name) {
  return {{"$ref", "#/components/schemas/" + std::string(name)}};
}

json response_ref(std::string_view name) {
  return {{"$ref", "#/components/responses/" + std::string(name)}};
}

/// A number constrained to `range` (OpenAPI 3.0 boolean exclusiveMinimum/exclusiveMaximum).
json number_in(const Range& range, const std::string& description) {
  json s{{"type", "number"}, {"minimum", range.lo}, {"maximum", range.hi}};
  if (range.lo_open) s["exclusiveMinimum"] = true;
  if (range.hi_open) s["exclusiveMaximum"] = true;
  std::string text = description;
  if (!range.unit.empty()) text += " [" + std::string(range.unit) + "]";
  text += ". Allowed: " + range.describe() + ".";
  s["description"] = text;
  return s;
}

json number(const std::string& description) {
  return {{"type", "number"}, {"description", description}};
}

json integer(const std::string& description) {
  return {{"type", "integer"}, {"description", description}};
}

json text(const std::string& description) {
  return {{"type", "string"}, {"description", description}};
}

json boolean(const std::string& description) {
  return {{"type", "boolean"}, {"description", description}};
}

json numbers(const std::string& description) {
  return {{"type", "array"}, {"items", {{"type", "number"}}}, {"description", description}};
}

json fixed_numbers(int n, const std::string& description) {
  json s = numbers(description);
  s["minItems"] = n;
  s["maxItems"] = n;
  return s;
}

json strings(const std::string& description) {
  return {{"type", "array"}, {"items", {{"type", "string"}}}, {"description", description}};
}

/// The full plan's "warnings": every kind of plan_warning_kinds, by how its sentence begins.
std::string warning_kinds_description() {
  std::string out =
      "Warnings about this plan, each a sentence; the kinds, by how the sentence begins:";
  for (const PlanWarningKind& kind : plan_warning_kinds()) {
    out += " \"" + std::string(kind.prefix) + "...\" (" + std::string(kind.code) +
           "): " + std::string(kind.meaning) + ";";
  }
  out.back() = '.';
  return out;
}

/// The compact plan's "warnings": the codes of plan_warning_kinds.
std::string warning_codes_description() {
  std::string codes;
  for (const PlanWarningKind& kind : plan_warning_kinds()) {
    codes += (codes.empty() ? "" : ", ") + std::string(kind.code);
  }
  return "The code of each warning's kind, each once (" + codes +
         "); the full plan has the sentences. A plan stored before the codes existed lists each "
         "warning's finding (its text up to the first \": \").";
}

/// An object with the given properties; `closed` marks request objects (unknown members are
/// rejected with 422).
json object(json properties, std::vector<std::string> required, const std::string& description,
            bool closed) {
  json s{{"type", "object"}, {"properties", std::move(properties)}};
  if (!required.empty()) s["required"] = std::move(required);
  if (closed) s["additionalProperties"] = false;
  if (!description.empty()) s["description"] = description;
  return s;
}

json nullable(json schema) {
  schema["nullable"] = true;
  return schema;
}

json with_default(json schema, json value) {
  schema["default"] = std::move(value);
  return schema;
}

json string_enum(std::vector<std::string> values, const std::string& description) {
  return {{"type", "string"}, {"enum", std::move(values)}, {"description", description}};
}

// ---- enumerations, from their name tables ---------------------------------------------------

/// The reasons auto gives a candidate it did not return (the chosen one has none: null).
std::vector<std::string> candidate_loss_names() {
  std::vector<std::string> out;
  for (CandidateLoss loss : enum_values<CandidateLoss>()) {
    if (loss != CandidateLoss::kNone) out.emplace_back(name_of(loss));
  }
  return out;
}

std::vector<std::string> fluid_names() {
  std::vector<std::string> out;
  for (const Fluid& f : fluid_catalogue()) out.push_back(f.name);
  return out;
}

/// The damping correlations a request may name (explicit is given as {"zeta": z}).
/// The damping names a model reports: the correlations, and "rectangular" (a rectangular tank's
/// own damping).
std::vector<std::string> rectangular_damping(std::vector<std::string> names) {
  names.emplace_back("rectangular");
  return names;
}

std::vector<std::string> damping_names(bool with_explicit) {
  std::vector<std::string> out;
  for (DampingCorrelation c : enum_values<DampingCorrelation>()) {
    if (with_explicit || c != DampingCorrelation::kExplicit) out.emplace_back(name_of(c));
  }
  return out;
}

// ---- request schemas ------------------------------------------------------------------------

void add_format_schemas(json& s) {
  json height = number_in(ranges::kContainerHeightMm,
                          "Container height (optional; used for the spill warning). Must exceed "
                          "fill_height_mm");
  // The other shape's member given null is read as left out (a form sending every field).
  auto only_null = [](const char* of) {
    return json{{"type", "number"},
                {"nullable", true},
                {"enum", json::array({nullptr})},
                {"description", std::string("Only null (read as left out): ") + of}};
  };
  s["Container"] = object(
      {{"shape", string_enum({"cylinder"}, "The cylinder (the default when absent).")},
       {"radius_mm", number_in(ranges::kRadiusMm, "Inner radius R of the cylindrical container")},
       {"height_mm", height},
       {"length_mm", only_null("a rectangular container's side")},
       {"width_mm", only_null("a rectangular container's side")},
       {"orientation_deg", only_null("a rectangular container's orientation")}},
      {"radius_mm"}, "Cylindrical container.", true);
  s["RectangularContainer"] = object(
      {{"shape", string_enum({"rectangular"}, "A rectangular container (SPEC §15).")},
       {"length_mm",
        number_in(ranges::kSideMm, "Inner side L (along the motion at orientation 0)")},
       {"width_mm", number_in(ranges::kSideMm, "Inner side W")},
       {"height_mm", height},
       {"orientation_deg",
        with_default(number_in(ranges::kOrientationDeg,
                               "Angle of the side L to the direction of motion: 0 moves the tank "
                               "along L, 90 along W; between them both directions slosh"),
                     0)},
       {"radius_mm", only_null("the cylinder's radius")}},
      {"shape", "length_mm", "width_mm"},
      "Open rectangular container (cup, tray of a form-fill-seal line): each horizontal "
      "direction's modes on their own, the wall height reported the highest over its walls and "
      "corners (docs/models.md). A container gives radius_mm or the sides, never both (422).",
      true);
  s["FluidName"] =
      string_enum(fluid_names(), "A fluid of the catalogue (GET /v1/fluids; properties at 20 °C).");
  s["CustomFluid"] = object(
      {{"density_kg_m3", number_in(ranges::kDensity, "Density rho")},
       {"viscosity_pa_s", number_in(ranges::kViscosity, "Dynamic viscosity mu")},
       {"name",
        {{"type", "string"},
         {"minLength", 1},
         {"maxLength", 64},
         {"description", "Label echoed back (default \"custom\"); 1 to 64 characters."}}}},
      {"density_kg_m3", "viscosity_pa_s"}, "A Newtonian liquid given by its properties.", true);
  s["Fluid"] = {{"oneOf", {ref("FluidName"), ref("CustomFluid")}},
                {"description", "A catalogue name or {density_kg_m3, viscosity_pa_s, name?}."}};
  s["Format"] =
      object({{"container", {{"oneOf", {ref("Container"), ref("RectangularContainer")}}}},
              {"fill_height_mm", number_in(ranges::kFillHeightMm, "Fill height h of the liquid")},
              {"fluid", ref("Fluid")},
              {"stroke_mm", number_in(ranges::kStrokeMm, "Stroke s of the rest-to-rest motion")},
              {"motion_time_s", number_in(ranges::kMotionTimeS, "Motion time T")}},
             {"container", "fill_height_mm", "fluid", "stroke_mm", "motion_time_s"},
             "One format: container, liquid and move. The JSON surface speaks mm and s.", true);
}

void add_model_option_schemas(json& s) {
  s["DampingName"] = string_enum(damping_names(false),
                                 "Damping correlation: thesis (eq. 2.26, default), paper (JDSMC "
                                 "2022 eq. 2), eq227, eq228.");
  s["ExplicitDamping"] = object(
      {{"zeta",
        number_in(ranges::kZeta, "Damping ratio zeta, e.g. measured by logarithmic decrement")}},
      {"zeta"}, "A measured damping ratio.", true);
  s["Damping"] = {{"oneOf", {ref("DampingName"), ref("ExplicitDamping")}},
                  {"default", to_string(DampingCorrelation::kThesis)},
                  {"description", "A correlation name or {\"zeta\": z}."}};
}

/// The schemas of the named options of the registry.
json option_properties(const OptionRegistry& registry,
                       std::initializer_list<std::string_view> names) {
  json p = json::object();
  for (std::string_view name : names) p[std::string(name)] = option_schema(*registry.find(name));
  return p;
}

/// PlanOptions and the objects of its groups (MachineLimits), from the registry.
void add_plan_option_schemas(json& s, const OptionRegistry& registry) {
  json p = json::object();
  for (const OptionSpec& o : registry.options()) {
    if (o.group.empty()) {
      p[std::string(o.name)] = option_schema(o);
    } else {
      p[std::string(o.group)] = ref(registry.group(o.group)->schema_name);
    }
  }
  s["PlanOptions"] = object(
      p, {},
      "Every member is optional (null counts as absent) and defaults to the seed value of SPEC "
      "§5; each violation is a 422 naming the field, the value and the range.",
      true);
  for (const OptionGroup& g : registry.groups()) {
    json members = json::object();
    for (const OptionSpec& o : registry.options()) {
      if (o.group == g.name) members[std::string(o.name)] = option_schema(o);
    }
    s[std::string(g.schema_name)] = object(members, {}, g.doc, true);
  }
}

void add_plan_request_schemas(json& s, const OptionRegistry& registry) {
  s["Strategy"] = with_default(
      string_enum(enum_names<Strategy>(),
                  "What the planner optimises (SPEC §5): baseline (uniform T/7), notch, "
                  "multi_notch, min_jerk_band, time_domain; or how it filters (JDSMC 2022): "
                  "fir_chain (three rectangular FIR filters, a 7-segment law when conditions "
                  "(14) hold), shaper (base law convolved with an input shaper), iir (base law "
                  "through the IIR filter); auto (runs all but iir and picks)."),
      to_string(Strategy::kAuto));
  add_plan_option_schemas(s, registry);

  json sample =
      number_in(ranges::kSamplePeriodS,
                "Adds the time series of the law at this sampling period; at most " +
                    std::to_string(ranges::kMaxSeriesSamples) + " samples over motion + rest");
  s["PlanRequest"] = object({{"format", ref("Format")},
                             {"strategy", ref("Strategy")},
                             {"options", ref("PlanOptions")},
                             {"sample_period_s", sample}},
                            {"format"}, "One format + strategy + options.", true);
  s["PlanRequest"]["example"] = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
    "strategy": "multi_notch",
    "options": {"p_notch": 0.15, "weights": [1, 1, 1], "band": 0.15, "n_band": 51,
                "tol_rel": 0.2, "eta_rest_max_mm": 3, "objective": "motion",
                "rest_time_s": 1.0, "min_ramp_s": 0.05, "fix_constant_velocity_zero": false,
                "plateau_min_s": [0, 0], "limits": {"a_max": 10, "v_max": 3, "j_max": 250},
                "damping": "thesis", "alpha": 0.58, "modes": 3, "solver": "auto",
                "time_limit_s": 5}})");

  json requests{{"type", "array"},
                {"items", ref("PlanRequest")},
                {"minItems", 1},
                {"maxItems", kOpenApiBatchMax},
                {"description", "1 to batch_max plan requests (server setting, default " +
                                    std::to_string(kOpenApiBatchMax) + ")."}};
  s["BatchRequest"] = object({{"requests", requests},
                              {"view", with_default(string_enum(plan_view_names(),
                                                                "The view of every plan of the "
                                                                "results (as ?view=)."),
                                                    "full")}},
                             {"requests"}, "Many recipes, planned in parallel.", true);
}

void add_simulate_request_schemas(json& s) {
  json durations = fixed_numbers(
      7,
      "seven_segment only: the 7 durations [s]; sum = format.motion_time_s within 1e-6 s, ramps "
      "1, 3, 5, 7 >= options.min_ramp_s, plateaus >= 0.");
  durations["items"] = {{"type", "number"}, {"minimum", 0.0}};
  s["LawType"] = string_enum(
      enum_names<LawType>(),
      "seven_segment (with durations_s), seven_segment_uniform (T/7 each, the thesis baseline), "
      "poly5, modified_trapezoid, cycloidal, piecewise_linear (with breakpoints_s and "
      "acceleration_m_s2), piecewise (with pieces).");
  json breakpoints = numbers(
      "piecewise_linear only: breakpoint times [s], from 0, strictly increasing, the last = "
      "format.motion_time_s within 1e-6 s; at most " +
      std::to_string(kMaxLawPieces + 1) + ".");
  breakpoints["minItems"] = 2;
  json accelerations = numbers(
      "piecewise_linear only: acceleration at each breakpoint, linear in between [m/s^2]. The "
      "law must end at rest (|v| <= 1e-6 m/s) at the stroke (within 0.001 mm).");
  accelerations["minItems"] = 2;
  json a_poly = numbers(
      "Acceleration polynomial c0..c3 in tau = t - t_begin_s: c0 + c1 tau + c2 tau² + c3 tau³ "
      "[m/s², m/s³, m/s⁴, m/s⁵]; 1 to 4 coefficients.");
  a_poly["minItems"] = 1;
  a_poly["maxItems"] = 4;
  s["LawPiece"] = object(
      {{"t_begin_s", number("Start [s]: 0, then the previous piece's t_end_s (within 1e-9 s).")},
       {"t_end_s", number("End [s], after t_begin_s; the last = format.motion_time_s.")},
       {"a_poly", a_poly},
       {"harmonic",
        object({{"cos", number("Amplitude of cos(omega tau) [m/s^2].")},
                {"sin", number("Amplitude of sin(omega tau) [m/s^2].")},
                {"omega_rad_s", number("omega [rad/s].")}},
               {"cos", "sin", "omega_rad_s"}, "Harmonic term added to the polynomial.", true)}},
      {"t_begin_s", "t_end_s", "a_poly"}, "One piece of a piecewise law.", true);
  json pieces{{"type", "array"},
              {"items", ref("LawPiece")},
              {"minItems", 1},
              {"description",
               "piecewise only: contiguous pieces from 0 to format.motion_time_s; the law must "
               "end at rest at the stroke."}};
  s["LawSpec"] = object({{"type", ref("LawType")},
                         {"durations_s", durations},
                         {"breakpoints_s", breakpoints},
                         {"acceleration_m_s2", accelerations},
                         {"pieces", pieces}},
                        {"type"},
                        "A motion law: what simulate and export accept and what a plan returns "
                        "as `law`.",
                        true);
  // Simulate reads the model options and min_ramp_s as plan does.
  json options =
      option_properties(plan_option_registry(), {"modes", "damping", "alpha", "min_ramp_s"});
  options["model"] = ref("CalibratedModel");
  s["SimulateOptions"] = object(options, {}, "Model options; every member optional.", true);
  s["SimulateRequest"] = object(
      {{"format", ref("SimulateFormat")},
       {"law", ref("LawSpec")},
       {"rest_time_s", with_default(number_in(ranges::kRestTimeS, "Rest window after the motion"),
                                    kDefaultRestTime)},
       {"sample_period_s",
        number_in(ranges::kSamplePeriodS, "Adds the time series at this sampling period; at most " +
                                              std::to_string(ranges::kMaxSeriesSamples) +
                                              " samples over motion + rest")},
       {"options", ref("SimulateOptions")}},
      {"format"}, "Any supported law on a format (law required but for a trajectory motion).",
      true);
  s["SimulateRequest"]["example"] = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
    "law": {"type": "seven_segment", "durations_s": [0.08, 0.17, 0.06, 0.21, 0.12, 0.09, 0.27]},
    "rest_time_s": 1.0, "sample_period_s": 0.001,
    "options": {"modes": 3, "damping": "thesis", "alpha": 0.58, "min_ramp_s": 0.05}})");
}

// ---- response schemas ----------------------------------------------------------------------

/// Prediction: both models' peaks (and a rectangular container's directions in a simulation).
void add_prediction_schema(json& s) {
  s["Prediction"] =
      object({{"nonlinear", ref("Peaks")},
              {"linear", ref("Peaks")},
              {"directions",
               object({{"length", ref("Peaks")}, {"width", ref("Peaks")}}, {"length", "width"},
                      "A rectangular container's simulation: each direction's own walls "
                      "(nonlinear model, or linear outside its range).",
                      false)}},
             {"nonlinear", "linear"},
             "Predictions of the dense accurate simulation of both models.", false);
}

/// Model.rectangular: a rectangular tank's two directions.
void add_rectangular_model_schema(json& s) {
  json direction = object(
      {{"excited", boolean("Whether the motion drives this direction (share != 0).")},
       {"component", number("Share c of the acceleration along the motion: cos(orientation) "
                            "along L, sin(orientation) along W [-].")},
       {"side_mm", number("The side along this direction [mm].")},
       {"omega_rad_s", numbers("omega_n = sqrt(g k_n tanh(k_n h)), k_n = (2n-1) pi / side.")},
       {"f_hz", numbers("[Hz].")},
       {"zeta", number("Damping ratio [-].")},
       {"alpha", number("Duffing coefficient of the dominant mode [-].")},
       {"K_mm", number("Nonlinear height gain [mm].")},
       {"sloshing_mass_kg", numbers("Sloshing masses [kg].")},
       {"eta_gain", numbers("Linear wall-height gains per mode [-].")}},
      {"excited", "component", "side_mm", "omega_rad_s", "f_hz", "zeta", "alpha", "K_mm",
       "sloshing_mass_kg", "eta_gain"},
      "", false);
  s["RectangularModel"] =
      object({{"length", direction}, {"width", direction}, {"orientation_deg", number("[deg]")}},
             {"length", "width", "orientation_deg"},
             "A rectangular tank's two directions (SPEC §15).", false);
}

/// The format as a response echoes it: user units, the resolved fluid, the motion as planned.
void add_format_echo_schema(json& s) {
  s["FormatEcho"] =
      object({{"container",
               object({{"radius_mm", number("[mm] (the cylinder)")},
                       {"shape", text("\"rectangular\" (absent for the cylinder).")},
                       {"length_mm", number("[mm] (rectangular)")},
                       {"width_mm", number("[mm] (rectangular)")},
                       {"orientation_deg", number("[deg] (rectangular)")},
                       {"height_mm", number("[mm], when given")}},
                      {}, "The cylinder's radius_mm, or a rectangular container's sides.", false)},
              {"fill_height_mm", number("[mm]")},
              {"fluid", ref("ResolvedFluid")},
              {"stroke_mm", number("[mm]")},
              {"motion_time_s", number("[s]")},
              {"motion", ref("Motion")}},
             {"container", "fill_height_mm", "fluid", "stroke_mm", "motion_time_s"},
             "The format in user units, with the resolved fluid; along an arc or a path also the "
             "motion as planned (canonical: its defaults filled in), stroke_mm then the path "
             "length.",
             false);
}

void add_shared_response_schemas(json& s) {
  s["ResolvedFluid"] = object({{"name", text("Catalogue name, the caller's name or \"custom\".")},
                               {"density_kg_m3", number("Density [kg/m^3].")},
                               {"viscosity_pa_s", number("Dynamic viscosity [Pa·s].")}},
                              {"name", "density_kg_m3", "viscosity_pa_s"}, "", false);
  add_format_echo_schema(s);
  s["Kinematics"] = object(
      {{"a_max", number("Positive plateau level A [m/s^2]. Along an arc or a path: of the "
                        "tangential acceleration s'' alone; limits.a_max bounds the total "
                        "horizontal acceleration (path.prediction.kinematics.a_total_peak).")},
       {"a_min", number("Negative plateau level B (magnitude, positive) [m/s^2]. Along a path: "
                        "tangential, as a_max.")},
       {"v_peak", number("Peak velocity [m/s].")},
       {"j_peak", number("Peak |jerk| [m/s^3].")},
       {"jerks_m_s3",
        nullable(fixed_numbers(7,
                               "Plans: the jerk of each of the 7 segments, 0 on the plateaus "
                               "[m/s^3]; null for a general law."))}},
      {"a_max", "a_min", "v_peak", "j_peak"},
      "Peaks of the law. For non-7-segment laws a_max and a_min are the peaks of a(t) and -a(t).",
      false);
  s["Model"] = object(
      {{"omega_rad_s", numbers("Natural circular frequencies omega_n [rad/s].")},
       {"f_hz", numbers("Natural frequencies f_n [Hz].")},
       {"zeta", number("Damping ratio [-].")},
       {"damping", string_enum(rectangular_damping(damping_names(true)),
                               "Correlation used (explicit = given zeta; rectangular = the "
                               "rectangular tank's laminar boundary-layer damping).")},
       {"C", number("C = xi_1 tanh(xi_1 h/R) = omega_1² R / g [-].")},
       {"alpha", number("Nonlinear stiffening [-].")},
       {"K_mm", number("Nonlinear height gain K [mm].")},
       {"sloshing_mass_kg", numbers("Sloshing masses m_n [kg].")},
       {"fluid_mass_kg", number("Fluid mass [kg].")},
       {"eta_gain", numbers("Linear wall-height gains per mode [-].")},
       {"rectangular", ref("RectangularModel")}},
      {"omega_rad_s", "f_hz", "zeta", "damping", "C", "alpha", "K_mm", "sloshing_mass_kg",
       "fluid_mass_kg", "eta_gain"},
      "Sloshing model parameters of the format. A rectangular container's are those of its "
      "most excited direction driven by the whole acceleration along the motion (its share c: "
      "gains times |c|, alpha times c²; C = 0), with both directions in \"rectangular\".",
      false);
  add_rectangular_model_schema(s);
  s["Peaks"] =
      object({{"eta_motion_mm", number("Peak |eta| at the wall during the motion [mm].")},
              {"eta_rest_mm", number("Peak |eta| in the rest window (residual wave) [mm].")},
              {"t_motion_s", number("Time of the motion peak [s].")},
              {"t_rest_s", number("Time of the rest peak [s].")}},
             {"eta_motion_mm", "eta_rest_mm", "t_motion_s", "t_rest_s"},
             "Wave-height peaks of one model.", false);
  add_prediction_schema(s);
  json units{{"type", "object"},
             {"additionalProperties", {{"type", "string"}}},
             {"description", "Unit of each series."}};
  s["Series"] = object({{"t_s", numbers("Time [s].")},
                        {"a", numbers("Acceleration [m/s^2].")},
                        {"v", numbers("Velocity [m/s].")},
                        {"s", numbers("Position [m].")},
                        {"eta_linear_mm", numbers("Wave height, linear model [mm].")},
                        {"eta_nonlinear_mm", numbers("Wave height, nonlinear model [mm].")},
                        {"units", units}},
                       {"t_s", "a", "v", "s", "eta_linear_mm", "eta_nonlinear_mm", "units"},
                       "Time series (both ends included) when sample_period_s is given.", true);
}

/// The blocks of a plan response: baseline, reductions, spectrum, solver, candidates.
void add_plan_block_schemas(json& s) {
  json baseline_props{{"nonlinear", ref("Peaks")},
                      {"linear", ref("Peaks")},
                      {"durations_s", fixed_numbers(7, "The uniform durations T/7 [s].")}};
  s["Baseline"] =
      object(baseline_props, {"nonlinear", "linear", "durations_s"},
             "Predictions of the uniform law (the reference of the reductions).", false);
  json reduction_pair{{"motion", number("[%]")}, {"rest", number("[%]")}};
  s["Reduction"] = object(
      {{"motion", number("eta_motion reduction vs the baseline, on `model` [%].")},
       {"rest", number("eta_rest reduction vs the baseline, on `model` [%].")},
       {"model", string_enum({"nonlinear", "linear"},
                             "The model motion and rest compare: nonlinear, or linear when the "
                             "plan's and the uniform law's nonlinear figures come from different "
                             "models (a rectangular tank's nonlinear model holds for one law only; "
                             "warning reductions_on_linear_model).")},
       {"linear",
        object(reduction_pair, {"motion", "rest"}, "The same on the linear model.", false)}},
      {"motion", "rest", "model", "linear"}, "100 (1 - plan / baseline).", false);
  json markers =
      object({{"f1_hz", number("First natural frequency [Hz].")},
              {"band_hz", fixed_numbers(2, "Band edges (1 ± band) f1 [Hz].")},
              {"f_modes_hz", numbers("Natural frequencies of the modes [Hz].")},
              {"notch_hz",
               numbers("notch and multi_notch only (also as auto's choice): the frequencies the "
                       "law notches, ascending: notch's f1, multi_notch's (1 - p) f, f, (1 + p) f; "
                       "on a turned rectangular tank around each excited direction's first mode, "
                       "under an uncertainty range around its middle [Hz].")}},
             {"f1_hz", "band_hz", "f_modes_hz"}, "", false);
  json spectrum_units{{"type", "object"},
                      {"additionalProperties", {{"type", "string"}}},
                      {"description", "Units of f_hz and amplitude."}};
  s["Spectrum"] = object({{"f_hz", numbers("512 frequencies from 0 to 5 f1 [Hz].")},
                          {"amplitude", numbers("|X_a| of the plan [m/s].")},
                          {"baseline_amplitude", numbers("|X_a| of the uniform law [m/s].")},
                          {"units", spectrum_units},
                          {"markers", markers}},
                         {"f_hz", "amplitude", "baseline_amplitude", "units", "markers"},
                         "Acceleration amplitude spectrum.", false);
  s["SolverReport"] = object(
      {{"name", text("\"nlopt-slsqp\", \"ipopt\" or \"none\".")},
       {"iterations", integer("Objective evaluations over all starts and phases.")},
       {"starts", integer("Starts solved.")},
       {"objective", number("Objective of the returned point, in the strategy's scaled units.")},
       {"solve_ms", number("Wall-clock time of the whole plan [ms].")}},
      {"name", "iterations", "starts", "objective", "solve_ms"}, "", false);
  s["SolveStatus"] = string_enum(enum_names<SolveStatus>(), "Outcome of the solve.");
  s["Candidate"] = object(
      {{"strategy", ref("Strategy")},
       {"status", ref("SolveStatus")},
       {"durations_s", nullable(fixed_numbers(7, "[s]; null for a general law"))},
       {"law_type", ref("LawType")},
       {"prediction", ref("Prediction")},
       {"a_peak", number("Peak |acceleration| [m/s^2]; along an arc or a path the tangential "
                         "s'' alone (limits.a_max bounds the total horizontal acceleration).")},
       {"chosen", boolean("The candidate auto returned.")},
       {"reason",
        nullable(string_enum(
            candidate_loss_names(),
            "Why auto did not return it (null for the chosen one), in the order SPEC §5's "
            "rule excludes: not_usable (infeasible or failed), eta_above_limit (verified "
            "eta_rest above eta_rest_max_mm, or eta_motion above eta_motion_max_mm with "
            "objective rest, while another candidate meets it; or, none meeting it, above "
            "the least infeasible one auto returns as infeasible), worse_than_baseline (while "
            "a candidate that is not competes), eta_motion_above_best (nonlinear "
            "eta_motion more than 5 % above the best competitor's), higher_eta_rest "
            "(above the chosen one's), tie_on_eta_rest (tied within 1e-6, peak "
            "acceleration not lower). The tie is not transitive, so a candidate can "
            "have lost to one that was later replaced: then reason_detail names that "
            "one. With an uncertainty range the worst case is judged."))},
       {"reason_detail",
        nullable(text("The reason with the figures that decided it (null for the chosen "
                      "one), e.g. \"eta_rest 1.2 mm vs 0.8 mm of the chosen multi_notch\"."))},
       {"warnings", strings("Its worse_than_baseline warning as a plan of its strategy "
                            "carries it; empty when it is not worse than the uniform law.")},
       {"worst_case", ref("WorstCase")}},
      {"strategy", "status", "durations_s", "law_type", "prediction", "a_peak", "chosen", "reason",
       "reason_detail", "warnings"},
      "One strategy's result inside an auto plan.", false);
}

/// How fir_chain, shaper or iir built their law.
void add_filter_design_schema(json& s) {
  s["FilterDesign"] = object(
      {{"method", string_enum({"fir_chain", "shaper", "iir"}, "The filtering strategy.")},
       {"t1_s", number("fir_chain: T1 [s].")},
       {"t2_s", number("fir_chain: T2 [s].")},
       {"t3_s", number("fir_chain: T3 = damped period of mode 1 [s].")},
       {"conditions_14", boolean("fir_chain: T1 >= T2 + T3 and T2 >= T3 (a 7-segment law).")},
       {"shaper", text("shaper: zv, mzv, zvd, zvdd, ei, ei2 or ei3.")},
       {"impulses",
        {{"type", "array"},
         {"items", object({{"t_s", number("[s]")}, {"amplitude", number("[-]")}},
                          {"t_s", "amplitude"}, "", false)},
         {"description", "shaper: the impulse train (amplitudes sum to 1)."}}},
       {"residual_at_f1", number("shaper: residual vibration of mode 1 after the train [-].")},
       {"base", text("shaper, iir: the base law.")},
       {"base_duration_s", number("shaper, iir: duration of the base law, T - delay [s].")},
       {"delay_s", number("shaper, iir: delay the filter adds [s].")},
       {"order", integer("iir: 2 or 3.")},
       {"tau", number("iir: tau [1/s].")},
       {"sample_period_s", number("iir: sample period [s].")},
       {"filtered_duration_s",
        number("iir: end of the filtered law before the rest padding, within one sample of T "
               "[s].")},
       {"iterations", integer("iir: filter passes of the delay compensation.")},
       {"correction_pct",
        number("iir: the rest-to-rest correction, largest change relative to the peak "
               "acceleration [%].")},
       {"a", numbers("iir: a_1..a_n of the difference equation.")},
       {"b", numbers("iir: b_0..b_(n+1) of the difference equation.")}},
      {"method"}, "How fir_chain, shaper or iir built the law (absent for the optimisers).", false);
}

/// A plan in either view: the full PlanResponse or the CompactPlan (view=compact).
json any_plan() {
  return {{"oneOf", {ref("PlanResponse"), ref("CompactPlan")}}};
}

/// The compact plan (SPEC §11, api::compact_plan): what a controller needs, under 1 kB for a
/// 7-segment law.
void add_compact_plan_schemas(json& s) {
  json law = s["LawSpec"];
  law.erase("additionalProperties");
  law.erase("example");
  law["properties"]["stroke_mm"] = number("The stroke the law moves (format.stroke_mm) [mm].");
  law["properties"]["motion_time_s"] = number("The time the law lasts (format.motion_time_s) [s].");
  law["required"] = {"type", "stroke_mm", "motion_time_s"};
  law["description"] = "The plan's law (a 7-segment law: its 7 durations) with the move it makes.";
  s["CompactLaw"] = law;
  const json eta{
      {"eta_motion_mm", number("Peak |eta| at the wall during the motion [mm], to 1 um.")},
      {"eta_rest_mm", number("Peak |eta| in the rest window [mm], to 1 um.")}};
  const json peaks = object(eta, {"eta_motion_mm", "eta_rest_mm"}, "", false);
  s["CompactPlan"] = object(
      {{"view", string_enum({"compact"}, "Always compact: the view of this plan.")},
       {"key", text("Recipe key, as in the full plan (GET /v1/plans/{key} answers it).")},
       {"cached", boolean("True when served from the plan cache.")},
       {"version", text("The slosh version that made the plan.")},
       {"strategy", ref("Strategy")},
       {"status", ref("SolveStatus")},
       {"law", ref("CompactLaw")},
       {"kinematics",
        object({{"a_max", number("Positive plateau level A [m/s^2], to 1e-4; along an arc "
                                 "or a path the tangential s'' alone (the total "
                                 "is path.a_total_peak).")},
                {"a_min", number("Negative plateau level B (magnitude) [m/s^2], to 1e-4.")},
                {"v_peak", number("Peak velocity [m/s], to 1e-5.")},
                {"j_peak", number("Peak |jerk| [m/s^3], to 1e-3.")}},
               {"a_max", "a_min", "v_peak", "j_peak"},
               "Peaks of the law; absent when move_absolute is given (its acceleration, "
               "deceleration, velocity and jerk are the same peaks).",
               false)},
       {"prediction", object({{"nonlinear", peaks}, {"linear", peaks}}, {"nonlinear", "linear"},
                             "Predicted peaks of both models.", false)},
       {"warnings", strings(warning_codes_description())},
       {"move_absolute", ref("MoveAbsolute")},
       {"robustness", ref("CompactRobustness")}},
      {"view", "key", "cached", "version", "strategy", "status", "law", "prediction", "warnings"},
      "The compact plan (?view=compact): what a controller needs, under 1 kB for a 7-segment "
      "law. The message is not in it: the full plan of the same key has it.",
      false);
}

/// The results of POST /v1/plans/batch.
void add_batch_response_schemas(json& s) {
  json ok = object({{"index", integer("Position in the request array.")}, {"plan", any_plan()}},
                   {"index", "plan"}, "A planned recipe (in the batch's view).", false);
  json failed = object(
      {{"index", integer("Position in the request array.")}, {"error", ref("Error")}},
      {"index", "error"}, "A recipe that failed; field paths start with requests[index].", false);
  s["BatchResult"] = {{"oneOf", {ok, failed}}};
  s["BatchResponse"] = object({{"results", {{"type", "array"}, {"items", ref("BatchResult")}}}},
                              {"results"}, "One result per request, in request order.", false);
}

void add_move_absolute_schema(json& s) {
  s["MoveAbsolute"] = object(
      {{"distance_mm", number("Distance: the stroke [mm].")},
       {"velocity_mm_s", number("Velocity: the law's peak velocity [mm/s].")},
       {"acceleration_mm_s2", number("Acceleration: A [mm/s^2].")},
       {"deceleration_mm_s2", number("Deceleration: B [mm/s^2].")},
       {"jerk_mm_s3", number("Jerk: the one jerk of the four ramps [mm/s^3].")}},
      {"distance_mm", "velocity_mm_s", "acceleration_mm_s2", "deceleration_mm_s2", "jerk_mm_s3"},
      "Only with options.drive_profile move_absolute, when the law is a one-jerk 7-segment law: "
      "the inputs of a PLCopen MC_MoveAbsolute block (jerk-limited) whose profile is the planned "
      "law.",
      false);
}

/// The worst case over an uncertainty range (plans and auto's candidates).
void add_worst_case_schema(json& s) {
  json worst_peaks = nullable(s.at("Peaks"));
  worst_peaks["description"] =
      "The largest peaks of one model over the range, each with its time on the model where it "
      "is largest; null when the model diverges somewhere in the range.";
  s["WorstCase"] =
      object({{"nonlinear", worst_peaks}, {"linear", worst_peaks}}, {"nonlinear", "linear"},
             "Only with options.uncertainty: the law's largest verified eta over the models of the "
             "range (21 evenly, at its least damping): what robust designs and auto are judged by.",
             false);
}

/// The range of the model an options.uncertainty implies, and the robustness of a compact plan.
void add_uncertainty_range_schemas(json& s) {
  const auto range = [](const std::string& what) { return fixed_numbers(2, what + " [lo, hi]."); };
  s["UncertaintyRange"] = object(
      {{"omega_error_pct", number("options.uncertainty.omega_error_pct as given (0: none) [%].")},
       {"fill_height_mm", nullable(fixed_numbers(2,
                                                 "options.uncertainty.fill_height_mm as given, "
                                                 "null when not given [mm]."))},
       {"viscosity_pa_s", nullable(fixed_numbers(2,
                                                 "options.uncertainty.viscosity_pa_s as given, "
                                                 "null when not given [Pa·s]."))},
       {"sample_points",
        nullable(integer("options.uncertainty.sample_points; null for a strategy that does not "
                         "read it (every one but time_domain and auto): it is not part of "
                         "that plan's key."))},
       {"omega1_rad_s", range("omega_1 over the range [rad/s]")},
       {"f1_hz", range("f1 over the range [Hz]")},
       {"scale", range("Factor on every nominal mode frequency [-]")},
       {"zeta", range("Damping ratio over the range [-]")}},
      {"omega_error_pct", "fill_height_mm", "viscosity_pa_s", "sample_points", "omega1_rad_s",
       "f1_hz", "scale", "zeta"},
      "Only with options.uncertainty (omega_error_pct > 0 or a range): the range of the model it "
      "implies, the one the plan was made to hold over.",
      false);
  s["CompactRobustness"] = object(
      {{"holds_pct", nullable(fixed_numbers(2,
                                            "robustness.holds.nonlinear: from_pct and to_pct "
                                            "[%]; null when the limits do not hold at delta = "
                                            "0."))},
       {"worst_mm", nullable(fixed_numbers(2,
                                           "robustness.worst.nonlinear: eta_motion_mm and "
                                           "eta_rest_mm [mm]; null when it is null."))}},
      {"holds_pct", "worst_mm"},
      "The robustness of the full plan on the nonlinear model, rounded to hundredths (the compact "
      "plan stays under 1 kB): where the limits hold and the worst eta over the sweep.",
      false);
}

/// The robustness report of SPEC §10.
void add_robustness_schema(json& s) {
  const json eta_props{{"eta_motion_mm", number("Peak |eta| at the wall during the motion [mm].")},
                       {"eta_rest_mm", number("Peak |eta| in the rest window [mm].")}};
  // Null where the model diverged (the nonlinear one can, far outside its validity).
  const json eta = nullable(object(eta_props, {"eta_motion_mm", "eta_rest_mm"},
                                   "The two peaks of one model; null where it diverged (the "
                                   "nonlinear model can, far outside its validity).",
                                   false));
  const json worst_eta =
      nullable(object(eta_props, {"eta_motion_mm", "eta_rest_mm"},
                      "The largest peaks of one model over the sweep; null when it diverged at "
                      "some point (no bound to give).",
                      false));
  json interval = nullable(object(
      {{"from_pct", number("Lower end of delta [%]: where the margin crosses 0, linearly "
                           "interpolated between the last point that holds and the first that "
                           "does not; the sweep's first delta when every point down to it holds.")},
       {"to_pct", number("Upper end of delta [%], likewise.")},
       {"from_is_sweep_end", boolean("from_pct is the sweep's end: the interval may extend.")},
       {"to_is_sweep_end", boolean("to_pct is the sweep's end: the interval may extend.")}},
      {"from_pct", "to_pct", "from_is_sweep_end", "to_is_sweep_end"},
      "The interval of delta around 0 where eta_rest <= eta_rest_max_mm (and eta_motion <= "
      "eta_motion_max_mm when given) on one model; null when they do not hold at delta = 0.",
      false));
  json sweep = object(
      {{"delta_pct", fixed_numbers(2,
                                   "First and last delta of the sweep [%]: +-10 % by default, "
                                   "the uncertainty's range of omega_1 when given.")},
       {"points", integer("Points evenly from the first to the last delta, both included.")},
       {"zeta", number("Damping ratio at every point (the least of the uncertainty's range).")},
       {"rest_time_s", number("Rest window [s].")},
       {"eta_rest_max_mm", number("The eta_rest limit judged [mm].")},
       {"eta_motion_max_mm",
        nullable(number("The eta_motion limit judged, null when none [mm]."))}},
      {"delta_pct", "points", "zeta", "rest_time_s", "eta_rest_max_mm", "eta_motion_max_mm"},
      "What was swept and judged.", false);
  json point = object(
      {{"delta_pct", number("Every mode frequency is omega_n (1 + delta) [%].")},
       {"f1_hz", number("f1 (1 + delta) [Hz].")},
       {"linear", eta},
       {"nonlinear", eta},
       {"holds_linear", boolean("The limits hold on the linear model (each eta / limit <= 1 + "
                                "1e-6, the verification's round-off).")},
       {"holds_nonlinear", boolean("The limits hold on the nonlinear model, likewise.")}},
      {"delta_pct", "f1_hz", "linear", "nonlinear", "holds_linear", "holds_nonlinear"},
      "The returned law re-simulated at one delta.", false);
  s["Robustness"] = object(
      {{"sweep", sweep},
       {"points",
        {{"type", "array"},
         {"items", point},
         {"description",
          "Sorted by delta: the evenly spaced points, plus delta = 0 when "
          "the grid misses it."}}},
       {"holds", object({{"linear", interval}, {"nonlinear", interval}}, {"linear", "nonlinear"},
                        "Where the limits hold around delta = 0.", false)},
       {"worst", object({{"linear", worst_eta}, {"nonlinear", worst_eta}}, {"linear", "nonlinear"},
                        "The largest eta over the sweep.", false)}},
      {"sweep", "points", "holds", "worst"},
      "SPEC §10 (absent with options.robustness false): the returned law with every mode "
      "frequency scaled by (1 + delta) on both models, and where the limits hold.",
      false);
}

void add_plan_response_schemas(json& s) {
  add_plan_block_schemas(s);
  add_worst_case_schema(s);
  add_robustness_schema(s);
  add_uncertainty_range_schemas(s);
  add_filter_design_schema(s);
  s["PlanResponse"] = object(
      {{"key", text("Recipe key: first 32 hex digits of the SHA-256 of the normalised recipe "
                    "and the slosh version.")},
       {"cached", boolean("True when served from the plan cache.")},
       {"version", text("The slosh version that made the plan (as GET /healthz says).")},
       {"strategy", ref("Strategy")},
       {"status", ref("SolveStatus")},
       {"message", text("What happened and what the law does, actionable by a line engineer.")},
       {"durations_s",
        nullable(fixed_numbers(7,
                               "The 7 durations [s] (always admissible); null when the law is "
                               "not a 7-segment law (shaper, iir, fir_chain without (14))."))},
       {"durations_pct", nullable(fixed_numbers(7, "The durations in % of T; null likewise."))},
       {"warm_start_s",
        nullable(fixed_numbers(7,
                               "Only in the plans of a min-time answer: the durations of the "
                               "neighbouring T this plan was warm-started from [s] (part of its "
                               "key); null when it was planned from the planner's own starts."))},
       {"switch_times_s",
        nullable(fixed_numbers(8, "Segment boundaries from 0 to T [s]; null likewise."))},
       {"law", ref("LawSpec")},
       {"design", ref("FilterDesign")},
       {"kinematics", ref("Kinematics")},
       {"model", ref("Model")},
       {"prediction", ref("Prediction")},
       {"baseline", ref("Baseline")},
       {"reduction_pct", ref("Reduction")},
       {"spectrum", ref("Spectrum")},
       {"solver", ref("SolverReport")},
       {"candidates",
        {{"type", "array"},
         {"items", ref("Candidate")},
         {"description", "auto only: every strategy's result."}}},
       {"format", ref("FormatEcho")},
       {"rest_time_s", number("Rest window [s].")},
       {"warnings", strings(warning_kinds_description())},
       {"warning_codes",
        strings("The code of each warning's kind, one per entry of warnings and in its order (the "
                "codes of the warnings description). A plan that meets its constraints but has a "
                "warning of kind spill or wave_exceeds_fill, or (all but baseline) "
                "worse_than_baseline or motion_too_short, is acceptable, not optimal.")},
       {"move_absolute", ref("MoveAbsolute")},
       {"uncertainty", ref("UncertaintyRange")},
       {"worst_case", ref("WorstCase")},
       {"robustness", ref("Robustness")},
       {"series", ref("Series")}},
      {"key",         "cached",        "version",        "strategy", "status",     "message",
       "durations_s", "durations_pct", "switch_times_s", "law",      "kinematics", "model",
       "prediction",  "baseline",      "reduction_pct",  "spectrum", "solver",     "format",
       "rest_time_s", "warnings",      "warning_codes"},
      "The plan of SPEC §6-§7 (also what `slosh plan` prints).", false);
  add_compact_plan_schemas(s);
  add_batch_response_schemas(s);
  add_move_absolute_schema(s);
}

/// The formats that carry a motion: simulate's (any motion) and a plan's (a line, an arc or a
/// path).
void add_motion_format_schemas(json& s) {
  json format = s["Format"];
  format["properties"]["motion"] = ref("Motion");
  format["required"] = {"container", "fill_height_mm", "fluid"};
  format["description"] =
      "A format with its motion: stroke_mm (the straight line) or motion (the law moves the "
      "container along its length; giving both is a 422); motion_time_s required except for a "
      "trajectory.";
  s["SimulateFormat"] = format;
  json plan_format = format;
  plan_format["properties"]["motion"] = {
      {"oneOf", {ref("LineMotion"), ref("ArcMotion"), ref("PathMotion")}},
      {"description",
       "The law moves the container along it (its length is the stroke; giving stroke_mm too is "
       "a 422). Along an arc or a path every strategy plans s(t); see docs/api.md."}};
  plan_format["required"] = {"container", "fill_height_mm", "fluid", "motion_time_s"};
  plan_format["description"] = "A format with stroke_mm (the straight line) or motion.";
  s["PlanFormat"] = plan_format;
  s["PlanRequest"]["properties"]["format"] = ref("PlanFormat");
}

// format.motion (SPEC §14): what simulate accepts, and the line plans and min-time take.
void add_motion_request_schemas(json& s) {
  namespace mr = motion_ranges;
  const json turns = boolean(
      "The container turns with the table or path tangent (a rotary table) or keeps its "
      "orientation (a carriage on a curved track).");
  const json heading = number_in(mr::kHeadingDeg, "Tangent direction at the start, from +x");
  s["LineMotion"] = object(
      {{"type", string_enum({"line"}, "A straight move.")},
       {"length_mm", number_in(ranges::kStrokeMm, "Length of the move (stroke_mm's long form)")},
       {"direction_deg", with_default(number_in(mr::kHeadingDeg, "Direction from +x"), 0)}},
      {"type", "length_mm"}, "The straight move (stroke_mm's long form).", true);
  s["ArcMotion"] = object(
      {{"type", string_enum({"arc"}, "An arc of a rotary table, carousel or curved track.")},
       {"radius_mm", number_in(mr::kArcRadiusMm, "Radius of the arc")},
       {"angle_deg", number_in(mr::kAngleDeg, "Angle turned, signed (left positive), not 0")},
       {"container_turns", with_default(turns, true)},
       {"start_heading_deg", with_default(heading, 0)}},
      {"type", "radius_mm", "angle_deg"}, "", true);
  s["PathSegment"] =
      object({{"line_mm", number_in(ranges::kStrokeMm, "A line of this length")},
              {"arc", object({{"radius_mm", number_in(mr::kArcRadiusMm, "Radius")},
                              {"angle_deg", number_in(mr::kAngleDeg, "Signed angle, not 0")}},
                             {"radius_mm", "angle_deg"}, "An arc.", true)},
              {"heading_deg",
               number_in(mr::kHeadingDeg,
                         "Optional: the tangent direction the segment starts with; it "
                         "must equal the direction the path arrives with (within 1e-6 rad)")}},
             {}, "One of line_mm or arc.", true);
  s["PathMotion"] =
      object({{"type", string_enum({"path"}, "Lines and arcs joined with a common tangent.")},
              {"segments",
               {{"type", "array"},
                {"minItems", 1},
                {"maxItems", mr::kMaxPathSegments},
                {"items", ref("PathSegment")}}},
              {"start_heading_deg", with_default(heading, 0)},
              {"container_turns", with_default(turns, false)}},
             {"type", "segments"}, "", true);
  const std::string most = std::to_string(mr::kMaxTrajectorySamples);
  s["TrajectoryMotion"] = object(
      {{"type", string_enum({"trajectory"}, "Sampled poses (simulate only).")},
       {"t_s", numbers("Times, strictly increasing, at least 4, at most " + most +
                       ", spanning at most 60 s, at least 20 samples per first-mode period [s].")},
       {"x_mm", numbers("Positions [mm].")},
       {"y_mm", numbers("Positions [mm].")},
       {"z_mm", numbers("Optional: heights (up) [mm].")},
       {"theta_deg", numbers("Optional: heading about the vertical axis [deg]; may be logged "
                             "wrapped to +-180 deg: each sample is taken at the turn nearest "
                             "the previous one.")}},
      {"type", "t_s", "x_mm", "y_mm"},
      "Smoothing cubic splines with not-a-knot ends: each coordinate is smoothed with a penalty "
      "on its fourth divided differences (a cubic is never bent), weighted so that the residual "
      "matches the noise estimated from the samples' sixth differences (Reinsch's criterion); "
      "a clean commanded trajectory is kept to round-off, a log's rounding does not become "
      "acceleration. The format then has no stroke_mm, no motion_time_s and the request no law.",
      true);
  s["Motion"] = {
      {"oneOf", {ref("LineMotion"), ref("ArcMotion"), ref("PathMotion"), ref("TrajectoryMotion")}},
      {"description",
       "The container's motion (SPEC §14). Plans and min-time take a line, an arc or a path "
       "(PlannedMotion); a trajectory is simulated only."}};
  s["PlannedMotion"] = {
      {"oneOf", {ref("LineMotion"), ref("ArcMotion"), ref("PathMotion")}},
      {"description",
       "The motion a plan or a min-time search moves along: the law s(t) spans its length; on "
       "an arc or a path a_max limits the total horizontal acceleration, v_max s' and j_max the "
       "tangential jerk, and the wave is the planar models' maximum over the wall."}};
  add_motion_format_schemas(s);
}

// A plan along an arc or a path: the planar models' figures with the wall directions and the
// path's kinematics (after PlanarPeaks).
void add_path_plan_schemas(json& s) {
  const json kinematics =
      object({{"a_total_peak", number("Largest horizontal acceleration sqrt(s''^2 + (s'^2/rho)^2) "
                                      "[m/s^2] (what limits.a_max bounds along a path).")},
              {"t_a_total_peak_s", number("Where [s].")},
              {"a_normal_peak", number("Largest normal acceleration s'^2/rho [m/s^2].")},
              {"v_peak", number("Largest speed ds/dt [m/s].")},
              {"j_peak", number("Largest tangential jerk |d3s/dt3| [m/s^3].")}},
             {"a_total_peak", "a_normal_peak", "v_peak", "j_peak"}, "", false);
  const json figures = object({{"nonlinear", ref("PlanarPeaks")},
                               {"linear", ref("PlanarPeaks")},
                               {"kinematics", kinematics}},
                              {"nonlinear", "linear", "kinematics"}, "", false);
  s["PathPlan"] =
      object({{"type", string_enum({"arc", "path"}, "")},
              {"length_mm", number("Length the law moves along [mm] (format.stroke_mm).")},
              {"container_turns", boolean("Whether the container turns with the path.")},
              {"prediction", figures},
              {"baseline", figures}},
             {"type", "length_mm", "container_turns", "prediction", "baseline"},
             "Only along an arc or a path: the plan's law and the uniform law on the planar models "
             "(a rectangular container: the tank's models, the highest corner; prediction and "
             "baseline of the plan hold the same peaks), with the wall angle of each peak.",
             false);
  s["PlanResponse"]["properties"]["path"] = ref("PathPlan");
  s["CompactPlan"]["properties"]["path"] = object(
      {{"a_total_peak", number("Largest total horizontal acceleration sqrt(s''^2 + "
                               "(s'^2/rho)^2), to 1 mm/s^2 [m/s^2]: what limits.a_max bounds "
                               "(kinematics.a_max is the tangential s'' alone).")}},
      {"a_total_peak"},
      "Only along an arc or a path (its length is law.stroke_mm; the peaks' wall directions are "
      "in the full plan of the same key).",
      false);
  s["CompactLaw"]["properties"]["motion"] = object(
      {{"type", string_enum({"line", "arc", "path"}, "The motion's type.")},
       {"segment_count", integer("A path's lines and arcs (a path only).")}},
      {"type"},
      "The motion the law moves along, summarised: its length is law.stroke_mm; its geometry "
      "(an arc's radius and angle, a path's segments, the start heading, container_turns) is in "
      "the full plan of the same key, so that the compact plan stays under 1 kB.",
      false);
}

// The answer of simulate with format.motion: both planar models' peaks with their wall angles.
void add_motion_response_schemas(json& s) {
  json peaks = s["Peaks"];
  peaks["properties"]["direction_motion_deg"] =
      number("Wall angle of the motion peak, world frame from +x [deg].");
  peaks["properties"]["direction_rest_deg"] = number("Wall angle of the rest peak [deg].");
  peaks["required"].push_back("direction_motion_deg");
  peaks["required"].push_back("direction_rest_deg");
  peaks["properties"]["t_motion_s"] = number(
      "Time of the motion peak: from the start of a law, on the samples' clock (as t_s "
      "gives it) for a trajectory [s].");
  peaks["properties"]["t_rest_s"] = number("Time of the rest peak, on the same clock [s].");
  peaks["description"] = "Peaks of one planar model, maximised over the wall.";
  s["PlanarPeaks"] = peaks;
  s["PlanarPrediction"] = object(
      {{"nonlinear", ref("PlanarPeaks")},
       {"linear", ref("PlanarPeaks")},
       {"directions",
        object({{"length", ref("Peaks")}, {"width", ref("Peaks")}}, {"length", "width"},
               "A rectangular container: each direction's own walls along the motion (nonlinear "
               "model, or linear outside its range).",
               false)}},
      {"nonlinear", "linear"},
      "Both planar models (format.motion given); for a rectangular container the tank's models "
      "in its own frame, the peaks the highest corner and their angle the corner's.",
      false);
  // FormatEcho holds a line, an arc or a path (with their stroke_mm and motion_time_s); a
  // trajectory's format has neither, so it is an echo of its own (and a oneOf tells them apart).
  json echo = s["FormatEcho"];
  echo["properties"].erase("stroke_mm");
  echo["properties"].erase("motion_time_s");
  echo["required"] = {"container", "fill_height_mm", "fluid", "motion"};
  echo["description"] =
      "The format of a sampled trajectory: its motion, no stroke_mm nor motion_time_s.";
  s["SpatialFormatEcho"] = echo;
  s["MotionSummary"] =
      object({{"type", string_enum({"line", "arc", "path", "trajectory"}, "")},
              {"duration_s", number("End of the motion [s].")},
              {"length_mm", number("Path length (not for a trajectory) [mm].")},
              {"container_turns", boolean("Whether the container turns (not for a trajectory).")},
              {"samples", integer("Samples of a trajectory.")}},
             {"type", "duration_s"}, "The simulated motion.", false);
  json units{{"type", "object"},
             {"additionalProperties", {{"type", "string"}}},
             {"description", "Unit of each series."}};
  s["SpatialSeries"] = object(
      {{"t_s", numbers("Time: from the start of a law (0, dt, ...), on the samples' clock for a "
                       "trajectory (t_s[0], t_s[0] + dt, ...) [s].")},
       {"x_mm", numbers("Container position, world frame [mm].")},
       {"y_mm", numbers("Container position, world frame [mm].")},
       {"theta_deg", numbers("Container heading about the vertical, world frame as x_mm and y_mm: "
                             "the path's start heading at the start (the heading a trajectory's "
                             "theta_deg gives) [deg].")},
       {"a_h", numbers("Magnitude of the horizontal acceleration, normal part included [m/s^2].")},
       {"eta_linear_mm", numbers("Linear planar model: wall height maximised over the wall [mm].")},
       {"eta_nonlinear_mm", numbers("Nonlinear planar model: the same [mm].")},
       {"direction_linear_deg", numbers("Wall angle of the linear maximum, from +x [deg].")},
       {"direction_nonlinear_deg", numbers("Wall angle of the nonlinear maximum [deg].")},
       {"s", numbers("A law along a path: distance along it [m].")},
       {"v", numbers("A law along a path: speed along it [m/s].")},
       {"a", numbers("A law along a path: tangential acceleration [m/s^2].")},
       {"units", units}},
      {"t_s", "x_mm", "y_mm", "theta_deg", "a_h", "eta_linear_mm", "eta_nonlinear_mm",
       "direction_linear_deg", "direction_nonlinear_deg", "units"},
      "Time series along format.motion (both ends included) when sample_period_s is given.", true);
  add_path_plan_schemas(s);
}

void add_simulate_response_schemas(json& s) {
  s["LawEcho"] = object(
      {{"type", ref("LawType")},
       {"duration_s", number("Motion time [s].")},
       {"stroke_mm", number("Stroke [mm].")},
       {"breakpoints_s", numbers("Breakpoints of the piecewise law [s].")},
       {"durations_s", fixed_numbers(7, "7-segment laws: durations [s].")},
       {"switch_times_s", fixed_numbers(8, "7-segment laws: switch times [s].")},
       {"jerks_m_s3",
        fixed_numbers(7, "7-segment laws: jerk of each segment, 0 on the plateaus [m/s^3].")}},
      {"type", "duration_s", "stroke_mm", "breakpoints_s"}, "The simulated law.", false);
  s["SimulateResponse"] =
      object({{"format", {{"oneOf", {ref("FormatEcho"), ref("SpatialFormatEcho")}}}},
              {"law", ref("LawEcho")},
              {"kinematics", ref("Kinematics")},
              {"motion", ref("MotionSummary")},
              {"model", ref("Model")},
              {"prediction", {{"oneOf", {ref("Prediction"), ref("PlanarPrediction")}}}},
              {"rest_time_s", number("Rest window [s].")},
              {"series", {{"oneOf", {ref("Series"), ref("SpatialSeries")}}}},
              {"warnings", strings("Validity limits of the models reached by this law.")},
              {"warning_codes",
               strings("The code of each warning's kind, one per entry of warnings and in its "
                       "order (the codes of the plan's warnings description).")}},
             {"format", "model", "prediction", "rest_time_s", "warnings", "warning_codes"},
             "Wave-height response of the law (also what `slosh simulate` prints); with "
             "format.motion: motion, no kinematics, no law for a trajectory.",
             false);
}

void add_service_schemas(json& s) {
  s["Error"] = object(
      {{"code", string_enum(enum_names<ErrorCode>(), "Error class.")},
       {"message", text("What is wrong: for invalid values the field, the value and the allowed "
                        "range.")},
       {"field",
        {{"type", "string"},
         {"nullable", true},
         {"description", "JSON path of the offending field, or null."}}}},
      {"code", "message", "field"}, "", false);
  s["ErrorEnvelope"] =
      object({{"error", ref("Error")}}, {"error"}, "The one error body of every endpoint.", false);
  s["CatalogueFluid"] = object({{"name", text("Catalogue name.")},
                                {"density_kg_m3", number("[kg/m^3]")},
                                {"viscosity_pa_s", number("[Pa·s]")},
                                {"source", text("Where the figures come from.")}},
                               {"name", "density_kg_m3", "viscosity_pa_s", "source"}, "", false);
  s["FluidsResponse"] = object({{"fluids", {{"type", "array"}, {"items", ref("CatalogueFluid")}}},
                                {"temperature_c", number("Temperature of the properties [°C].")}},
                               {"fluids", "temperature_c"}, "The fluid catalogue.", false);
  s["Health"] = object({{"status", string_enum({"ok"}, "Always ok while the process serves.")},
                        {"version", text("Service version.")}},
                       {"status", "version"}, "", false);
  s["Readiness"] = object(
      {{"status", string_enum({"ready", "stopping", "stalled", "degraded"},
                              "ready (200); stopping during shutdown, stalled when the solve pool "
                              "has work but finished nothing for max(30 s, 3 solve budgets) "
                              "(both 503); degraded (200, 503 with redis_required) when the plan "
                              "store cannot be written or the shared Redis is down: plans are "
                              "answered from the local levels.")},
       {"reason", text("Why the service is stalled or degraded.")},
       {"workers", integer("Solve workers.")},
       {"busy_workers", integer("Workers running a solve.")},
       {"queue_depth", integer("Solves waiting for a worker.")},
       {"cache",
        object({{"persistent", boolean("The persistent store is in use.")},
                {"memory_entries", integer("Plans in the in-memory LRU.")},
                {"memory_bytes", integer("Bytes of keys and plans in the LRU.")},
                {"storage_error", text("Why the persistent store is unavailable.")},
                {"redis", object({{"url", text("The shared level (password hidden).")},
                                  {"up", boolean("Redis answers within redis_timeout_ms.")},
                                  {"required", boolean("redis_required: 503 while down.")},
                                  {"error", text("The last failure while down.")}},
                                 {"url", "up", "required"},
                                 "The Redis shared by the replicas (cache = redis://...); "
                                 "absent without one.",
                                 false)}},
               {"persistent", "memory_entries"}, "", false)}},
      {"status", "workers", "queue_depth", "cache"}, "", false);
}

// ---- responses and paths --------------------------------------------------------------------

json error_response(const std::string& description) {
  return {{"description", description},
          {"content", {{"application/json", {{"schema", ref("ErrorEnvelope")}}}}}};
}

json json_response(const std::string& description, json schema) {
  return {{"description", description},
          {"content", {{"application/json", {{"schema", std::move(schema)}}}}}};
}

json responses_component() {
  json overloaded = error_response(
      "Overloaded: the solve queue is full (or the service is shutting down); retry later.");
  overloaded["headers"] = {
      {"Retry-After",
       {{"description", "Seconds to wait before retrying."}, {"schema", {{"type", "integer"}}}}}};
  return {{"BadRequest", error_response("Malformed JSON, also nested deeper than 64 levels (code "
                                        "malformed_json), or not HTTP (code bad_request).")},
          {"UnsupportedMediaType",
           error_response("The body is declared as something other than JSON (code "
                          "unsupported_media_type): send Content-Type: application/json.")},
          {"RequestTimeout",
           error_response("The body did not arrive within the server's request_timeout_s (code "
                          "request_timeout).")},
          {"NotFound", error_response("Not found (code not_found).")},
          {"PayloadTooLarge", error_response("The body exceeds the server's max_body_bytes (code "
                                             "payload_too_large).")},
          {"InvalidValue",
           error_response("A field is missing, of the wrong type, out of range or unknown (code "
                          "invalid_value); the message names the field, the value and the "
                          "allowed range.")},
          {"Overloaded", overloaded},
          {"Conflict", error_response("The batch job is not finished yet (code conflict); poll "
                                      "GET /v1/batches/{id}.")},
          {"Timeout", error_response("The plan did not finish within its budget plus the "
                                     "queueing grace (code timeout).")},
          {"Internal", error_response("Internal error (code internal).")},
          {"NotModified", {{"description", "The plan matches If-None-Match."}}}};
}

json json_body(std::string_view schema) {
  return {{"required", true}, {"content", {{"application/json", {{"schema", ref(schema)}}}}}};
}

json plan_ok() {
  json ok = json_response(
      "The plan, in the view of ?view= (full: PlanResponse, compact: "
      "CompactPlan).",
      any_plan());
  ok["headers"] = {{"ETag",
                    {{"description",
                      "The recipe key in quotes (with ;view=compact for the "
                      "compact view, ;series=<period> with series). Absent on a plan that is "
                      "not cached (cut short by its time budget, or failed)."},
                     {"schema", {{"type", "string"}}}}}};
  return ok;
}

/// The `view` query parameter of the plan endpoints.
json view_parameter() {
  return {{"name", "view"},
          {"in", "query"},
          {"required", false},
          {"schema", {{"type", "string"}, {"enum", plan_view_names()}, {"default", "full"}}},
          {"description",
           "full: the whole plan; compact: the compact plan (CompactPlan). The view changes "
           "neither the recipe key nor the cached plan. Any other value is a 422 naming view."}};
}

json if_none_match() {
  return {{"name", "If-None-Match"},
          {"in", "header"},
          {"required", false},
          {"schema", {{"type", "string"}}},
          {"description", "An ETag of a plan: 304 when it matches the cached plan."}};
}

// The component response of each error status an operation can answer.
std::string_view status_component(int status) {
  switch (status) {
    case 304:
      return "NotModified";
    case 400:
      return "BadRequest";
    case 404:
      return "NotFound";
    case 409:
      return "Conflict";
    case 408:
      return "RequestTimeout";
    case 413:
      return "PayloadTooLarge";
    case 415:
      return "UnsupportedMediaType";
    case 422:
      return "InvalidValue";
    case 503:
      return "Overloaded";
    case 504:
      return "Timeout";
    default:
      return "Internal";
  }
}

/// The request of POST /v1/min-time (SPEC §9).
void add_min_time_request_schemas(json& s) {
  namespace mr = min_time_ranges;
  json format = s["Format"];
  format["properties"].erase("motion_time_s");
  format["properties"]["motion"] = ref("PlannedMotion");
  format["required"] = {"container", "fill_height_mm", "fluid"};
  format["description"] =
      "The format without motion_time_s: the search finds it (giving it is a 422); stroke_mm "
      "(the straight line) or motion (a line, an arc or a path: every T is planned along it).";
  s["MinTimeFormat"] = format;
  json options = s["PlanOptions"];
  options["properties"].erase("eta_rest_max_mm");
  options["properties"].erase("eta_motion_max_mm");
  options["description"] =
      "The plan options every plan of the search runs with (machine limits in limits); "
      "time_limit_s is the budget of each strategy's search. eta_rest_max_mm and "
      "eta_motion_max_mm are set by the search (top-level members).";
  s["MinTimeOptions"] = options;
  std::vector<std::string> strategies;
  for (Strategy st : enum_values<Strategy>()) {
    if (st != Strategy::kAuto) strategies.push_back(to_string(st));
  }
  json strategy_list{{"type", "array"},
                     {"items", string_enum(strategies, "A strategy to search.")},
                     {"minItems", 1},
                     {"maxItems", strategies.size()},
                     {"uniqueItems", true},
                     {"description", "The strategies to search; default every strategy but iir."}};
  json max_plans{{"type", "integer"},
                 {"minimum", mr::kMaxPlansLo},
                 {"maximum", mr::kMaxPlansHi},
                 {"default", MinTimeOptions{}.max_plans},
                 {"description", "Most plans one strategy's search solves."}};
  s["MinTimeRequest"] = object(
      {{"format", ref("MinTimeFormat")},
       {"motion_time_max_s", with_default(number_in(mr::kMotionTimeMax, "Upper end of the search"),
                                          kDefaultMotionTimeMax)},
       {"eta_motion_max_mm",
        number_in(mr::kEtaMm,
                  "Largest eta_motion; default the free board height_mm - fill_height_mm - "
                  "free_board_margin_mm (required without height_mm)")},
       {"free_board_margin_mm",
        with_default(number_in(mr::kMarginMm, "Margin below the free board"),
                     kDefaultFreeBoardMargin * 1e3)},
       {"eta_rest_max_mm",
        with_default(number_in(mr::kEtaMm, "Largest eta_rest over the rest window"), 3.0)},
       {"limit_model", with_default(string_enum(enum_names<LimitModel>(),
                                                "The model the eta limits apply to (both: the "
                                                "larger of the two)."),
                                    to_string(LimitModel::kNonlinear))},
       {"strategies", strategy_list},
       {"scan_step_s", with_default(number_in(mr::kScanStep, "Step of the coarse scan"),
                                    MinTimeOptions{}.scan_step)},
       {"max_plans", max_plans},
       {"curve_factor",
        with_default(number_in(mr::kCurveFactor, "The curve reaches this factor times T_min"),
                     MinTimeOptions{}.curve_factor)},
       {"refine_excess",
        with_default(number_in(mr::kRefineExcess,
                               "A scanned local minimum of max(eta / limit) at or below this is "
                               "refined by golden-section search; a time_domain plan below the "
                               "best feasible T that misses by at most this is planned again "
                               "from the planner's own starts"),
                     MinTimeOptions{}.refine_excess)},
       {"options", ref("MinTimeOptions")}},
      {"format"}, "A format without motion time, the limits and the strategies to search.", true);
}

/// The response of POST /v1/min-time (SPEC §9).
void add_min_time_response_schemas(json& s) {
  json nullable_number = {{"type", "number"}, {"nullable", true}};
  json eta_pair =
      object({{"eta_motion_mm", numbers("[mm]")}, {"eta_rest_mm", numbers("[mm]")}}, {}, "", false);
  json curve = object(
      {{"t_s", numbers("Every planned T, ascending [s].")},
       {"feasible", {{"type", "array"}, {"items", {{"type", "boolean"}}}}},
       {"plan_status", strings("Status of the plan at each T.")},
       {"nonlinear", eta_pair},
       {"linear", eta_pair},
       {"units",
        {{"type", "object"},
         {"additionalProperties", {{"type", "string"}}},
         {"description", "Unit of each series: t_s s, eta_motion_mm and eta_rest_mm mm."}}}},
      {"t_s", "units"}, "The eta curve over T (every planned T, with its verified peaks).", false);
  json best = object(
      {{"t_s", number("[s]")}, {"eta_motion_mm", number("[mm]")}, {"eta_rest_mm", number("[mm]")}},
      {}, "The least excess reached (infeasible searches).", false);
  best["nullable"] = true;
  json plan = ref("PlanResponse");
  s["MinTimeStrategyResult"] = object(
      {{"strategy", text("Strategy searched.")},
       {"status", text("optimal (T_min found, curve complete), acceptable (the same, but the "
                       "plan at T_min is not optimal by its own warnings, e.g. it spills by the "
                       "larger model: the message leads with \"not optimal: \"), infeasible (no "
                       "T up to "
                       "motion_time_max met the limits; best), time_limit (budget ran out; "
                       "t_min_s is the best bound so far, or T_min itself when "
                       "infeasible_below_s is t_min_s - 1 ms and the curve is partial), failed.")},
       {"message", text("What happened, for a line engineer.")},
       {"t_min_s", nullable_number},
       {"infeasible_below_s", nullable_number},
       {"feasible_above",
        {{"type", "boolean"},
         {"nullable", true},
         {"description",
          "Every planned T above t_min_s, up to curve_factor t_min_s, was feasible; false: one "
          "is infeasible from the planner's own starts too; null without t_min_s or when the "
          "budget ended the curve early before a T failed."}}},
       {"kinematic_lower_bound_s", number("Closed-form jerk-limited minimum time [s].")},
       {"scan_start_s", number("First T scanned [s].")},
       {"plans", integer("plan() calls of the search.")},
       {"search_ms", number("Wall-clock time of the search [ms].")},
       {"best", best},
       {"plan", {{"allOf", {plan}}, {"nullable", true}}},
       {"curve", curve}},
      {"strategy", "status", "message", "t_min_s", "plan", "curve"}, "One strategy's search.",
      false);
  s["MinTimeResponse"] = object(
      {{"key", text("Request key (32 hex digits).")},
       {"cached", boolean("Answered from the cache.")},
       {"version", text("The slosh version that searched.")},
       {"format", {{"type", "object"}}},
       {"motion_time_max_s", number("[s]")},
       {"limits", {{"type", "object"}}},
       {"kinematic_lower_bound_s", number("[s]")},
       {"strategies", {{"type", "array"}, {"items", ref("MinTimeStrategyResult")}}},
       {"headline",
        object({{"winner", {{"type", "string"}, {"nullable", true}}},
                {"t_min_s", nullable_number},
                {"cycles_per_min", nullable_number},
                {"baseline_t_min_s", nullable_number},
                {"baseline_cycles_per_min", nullable_number},
                {"gain_pct", nullable_number},
                {"gain_cycles_per_min", nullable_number},
                {"not_optimal",
                 {{"type", "string"},
                  {"nullable", true},
                  {"description",
                   "Null, or why the winner's plan at its T_min is not optimal (its warnings: "
                   "spill, wave_exceeds_fill, ...): then no strategy's T_min plan is optimal. A "
                   "strategy whose T_min plan is not optimal is acceptable and wins only then."}}},
                {"t_min_is_bound",
                 boolean("True when the winner's search ran out of its budget before its T_min "
                         "was final (status time_limit): t_min_s is a motion time its verified "
                         "plan meets, the true minimum at or below it.")}},
               {}, "The winner and its gain over the uniform law (motion time only).", false)}},
      {"key", "cached", "version", "strategies", "headline"}, "Minimum motion time per strategy.",
      false);
}

/// Batch jobs (POST /v1/batches, GET/DELETE /v1/batches/{id}; SPEC §13).
void add_batch_job_schemas(json& s) {
  json requests{{"type", "array"},
                {"items", ref("PlanRequest")},
                {"minItems", 1},
                {"description",
                 "1 to batch_job_max plan requests (server setting, default 100000); each may "
                 "carry a \"recipe_id\" (kept in its row), as in a .json table of `slosh batch`."}};
  s["BatchJobRequest"] = object(
      {{"requests", requests},
       {"table", text("Instead of requests: the text of a recipe table as `slosh batch --in` reads "
                      "it (unreadable rows become error rows).")},
       {"table_format",
        with_default(string_enum({"csv", "jsonl", "json"}, "The format of table."), "csv")},
       {"format", with_default(string_enum({"csv", "jsonl"},
                                           "The download the record points to first; both "
                                           "results.csv and results.jsonl are always served."),
                               "csv")},
       {"view", string_enum(plan_view_names(),
                            "Adds the plan in this view to each JSON row (as `slosh batch "
                            "--view`); absent: rows carry the figures only.")}},
      {}, "A batch job: either requests or table.", true);
  json progress = object({{"done", integer("Rows finished (planned or in error), in order.")},
                          {"total", integer("Rows of the job.")},
                          {"failed", integer("Rows in error among the done ones.")},
                          {"solved", integer("A job several replicas work on (with "
                                             "\"shares\"): its items solved on any replica, "
                                             "each once: the done rows and the items the helping "
                                             "replicas solved ahead of them.")},
                          {"rate_per_s", number("Items solved per second since the job started "
                                                "(the done rows, or \"solved\" when present).")},
                          {"eta_s", nullable(number("Seconds left at that rate (null before "
                                                    "the first row)."))}},
                         {"done", "total", "failed", "rate_per_s", "eta_s"}, "", false);
  json row = {{"type", "object"},
              {"description", "A row of the plan table of `slosh batch` (JSON form)."}};
  json results = object(
      {{"offset", integer("The first row of this page (0-based).")},
       {"limit", integer("Rows asked for (1 to 1000, default 100).")},
       {"rows", {{"type", "array"}, {"items", row}}},
       {"next_offset", nullable(integer("The offset of the next page; null after the last."))},
       {"partial", boolean("True when the job did not finish every row (cancelled, failed): the "
                           "rows are its done rows only.")}},
      {"offset", "limit", "rows", "next_offset"}, "A page of the results.", false);
  json unshared = object(
      {{"rows", nullable(integer("Rows held by the replica running the job only (null when "
                                 "another replica answers: it cannot count them)."))},
       {"reason", text("Why: the shared store's refusal or failure, naming it (e.g. Redis at "
                       "maxmemory: \"OOM command not allowed ...\").")}},
      {"rows", "reason"},
      "Present while the shared job store (Redis) lacks rows or the latest record of the job.",
      false);
  json time = nullable(text("ISO 8601 UTC time; null until then."));
  s["BatchJob"] = object(
      {{"id", text("The job id (32 random hex digits).")},
       {"state", string_enum({"queued", "running", "done", "cancelled", "failed"},
                             "failed also when the replica running the job stopped.")},
       {"format", string_enum({"csv", "jsonl"}, "The format asked for.")},
       {"view", nullable(text("The view of the plans in the rows, or null."))},
       {"progress", progress},
       {"created_at", text("ISO 8601 UTC time.")},
       {"started_at", time},
       {"finished_at", time},
       {"updated_at", text("Last write of the record by its replica (every 0.5 s while it runs).")},
       {"updated_unix_ms", integer("updated_at in ms since the Unix epoch.")},
       {"message", nullable(text("Why the job failed or was cancelled."))},
       {"note", nullable(text("What happened besides its state (its replica was paused and "
                              "carried on)."))},
       {"unshared", unshared},
       {"cancel_note",
        text("In the 202 of a DELETE of another replica's job: when that replica stops it.")},
       {"cancel_requested", boolean("A DELETE asked for the job to be cancelled.")},
       {"deleted", boolean("Present (true) in the answer of the DELETE that forgot the job.")},
       {"results_csv", text("Path of the CSV download.")},
       {"results_jsonl", text("Path of the JSON lines download.")},
       {"results", results}},
      {"id", "state", "format", "progress", "created_at", "updated_at", "results_csv",
       "results_jsonl"},
      "A batch job; results only once it is done, cancelled or failed.", false);
}

/// The request and response of POST /v1/min-time (SPEC §9).
void add_min_time_schemas(json& s) {
  add_min_time_request_schemas(s);
  add_min_time_response_schemas(s);
}

/// `responses` plus a reference to the component response of each of `statuses`.
json with_statuses(json responses, std::initializer_list<int> statuses) {
  for (int status : statuses) {
    responses[std::to_string(status)] = response_ref(status_component(status));
  }
  return responses;
}

/// The statuses of every operation with a JSON request body.
constexpr std::initializer_list<int> kBodyStatuses{400, 408, 413, 415, 422, 500};

json plan_operation(const Route& route) {
  switch (route.operation) {
    case Operation::kPlan:
      return {{"tags", {"plans"}},
              {"parameters", {view_parameter(), if_none_match()}},
              {"requestBody", json_body("PlanRequest")},
              {"responses",
               with_statuses(with_statuses({{"200", plan_ok()}}, kBodyStatuses), {304, 503, 504})}};
    case Operation::kGetPlan:
      return {{"tags", {"plans"}},
              {"parameters",
               {{{"name", "key"},
                 {"in", "path"},
                 {"required", true},
                 {"schema", {{"type", "string"}}},
                 {"description", "Recipe key (32 hex digits) of a plan returned earlier."}},
                view_parameter(),
                if_none_match()}},
              {"responses", with_statuses({{"200", plan_ok()}}, {304, 404, 500})}};
    case Operation::kPlanBatch:
      return {
          {"tags", {"plans"}},
          {"description",
           "Each result carries either the plan or the error of its request; a batch waits "
           "for room in the solve queue instead of answering 503. The view of the plans is "
           "?view= or the body's view (both given: the same)."},
          {"parameters", {view_parameter()}},
          {"requestBody", json_body("BatchRequest")},
          {"responses", with_statuses({{"200", json_response("One result per request, in order.",
                                                             ref("BatchResponse"))}},
                                      kBodyStatuses)}};
    case Operation::kMinTime:
      return {{"tags", {"plans"}},
              {"parameters", {if_none_match()}},
              {"requestBody", json_body("MinTimeRequest")},
              {"responses",
               with_statuses(with_statuses({{"200", json_response("Each strategy's search.",
                                                                  ref("MinTimeResponse"))}},
                                           kBodyStatuses),
                             {304, 503, 504})}};
    default:
      return {{"tags", {"simulation"}},
              {"requestBody", json_body("SimulateRequest")},
              {"responses",
               with_statuses({{"200", json_response("The response.", ref("SimulateResponse"))}},
                             kBodyStatuses)}};
  }
}

/// A query parameter of the cam table routes.
json query_parameter(const char* name, json schema, const char* description) {
  return {{"name", name},
          {"in", "query"},
          {"required", false},
          {"schema", std::move(schema)},
          {"description", description}};
}

/// The parameters of GET /v1/plans/{key}/cam.csv and cam.st (`st`: with st_name).
json cam_table_parameters(bool st) {
  const json master_units = {{"type", "number"}};
  json p = json::array(
      {{{"name", "key"},
        {"in", "path"},
        {"required", true},
        {"schema", {{"type", "string"}}},
        {"description", "Recipe key of a cached plan."}},
       query_parameter("period_ms",
                       {{"type", "number"}, {"minimum", 0.01}, {"maximum", 1000}, {"default", 1}},
                       "Time-based table: controller cycle [ms], as `slosh export --period-ms`. "
                       "Not with the master_* parameters."),
       query_parameter("master_period", {{"type", "number"}, {"minimum", 1e-6}},
                       "Master-axis table: length of the master cycle [master units, e.g. 360 "
                       "degrees]. master_period, master_start and master_end come together; the "
                       "table covers [0, master_period]: 0 mm before master_start, the law from "
                       "master_start to master_end at the constant master speed (master_end - "
                       "master_start) / T, the stroke from master_end on. A master speed outside "
                       "[1e-30, 1e30] master units/s is a 422 naming master_period."),
       query_parameter("master_start", master_units,
                       "Master position where the motion starts: 0 <= master_start < "
                       "master_end [master units], master_end - master_start >= 1e-6."),
       query_parameter("master_end", master_units,
                       "Master position where the motion ends at the stroke: master_start < "
                       "master_end <= master_period [master units]."),
       query_parameter("master_step",
                       {{"type", "number"}, {"exclusiveMinimum", true}, {"minimum", 0}},
                       "Master distance between rows [master units]; default master_period / "
                       "360. Rows are added at master_start, master_end and master_period when "
                       "they are off the step grid; at most 200000 rows."),
       query_parameter("allow_infeasible", {{"type", "boolean"}, {"default", false}},
                       "Export the law of an infeasible plan too.")});
  if (st) {
    p.push_back(query_parameter(
        "st_name",
        {{"type", "string"}, {"default", "SLOSH_CAM"}, {"minLength", 1}, {"maxLength", 64}},
        "Identifier of the ARRAY constant: an IEC 61131-3 identifier that is not a keyword, a "
        "data type, a standard function block (TON, CTU, R_TRIG, ...) or standard function, "
        "compared without case."));
  }
  for (json& parameter : p) {
    if (parameter["in"] != "query") continue;
    std::string text = parameter["description"].get<std::string>();
    if (parameter["schema"]["type"] == "number") {
      text += " A decimal number (no hex, inf, nan, '+' or spaces).";
    }
    parameter["description"] = text + " At most once; an empty value is a 422.";
  }
  return p;
}

/// GET /v1/plans/{key}/cam.csv (`st` false) and cam.st.
json cam_table_operation(bool st) {
  const char* csv_columns =
      "Time-based: t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3 (the last row, "
      "at or after the motion time, holds the stroke). Master-axis: "
      "master,position_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3 "
      "(slave derivatives per master unit). A plan along an arc or a path: "
      "t_s,s_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3,x_mm,y_mm,theta_deg (the pose, world "
      "frame from the path's start), plus table_deg (the table's rotation) for one arc; "
      "master-axis along one arc: master,table_deg,velocity_deg_per_unit,"
      "acceleration_deg_per_unit2,jerk_deg_per_unit3; along a path: master,s_mm,"
      "velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3,x_mm,y_mm,theta_deg.";
  const char* st_text =
      "IEC 61131-3 structured text: a comment header (format, strategy, recipe key, slosh "
      "version, law), TYPE SLOSH_CAM_POINT (time-based) or SLOSH_MASTER_CAM_POINT (master-axis), "
      "along an arc or a path SLOSH_PATH_CAM_POINT, SLOSH_TABLE_CAM_POINT, "
      "SLOSH_PATH_MASTER_CAM_POINT or SLOSH_TABLE_MASTER_CAM_POINT (the CSV's columns of cam.csv), "
      "a STRUCT of LREAL members named as the CSV columns, and VAR_GLOBAL CONSTANT <st_name> : "
      "ARRAY[0..N-1] OF that type := [(...), ...]; END_VAR.";
  const char* type = st ? "text/plain" : "text/csv";
  return {
      {"tags", {"plans"}},
      {"parameters", cam_table_parameters(st)},
      {"responses", with_statuses({{"200",
                                    {{"description", st ? st_text : csv_columns},
                                     {"content", {{type, {{"schema", {{"type", "string"}}}}}}}}}},
                                  {404, 422, 500, 503})}};
}

json read_operation(const Route& route) {
  switch (route.operation) {
    case Operation::kFluids:
      return {{"tags", {"catalogue"}},
              {"responses",
               with_statuses({{"200", json_response("The catalogue.", ref("FluidsResponse"))}},
                             {500})}};
    case Operation::kOpenapi:
      return {
          {"tags", {"catalogue"}},
          {"responses",
           with_statuses({{"200", json_response("OpenAPI 3.0.3 document.", {{"type", "object"}})}},
                         {500})}};
    case Operation::kHealth:
      return {
          {"tags", {"operations"}},
          {"responses",
           with_statuses({{"200", json_response("The process serves.", ref("Health"))}}, {500})}};
    case Operation::kReady:
      return {
          {"tags", {"operations"}},
          {"responses",
           {{"200", json_response("Ready.", ref("Readiness"))},
            {"503", json_response("Not ready: status stopping (shutting down), stalled (the solve "
                                  "pool finishes nothing), or degraded with redis_required set "
                                  "(the shared Redis is down), with a reason.",
                                  ref("Readiness"))}}}};
    case Operation::kCamTable:
    case Operation::kCamTableSt:
      return cam_table_operation(route.operation == Operation::kCamTableSt);
    case Operation::kPage:
    case Operation::kAsset:
      return {{"tags", {"page"}},
              {"responses",
               {{"200",
                 {{"description", "HTML, CSS or JavaScript, with an ETag (304 on If-None-Match)."},
                  {"content", {{"text/html", {{"schema", {{"type", "string"}}}}}}}}},
                {"404", response_ref("NotFound")}}}};
    default:
      return {{"tags", {"operations"}},
              {"responses",
               {{"200",
                 {{"description", "Prometheus text exposition format 0.0.4."},
                  {"content", {{"text/plain", {{"schema", {{"type", "string"}}}}}}}}}}}};
  }
}

/// The path parameter {id} of the batch job routes.
json job_id_parameter() {
  return {{"name", "id"},
          {"in", "path"},
          {"required", true},
          {"schema", {{"type", "string"}}},
          {"description", "Job id from POST /v1/batches."}};
}

json job_operation(const Route& route) {
  const json job = ref("BatchJob");
  switch (route.operation) {
    case Operation::kCreateJob: {
      json accepted = json_response("Accepted: the job is queued.", job);
      accepted["headers"] = {
          {"Location", {{"description", "/v1/batches/{id}"}, {"schema", {{"type", "string"}}}}}};
      return {
          {"tags", {"jobs"}},
          {"requestBody", json_body("BatchJobRequest")},
          {"responses", with_statuses({{"202", accepted}}, {400, 408, 413, 415, 422, 500, 503})}};
    }
    case Operation::kGetJob:
      return {
          {"tags", {"jobs"}},
          {"parameters",
           {job_id_parameter(),
            query_parameter("offset", {{"type", "integer"}, {"minimum", 0}, {"default", 0}},
                            "First row of the results page."),
            query_parameter(
                "limit", {{"type", "integer"}, {"minimum", 1}, {"maximum", 1000}, {"default", 100}},
                "Rows of the results page.")}},
          {"responses", with_statuses({{"200", json_response("The job.", job)}}, {404, 422, 500})}};
    case Operation::kCancelJob:
      return {{"tags", {"jobs"}},
              {"parameters", {job_id_parameter()}},
              {"responses",
               with_statuses({{"200", json_response("The job was finished: it is forgotten "
                                                    "(its last record, deleted: true).",
                                                    job)},
                              {"202", json_response("Cancellation asked (again on every DELETE "
                                                    "until the job has stopped).",
                                                    job)}},
                             {404, 500})}};
    default: {
      const bool csv = route.operation == Operation::kJobResultsCsv;
      return {{"tags", {"jobs"}},
              {"parameters",
               {job_id_parameter(),
                query_parameter(
                    "partial", {{"type", "string"}, {"enum", {"1", "true", "0", "false"}}},
                    "1 or true: the done rows of a cancelled or failed job (else 409), marked by "
                    "the headers X-Slosh-Partial: true, X-Slosh-Rows and X-Slosh-Rows-Total.")}},
              {"responses",
               with_statuses(
                   {{"200",
                     {{"description", csv ? "The plan table as `slosh batch` writes CSV."
                                          : "The plan table as `slosh batch` writes JSON lines."},
                      {"content",
                       {{csv ? "text/csv" : "application/x-ndjson",
                         {{"schema", {{"type", "string"}}}}}}}}}},
                   {404, 409, 422, 500, 503})}};
    }
  }
}

/// POST /v1/calibrations and GET /v1/calibrations/{name}.
json calibration_operation(const Route& route) {
  json ok = json_response(
      "The fit: fitted values with standard errors, residuals before and "
      "after per move, identifiability notes and the model object that "
      "options.model accepts (stored under `name` when given).",
      ref("CalibrationResponse"));
  if (route.operation == Operation::kGetCalibration) {
    return {
        {"tags", {"calibration"}},
        {"parameters",
         json::array({{{"name", "name"},
                       {"in", "path"},
                       {"required", true},
                       {"schema",
                        {{"type", "string"}, {"pattern", "^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$"}}}}})},
        {"responses", with_statuses({{"200", ok}}, {404, 422, 500})}};
  }
  return {{"tags", {"calibration"}},
          {"requestBody",
           {{"required", true},
            {"content", {{"application/json", {{"schema", ref("CalibrationRequest")}}}}}}},
          {"responses", with_statuses({{"200", ok}}, {400, 413, 422, 500, 503, 504})}};
}

void add_calibration_schemas(json& s) {
  const json number = {{"type", "number"}};
  const json numbers = {{"type", "array"}, {"items", number}, {"minItems", 2}};
  s["MeasuredSeries"] = object(
      {{"t_s", numbers},
       {"eta_mm", numbers},
       {"offset_s", number},
       {"fit_offset", {{"type", "boolean"}}},
       {"max_offset_s", number}},
      {"t_s", "eta_mm"},
      "A measured wall height eta(t) (the sign of simulate's series), any sampling rate; t_s "
      "strictly increasing on the measurement clock; offset_s is the move start on that clock "
      "(estimated within +-max_offset_s when fit_offset, for a cylinder and a rectangular "
      "container alike).",
      true);
  s["MeasuredPeaks"] =
      object({{"eta_motion_mm", number}, {"eta_rest_mm", number}, {"rest_window_s", number}}, {},
             "Measured peak heights; at least one of the two.", true);
  s["MeasuredMove"] = object({{"name", {{"type", "string"}}},
                              {"motion_time_s", number},
                              {"orientation_deg",
                               {{"type", "number"},
                                {"minimum", -180},
                                {"maximum", 180},
                                {"description",
                                 "A rectangular container's turn against this move [deg] "
                                 "(default format.container.orientation_deg); refused for a "
                                 "cylinder."}}},
                              {"law", ref("LawSpec")},
                              {"series", ref("MeasuredSeries")},
                              {"peaks", ref("MeasuredPeaks")}},
                             {"law"},
                             "A move the bench ran (motion_time_s defaults to the format's; the "
                             "law must reach the format's stroke) and what was measured.",
                             true);
  const json setting = object(
      {{"fit", {{"type", "boolean"}}}, {"initial", number}, {"min", number}, {"max", number}}, {},
      "Fitted or held, start value (prior) and bounds.", true);
  s["CalibrationRequest"] = object(
      {{"format", ref("Format")},
       {"options", ref("SimulateOptions")},
       {"moves", {{"type", "array"}, {"items", ref("MeasuredMove")}, {"minItems", 1}}},
       {"fit", object({{"omega_scale", setting},
                       {"zeta", setting},
                       {"alpha", setting},
                       {"height_gain", setting},
                       {"max_iterations", {{"type", "integer"}, {"minimum", 1}, {"maximum", 500}}}},
                      {}, "Which parameters are fitted, their priors and bounds.", true)},
       {"name", {{"type", "string"}, {"pattern", "^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$"}}}},
      {"format", "moves"},
      "Bench measurements to calibrate the nonlinear model on (bounded Levenberg-Marquardt with "
      "exact gradients). A rectangular container is fitted per direction on simulate's model of "
      "the tank, whether its moves run along one side or turned: fit.omega_scale and fit.zeta "
      "set each driven direction's parameters and fit.alpha is refused (the depth's).",
      true);
  s["CalibrationResponse"] = {
      {"type", "object"},
      {"description",
       "status (converged, max_iterations, time_limit, failed), iterations, sigma_mm, parameters "
       "{name: {value, prior, standard_error (null unless fitted), state (fitted, fixed, "
       "unidentifiable), at_bound}} (a cylinder: omega_scale, zeta, alpha, height_gain; a "
       "rectangular container: omega_scale, zeta and height_gain of the direction its moves "
       "drove, or when they drove both, omega_scale and zeta of the length and "
       "width_omega_scale and width_zeta of the width; a direction no move drove is not "
       "estimated and identifiability says it is unmeasured), moves [{name, residuals, "
       "rms_before_mm, rms_after_mm, offset_s, offset_standard_error_s}], identifiability "
       "[sentences], model (options.model), container (the container fitted on: shape, "
       "radius_mm or length_mm, width_mm and the directions moved; a request naming the "
       "calibration on another container or direction is refused), fit_version (the fit's "
       "numerics, calibration-v2; a rectangular container's calibration along one side stored "
       "without it is refused by name), name; with a name, stored (true when the fit "
       "converged and was stored) and not_stored (null, or why a fit that did not converge was "
       "not stored)."}};
}

/// Request and response details of one route's operation.
json operation(const Route& route) {
  switch (route.operation) {
    case Operation::kCreateCalibration:
    case Operation::kGetCalibration:
      return calibration_operation(route);
    case Operation::kPlan:
    case Operation::kGetPlan:
    case Operation::kPlanBatch:
    case Operation::kSimulate:
    case Operation::kMinTime:
      return plan_operation(route);
    case Operation::kCreateJob:
    case Operation::kGetJob:
    case Operation::kCancelJob:
    case Operation::kJobResultsCsv:
    case Operation::kJobResultsJsonl:
      return job_operation(route);
    default:
      return read_operation(route);
  }
}

json paths() {
  json p = json::object();
  for (const Route& route : routes()) {
    json op = operation(route);
    op["operationId"] = route.operation_id;
    op["summary"] = route.summary;
    const std::string method = route.method == "POST"     ? "post"
                               : route.method == "DELETE" ? "delete"
                                                          : "get";
    p[std::string(route.path)][method] = std::move(op);
  }
  return p;
}

/// The alternative of a member that may be null: OpenAPI 3.0.3's `nullable` acts only beside a
/// `type` in the same schema object, so a $ref or a oneOf takes null as one more alternative, a
/// schema whose only value is null.
json null_alternative() {
  return {{"type", "object"},
          {"nullable", true},
          {"enum", json::array({nullptr})},
          {"description", "null: read as if the member were left out"}};
}

/// `property` (a $ref, allOf or oneOf, without a type) admitting null too; its description stays
/// beside the oneOf (a $ref's siblings are ignored).
void admit_null(json& property) {
  if (property.contains("oneOf")) {
    property["oneOf"].push_back(null_alternative());
    return;
  }
  json outer = json::object();
  json inner = json::object();
  for (auto& [k, v] : property.items()) {
    (k == "description" || k == "default" ? outer : inner)[k] = v;
  }
  outer["oneOf"] = json::array({std::move(inner), null_alternative()});
  property = std::move(outer);
}

/// A request reads an optional member given null as absent (given_member): every closed
/// (request) object's optional members say so (a typed one is nullable, another admits null as an
/// alternative). Done once all schemas are built, as some are derived from others with fewer
/// members required (PlanFormat, MinTimeFormat).
void mark_optional_request_members_nullable(json& schemas) {
  for (auto& [name, schema] : schemas.items()) {
    if (schema.value("additionalProperties", true) != false || !schema.contains("properties")) {
      continue;
    }
    const json required = schema.value("required", json::array());
    for (auto& [key, property] : schema["properties"].items()) {
      const bool optional = std::find(required.begin(), required.end(), key) == required.end();
      if (!optional) continue;
      if (!property.contains("type")) {
        admit_null(property);
        continue;
      }
      property["nullable"] = true;
      // OpenAPI 3.0: nullable does not widen an enum, so null is one of its values.
      if (property.contains("enum")) property["enum"].push_back(nullptr);
    }
  }
}

}  // namespace

json openapi_document(const std::string& version, const OptionRegistry& registry) {
  json schemas = json::object();
  add_format_schemas(schemas);
  add_model_option_schemas(schemas);
  add_plan_request_schemas(schemas, registry);
  add_simulate_request_schemas(schemas);
  add_motion_request_schemas(schemas);
  add_shared_response_schemas(schemas);
  add_plan_response_schemas(schemas);
  add_motion_response_schemas(schemas);
  add_simulate_response_schemas(schemas);
  add_service_schemas(schemas);
  add_min_time_schemas(schemas);
  add_batch_job_schemas(schemas);
  add_calibration_schemas(schemas);
  mark_optional_request_members_nullable(schemas);
  return {{"openapi", "3.0.3"},
          {"info",
           {{"title", "slosh planner"},
            {"version", version},
            {"description",
             "Plans anti-sloshing 7-segment motion laws for packaging machines and predicts the "
             "wave height of any supported law (SPEC §7). Units: mm and s on the surface, SI "
             "elsewhere as named. Request objects reject unknown members (422); every error is the "
             "ErrorEnvelope."}}},
          {"tags",
           {{{"name", "plans"}, {"description", "Planning and the recipe cache."}},
            {{"name", "simulation"}, {"description", "Response of a given law."}},
            {{"name", "calibration"}, {"description", "Fitting the model to bench measurements."}},
            {{"name", "catalogue"}, {"description", "Reference data and this document."}},
            {{"name", "operations"}, {"description", "Health, readiness and metrics."}},
            {{"name", "page"}, {"description", "The web page served at / (SPEC §12)."}},
            {{"name", "jobs"},
             {"description", "Batch jobs: long recipe tables as resources (SPEC §13)."}}}},
          {"paths", paths()},
          {"components", {{"schemas", schemas}, {"responses", responses_component()}}}};
}

}  // namespace slosh::api
