#include "slosh/api/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "slosh/api/core_input.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"

namespace slosh::api {

namespace {

// The deepest nesting of arrays and objects in `text`, counted without recursion, or a value above
// kMaxJsonDepth as soon as that is exceeded.
int nesting_depth(std::string_view text) {
  int depth = 0;
  int deepest = 0;
  bool in_string = false;
  bool escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > kMaxJsonDepth) return deepest;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

// Refuses a member given twice in one object while the parser reads it (nlohmann keeps the last
// silently): the body would otherwise say two things and be read as one of them, the one case of
// input silently dropped. Each open object or array is a frame; the path names the member.
class DuplicateMembers {
 public:
  bool operator()(int /*depth*/, nlohmann::json::parse_event_t event,
                  const nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        frames_.push_back(Frame{event == Event::object_start, {}, {}, 0});
        break;
      case Event::key:
        add_key(parsed.get<std::string>());
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        next_element();
        break;
      case Event::value:
        next_element();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object{};
    std::vector<std::string> keys;  // the members read so far (objects are small)
    std::string key;                // the member being read
    std::size_t index{};            // the element being read (arrays)
  };

  void next_element() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }

  void add_key(const std::string& key) {
    Frame& frame = frames_.back();
    if (std::find(frame.keys.begin(), frame.keys.end(), key) != frame.keys.end()) {
      std::string field;
      for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
        field = frames_[i].object ? join_path(field, frames_[i].key)
                                  : field + "[" + std::to_string(frames_[i].index) + "]";
      }
      field = join_path(field, key);
      throw ApiError(ErrorCode::kInvalidValue, field,
                     field +
                         " is given twice: give each member once (a repeated member would "
                         "silently replace the first)");
    }
    frame.keys.push_back(key);
    frame.key = key;
  }

  std::vector<Frame> frames_;
};

}  // namespace

nlohmann::json parse_json_body(std::string_view body) {
  // Deep nesting would overflow the stack of every recursive walk of the value (dump, copy,
  // comparison): bounded before the parser builds anything.
  if (nesting_depth(body) > kMaxJsonDepth) {
    throw ApiError(ErrorCode::kMalformedJson, "",
                   "the body nests arrays and objects deeper than the limit of " +
                       std::to_string(kMaxJsonDepth) + " levels");
  }
  try {
    return nlohmann::json::parse(body, DuplicateMembers{});
  } catch (const nlohmann::json::exception& e) {  // parse errors and number overflow
    // Drop nlohmann's "[json.exception.parse_error.101] " prefix: the rest is the useful part.
    std::string detail = e.what();
    if (const auto end = detail.find("] ");
        detail.rfind("[json.exception.", 0) == 0 && end != std::string::npos) {
      detail.erase(0, end + 2);
    }
    throw ApiError(ErrorCode::kMalformedJson, "", "the body is not valid JSON: " + detail);
  }
}

SimulateRequest parse_simulate_request(const nlohmann::json& body) {
  require_object(body, "");
  reject_unknown_fields(body, "", {"format", "law", "rest_time_s", "sample_period_s", "options"});
  SimulateRequest r;
  r.format = parse_request_format(body);

  nlohmann::json options = body.value("options", nlohmann::json::object());
  if (options.is_null()) options = nlohmann::json::object();
  require_object(options, "options");
  reject_unknown_fields(options, "options", {"modes", "damping", "alpha", "model", "min_ramp_s"});
  refuse_cylinder_model_options(r.format, options, "options");
  parse_model_options(options, "options", r.options.model);
  parse_calibrated_model(options, "options", r.options.model);
  const Range min_ramp_range{ranges::kMinRampS.lo, r.format.motion_time / 4.0, "s"};
  try {
    r.min_ramp = optional_number(options, "options", "min_ramp_s", min_ramp_range, kDefaultMinRamp);
  } catch (const ApiError& e) {
    invalid(e.field(), std::string(e.what()) +
                           " (the upper bound is format.motion_time_s / 4: four ramps must fit)");
  }

  if (!body.contains("law")) {
    invalid("law", "law is required: {\"type\": ..., \"durations_s\": [...]}");
  }
  ParsedLaw law = parse_law(body["law"], "law", r.format, r.min_ramp);
  r.law_type = law.type;
  r.durations = law.durations;
  r.law = std::move(law.law);

  r.options.rest_time =
      optional_number(body, "", "rest_time_s", ranges::kRestTimeS, kDefaultRestTime);
  r.options.sample_period = parse_sample_period(body, r.format.motion_time + r.options.rest_time);
  return r;
}

std::optional<SevenSegmentLaw> seven_segment_law(const SimulateRequest& r) {
  if (r.law_type == LawType::kSevenSegment) return SevenSegmentLaw(*r.durations, r.format.stroke);
  if (r.law_type == LawType::kSevenSegmentUniform) {
    return SevenSegmentLaw(uniform_durations(r.format.motion_time), r.format.stroke);
  }
  return std::nullopt;
}

std::optional<double> parse_sample_period(const nlohmann::json& body, double span) {
  if (!body.contains("sample_period_s") || body["sample_period_s"].is_null()) return std::nullopt;
  const double dt = required_number(body, "", "sample_period_s", ranges::kSamplePeriodS);
  // Samples at 0, dt, ..., both ends included (same count as core::simulate).
  const auto samples = static_cast<long long>(std::floor(span / dt + 1e-9)) + 1;
  if (samples > ranges::kMaxSeriesSamples) {
    invalid("sample_period_s", "sample_period_s = " + number_text(dt) + " s gives " +
                                   std::to_string(samples) + " samples over " + number_text(span) +
                                   " s; at most " + std::to_string(ranges::kMaxSeriesSamples) +
                                   " are returned: use >= " +
                                   number_text(span / (ranges::kMaxSeriesSamples - 1)) + " s");
  }
  return dt;
}

nlohmann::json peaks_json(const SloshPeaks& p) {
  return {{"eta_motion_mm", p.motion.value * 1e3},
          {"eta_rest_mm", p.rest.value * 1e3},
          {"t_motion_s", p.motion.time},
          {"t_rest_s", p.rest.time}};
}

nlohmann::json prediction_json(const SloshPeaks& nonlinear, const SloshPeaks& linear) {
  return {{"nonlinear", peaks_json(nonlinear)}, {"linear", peaks_json(linear)}};
}

nlohmann::json prediction_json(const SimulationResult& r) {
  return prediction_json(r.nonlinear, r.linear);
}

namespace {

/// The simulated law's type, duration, stroke and breakpoints. A law the service builds from the
/// format (every type but the general ones) lasts format.motion_time_s and moves format.stroke_mm
/// by construction: those echo as given, not as the sum of its pieces (1.0, not
/// 0.9999999999999998). A general law's end and stroke are its own (its last breakpoint as given,
/// the integral of its acceleration).
nlohmann::json law_echo(const SimulateRequest& request, const MotionLaw& law) {
  const bool general =
      request.law_type == LawType::kPiecewiseLinear || request.law_type == LawType::kPiecewise;
  return {{"type", to_string(request.law_type)},
          {"duration_s", general ? law.duration() : request.format.motion_time},
          {"stroke_mm", general ? law.stroke() * 1e3 : mm_of(request.format.stroke)},
          {"breakpoints_s", law.breakpoints()}};
}

}  // namespace

nlohmann::json run_simulate(const SimulateRequest& request) {
  const std::optional<SevenSegmentLaw> seven = seven_segment_law(request);
  const MotionLaw& law = seven ? seven->law() : request.law;
  const SimulationResult r = simulate(request.format, law, request.options);
  if (r.invalid_input) {
    invalid(std::string(api_field_path(r.invalid_input->input, Endpoint::kSimulate)),
            simulate_refusal(*r.invalid_input));
  }
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  for (const auto& [model, peaks] : {std::pair{"nonlinear", &r.nonlinear}, {"linear", &r.linear}}) {
    // The peak search skips NaN samples: the series shows them too.
    const bool series_finite =
        !r.series ||
        finite(model == std::string("nonlinear") ? r.series->eta_nonlinear : r.series->eta_linear);
    if (!std::isfinite(peaks->motion.value) || !std::isfinite(peaks->rest.value) ||
        !series_finite) {
      // Outside what the model describes (e.g. hundreds of g on a 1 mm container): no numbers
      // to return, and the caller must know why.
      invalid("law", std::string("the ") + model +
                         " sloshing model diverges for this law on this format (peak |a| = " +
                         number_text(
                             std::max(r.kinematics.a_peak_positive, r.kinematics.a_peak_negative)) +
                         " m/s^2): the motion is outside what the model describes");
    }
  }
  nlohmann::json out;
  nlohmann::json law_json = law_echo(request, law);
  nlohmann::json kin{{"a_max", r.kinematics.a_peak_positive},
                     {"a_min", r.kinematics.a_peak_negative},
                     {"v_peak", r.kinematics.v_peak},
                     {"j_peak", r.kinematics.j_peak}};
  if (seven) {
    law_json["durations_s"] = seven->durations();
    law_json["switch_times_s"] = seven->switch_times();
    law_json["jerks_m_s3"] = seven->jerks();
    // The plateau levels exactly (SPEC §7), not the sampled summary.
    kin["a_max"] = seven->A();
    kin["a_min"] = seven->B();
    kin["v_peak"] = seven->v_peak();
  }
  out["format"] = format_json(request.format);
  out["law"] = law_json;
  out["kinematics"] = kin;
  out["model"] = model_json(r.model, request.options.model);
  out["prediction"] = prediction_json(r);
  if (r.rectangular) {
    add_rectangular_model(out["model"], *r.rectangular, request.options.model);
    // Each direction's own walls (the nonlinear model, or the linear one outside its range).
    out["prediction"]["directions"] = {{"length", peaks_json(r.rectangular_peaks->along_length)},
                                       {"width", peaks_json(r.rectangular_peaks->along_width)}};
  }
  out["rest_time_s"] = request.options.rest_time;
  if (r.series) {
    auto mm = [](std::vector<double> v) {
      for (double& x : v) x *= 1e3;
      return v;
    };
    out["series"] = {{"t_s", r.series->t},
                     {"a", r.series->a},
                     {"v", r.series->v},
                     {"s", r.series->s},
                     {"eta_linear_mm", mm(r.series->eta_linear)},
                     {"eta_nonlinear_mm", mm(r.series->eta_nonlinear)},
                     {"units",
                      {{"t_s", "s"},
                       {"a", "m/s^2"},
                       {"v", "m/s"},
                       {"s", "m"},
                       {"eta_linear_mm", "mm"},
                       {"eta_nonlinear_mm", "mm"}}}};
  }
  out["warnings"] = warning_texts(r.warnings);
  out["warning_codes"] = warning_codes(r.warnings);
  require_finite(out);
  return out;
}

}  // namespace slosh::api
