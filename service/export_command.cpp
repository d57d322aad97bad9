#include "export_command.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

#include "cli_commands.hpp"
#include "io.hpp"
#include "plan_service.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/law_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

/// Shortest and longest controller cycle accepted by --period-ms [ms].
constexpr double kMinPeriodMs = kCamMinPeriod * 1e3;
constexpr double kMaxPeriodMs = 1000.0;

// 12 significant digits; never "-0".
std::string cell(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g", v == 0.0 ? 0.0 : v);
  return buffer;
}

struct SegmentRow {
  int segment;
  double t_start, t_end, jerk, a_start, a_end, v_start, v_end, s_start, s_end;  // SI
};

std::array<SegmentRow, kSegments> segment_rows(const SevenSegmentLaw& law) {
  const auto t = law.switch_times();
  const auto jerks = law.jerks();
  const std::array<double, kSegments + 1> a{0.0, law.A(),  law.A(),  0.0,
                                            0.0, -law.B(), -law.B(), 0.0};
  std::array<SegmentRow, kSegments> rows{};
  for (std::size_t i = 0; i < kSegments; ++i) {
    const KinematicState begin = law.law().at(t[i]);
    const KinematicState end = law.law().at(t[i + 1]);
    rows[i] = {static_cast<int>(i + 1),
               t[i],
               t[i + 1],
               jerks[i],
               a[i],
               a[i + 1],
               begin.velocity,
               end.velocity,
               begin.position,
               i + 1 == kSegments ? law.stroke() : end.position};
  }
  return rows;
}

// The law to export and where it came from.
struct ExportSource {
  MotionLaw law;
  std::optional<SevenSegmentLaw> seven;
  double stroke{};
  json about;  // key/status/message of a plan, or the law type
};

ExportSource source_of(const std::string& text, const ServerConfig& config) {
  const json body = api::parse_json_body(text);
  ExportSource source;
  if (body.is_object() && body.contains("law")) {
    const api::SimulateRequest request = api::parse_simulate_request(body);
    source.seven = api::seven_segment_law(request);
    source.law = source.seven ? source.seven->law() : api::build_law(request);
    source.stroke = request.format.stroke;
    source.about = {{"source", "law"}, {"law", api::to_string(request.law_type)}};
    return source;
  }
  const api::PlanRequest request = api::parse_plan_request(body);
  ServerConfig one = config;
  one.workers = 1;
  PlanService service(one);
  const Reply reply = service.post_plan(text, "");
  const json plan = json::parse(reply.body);
  if (reply.status != 200) {
    const json& error = plan["error"];
    throw api::ApiError(
        reply.status < 500 ? api::ErrorCode::kInvalidValue : api::ErrorCode::kInternal,
        error["field"].is_string() ? error["field"].get<std::string>() : "",
        error.value("message", std::string("the plan failed")));
  }
  // The plan's law in the simulate form: 7-segment durations or a general law (shaper, iir,
  // fir_chain without conditions 14), validated like a simulate request's — ramps only above the
  // 1 ms floor: an infeasible fir_chain law's ramps (T3) may be shorter than min_ramp_s, and
  // --allow-infeasible exports it as it is.
  const api::ParsedLaw law =
      api::parse_law(plan.at("law"), "law", request.format, api::ranges::kMinRampS.lo);
  if (law.durations) source.seven.emplace(*law.durations, request.format.stroke);
  source.law = law.law;
  source.stroke = request.format.stroke;
  source.about = {{"source", "plan"},
                  {"key", plan["key"]},
                  {"cached", plan["cached"]},
                  {"status", plan["status"]},
                  {"law", api::to_string(law.type)},
                  {"message", plan["message"]}};
  return source;
}

void write_text(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text << std::flush;
    return;
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace

std::string cam_table_csv(const std::vector<CamSample>& samples) {
  std::string out = "t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3\n";
  out.reserve(out.size() + samples.size() * 64);
  for (const CamSample& s : samples) {
    out += cell(s.t) + ',' + cell(s.position * 1e3) + ',' + cell(s.velocity * 1e3) + ',' +
           cell(s.acceleration * 1e3) + ',' + cell(s.jerk * 1e3) + '\n';
  }
  return out;
}

std::string segment_table_csv(const SevenSegmentLaw& law) {
  std::string out =
      "segment,t_start_s,t_end_s,duration_s,jerk_mm_s3,a_start_mm_s2,a_end_mm_s2,v_start_mm_s,"
      "v_end_mm_s,s_start_mm,s_end_mm\n";
  for (const SegmentRow& r : segment_rows(law)) {
    out += std::to_string(r.segment) + ',' + cell(r.t_start) + ',' + cell(r.t_end) + ',' +
           cell(law.durations()[static_cast<std::size_t>(r.segment - 1)]) + ',' +
           cell(r.jerk * 1e3) + ',' + cell(r.a_start * 1e3) + ',' + cell(r.a_end * 1e3) + ',' +
           cell(r.v_start * 1e3) + ',' + cell(r.v_end * 1e3) + ',' + cell(r.s_start * 1e3) + ',' +
           cell(r.s_end * 1e3) + '\n';
  }
  return out;
}

int run_export_command(const ExportCommandOptions& options) {
  auto fail = [](int code, const api::ApiError& e) {
    std::cerr << api::dump_json(api::error_envelope(e), 2) << '\n';
    return code;
  };
  if (!(options.period_ms >= kMinPeriodMs && options.period_ms <= kMaxPeriodMs)) {
    return fail(kExitInvalidInput,
                api::ApiError(api::ErrorCode::kInvalidValue, "--period-ms",
                              "--period-ms = " + api::number_text(options.period_ms) +
                                  " is out of range [" + api::number_text(kMinPeriodMs) + ", " +
                                  api::number_text(kMaxPeriodMs) + "] ms"));
  }
  ExportSource source;
  try {
    std::string text;
    try {
      text = read_request_text(options.request);
    } catch (const std::exception& e) {
      throw api::ApiError(api::ErrorCode::kInvalidValue, "--request", e.what());
    }
    source = source_of(text, options.config);
  } catch (const api::ApiError& e) {
    return fail(e.status() < 500 ? kExitInvalidInput : kExitFailure, e);
  } catch (const std::exception& e) {
    return fail(kExitFailure, api::ApiError(api::ErrorCode::kInternal, "", e.what()));
  }
  if (source.about.value("source", "") == "plan") {
    const std::string status = source.about.value("status", "");
    if (status != "optimal" && status != "acceptable" && !options.allow_infeasible) {
      return fail(
          kExitFailure,
          api::ApiError(api::ErrorCode::kInternal, "",
                        "the plan is " + status + ", its law misses the requested limits: " +
                            source.about.value("message", std::string()) +
                            ". Not exported; pass --allow-infeasible to export the best "
                            "reachable law anyway"));
    }
  }
  if (!options.segments.empty() && !source.seven) {
    return fail(kExitInvalidInput,
                api::ApiError(api::ErrorCode::kInvalidValue, "--segments",
                              "--segments: the law " + source.about.value("law", std::string()) +
                                  " is not a 7-segment law; it has no segment table"));
  }
  const double period = options.period_ms * 1e-3;
  std::vector<CamSample> samples;
  try {
    samples = sample_cam_table(source.law, source.stroke, period);
  } catch (const std::invalid_argument& e) {
    return fail(kExitInvalidInput,
                api::ApiError(api::ErrorCode::kInvalidValue, "--period-ms", e.what()));
  }
  const double T = source.law.duration();
  json warnings = json::array();
  const double end_time = samples.back().t;
  if (end_time - T > kCamTimeTolerance) {
    warnings.push_back("the motion time " + api::number_text(T) + " s is not a multiple of the " +
                       api::number_text(options.period_ms) + " ms cycle: the law ends " +
                       api::number_text((end_time - T) * 1e3) +
                       " ms before the last sample, which holds the stroke");
  }
  try {
    write_text(options.out, cam_table_csv(samples));
    if (source.seven && !options.segments.empty()) {
      write_text(options.segments, segment_table_csv(*source.seven));
    }
  } catch (const std::exception& e) {
    return fail(kExitFailure, api::ApiError(api::ErrorCode::kInternal, "--out", e.what()));
  }
  if (options.out == "-") {
    for (const json& w : warnings)
      std::cerr << "slosh export: warning: " << w.get<std::string>() << '\n';
    return kExitOk;
  }

  json summary = source.about;
  summary["cam_table"] = options.out;
  summary["period_s"] = period;
  summary["samples"] = samples.size();
  summary["motion_time_s"] = T;
  summary["end_time_s"] = end_time;
  summary["stroke_mm"] = source.stroke * 1e3;
  if (source.seven) {
    const SevenSegmentLaw& law = *source.seven;
    json segments = json::array();
    for (const SegmentRow& r : segment_rows(law)) {
      segments.push_back({{"segment", r.segment},
                          {"t_start_s", r.t_start},
                          {"duration_s", law.durations()[static_cast<std::size_t>(r.segment - 1)]},
                          {"jerk_mm_s3", r.jerk * 1e3},
                          {"a_start_mm_s2", r.a_start * 1e3},
                          {"a_end_mm_s2", r.a_end * 1e3}});
    }
    summary["durations_s"] = law.durations();
    summary["A_mm_s2"] = law.A() * 1e3;
    summary["B_mm_s2"] = law.B() * 1e3;
    summary["v_peak_mm_s"] = law.v_peak() * 1e3;
    summary["segments"] = std::move(segments);
    if (!options.segments.empty()) summary["segment_table"] = options.segments;
  }
  summary["warnings"] = std::move(warnings);
  std::cout << api::dump_json(summary, 2) << '\n';
  return kExitOk;
}

}  // namespace slosh::service
