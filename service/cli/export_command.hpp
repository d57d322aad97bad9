#pragma once
// `slosh export`: the cam table of a law (time-based at the controller cycle, or on a master
// axis; CSV or IEC 61131-3 structured text, see cam_export.hpp), and the 7-segment table a
// jerk-limited profile block is fed with.

#include <cstddef>
#include <string>
#include <vector>

#include "config/server_config.hpp"
#include "export/cam_export.hpp"
#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/seven_segment.hpp"

namespace slosh::service {

struct ExportCommandOptions {
  /// A plan request (the /v1/plans body: the plan is solved, or read from the cache) or a law
  /// request (the /v1/simulate body with "law"); "-" = stdin. Default "-".
  std::string request{"-"};
  /// Cam table file path (CSV or ST), "-" = stdout. Required.
  std::string out;
  /// Which cam table and how it is written (CamOptions): --format csv|st (default csv),
  /// --period-ms (default 1), or --master-period, --master-start, --master-end and optionally
  /// --master-step (default period / 360) for a master-axis table, --st-name (ST only).
  CamOptions cam;
  /// 7-segment table CSV path; empty = not written.
  std::string segments;
  /// Export a plan whose status is infeasible or time_limit (the best reachable law, which
  /// misses the requested limits); refused otherwise (exit 1). Default false.
  bool allow_infeasible{false};
  /// Cache file, solve budget (plan requests only).
  ServerConfig config;
};

/// Writes the cam table (and the segment table); prints a JSON summary on stdout when the cam
/// table goes to a file, the warnings on stderr otherwise. Exit 0, 2 on invalid input (envelope
/// on stderr), 1 when the plan has no durations or is infeasible / time-limited without
/// allow_infeasible.
int run_export_command(const ExportCommandOptions& options);

/// 7-segment table CSV: header `segment,t_start_s,t_end_s,duration_s,jerk_mm_s3,a_start_mm_s2,
/// a_end_mm_s2,v_start_mm_s,v_end_mm_s,s_start_mm,s_end_mm`, one line per segment.
[[nodiscard]] std::string segment_table_csv(const SevenSegmentLaw& law);

}  // namespace slosh::service
