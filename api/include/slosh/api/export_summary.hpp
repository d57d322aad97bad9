#pragma once
// The JSON summary `slosh export` prints: where the exported law came from and the tables it
// wrote.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh::api {

/// The plan an exported law came from.
struct ExportedPlan {
  std::string key;
  bool cached{false};
  SolveStatus status{SolveStatus::kFailed};
  std::string message;
};

/// What an export wrote.
struct ExportSummary {
  std::string law_type;                  ///< LawType name
  std::optional<ExportedPlan> plan;      ///< empty when a law request was exported
  std::string cam_table;                 ///< path of the cam table
  double period{};                       ///< controller cycle [s]
  std::size_t samples{};                 ///< rows of the cam table
  double motion_time{};                  ///< [s]
  double end_time{};                     ///< time of the last sample [s]
  double stroke{};                       ///< [m]
  std::optional<SevenSegmentLaw> seven;  ///< the 7-segment law, when the law is one
  std::string segment_table;             ///< path of the segment table; empty when not written
  std::vector<std::string> warnings;
};

/// The summary as JSON text (2-space indented): source, key, cached, status, message (plans),
/// law, cam_table, period_s, samples, motion_time_s, end_time_s, stroke_mm, and for 7-segment
/// laws durations_s, A_mm_s2, B_mm_s2, v_peak_mm_s, segments (and segment_table), warnings.
[[nodiscard]] std::string export_summary_json(const ExportSummary& summary);

}  // namespace slosh::api
