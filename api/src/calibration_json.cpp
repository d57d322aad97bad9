#include "slosh/api/calibration_json.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "slosh/api/calibration_container.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/law_json.hpp"
#include "slosh/core/model/rectangular_calibration.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

const Range kEtaMm{0.0, 10000.0, "mm", true, false};
const Range kSampleEtaMm{-10000.0, 10000.0, "mm"};
const Range kSampleTimeS{-3600.0, 3600.0, "s"};
const Range kOffsetS{-3600.0, 3600.0, "s"};
const Range kMaxOffsetS{0.0, 10.0, "s", true, false};
const Range kRestWindowS{0.0, 60.0, "s", true, false};

// The allowed range of each parameter's bounds: what options.model accepts.
Range parameter_range(CalibrationParameter p) {
  switch (p) {
    case CalibrationParameter::kOmegaScale:
    case CalibrationParameter::kHeightGain:
      return ranges::kModelScale;
    case CalibrationParameter::kZeta:
      return ranges::kZeta;
    case CalibrationParameter::kAlpha:
      return ranges::kAlpha;
  }
  return ranges::kModelScale;
}

std::vector<double> number_list(const json& object, const std::string& path, std::string_view key,
                                const Range& range) {
  const std::string field = join_path(path, key);
  const json* v = given_member(object, key);
  if (v == nullptr || !v->is_array()) {
    invalid(field, field + " must be an array of numbers, got " + (v ? show(*v) : "nothing"));
  }
  if (v->size() < 2) {
    invalid(field,
            field + " has " + std::to_string(v->size()) + " samples: a series needs at least 2");
  }
  if (v->size() > kMaxSeriesSamples) {
    invalid(field, field + " has " + std::to_string(v->size()) + " samples: at most " +
                       std::to_string(kMaxSeriesSamples));
  }
  std::vector<double> out;
  out.reserve(v->size());
  for (std::size_t i = 0; i < v->size(); ++i) {
    out.push_back(checked_number(&(*v)[i], field + "[" + std::to_string(i) + "]", range));
  }
  return out;
}

MeasuredSeries parse_series(const json& s, const std::string& path) {
  require_object(s, path);
  reject_unknown_fields(s, path, {"t_s", "eta_mm", "offset_s", "fit_offset", "max_offset_s"});
  MeasuredSeries out;
  out.t = number_list(s, path, "t_s", kSampleTimeS);
  for (std::size_t i = 1; i < out.t.size(); ++i) {
    if (!(out.t[i] > out.t[i - 1])) {
      const std::string field = join_path(path, "t_s") + "[" + std::to_string(i) + "]";
      invalid(field, field + " = " + number_text(out.t[i]) + " is not after t_s[" +
                         std::to_string(i - 1) + "] = " + number_text(out.t[i - 1]) +
                         ": sample times must increase");
    }
  }
  out.eta = number_list(s, path, "eta_mm", kSampleEtaMm);
  if (out.eta.size() != out.t.size()) {
    const std::string field = join_path(path, "eta_mm");
    invalid(field, field + " has " + std::to_string(out.eta.size()) + " samples, t_s has " +
                       std::to_string(out.t.size()) + ": one height per time");
  }
  for (double& e : out.eta) e *= 1e-3;
  out.offset = optional_number(s, path, "offset_s", kOffsetS, 0.0);
  out.fit_offset = optional_bool(s, path, "fit_offset", false);
  out.max_offset = optional_number(s, path, "max_offset_s", kMaxOffsetS, 0.25);
  return out;
}

MeasuredPeaks parse_peaks(const json& p, const std::string& path) {
  require_object(p, path);
  reject_unknown_fields(p, path, {"eta_motion_mm", "eta_rest_mm", "rest_window_s"});
  MeasuredPeaks out;
  if (given_member(p, "eta_motion_mm") != nullptr)
    out.eta_motion = required_number(p, path, "eta_motion_mm", kEtaMm) * 1e-3;
  if (given_member(p, "eta_rest_mm") != nullptr)
    out.eta_rest = required_number(p, path, "eta_rest_mm", kEtaMm) * 1e-3;
  if (!out.eta_motion && !out.eta_rest) {
    invalid(path, path + " has neither eta_motion_mm nor eta_rest_mm: give at least one");
  }
  out.rest_window = optional_number(p, path, "rest_window_s", kRestWindowS, 1.0);
  return out;
}

MeasuredMove parse_move(const json& m, const std::string& path, const Format& format,
                        std::vector<double>* orientations) {
  require_object(m, path);
  reject_unknown_fields(m, path,
                        {"name", "motion_time_s", "orientation_deg", "law", "series", "peaks"});
  if (format.container.rectangular) {
    double phi = optional_number(m, path, "orientation_deg", ranges::kOrientationDeg,
                                 format.container.rectangular->orientation_deg);
    if (phi == -180.0) phi = 180.0;  // the same turn, as format.container.orientation_deg
    orientations->push_back(phi + 0.0);
  } else if (given_member(m, "orientation_deg") != nullptr) {
    const std::string field = join_path(path, "orientation_deg");
    invalid(field, field +
                       " applies to a rectangular container only (the turn of its sides "
                       "against the move)");
  }
  MeasuredMove out;
  out.name = m.contains("name") && m["name"].is_string() ? m["name"].get<std::string>() : path;
  Format f = format;
  f.motion_time =
      optional_number(m, path, "motion_time_s", ranges::kMotionTimeS, format.motion_time);
  if (!m.contains("law")) {
    invalid(join_path(path, "law"),
            join_path(path, "law") + " is required: the law the bench ran, as simulate takes it");
  }
  out.law = parse_law(m["law"], join_path(path, "law"), f, kDefaultMinRamp).law;
  if (given_member(m, "series") != nullptr)
    out.series = parse_series(m["series"], join_path(path, "series"));
  if (given_member(m, "peaks") != nullptr)
    out.peaks = parse_peaks(m["peaks"], join_path(path, "peaks"));
  if (!out.series && !out.peaks) {
    invalid(path, path + " has neither series nor peaks: give what was measured");
  }
  return out;
}

ParameterSetting parse_setting(const json& fit, CalibrationParameter p, ParameterSetting s) {
  const std::string name(name_of(p));
  const json* v = given_member(fit, name);
  if (v == nullptr) return s;
  const std::string path = "fit." + name;
  require_object(*v, path);
  reject_unknown_fields(*v, path, {"fit", "initial", "min", "max"});
  const Range range = parameter_range(p);
  s.fit = optional_bool(*v, path, "fit", true);
  s.lower = optional_number(*v, path, "min", range, s.lower);
  s.upper = optional_number(*v, path, "max", range, s.upper);
  if (!(s.lower < s.upper)) {
    invalid(path + ".max", path + ".max = " + number_text(s.upper) + " must exceed " + path +
                               ".min = " + number_text(s.lower));
  }
  if (given_member(*v, "initial") != nullptr) {
    s.initial = required_number(*v, path, "initial", Range{s.lower, s.upper, ""});
  }
  return s;
}

void parse_fit(const json& body, CalibrationSettings& settings) {
  const json* fit = given_member(body, "fit");
  if (fit == nullptr) return;
  require_object(*fit, "fit");
  reject_unknown_fields(*fit, "fit",
                        {"omega_scale", "zeta", "alpha", "height_gain", "max_iterations"});
  for (std::size_t j = 0; j < kCalibrationParameters; ++j) {
    settings.parameters[j] =
        parse_setting(*fit, static_cast<CalibrationParameter>(j), settings.parameters[j]);
  }
  settings.max_iterations = optional_integer(*fit, "fit", "max_iterations", 1, 500, 60);
}

// A start value the caller left to the model must lie within the bounds given (no silent clamp).
void check_priors(const CalibrationRequest& r) {
  ModelOptions unit = r.base;
  unit.omega_scale = 1.0;
  unit.height_gain = 1.0;
  const SloshingModel m = make_sloshing_model(r.format, unit);
  const std::array<double, kCalibrationParameters> own{1.0, m.zeta, r.base.alpha, 1.0};
  for (std::size_t j = 0; j < kCalibrationParameters; ++j) {
    const ParameterSetting& s = r.settings.parameters[j];
    if (s.initial || (own[j] >= s.lower && own[j] <= s.upper)) continue;
    const std::string path = "fit." + std::string(name_of(static_cast<CalibrationParameter>(j)));
    invalid(path, path + ": the model's own value " + number_text(own[j]) + " is outside [" +
                      number_text(s.lower) + ", " + number_text(s.upper) + "]: widen min/max or " +
                      "give " + path + ".initial");
  }
}

}  // namespace

void validate_calibration_name(const std::string& name, const std::string& field) {
  bool ok = !name.empty() && name.size() <= kMaxCalibrationName &&
            std::isalnum(static_cast<unsigned char>(name.front())) != 0;
  for (const char c : name) {
    ok = ok &&
         (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '-');
  }
  if (!ok) {
    invalid(field, field + " = " + show(json(name)) +
                       " is not a calibration name: 1 to 64 characters of A-Z a-z 0-9 . _ -, "
                       "starting with a letter or digit");
  }
}

/// A rectangular tank is calibrated per direction (calibrate_rectangular), each direction's
/// Duffing coefficient following from the depth: alpha is not fitted but held at the theory's
/// value (the settings say so, and the priors' check passes it whatever its sign).
void fix_rectangular_alpha(const json& body, CalibrationRequest& r) {
  const json* fit = given_member(body, "fit");
  const json* alpha_fit = fit != nullptr ? given_member(*fit, "alpha") : nullptr;
  // {"fit": false} asks for what happens anyway (the theory's alpha, held): accepted.
  const bool held = alpha_fit != nullptr && *alpha_fit == json{{"fit", false}};
  if (alpha_fit != nullptr && !held) {
    invalid("fit.alpha",
            "fit.alpha applies to the cylinder's model only: a rectangular "
            "container's nonlinear coefficient follows from its depth");
  }
  ModelOptions unit = r.base;
  unit.omega_scale = unit.height_gain = 1.0;
  r.base.alpha = make_sloshing_model(r.format, unit).alpha;
  ParameterSetting& alpha =
      r.settings.parameters[static_cast<std::size_t>(CalibrationParameter::kAlpha)];
  alpha.fit = false;
  alpha.initial = r.base.alpha;
  // (Above the critical depth the coefficient is negative, softening: the bounds hold it.)
  alpha.lower = std::min(alpha.lower, r.base.alpha - 1.0);
  alpha.upper = std::max(alpha.upper, r.base.alpha + 1.0);
}

CalibrationRequest parse_calibration_request(const json& body) {
  require_object(body, "");
  reject_unknown_fields(body, "", {"format", "options", "moves", "fit", "name"});
  CalibrationRequest r;
  r.format = parse_request_format(body);
  json options = body.value("options", json::object());
  if (options.is_null()) options = json::object();
  require_object(options, "options");
  reject_unknown_fields(options, "options", {"modes", "damping", "alpha"});
  refuse_cylinder_model_options(r.format, options, "options");
  parse_model_options(options, "options", r.base);
  if (given_member(body, "name") != nullptr) {
    if (!body["name"].is_string())
      invalid("name", "name must be a string, got " + show(body["name"]));
    r.name = body["name"].get<std::string>();
    validate_calibration_name(*r.name, "name");
  }
  const json* moves = given_member(body, "moves");
  if (moves == nullptr || !moves->is_array() || moves->empty() ||
      moves->size() > kMaxCalibrationMoves) {
    invalid("moves", "moves must be an array of 1 to " + std::to_string(kMaxCalibrationMoves) +
                         " measured moves, got " + (moves ? show(*moves) : "nothing"));
  }
  for (std::size_t i = 0; i < moves->size(); ++i) {
    r.moves.push_back(
        parse_move((*moves)[i], "moves[" + std::to_string(i) + "]", r.format, &r.orientations));
  }
  parse_fit(body, r.settings);
  if (r.format.container.rectangular) fix_rectangular_alpha(body, r);
  check_priors(r);
  return r;
}

json calibrated_model_json(const ModelOptions& m) {
  return {{"omega_scale", m.omega_scale},
          {"zeta", m.explicit_zeta},
          {"alpha", m.alpha},
          {"height_gain", m.height_gain}};
}

namespace {

json parameter_json(const FittedParameter& p) {
  return {{"value", p.value},
          {"prior", p.prior},
          {"standard_error", p.standard_error ? json(*p.standard_error) : json(nullptr)},
          {"state", name_of(p.state)},
          {"at_bound", p.at_bound}};
}

json move_fits_json(const std::vector<MoveFit>& fits) {
  json moves = json::array();
  for (const MoveFit& m : fits) {
    moves.push_back({{"name", m.name},
                     {"residuals", m.residuals},
                     {"rms_before_mm", m.rms_before * 1e3},
                     {"rms_after_mm", m.rms_after * 1e3},
                     {"offset_s", m.offset ? json(*m.offset) : json(nullptr)},
                     {"offset_standard_error_s",
                      m.offset_standard_error ? json(*m.offset_standard_error) : json(nullptr)}});
  }
  return moves;
}

/// A rectangular container fitted per direction (calibrate_rectangular): its parameters and
/// model named as options.model takes them: omega_scale and zeta of the length and
/// width_omega_scale and width_zeta of the width when the moves drove both, else omega_scale
/// and zeta of the one direction they drove.
json run_per_direction(const CalibrationRequest& request) {
  std::vector<RectangularMeasuredMove> moves;
  for (std::size_t i = 0; i < request.moves.size(); ++i) {
    moves.push_back({request.moves[i], request.orientations[i]});
  }
  const RectangularCalibrationResult fit =
      calibrate_rectangular(request.format, request.base, moves, request.settings);
  if (!fit.refused.empty()) {
    invalid("moves", "moves cannot calibrate this container: " + fit.refused);
  }
  json out;
  out["status"] = name_of(fit.status);
  out["iterations"] = fit.iterations;
  out["sigma_mm"] = fit.sigma * 1e3;
  const bool both = fit.length.measured && fit.width.measured;
  const DirectionCalibration& first = fit.length.measured ? fit.length : fit.width;
  json parameters{{"omega_scale", parameter_json(first.omega_scale)},
                  {"zeta", parameter_json(first.zeta)},
                  {"height_gain", parameter_json(fit.height_gain)}};
  json model{{"omega_scale", first.omega_scale.value},
             {"zeta", first.zeta.value},
             {"height_gain", fit.height_gain.value}};
  if (both) {
    parameters["width_omega_scale"] = parameter_json(fit.width.omega_scale);
    parameters["width_zeta"] = parameter_json(fit.width.zeta);
    model["width_omega_scale"] = fit.width.omega_scale.value;
    model["width_zeta"] = fit.width.zeta.value;
  }
  // A zeta neither fitted nor given is the tank's own boundary-layer damping at the fitted
  // fill: left out, so that a plan at another fill keeps its own.
  const auto zeta = static_cast<std::size_t>(CalibrationParameter::kZeta);
  if (!request.settings.parameters[zeta].initial) {
    if (first.zeta.state != ParameterState::kFitted) model.erase("zeta");
    if (both && fit.width.zeta.state != ParameterState::kFitted) model.erase("width_zeta");
  }
  out["parameters"] = std::move(parameters);
  out["moves"] = move_fits_json(fit.moves);
  out["identifiability"] = fit.notes;
  out["model"] = std::move(model);
  json container = fitted_container_json(request.format);
  container["directions"] = both ? json::array({"length", "width"})
                                 : json::array({fit.length.measured ? "length" : "width"});
  out["container"] = std::move(container);
  if (request.name) out["name"] = *request.name;
  return out;
}

/// The cylinder's fit (calibrate): its four parameters, its model as options.model takes it.
json run_cylinder(const CalibrationRequest& request) {
  const CalibrationResult fit =
      calibrate(request.format, request.base, request.moves, request.settings);
  json out;
  out["status"] = name_of(fit.status);
  out["iterations"] = fit.iterations;
  out["sigma_mm"] = fit.sigma * 1e3;
  json parameters = json::object();
  for (std::size_t j = 0; j < kCalibrationParameters; ++j) {
    parameters[std::string(name_of(static_cast<CalibrationParameter>(j)))] =
        parameter_json(fit.parameters[j]);
  }
  out["parameters"] = std::move(parameters);
  out["moves"] = move_fits_json(fit.moves);
  out["identifiability"] = fit.identifiability;
  out["model"] = calibrated_model_json(fit.model);
  // What the fit holds for: a request naming it on another container is refused.
  out["container"] = fitted_container_json(request.format);
  if (request.name) out["name"] = *request.name;
  return out;
}

}  // namespace

json run_calibration(const CalibrationRequest& request) {
  json out =
      request.format.container.rectangular ? run_per_direction(request) : run_cylinder(request);
  out["fit_version"] = kCalibrationFitVersion;
  return out;
}

}  // namespace slosh::api
