#pragma once
// The cam table files of `slosh export` and of GET /v1/plans/{key}/cam.csv and cam.st (SPEC §6,
// §11): a time-based table at the controller cycle, or a master-axis table over one master period
// (core/law/cam_table.hpp), written as CSV or as an IEC 61131-3 structured-text declaration that a
// PLC programmer pastes into a project.
//
// The options are the same on the command line and in the query string; only their names differ
// (CamOptionNames), and every refusal names the option as the caller wrote it.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "export/cam_numbers.hpp"
#include "http/query_params.hpp"
#include "slosh/core/law/cam_table.hpp"
#include "slosh/core/law/motion_law.hpp"

namespace slosh::service {

/// How a cam table is written.
enum class CamFileFormat {
  kCsv,  ///< CSV with a header line (cam_table_csv, master_cam_table_csv)
  kSt,   ///< IEC 61131-3 structured text (cam_table_st)
};

/// One text per cam table option.
struct CamOptionTexts {
  std::string period_ms;
  std::string master_period;
  std::string master_start;
  std::string master_end;
  std::string master_step;
  std::string st_name;
};

/// The names of the cam table options as the caller gave them: CLI flags ("--master-start") or
/// query parameters ("master_start"). They are the `field` and the subject of every refusal.
using CamOptionNames = CamOptionTexts;

/// "--period-ms", "--master-period", "--master-start", "--master-end", "--master-step",
/// "--st-name".
[[nodiscard]] const CamOptionNames& cli_option_names();
/// "period_ms", "master_period", "master_start", "master_end", "master_step", "st_name".
[[nodiscard]] const CamOptionNames& query_option_names();

/// Controller cycle of a time-based table when none is given [ms].
inline constexpr double kDefaultPeriodMs{1.0};
/// Rows per master period when no master step is given: step = period / this (1 degree of a
/// 360-degree cycle, 361 rows) [-].
inline constexpr double kDefaultMasterStepsPerPeriod{360.0};
/// Identifier of the ST array constant when none is given.
inline constexpr std::string_view kDefaultStName{"SLOSH_CAM"};
/// Longest ST array identifier accepted [characters].
inline constexpr std::size_t kMaxStNameLength{64};
/// The ST structure types (the same in every export: a project declares each once).
inline constexpr std::string_view kStTimePointType{"SLOSH_CAM_POINT"};
inline constexpr std::string_view kStMasterPointType{"SLOSH_MASTER_CAM_POINT"};
/// The ST structure types of a law along an arc or a path (path_cam_export.hpp): time-based with
/// the pose, plus the table's rotation for one arc; master-axis with the pose, or a rotary
/// table's rotation.
inline constexpr std::string_view kStPathPointType{"SLOSH_PATH_CAM_POINT"};
inline constexpr std::string_view kStTablePointType{"SLOSH_TABLE_CAM_POINT"};
inline constexpr std::string_view kStPathMasterPointType{"SLOSH_PATH_MASTER_CAM_POINT"};
inline constexpr std::string_view kStTableMasterPointType{"SLOSH_TABLE_MASTER_CAM_POINT"};

/// The cam table options as given (an unset option was not given).
struct CamOptions {
  /// CSV or ST. CLI `--format csv|st` (default csv); HTTP: the route (cam.csv, cam.st).
  CamFileFormat format{CamFileFormat::kCsv};
  /// Controller cycle of a time-based table [ms], in [0.01, 1000]; unset = kDefaultPeriodMs.
  /// Refused together with a master axis (the master step is the sampling then).
  std::optional<double> period_ms;
  /// Master-axis table: length of the master cycle [master units], > 0. Period, start and end
  /// come together (one of them alone is refused, naming the missing one).
  std::optional<double> master_period;
  /// Master position where the motion starts, 0 <= start < end [master units].
  std::optional<double> master_start;
  /// Master position where the motion ends at the stroke, start < end <= period [master units].
  std::optional<double> master_end;
  /// Master distance between rows, > 0 [master units]; unset = period /
  /// kDefaultMasterStepsPerPeriod. Only with the master axis.
  std::optional<double> master_step;
  /// Identifier of the ST array constant (an IEC 61131-3 identifier, not a keyword); unset =
  /// kDefaultStName. Only with the ST format.
  std::optional<std::string> st_name;
};

/// Validated options: what to sample and how to write it.
struct CamTableSpec {
  CamFileFormat format{CamFileFormat::kCsv};
  double period_ms{kDefaultPeriodMs};   ///< controller cycle of a time-based table [ms]
  std::optional<MasterAxis> master;     ///< a master-axis table instead (master units)
  std::string st_name{kDefaultStName};  ///< ST array identifier
};

/// The cam table query parameters of GET /v1/plans/{key}/cam.csv and cam.st as received.
struct CamQuery {
  QueryValues period_ms;
  QueryValues master_period;
  QueryValues master_start;
  QueryValues master_end;
  QueryValues master_step;
  QueryValues st_name;
  QueryValues allow_infeasible;
};

/// The options of a query: each parameter given at most once (single_query_value), the numbers
/// read whole as decimal numbers (`-`, digits, an optional fraction and exponent: no `+`, spaces,
/// hex, inf or nan; ApiError naming the parameter, "master_start = 0x10 is not a decimal number
/// [master units]"), an empty value refused like any other; `format` from the route.
[[nodiscard]] CamOptions parse_cam_query(const CamQuery& query, CamFileFormat format);

/// Validates `options` and fills the defaults. A master axis may have at most `max_rows` rows;
/// `rows_hint` ends the refusal of a step that gives more (e.g. " here (slosh export writes
/// longer tables)"). Throws ApiError(kInvalidValue, name) naming the option, its value and the
/// allowed range. The row bound of a time-based table depends on the law (not checked here).
[[nodiscard]] CamTableSpec resolve_cam_options(const CamOptions& options,
                                               const CamOptionNames& names, std::size_t max_rows,
                                               std::string_view rows_hint);

/// Throws ApiError(kInvalidValue, field) unless the controller cycle is in [0.01, 1000] ms.
void check_period_ms(double period_ms, const std::string& field);

/// Where a law came from, as the ST header states it.
struct CamSource {
  std::string law_type;  ///< api::LawType name
  std::string strategy;  ///< planning strategy; empty for a law request
  std::string key;       ///< recipe key; empty for a law request
  double stroke{};       ///< [m]
  double motion_time{};  ///< [s]
  /// Where a master-axis table's slave dwells, as the ST header says it; empty: the straight
  /// line's "0 mm before the start and at the stroke from the end on".
  std::string slave_dwell;
};

/// A sampled cam table: time-based (`time`, every `period` seconds) or master-axis (`master`
/// rows on `axis`).
struct CamTable {
  double motion_time{};  ///< duration of the law [s]
  std::vector<CamSample> time;
  double period{};  ///< controller cycle of a time-based table [s]
  std::vector<MasterCamSample> master;
  std::optional<MasterAxis> axis;  ///< set for a master-axis table

  [[nodiscard]] std::size_t rows() const { return axis ? master.size() : time.size(); }
};

/// Samples `law` as `spec` asks (time-based or master-axis). Throws ApiError(kInvalidValue)
/// naming the option (`names`) when sample_cam_table or sample_master_cam_table refuse: a master
/// speed out of range names the master period.
[[nodiscard]] CamTable sample_cam(const MotionLaw& law, double stroke, const CamTableSpec& spec,
                                  const CamOptionNames& names);

/// Rows of the table `spec` gives for a law of duration `motion_time` [s], as sample_cam samples
/// it (a master axis: an upper bound, its grid points plus the start, end and period). Throws
/// ApiError as sample_cam does for a time-based table of more than kCamMaxSamples rows.
[[nodiscard]] std::size_t cam_rows(const CamTableSpec& spec, double motion_time,
                                   const CamOptionNames& names);

/// Upper bound of the bytes an export of `rows` rows holds at once: each row sampled (and its
/// master position) and written in the format of `spec` with the longest numbers, and the
/// header [bytes].
[[nodiscard]] std::size_t cam_export_bytes(const CamTableSpec& spec, std::size_t rows);

/// Cam table CSV: header `t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3`, one line
/// per sample, each number csv_number.
[[nodiscard]] std::string cam_table_csv(const std::vector<CamSample>& samples);

/// Master-axis cam table CSV: header
/// `master,position_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3` (master
/// position in master units; slave position in mm and its first three derivatives per master
/// unit), one line per row, each number csv_number.
[[nodiscard]] std::string master_cam_table_csv(const std::vector<MasterCamSample>& samples);

/// The IEC 61131-3 structured text of a cam table: a comment header (format, strategy, recipe
/// key, slosh version, law, units), `TYPE SLOSH_CAM_POINT` or `SLOSH_MASTER_CAM_POINT` (a STRUCT
/// of LREAL members named as the CSV columns) and `VAR_GLOBAL CONSTANT <name> : ARRAY[0..N-1] OF
/// <type> := [(...), ...]; END_VAR` with one structure initialiser per row.
[[nodiscard]] std::string cam_table_st(const CamTable& table, const CamSource& source,
                                       const std::string& name);

/// The comment header of a cam table's structured text (cam_table_st's): format, strategy,
/// recipe key, slosh version, law; the master axis; `extra` (lines of its own, each starting
/// with three spaces and ending with a line break); and that TYPE `type` is the same in every
/// export.
[[nodiscard]] std::string cam_st_header(const CamTable& table, const CamSource& source,
                                        std::string_view type, const std::string& extra = {});

/// A member of an ST structure (and a CSV column) with its comment.
struct CamColumn {
  std::string_view name;
  std::string_view comment;
};

/// `header`, then `TYPE <type>` (a STRUCT of LREAL members `columns`) and `VAR_GLOBAL CONSTANT
/// <name> : ARRAY[0..N-1] OF <type> := [(...), ...]; END_VAR` with one initialiser per row (each
/// row as many values as columns, st_real_literal): cam_table_st's layout for any columns.
[[nodiscard]] std::string st_declaration(const std::string& header, std::string_view type,
                                         const std::vector<CamColumn>& columns,
                                         const std::vector<std::vector<double>>& rows,
                                         const std::string& name);

/// The file of `table` in the format of `spec` (CSV or ST).
[[nodiscard]] std::string cam_file(const CamTable& table, const CamSource& source,
                                   const CamTableSpec& spec);

/// The warnings of a table (CLI option names): a time-based table whose motion time is not a
/// multiple of the cycle; a master-axis table whose start, end or period is off the step grid
/// (rows added there: not equidistant).
[[nodiscard]] std::vector<std::string> cam_warnings(const CamTable& table);

}  // namespace slosh::service
