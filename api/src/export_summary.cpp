#include "slosh/api/export_summary.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

namespace slosh::api {

namespace {

nlohmann::json segments_json(const SevenSegmentLaw& law) {
  const auto t = law.switch_times();
  const auto jerks = law.jerks();
  const std::array<double, kSegments + 1> a{0.0, law.A(),  law.A(),  0.0,
                                            0.0, -law.B(), -law.B(), 0.0};
  nlohmann::json segments = nlohmann::json::array();
  for (std::size_t i = 0; i < kSegments; ++i) {
    segments.push_back({{"segment", i + 1},
                        {"t_start_s", t[i]},
                        {"duration_s", law.durations()[i]},
                        {"jerk_mm_s3", jerks[i] * 1e3},
                        {"a_start_mm_s2", a[i] * 1e3},
                        {"a_end_mm_s2", a[i + 1] * 1e3}});
  }
  return segments;
}

}  // namespace

std::string export_summary_json(const ExportSummary& s) {
  nlohmann::json out;
  if (s.plan) {
    out = {{"source", "plan"},
           {"key", s.plan->key},
           {"cached", s.plan->cached},
           {"status", name_of(s.plan->status)},
           {"law", s.law_type},
           {"message", s.plan->message},
           {"plan_warnings", s.plan->warnings}};
  } else {
    out = {{"source", "law"}, {"law", s.law_type}};
  }
  out["cam_table"] = s.cam_table;
  out["file_format"] = s.file_format;
  out["table"] = s.master ? "master" : "time";
  if (s.master) {
    const MasterAxis& m = *s.master;
    out["master"] = {{"period", m.period},
                     {"start", m.start},
                     {"end", m.end},
                     {"step", m.step},
                     {"speed_per_s", (m.end - m.start) / s.motion_time},
                     {"equidistant", master_grid_is_equidistant(m)}};
  } else {
    out["period_s"] = s.period;
  }
  out["samples"] = s.samples;
  out["motion_time_s"] = s.motion_time;
  if (!s.master) out["end_time_s"] = s.end_time;
  out["stroke_mm"] = mm_of(s.stroke);
  if (s.seven) {
    const SevenSegmentLaw& law = *s.seven;
    out["durations_s"] = law.durations();
    out["A_mm_s2"] = law.A() * 1e3;
    out["B_mm_s2"] = law.B() * 1e3;
    out["v_peak_mm_s"] = law.v_peak() * 1e3;
    out["segments"] = segments_json(law);
    if (!s.segment_table.empty()) out["segment_table"] = s.segment_table;
  }
  if (!s.motion_type.empty()) {
    out["motion"] = {{"type", s.motion_type}, {"length_mm", mm_of(s.stroke)}};
    if (s.table_rotation_deg) out["motion"]["table_rotation_deg"] = *s.table_rotation_deg;
  }
  out["warnings"] = s.warnings;
  return dump_json(out, 2);
}

}  // namespace slosh::api
