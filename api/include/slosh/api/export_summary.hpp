#pragma once
// The JSON summary `slosh export` prints: where the exported law came from and the tables it
// wrote.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh::api {

/// The plan an exported law came from.
struct ExportedPlan {
  std::string key;
  bool cached{false};
  SolveStatus status{SolveStatus::kFailed};
  std::string message;
  std::vector<std::string> warnings;  ///< the plan's own (the cam table's are the summary's)
};

/// What an export wrote.
struct ExportSummary {
  std::string law_type;                  ///< LawType name
  std::optional<ExportedPlan> plan;      ///< empty when a law request was exported
  std::string cam_table;                 ///< path of the cam table
  std::string file_format{"csv"};        ///< how the cam table is written: "csv" or "st"
  double period{};                       ///< controller cycle [s] (time-based table)
  std::optional<MasterAxis> master;      ///< the master axis of a master-axis table
  std::size_t samples{};                 ///< rows of the cam table
  double motion_time{};                  ///< [s]
  double end_time{};                     ///< time of the last sample [s] (time-based table)
  double stroke{};                       ///< [m]
  std::optional<SevenSegmentLaw> seven;  ///< the 7-segment law, when the law is one
  std::string segment_table;             ///< path of the segment table; empty when not written
  std::vector<std::string> warnings;
  /// "arc" or "path" for a law exported along format.motion (the cam table's columns then add
  /// the pose); empty for the straight line.
  std::string motion_type;
  /// The table's rotation of a one-arc motion [deg] (its master-axis table is in degrees).
  std::optional<double> table_rotation_deg;
};

/// The summary as JSON text (2-space indented): source, key, cached, status, message and
/// plan_warnings (plans: the plan's warnings, which the law carries into the table),
/// law, cam_table, file_format, table ("time" or "master"), period_s (time) or master {period,
/// start, end, step, speed_per_s, equidistant} (master), samples, motion_time_s, end_time_s
/// (time), stroke_mm, and for 7-segment laws durations_s, A_mm_s2, B_mm_s2, v_peak_mm_s, segments
/// (and segment_table), warnings; along an arc or a path also motion {type, length_mm,
/// table_rotation_deg (one arc)}.
[[nodiscard]] std::string export_summary_json(const ExportSummary& summary);

}  // namespace slosh::api
