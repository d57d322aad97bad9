#include "slosh/api/min_time.hpp"

#include "slosh/api/exact_number.hpp"
#include "slosh/api/plan_reply.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slosh/api/core_input.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;
namespace mr = min_time_ranges;

/// Version of the search; part of every min-time key, bumped when results change.
// v3: infeasible points confirmed from the planner's own starts; v4: above T_min only up to the
// first one that fails from them, the warm-started failures above it left off the curve; v5: a
// rectangular tank's near misses refined only where eta_rest alone misses (the plans' statuses of
// plan-v11 too); v6: a T_min whose plan is not optimal by its warnings (it spills, ...) makes the
// strategy acceptable and wins the headline only when no T_min plan is optimal (plan-v12 too);
// v7: so does a T_min met on a rectangular tank's linear figures standing in for the nonlinear
// model, and a plan past its budget is time_limit; v8: the plans of plan-v17; v9: of plan-v18,
// and a bound the budget left is judged as a T_min (its linear figures standing in).
constexpr const char* kMinTimeVersion = "min-time-v9";
/// Version of the search along an arc or a path, in those keys only (the line's keys unchanged).
// v2: the scan's step grows geometrically far from the limits (path_scan_step).
// v3: a spectral law's better mirror along the path.
// v4: time_domain along a path starts from the symmetric families and retries a failed round.
// v5: as min-time-v5.
// v6: as min-time-v6, and a rectangular tank's time_domain plans optimise along the path.
// v7: as min-time-v7, and the spectral strategies keep a_max on the total acceleration.
// v8: as min-time-v8.
// v9: as min-time-v9, the plans of path-v12.
constexpr const char* kMinTimePathVersion = "min-time-path-v9";

/// Members of a min-time request's format (a plan's format without motion_time_s).
const std::vector<std::string_view> kFormatMembers{"container", "fill_height_mm", "fluid",
                                                   "stroke_mm"};

/// Plan options the search sets itself: given at the top level of the request instead.
bool set_by_search(std::string_view option) {
  return option == "eta_rest_max_mm" || option == "eta_motion_max_mm";
}

std::vector<Strategy> parse_strategies(const json& body) {
  const json* list = given_member(body, "strategies");
  if (list == nullptr) return default_min_time_strategies();
  std::vector<std::string> allowed;
  for (Strategy s : enum_values<Strategy>()) {
    if (s != Strategy::kAuto) allowed.push_back(to_string(s));
  }
  if (!list->is_array() || list->empty() || list->size() > allowed.size()) {
    invalid("strategies", "strategies must be an array of 1 to " + std::to_string(allowed.size()) +
                              " distinct names (" + quoted_names(allowed) + "), got " +
                              show(*list));
  }
  std::vector<Strategy> out;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const json& item = (*list)[i];
    const std::string field = "strategies[" + std::to_string(i) + "]";
    std::optional<Strategy> s;
    if (item.is_string()) s = parse_strategy(item.get<std::string>());
    if (!s || *s == Strategy::kAuto) {
      invalid(field,
              field + " = " + show(item) + " is not allowed: one of " + quoted_names(allowed) +
                  (s ? " (auto is not searched: the response compares the strategies)" : ""));
    }
    if (std::find(out.begin(), out.end(), *s) != out.end()) {
      invalid(field, field + " = " + show(item) + " is listed twice");
    }
    out.push_back(*s);
  }
  return out;
}

json optional_json(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json curve_json(const MinTimeResult& r) {
  json t = json::array(), feasible = json::array(), status = json::array();
  json nl_motion = json::array(), nl_rest = json::array();
  json lin_motion = json::array(), lin_rest = json::array();
  for (const MinTimePoint& p : r.curve) {
    t.push_back(p.motion_time);
    feasible.push_back(p.feasible);
    status.push_back(to_string(p.plan_status));
    nl_motion.push_back(p.prediction.nonlinear.motion.value * 1e3);
    nl_rest.push_back(p.prediction.nonlinear.rest.value * 1e3);
    lin_motion.push_back(p.prediction.linear.motion.value * 1e3);
    lin_rest.push_back(p.prediction.linear.rest.value * 1e3);
  }
  return {{"t_s", t},
          {"feasible", feasible},
          {"plan_status", status},
          {"nonlinear", {{"eta_motion_mm", nl_motion}, {"eta_rest_mm", nl_rest}}},
          {"linear", {{"eta_motion_mm", lin_motion}, {"eta_rest_mm", lin_rest}}},
          {"units", {{"t_s", "s"}, {"eta_motion_mm", "mm"}, {"eta_rest_mm", "mm"}}}};
}

/// The plan request a search's plan answers (its key is the key POST /v1/plans gives it).
PlanRequest plan_request_at(const MinTimeRequest& request, const MinTimeResult& r, double T) {
  PlanRequest p;
  p.format = request.format;
  p.format.motion_time = T;
  p.strategy = r.strategy;
  p.options = request.options.plan;
  p.options.eta_rest_max = r.eta_rest_max;
  p.options.eta_motion_max = r.eta_motion_max;
  p.motion = request.motion;
  for (const MinTimePoint& point : r.curve) {
    if (point.motion_time == T) p.options.warm_start = point.warm_start;
  }
  return p;
}

json strategy_json(const MinTimeRequest& request, const MinTimeResult& r) {
  json out{
      {"strategy", to_string(r.strategy)},
      {"status", to_string(r.status)},
      {"message", r.message},
      {"t_min_s", optional_json(r.t_min)},
      {"infeasible_below_s", optional_json(r.infeasible_below)},
      {"feasible_above", r.t_min && r.feasible_above ? json(*r.feasible_above) : json(nullptr)},
      {"kinematic_lower_bound_s", r.kinematic_bound},
      {"scan_start_s", r.scan_start},
      {"plans", r.plans},
      {"search_ms", r.search_ms}};
  if (r.best) {
    out["best"] = {{"t_s", r.best->motion_time},
                   {"eta_motion_mm", r.best->eta_motion * 1e3},
                   {"eta_rest_mm", r.best->eta_rest * 1e3}};
  } else {
    out["best"] = nullptr;
  }
  if (r.plan) {
    const double T = r.t_min ? *r.t_min : r.best ? r.best->motion_time : r.plan->law.duration();
    const PlanRequest at = plan_request_at(request, r, T);
    out["plan"] = plan_json(at, *r.plan);
    // The durations it was warm-started from (part of its key); null: the planner's own starts.
    out["plan"]["warm_start_s"] =
        at.options.warm_start ? json(*at.options.warm_start) : json(nullptr);
  } else {
    out["plan"] = nullptr;
  }
  out["curve"] = curve_json(r);
  return out;
}

}  // namespace

std::vector<Strategy> default_min_time_strategies() {
  std::vector<Strategy> out;
  for (Strategy s : enum_values<Strategy>()) {
    if (s != Strategy::kAuto && s != Strategy::kIir) out.push_back(s);
  }
  return out;
}

namespace {

// The format without motion time (the search finds it), parsed at motion_time_max.
void refuse_motion_time(const json& format) {
  if (format.contains("motion_time_s")) {
    invalid("format.motion_time_s",
            "format.motion_time_s is not part of a min-time request: the search finds the motion "
            "time; bound it with motion_time_max_s (default 5 s)");
  }
}

Format parse_min_time_format(const json& body, double motion_time_max) {
  if (!body.contains("format")) {
    invalid("format",
            "format is required: {\"container\", \"fill_height_mm\", \"fluid\", \"stroke_mm\"}");
  }
  const json& format = body["format"];
  require_object(format, "format");
  refuse_motion_time(format);
  reject_unknown_fields(format, "format", kFormatMembers);
  json with_time = format;
  with_time["motion_time_s"] = motion_time_max;
  return parse_format(with_time, "format");
}

// eta_motion_max_mm: given, or the free board minus the margin (then the height is required).
void parse_sloshing_limits(const json& body, const Format& format, MinTimeOptions& o) {
  const double margin_mm = optional_number(body, "", "free_board_margin_mm", mr::kMarginMm,
                                           kDefaultFreeBoardMargin * 1e3);
  o.free_board_margin = margin_mm * 1e-3;
  if (const json* eta = given_member(body, "eta_motion_max_mm")) {
    o.eta_motion_max = checked_number(eta, "eta_motion_max_mm", mr::kEtaMm) * 1e-3;
  } else if (!format.container.height) {
    invalid("eta_motion_max_mm",
            "eta_motion_max_mm is required when format.container.height_mm is not given (its "
            "default is the free board: height_mm - fill_height_mm - free_board_margin_mm)");
  } else {
    // In the request's millimetres (validated by parse_min_time_format): 150 - 82 - 0 is 68 mm,
    // the limit an explicit eta_motion_max_mm = 68 gives, where metres leave 67.99999999999999.
    const json& f = body.at("format");
    const double free_board_mm =
        f.at("container").at("height_mm").get<double>() - f.at("fill_height_mm").get<double>();
    if (margin_mm >= free_board_mm) {
      invalid("free_board_margin_mm",
              "free_board_margin_mm = " + number_text(margin_mm) +
                  " leaves no eta_motion_max: the free board (height_mm - fill_height_mm) is " +
                  number_text(free_board_mm) + " mm; allowed below it, or give eta_motion_max_mm");
    }
    // Rounded to 1e-9 mm, so the round-off of the subtraction (150.3 - 82.1 - 5.7 =
    // 62.500000000000014) leaves the limit, and the key, of the same explicit value.
    o.eta_motion_max = std::round((free_board_mm - margin_mm) * 1e9) / 1e9 * 1e-3;
  }
  o.eta_rest_max = optional_number(body, "", "eta_rest_max_mm", mr::kEtaMm, 3.0) * 1e-3;
  if (const json* model = given_member(body, "limit_model")) {
    std::optional<LimitModel> m;
    if (model->is_string()) m = enum_from_name<LimitModel>(model->get<std::string>());
    if (!m) {
      invalid("limit_model", "limit_model = " + show(*model) + " is not allowed: one of " +
                                 quoted_names(enum_names<LimitModel>()));
    }
    o.model = *m;
  }
}

// A plan option's refusal in a min-time request's terms: its motion time is the search's, not
// format.motion_time_s (which a min-time request does not take).
ApiError in_search_terms(const ApiError& e) {
  constexpr std::string_view kPlanTime = "format.motion_time_s";
  std::string message = e.what();
  const std::string search_time =
      "the longest motion time a search plans (" + number_text(mr::kMotionTimeMax.hi) + " s)";
  for (std::size_t at = message.find(kPlanTime); at != std::string::npos;
       at = message.find(kPlanTime, at + search_time.size())) {
    message.replace(at, kPlanTime.size(), search_time);
  }
  return ApiError(e.code(), e.field(), message);
}

// The plan options, as a plan request reads them (at T = motion_time_max for the ranges that
// depend on T), but for the limits the search sets itself; the server's budget applies.
void parse_min_time_plan_options(const json& body, const Format& format, double budget,
                                 PlanOptions& plan) {
  json options = body.value("options", json::object());
  if (options.is_null()) options = json::object();
  require_object(options, "options");
  const OptionRegistry& registry = plan_option_registry();
  for (const auto& [key, value] : options.items()) {
    if (set_by_search(key)) {
      invalid("options." + key, "options." + key +
                                    " is not an option of a min-time request: give the limit as " +
                                    key + " at the top level");
    }
  }
  std::vector<std::string_view> allowed;
  for (std::string_view key : registry.option_keys()) {
    if (!set_by_search(key)) allowed.push_back(key);
  }
  reject_unknown_fields(options, "options", allowed);
  // Ranges that depend on T (min_ramp_s <= T / 4, plateau_min_s <= T) at the longest T the API
  // allows: ramps too long for motion_time_max_s make an empty search, answered infeasible.
  Format widest = format;
  widest.motion_time = mr::kMotionTimeMax.hi;
  try {
    registry.parse(options, widest, plan);
  } catch (const ApiError& e) {
    throw in_search_terms(with_server_range(e, budget));
  }
  Format at = format;  // the plan options hold at the longest T planned (see plan_validation_time)
  at.motion_time = plan_validation_time(format.motion_time, plan);
  InvalidInput error;
  if (!plan.is_valid(at, &error)) {
    invalid(options_field(error, plan), "options." + input_sentence(error, at, plan));
  }
  if (given_member(options, "time_limit_s") == nullptr) {
    plan.time_limit = budget;
  } else if (plan.time_limit > budget) {
    invalid("options.time_limit_s", "options.time_limit_s = " + exact_number_text(plan.time_limit) +
                                        " is out of range: this server allows at most " +
                                        number_text(budget) + " s");
  }
}

}  // namespace

namespace {

// Under drive_profile move_absolute the default list leaves out the strategies whose laws are
// not 7-segment laws; a list that names one is refused at its place.
void fit_strategies_to_drive(const json& body, DriveProfile profile,
                             std::vector<Strategy>& strategies) {
  const bool listed = given_member(body, "strategies") != nullptr;
  for (std::size_t i = 0; i < strategies.size();) {
    const auto why = drive_profile_refusal(strategies[i], profile);
    if (!why) {
      ++i;
      continue;
    }
    if (listed) {
      const std::string field = "strategies[" + std::to_string(i) + "]";
      invalid(field, field + " = \"" + to_string(strategies[i]) +
                         "\" is not allowed with options.drive_profile = move_absolute: its law "
                         "is not a 7-segment law (allowed: baseline, notch, multi_notch, "
                         "min_jerk_band, time_domain, fir_chain)");
    }
    strategies.erase(strategies.begin() + static_cast<std::ptrdiff_t>(i));
  }
}

/// A body whose format.motion is an arc or a path: the body with the motion replaced by its
/// length as format.stroke_mm (the search's format), `motion` the parsed motion; nullopt for any
/// other body (stroke_mm, a line, a trajectory: straight_line_body's).
std::optional<json> path_as_stroke(const json& given, std::optional<SpatialMotion>& motion) {
  const json* m = given_motion(given);
  if (m == nullptr || !m->is_object()) return std::nullopt;
  const auto type = m->find("type");
  if (type == m->end() || (*type != "arc" && *type != "path")) return std::nullopt;
  json timed = given;
  json& format = timed["format"];
  refuse_motion_time(format);
  format["motion_time_s"] = kDefaultMotionTimeMax;  // parsed for the motion; the search's own T
  SpatialFormat spatial = parse_spatial_format(timed, false);
  json body = given;
  body["format"].erase("motion");
  body["format"]["stroke_mm"] = mm_of(spatial.format.stroke);
  motion = std::move(spatial.motion);
  return body;
}

}  // namespace

MinTimeRequest parse_min_time_request(const json& given, double budget) {
  // An arc or a path: the search runs on the format with the path's length as its stroke and
  // plans along the path; a line motion is the stroke (motion_json.hpp).
  std::optional<SpatialMotion> motion;
  const std::optional<json> along = path_as_stroke(given, motion);
  const std::optional<json> line = along ? std::nullopt : straight_line_body(given);
  const json& body = along ? *along : line ? *line : given;
  require_object(body, "");
  reject_unknown_fields(body, "",
                        {"format", "motion_time_max_s", "eta_motion_max_mm", "free_board_margin_mm",
                         "eta_rest_max_mm", "limit_model", "strategies", "scan_step_s", "max_plans",
                         "curve_factor", "refine_excess", "options"});
  MinTimeRequest r;
  MinTimeOptions& o = r.options;
  o.motion_time_max =
      optional_number(body, "", "motion_time_max_s", mr::kMotionTimeMax, kDefaultMotionTimeMax);
  r.format = parse_min_time_format(body, o.motion_time_max);
  parse_sloshing_limits(body, r.format, o);
  r.strategies = parse_strategies(body);
  o.scan_step = optional_number(body, "", "scan_step_s", mr::kScanStep, o.scan_step);
  o.max_plans =
      optional_integer(body, "", "max_plans", mr::kMaxPlansLo, mr::kMaxPlansHi, o.max_plans);
  o.curve_factor = optional_number(body, "", "curve_factor", mr::kCurveFactor, o.curve_factor);
  o.refine_excess = optional_number(body, "", "refine_excess", mr::kRefineExcess, o.refine_excess);
  parse_min_time_plan_options(body, r.format, budget, o.plan);
  fit_strategies_to_drive(body, o.plan.drive_profile, r.strategies);
  if (auto e = o.validate(r.format)) {
    invalid(std::string(api_field_path(e->input)), e->message);
  }
  if (motion) {
    if (o.plan.uncertainty.active()) {
      const std::string field = uncertainty_range_field(o.plan.uncertainty);
      invalid(field, field +
                         " is not available along an arc or a path yet: a plan along a path is "
                         "verified at the nominal model (leave options.uncertainty out, or "
                         "search on a straight line)");
    }
    o.path = motion->path;
    r.motion = std::move(motion);
  }
  return r;
}

std::string min_time_key(const MinTimeRequest& request, std::string_view version) {
  PlanRequest at_max;
  at_max.format = request.format;
  at_max.strategy = Strategy::kBaseline;
  at_max.options = request.options.plan;
  json recipe = canonical_recipe(at_max, plan_option_registry(), version, request.strategies);
  recipe["format"].erase("motion_time_s");
  recipe.erase("strategy");
  const MinTimeOptions& o = request.options;
  json strategies = json::array();
  for (Strategy s : request.strategies) strategies.push_back(to_string(s));
  // Only a search along an arc or a path has the member: every other key stays as it was.
  if (request.motion) recipe["motion"] = canonical_motion(*request.motion);
  recipe["min_time"] = {{"version", kMinTimeVersion},
                        {"motion_time_max_s", o.motion_time_max},
                        {"eta_motion_max_m", *o.eta_motion_limit(request.format)},
                        {"eta_rest_max_m", o.eta_rest_max},
                        {"limit_model", to_string(o.model)},
                        {"strategies", strategies},
                        {"scan_step_s", o.scan_step},
                        {"max_plans", o.max_plans},
                        {"curve_factor", o.curve_factor},
                        {"refine_excess", o.refine_excess}};
  if (request.motion) recipe["min_time"]["path_search"] = kMinTimePathVersion;
  return sha256_key(recipe.dump());
}

json min_time_json(const MinTimeRequest& request, const std::vector<MinTimeResult>& results,
                   const std::string& key) {
  const MinTimeOptions& o = request.options;
  json out;
  out["key"] = key;
  out["cached"] = false;
  out["version"] = kVersion;
  json format = format_json(request.format);
  format.erase("motion_time_s");
  if (request.motion) format["motion"] = request.motion->echo;
  out["format"] = format;
  out["motion_time_max_s"] = o.motion_time_max;
  const MachineLimits& m = o.plan.limits;
  out["limits"] = {{"eta_motion_max_mm", mm_of(*o.eta_motion_limit(request.format))},
                   {"eta_rest_max_mm", mm_of(o.eta_rest_max)},
                   {"model", to_string(o.model)},
                   {"rest_time_s", o.plan.rest_time},
                   {"a_max", optional_json(m.a_max)},
                   {"v_max", optional_json(m.v_max)},
                   {"j_max", optional_json(m.j_max)}};
  out["kinematic_lower_bound_s"] =
      o.path ? kinematic_lower_bound(*o.path, m) : kinematic_lower_bound(request.format.stroke, m);
  json list = json::array();
  for (const MinTimeResult& r : results) list.push_back(strategy_json(request, r));
  out["strategies"] = list;
  const MinTimeSummary s = summarize_min_time(results);
  json headline{
      {"winner", nullptr},
      {"t_min_s", nullptr},
      {"cycles_per_min", nullptr},
      {"baseline_t_min_s", nullptr},
      {"baseline_cycles_per_min", nullptr},
      {"gain_pct", optional_json(s.gain_pct)},
      {"gain_cycles_per_min", optional_json(s.gain_cycles_per_min)},
      {"not_optimal", s.winner_not_optimal.empty() ? json(nullptr) : json(s.winner_not_optimal)},
      {"t_min_is_bound", s.winner_bound}};
  if (s.winner) {
    const double t = *results[*s.winner].t_min;
    headline["winner"] = to_string(results[*s.winner].strategy);
    headline["t_min_s"] = t;
    headline["cycles_per_min"] = 60.0 / t;
  }
  if (s.baseline) {
    const double t = *results[*s.baseline].t_min;
    headline["baseline_t_min_s"] = t;
    headline["baseline_cycles_per_min"] = 60.0 / t;
  }
  out["headline"] = headline;
  require_finite(out);
  return out;
}

json min_time_body_from_recipe(const json& plan_request) {
  if (!plan_request.is_object()) return plan_request;  // the parser names the problem
  json body = plan_request;
  body.erase("strategy");
  if (body.contains("format") && body["format"].is_object() &&
      body["format"].contains("motion_time_s")) {
    body["motion_time_max_s"] = body["format"]["motion_time_s"];
    body["format"].erase("motion_time_s");
  }
  if (body.contains("options") && body["options"].is_object()) {
    for (const char* limit : {"eta_rest_max_mm", "eta_motion_max_mm"}) {
      if (body["options"].contains(limit)) {
        body[limit] = body["options"][limit];
        body["options"].erase(limit);
      }
    }
  }
  return body;
}

json min_time_row_figures(std::string_view answer) {
  json body;
  try {
    body = json::parse(answer);
    json row{{"key", body.at("key")}};
    std::string message;
    for (const json& s : body.at("strategies")) {
      const std::string strategy = s.at("strategy").get<std::string>();
      row["t_min_" + strategy + "_s"] = s.at("t_min_s");
      if (s.at("status") != "optimal") {
        message +=
            (message.empty() ? "" : "; ") + strategy + ": " + s.at("status").get<std::string>();
      }
    }
    const json& h = body.at("headline");
    row["winner"] = h.at("winner");
    row["winner_t_min_s"] = h.at("t_min_s");
    row["baseline_t_min_s"] = h.at("baseline_t_min_s");
    row["gain_pct"] = h.at("gain_pct");
    row["gain_cycles_per_min"] = h.at("gain_cycles_per_min");
    row["message"] = message.empty() ? json(nullptr) : json(message);
    return row;
  } catch (const json::exception& e) {
    throw std::invalid_argument(std::string("the min-time answer is not a min-time response (") +
                                e.what() + ")");
  }
}

void check_min_time_inputs(const MinTimeRequest& request,
                           const std::vector<MinTimeResult>& results) {
  for (const MinTimeResult& r : results) {
    if (r.invalid_input) {
      throw ApiError(ErrorCode::kInvalidValue, "format",
                     plan_refusal(*r.invalid_input, request.format, request.options.plan));
    }
  }
}

bool is_min_time_cacheable(const std::vector<MinTimeResult>& results) {
  return std::all_of(results.begin(), results.end(), [](const MinTimeResult& r) {
    // acceptable: T_min found, its plan not optimal by its warnings; as final as optimal.
    return r.status == SolveStatus::kOptimal || r.status == SolveStatus::kAcceptable ||
           r.status == SolveStatus::kInfeasible;
  });
}

std::string stored_min_time(const MinTimeRequest& request,
                            const std::vector<MinTimeResult>& results, const std::string& key) {
  json out = min_time_json(request, results, key);
  out.erase("cached");
  return dump_json(out);
}

std::string render_min_time_reply(std::string_view stored, bool cached) {
  return with_cached_flag(stored, cached);
}

json run_min_time(const MinTimeRequest& request) {
  std::vector<MinTimeResult> results;
  for (Strategy s : request.strategies) {
    results.push_back(min_time(request.format, s, request.options));
    check_min_time_inputs(request, results);  // stop at the first refused input
  }
  return min_time_json(request, results, min_time_key(request));
}

}  // namespace slosh::api
