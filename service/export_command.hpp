#pragma once
// `slosh export`: the cam table of a law at the controller cycle, and the 7-segment table a
// jerk-limited profile block is fed with.

#include <cstddef>
#include <string>
#include <vector>

#include "server_config.hpp"
#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/seven_segment.hpp"

namespace slosh::service {

struct ExportCommandOptions {
  /// A plan request (the /v1/plans body: the plan is solved, or read from the cache) or a law
  /// request (the /v1/simulate body with "law"); "-" = stdin. Default "-".
  std::string request{"-"};
  /// Cam table CSV path, "-" = stdout. Required.
  std::string out;
  /// Controller cycle [ms]. Default 1.
  double period_ms{1.0};
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

/// Throws ApiError(kInvalidValue, field) unless the controller cycle is in the allowed range.
void check_period_ms(double period_ms, const std::string& field);

/// Most rows GET /v1/plans/{key}/cam.csv serves (about 12 MB of CSV); `slosh export` has no
/// such bound.
inline constexpr std::size_t kMaxServedCamRows{200000};

/// The cam table CSV of a rendered plan at `period_ms` (GET /v1/plans/{key}/cam.csv): the same
/// bytes as `slosh export --period-ms`; more than kMaxServedCamRows rows is refused (period_ms).
/// Throws ApiError naming period_ms, or allow_infeasible for an infeasible or time-limited plan
/// when `allow_infeasible` is false.
[[nodiscard]] std::string plan_cam_table_csv(const std::string& plan_text, double period_ms,
                                             bool allow_infeasible);

/// Cam table CSV: header `t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3`, one line
/// per sample, 12 significant digits.
[[nodiscard]] std::string cam_table_csv(const std::vector<CamSample>& samples);

/// 7-segment table CSV: header `segment,t_start_s,t_end_s,duration_s,jerk_mm_s3,a_start_mm_s2,
/// a_end_mm_s2,v_start_mm_s,v_end_mm_s,s_start_mm,s_end_mm`, one line per segment.
[[nodiscard]] std::string segment_table_csv(const SevenSegmentLaw& law);

}  // namespace slosh::service
