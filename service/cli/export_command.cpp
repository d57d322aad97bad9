#include "cli/export_command.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <variant>

#include "cli/cli_commands.hpp"
#include "cli/io.hpp"
#include "engine/plan_engine.hpp"
#include "export/path_cam_export.hpp"
#include "slosh/api/command_replies.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/export_request.hpp"
#include "slosh/api/export_summary.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/law_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_law.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/law/path_cam_table.hpp"

namespace slosh::service {

namespace {

std::string cell(double v) {
  return csv_number(v);
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
  std::string law_type;                   // api::LawType name
  std::string strategy;                   // the plan's strategy; empty for a law request
  std::optional<api::ExportedPlan> plan;  // empty for a law request
  std::optional<PlanarPath> path;         // an arc or a path (format.motion); empty: the line
  std::string motion_type;                // "arc" or "path" with a path
};

ExportSource law_source(const api::ExportLawRequest& export_request) {
  const api::SimulateRequest& request = export_request.request;
  ExportSource source;
  source.path = export_request.path;
  if (source.path) {
    source.motion_type = export_request.motion_type == api::MotionType::kArc ? "arc" : "path";
  }
  source.seven = api::seven_segment_law(request);
  source.law = source.seven ? source.seven->law() : api::build_law(request);
  source.stroke = request.format.stroke;
  source.law_type = api::to_string(request.law_type);
  return source;
}

// The plan of the request `text` (already checked by api::parse_export_request).
ExportSource plan_source(const std::string& text, const ServerConfig& config) {
  ServerConfig one = config;
  one.workers = 1;
  PlanEngine engine(one);
  std::string plan_text;
  try {
    const PlanAnswer answer = engine.answer_plan(text, api::PlanView::kFull);
    plan_text = engine.plan_body(answer, false).body;
  } catch (const api::ApiError& e) {
    // The request's own errors are invalid input; the engine's (overloaded, timeout) are not.
    throw api::ApiError(
        e.status() < 500 ? api::ErrorCode::kInvalidValue : api::ErrorCode::kInternal, e.field(),
        e.what());
  }
  api::PlanLaw plan = api::plan_law(plan_text);
  ExportSource source;
  source.seven = plan.seven;
  source.law = plan.law;
  source.stroke = plan.stroke;
  source.law_type = api::to_string(plan.type);
  source.strategy = plan.strategy;
  source.plan = api::ExportedPlan{plan.key, plan.cached, plan.status, plan.message, plan.warnings};
  // A plan along an arc or a path: its cam table carries the pose too.
  if (std::optional<api::SpatialMotion> motion = api::plan_path_motion(plan_text)) {
    source.path = std::move(motion->path);
    source.motion_type = motion->type == api::MotionType::kArc ? "arc" : "path";
  }
  return source;
}

ExportSource source_of(const std::string& text, const ServerConfig& config) {
  if (const auto law = api::parse_export_request(text)) return law_source(*law);
  return plan_source(text, config);
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

namespace {

// What a failed export prints (the envelope on stderr) and its exit code.
struct ExportFailure {
  int exit_code;
  api::ApiError error;
};

int report(const ExportFailure& f) {
  std::cerr << api::error_envelope_text(f.error) << '\n';
  return f.exit_code;
}

ExportFailure invalid(std::string field, const std::string& message) {
  return {kExitInvalidInput,
          api::ApiError(api::ErrorCode::kInvalidValue, std::move(field), message)};
}

// The validated cam table options of the command line.
std::variant<CamTableSpec, ExportFailure> cam_spec(const CamOptions& options) {
  try {
    return resolve_cam_options(options, cli_option_names(), kCamMaxSamples, "");
  } catch (const api::ApiError& e) {
    return ExportFailure{kExitInvalidInput, e};
  }
}

// The law of the request (a plan is solved or read from the cache).
std::variant<ExportSource, ExportFailure> load_source(const ExportCommandOptions& options) {
  try {
    std::string text;
    try {
      text = read_request_text(options.request);
    } catch (const std::exception& e) {
      throw api::ApiError(api::ErrorCode::kInvalidValue, "--request", e.what());
    }
    return source_of(text, options.config);
  } catch (const api::ApiError& e) {
    return ExportFailure{e.status() < 500 ? kExitInvalidInput : kExitFailure, e};
  } catch (const std::exception& e) {
    return ExportFailure{kExitFailure, api::ApiError(api::ErrorCode::kInternal, "", e.what())};
  }
}

// An infeasible or time-limited plan only with --allow-infeasible; a segment table only of a
// 7-segment law.
std::optional<ExportFailure> check_exportable(const ExportSource& source,
                                              const ExportCommandOptions& options) {
  if (source.plan && !options.allow_infeasible && !api::exportable(source.plan->status)) {
    api::PlanLaw plan;
    plan.status = source.plan->status;
    plan.message = source.plan->message;
    // The refusal the service gives (422 naming allow_infeasible), with the command's exit code.
    return ExportFailure{
        kExitFailure, api::ApiError(api::ErrorCode::kInvalidValue, "allow_infeasible",
                                    api::not_exportable_message(plan, "pass --allow-infeasible"))};
  }
  if (!options.segments.empty() && !source.seven) {
    return invalid("--segments", "--segments: the law " + source.law_type +
                                     " is not a 7-segment law; it has no segment table");
  }
  return std::nullopt;
}

api::ExportSummary summary_of(const ExportSource& source, const ExportCommandOptions& options,
                              const CamTableSpec& spec, const CamTable& table) {
  api::ExportSummary s;
  s.law_type = source.law_type;
  s.plan = source.plan;
  s.cam_table = options.out;
  s.file_format = spec.format == CamFileFormat::kSt ? "st" : "csv";
  s.period = table.period;
  s.master = table.axis;
  s.samples = table.rows();
  s.motion_time = source.law.duration();
  s.end_time = table.axis ? 0.0 : table.time.back().t;
  s.stroke = source.stroke;
  s.seven = source.seven;
  if (source.seven) s.segment_table = options.segments;
  s.warnings = cam_warnings(table);
  s.motion_type = source.motion_type;
  if (source.path) s.table_rotation_deg = table_rotation_deg(*source.path);
  return s;
}

CamSource cam_source(const ExportSource& source) {
  CamSource c;
  c.law_type = source.law_type;
  c.strategy = source.strategy;
  c.key = source.plan ? source.plan->key : "";
  c.stroke = source.stroke;
  c.motion_time = source.law.duration();
  return c;
}

}  // namespace

int run_export_command(const ExportCommandOptions& options) {
  auto resolved = cam_spec(options.cam);
  if (auto* failure = std::get_if<ExportFailure>(&resolved)) return report(*failure);
  const CamTableSpec& spec = std::get<CamTableSpec>(resolved);
  auto loaded = load_source(options);
  if (auto* failure = std::get_if<ExportFailure>(&loaded)) return report(*failure);
  const ExportSource& source = std::get<ExportSource>(loaded);
  if (auto failure = check_exportable(source, options)) return report(*failure);
  CamTable table;
  std::string file;
  try {
    table = sample_cam(source.law, source.stroke, spec, cli_option_names());
  } catch (const api::ApiError& e) {
    return report({kExitInvalidInput, e});
  }
  try {
    file = source.path ? path_cam_file(table, *source.path, cam_source(source), spec)
                       : cam_file(table, cam_source(source), spec);
  } catch (const std::exception& e) {
    return report({kExitFailure, api::ApiError(api::ErrorCode::kInternal, "", e.what())});
  }
  const api::ExportSummary summary = summary_of(source, options, spec, table);
  try {
    write_text(options.out, file);
    if (source.seven && !options.segments.empty()) {
      write_text(options.segments, segment_table_csv(*source.seven));
    }
  } catch (const std::exception& e) {
    return report({kExitFailure, api::ApiError(api::ErrorCode::kInternal, "--out", e.what())});
  }
  if (options.out == "-") {
    for (const std::string& w : summary.warnings) {
      std::cerr << "slosh export: warning: " << w << '\n';
    }
    return kExitOk;
  }
  std::cout << api::export_summary_json(summary) << '\n';
  return kExitOk;
}

}  // namespace slosh::service
