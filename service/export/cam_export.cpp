#include "export/cam_export.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "config/version.hpp"
#include "export/export_units.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

namespace slosh::service {

namespace {

/// Shortest and longest controller cycle of a time-based table [ms].
constexpr double kMinPeriodMs = kCamMinPeriod * 1e3;
constexpr double kMaxPeriodMs = 1000.0;
/// Characters of an ST row besides its members ("    (", ")," and the line break), and of each
/// member besides its name and literal (" := ", ", ") [characters].
constexpr std::size_t kStRowOverhead = 8;
constexpr std::size_t kStMemberOverhead = 6;
/// Bound of the CSV header or of the ST comment header, TYPE and declaration [bytes].
constexpr std::size_t kMaxCamHeaderBytes = 4096;

api::ApiError invalid(const std::string& field, const std::string& message) {
  return api::ApiError(api::ErrorCode::kInvalidValue, field, message);
}

std::string cell(double v) {
  return csv_number(v);
}

const std::string& option_name(MasterAxisInput input, const CamOptionNames& names) {
  switch (input) {
    case MasterAxisInput::kPeriod:
      return names.master_period;
    case MasterAxisInput::kStart:
      return names.master_start;
    case MasterAxisInput::kEnd:
      return names.master_end;
    case MasterAxisInput::kStep:
      break;
  }
  return names.master_step;
}

// `v` > 0 rounded up to 10 significant digits (what number_text prints), a little above `v`.
double rounded_up(double v) {
  const double up = v * (1.0 + 1e-12);
  const double unit = std::pow(10.0, std::floor(std::log10(up)) - 9.0);
  return std::ceil(up / unit) * unit;
}

// The refusal of a master speed out of range, at the period.
api::ApiError master_speed_error(const MasterAxisRefusal& r, const MasterAxis& axis,
                                 const CamOptionNames& names, double motion_time) {
  const double speed = *r.speed;
  const std::string verdict = std::isfinite(speed) ? "out of range" : "not finite";
  const std::string span = names.master_end + " - " + names.master_start;
  return invalid(
      names.master_period,
      names.master_period + " = " + master_value_text(axis.period) + " makes the master speed (" +
          span + ") / motion time = " + master_value_text(speed) + " master units/s over the " +
          api::number_text(motion_time) + " s motion, which is " + verdict + ": allowed " +
          r.allowed() + " master units/s, i.e. " + span + " in " +
          bounds_text(
              InputBounds{r.bounds.lo * motion_time, r.bounds.hi * motion_time, false, false},
              [](double v) { return master_number_text(v); }) +
          " master units");
}

// The refusal of a master axis, worded with the caller's option names. `motion_time` is the
// law's duration for a speed refusal [s].
api::ApiError master_error(const MasterAxisRefusal& r, const MasterAxis& axis,
                           const CamOptionNames& names, std::size_t max_rows,
                           std::string_view rows_hint, double motion_time = 0.0) {
  if (r.speed) return master_speed_error(r, axis, names, motion_time);
  const std::string& name = option_name(r.input, names);
  if (r.too_many_rows) {
    // The smallest step printed with 10 digits, rounded up: a step of that text is accepted.
    return invalid(name, name + " = " + r.value_text() + " gives more than " +
                             std::to_string(max_rows) + " rows over the master period " +
                             master_value_text(axis.period) +
                             ": allowed >= " + api::number_text(rounded_up(r.bounds.lo)) +
                             " master units" + std::string(rows_hint));
  }
  const std::string head = name + " = " + r.value_text();
  const std::string verdict = std::isfinite(r.value) ? " is out of range" : " is not finite";
  if (std::isfinite(r.bounds.lo) && std::isfinite(r.bounds.hi)) {
    return invalid(name, head + verdict + " " + r.allowed() + " master units (0 <= " +
                             names.master_start + " < " + names.master_end +
                             " <= " + names.master_period + ", " + names.master_end + " - " +
                             names.master_start + " >= " + api::number_text(kMinMasterSpan) + ")");
  }
  return invalid(name, head + verdict + ": allowed " + r.allowed() + " master units");
}

// A master-axis table: period, start and end all given, or none of them (nor the step).
std::optional<MasterAxis> master_axis_of(const CamOptions& o, const CamOptionNames& n) {
  if (!o.master_period && !o.master_start && !o.master_end && !o.master_step) return std::nullopt;
  const std::array<std::pair<const std::optional<double>*, const std::string*>, 3> required{
      {{&o.master_period, &n.master_period},
       {&o.master_start, &n.master_start},
       {&o.master_end, &n.master_end}}};
  for (const auto& [value, name] : required) {
    if (!value->has_value()) {
      throw invalid(*name, *name + " is missing: a master-axis table needs " + n.master_period +
                               ", " + n.master_start + " and " + n.master_end);
    }
  }
  MasterAxis axis{*o.master_period, *o.master_start, *o.master_end, 0.0};
  axis.step = o.master_step.value_or(axis.period / kDefaultMasterStepsPerPeriod);
  return axis;
}

// Names an ST identifier may not take (IEC 61131-3 ed. 3, upper case; identifiers are not
// case-sensitive), by why: each text is a list of names separated by spaces.
constexpr std::string_view kStKeywords =
    "ABSTRACT ACTION AND ARRAY AT BY CASE CLASS CONFIGURATION CONSTANT CONTINUE DO ELSE ELSIF EN "
    "END_ACTION END_CASE END_CLASS END_CONFIGURATION END_FOR END_FUNCTION END_FUNCTION_BLOCK "
    "END_IF END_INTERFACE END_METHOD END_NAMESPACE END_PROGRAM END_REPEAT END_RESOURCE END_STEP "
    "END_STRUCT END_TRANSITION END_TYPE END_VAR END_WHILE ENO EXIT EXTENDS FALSE FINAL FOR FROM "
    "FUNCTION FUNCTION_BLOCK F_EDGE IF IMPLEMENTS "
    "INITIAL_STEP INTERFACE INTERNAL INTERVAL METHOD MOD NAMESPACE NON_RETAIN NOT NULL OF ON OR "
    "OVERLAP OVERRIDE PRIORITY PRIVATE PROGRAM PROTECTED PUBLIC READ_ONLY READ_WRITE REF REF_TO "
    "REPEAT RESOURCE RETAIN RETURN R_EDGE SINGLE STEP STRUCT SUPER TASK THEN THIS TO TRANSITION "
    "TRUE TYPE UNTIL USING VAR WHILE WITH XOR";
constexpr std::string_view kStTypes =
    "ANY ANY_BIT ANY_CHAR ANY_CHARS ANY_DATE ANY_DERIVED ANY_DURATION ANY_ELEMENTARY ANY_INT "
    "ANY_MAGNITUDE ANY_NUM ANY_REAL ANY_SIGNED ANY_STRING ANY_UNSIGNED BOOL BYTE CHAR DATE "
    "DATE_AND_TIME DINT DT DWORD INT LDATE LDATE_AND_TIME LDT LINT LREAL "
    "LTIME LTIME_OF_DAY LTOD LWORD REAL SINT STRING TIME TIME_OF_DAY TOD UDINT UINT ULINT USINT "
    "WCHAR WORD WSTRING";
constexpr std::string_view kStFunctionBlocks =
    "CTD CTD_DINT CTD_INT CTD_LINT CTD_UDINT CTD_ULINT CTU CTU_DINT CTU_INT CTU_LINT CTU_UDINT "
    "CTU_ULINT CTUD CTUD_DINT CTUD_INT CTUD_LINT CTUD_UDINT CTUD_ULINT F_TRIG RS R_TRIG SR TOF "
    "TOF_LTIME TON TON_LTIME TP TP_LTIME";
constexpr std::string_view kStFunctions =
    "ABS ACOS ADD ADD_TIME ASIN ATAN ATAN2 CONCAT CONCAT_DATE_TOD COS DELETE DIV DIVTIME EQ EXP "
    "EXPT FIND GE GT INSERT LE LEFT LEN LIMIT LN LOG LT MAX MID MIN MOVE MUL MULTIME MUX NE "
    "REPLACE RIGHT ROL ROR SEL SHL SHR SIN SQRT SUB SUB_TIME TAN TRUNC";

bool ascii_letter(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

bool ascii_digit(char c) {
  return c >= '0' && c <= '9';
}

// IEC 61131-3: a letter or "_" first, then letters, digits and single underscores, no "_" last.
bool st_identifier(const std::string& name) {
  if (name.empty() || name.size() > kMaxStNameLength) return false;
  if (!ascii_letter(name.front()) && name.front() != '_') return false;
  if (name.back() == '_') return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (!ascii_letter(c) && !ascii_digit(c) && c != '_') return false;
    if (c == '_' && i > 0 && name[i - 1] == '_') return false;
  }
  return true;
}

std::string upper(std::string text) {
  for (char& c : text) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  }
  return text;
}

// Whether the space-separated `names` hold `name`.
bool listed(std::string_view names, std::string_view name) {
  for (std::size_t at = 0; at < names.size();) {
    const std::size_t end = std::min(names.find(' ', at), names.size());
    if (names.substr(at, end - at) == name) return true;
    at = end + 1;
  }
  return false;
}

// Why the upper-case identifier `key` is reserved in IEC 61131-3 or by slosh; empty when it is
// not.
std::string st_reserved_reason(const std::string& key) {
  if (listed(kStKeywords, key) || key.starts_with("VAR_")) return "an IEC 61131-3 keyword";
  if (listed(kStTypes, key)) return "an IEC 61131-3 elementary or generic data type";
  if (listed(kStFunctionBlocks, key)) return "an IEC 61131-3 standard function block";
  if (listed(kStFunctions, key)) return "an IEC 61131-3 standard function";
  // Type conversions: <type>_TO_<type>, TO_<type>, TRUNC_<type>, BCD_TO_<type>, <type>_TO_BCD.
  const std::size_t to = key.find("_TO_");
  const auto type_or_bcd = [](std::string_view t) { return t == "BCD" || listed(kStTypes, t); };
  if ((to != std::string::npos && type_or_bcd(key.substr(0, to)) &&
       type_or_bcd(key.substr(to + 4))) ||
      (key.starts_with("TO_") && listed(kStTypes, key.substr(3))) ||
      (key.starts_with("TRUNC_") && listed(kStTypes, key.substr(6)))) {
    return "an IEC 61131-3 standard type conversion function";
  }
  if (key == kStTimePointType || key == kStMasterPointType || key == kStPathPointType ||
      key == kStTablePointType || key == kStPathMasterPointType || key == kStTableMasterPointType) {
    return "the structure type every slosh export declares";
  }
  return "";
}

void check_st_name(const std::string& name, const std::string& field) {
  const std::string shown = name.empty() ? "(empty)" : name.substr(0, kMaxStNameLength + 8);
  if (!st_identifier(name)) {
    throw invalid(field, field + " = " + shown +
                             " is not an IEC 61131-3 identifier: letters, digits and single "
                             "underscores, not starting with a digit nor ending with an "
                             "underscore, at most " +
                             std::to_string(kMaxStNameLength) + " characters");
  }
  const std::string key = upper(name);
  if (const std::string reason = st_reserved_reason(key); !reason.empty()) {
    throw invalid(field, field + " = " + shown + " is reserved: " + key + " is " + reason +
                             " (identifiers are not case-sensitive)");
  }
}

// The values of a row in the file's units: the slave columns in mm. A row at the stroke
// (`stroke`, the position of the last row [m]) holds the stroke in mm as the request gave it
// (api::mm_of: 800.123456789012, not 800.1234567890121).
std::array<double, 5> row_values(const CamSample& s, double stroke) {
  const double position = s.position == stroke ? api::mm_of(stroke) : s.position * kMmPerM;
  return {s.t, position, s.velocity * kMmPerM, s.acceleration * kMmPerM, s.jerk * kMmPerM};
}
std::array<double, 5> row_values(const MasterCamSample& s, double stroke) {
  const double position = s.position == stroke ? api::mm_of(stroke) : s.position * kMmPerM;
  return {s.master, position, s.velocity * kMmPerM, s.acceleration * kMmPerM, s.jerk * kMmPerM};
}

// A member of the ST structure (and column of the CSV) with its comment.
struct StColumn {
  std::string_view name;
  std::string_view comment;
};
using StColumns = std::array<StColumn, 5>;

constexpr StColumns kTimeColumns{{{"t_s", "time since the start of the motion [s]"},
                                  {"position_mm", "slave position [mm]"},
                                  {"velocity_mm_s", "slave velocity [mm/s]"},
                                  {"acceleration_mm_s2", "slave acceleration [mm/s^2]"},
                                  {"jerk_mm_s3", "slave jerk [mm/s^3]"}}};
constexpr StColumns kMasterColumns{
    {{"master", "master position [master units]"},
     {"position_mm", "slave position [mm]"},
     {"velocity_mm_per_unit", "d position / d master [mm/master unit]"},
     {"acceleration_mm_per_unit2", "d2 position / d master2 [mm/master unit^2]"},
     {"jerk_mm_per_unit3", "d3 position / d master3 [mm/master unit^3]"}}};

// The longest text of a row in `format` with `columns` (a CSV line or an ST initialiser) [bytes].
std::size_t row_text_bound(const StColumns& columns, CamFileFormat format) {
  if (format == CamFileFormat::kCsv) return columns.size() * (kMaxCsvCell + 1);
  std::size_t text = kStRowOverhead;
  for (const StColumn& c : columns) text += c.name.size() + kStMemberOverhead + kMaxStLiteral;
  return text;
}

template <typename Sample>
std::string csv_of(const StColumns& columns, const std::vector<Sample>& samples) {
  std::string out;
  for (const StColumn& c : columns) {
    if (!out.empty()) out += ',';
    out += c.name;
  }
  out += '\n';
  out.reserve(out.size() + samples.size() * row_text_bound(columns, CamFileFormat::kCsv));
  const double stroke = samples.empty() ? 0.0 : samples.back().position;
  for (const Sample& s : samples) {
    const std::array<double, 5> v = row_values(s, stroke);
    out += cell(v[0]) + ',' + cell(v[1]) + ',' + cell(v[2]) + ',' + cell(v[3]) + ',' + cell(v[4]) +
           '\n';
  }
  return out;
}

// Text safe inside an IEC 61131-3 comment: no comment delimiters, no line breaks.
std::string comment_text(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  for (std::size_t at = 0; at + 1 < text.size(); ++at) {
    const bool opens = text[at] == '(' && text[at + 1] == '*';
    const bool closes = text[at] == '*' && text[at + 1] == ')';
    if (opens || closes) text.insert(at + 1, " ");
  }
  return text;
}

// "a", "a and b", "a, b and c".
std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? " and " : ", ";
    out += items[i];
  }
  return out;
}

// The master positions (start, end, period) off the step grid, with the CLI option names.
std::vector<std::string> off_grid(const MasterAxis& a) {
  const CamOptionNames& n = cli_option_names();
  std::vector<std::string> off;
  const std::array<std::pair<const std::string*, double>, 3> anchors{
      {{&n.master_start, a.start}, {&n.master_end, a.end}, {&n.master_period, a.period}}};
  for (const auto& [name, value] : anchors) {
    if (!on_master_grid(value, a.step)) off.push_back(*name + " " + master_value_text(value));
  }
  return off;
}

// The "format:" line of the ST header.
std::string st_format_line(const CamTable& table) {
  const std::string rows = std::to_string(table.rows());
  if (!table.axis) {
    return "   format: time-based cam table, " + rows + " points, one every " +
           api::number_text(table.period * 1e3) +
           " ms (the last one, at or after the motion time, holds the stroke)\n";
  }
  const MasterAxis& a = *table.axis;
  const std::string spacing = master_grid_is_equidistant(a)
                                  ? "equidistant"
                                  : "not equidistant: rows added at the start, end or period "
                                    "off the step grid";
  return "   format: master-axis cam table over one master period, " + rows + " points, step " +
         api::number_text(a.step) + " master units (" + spacing + ")\n";
}

// The "master axis:" line of the ST header of a master-axis table.
std::string st_master_line(const MasterAxis& a, const CamSource& source) {
  const std::string dwell = source.slave_dwell.empty()
                                ? "0 mm before the start and at the stroke from the end on"
                                : source.slave_dwell;
  return "   master axis: period " + api::number_text(a.period) + ", motion from " +
         api::number_text(a.start) + " to " + api::number_text(a.end) + " at " +
         api::number_text((a.end - a.start) / source.motion_time) +
         " master units/s; the slave dwells at " + dwell + "\n";
}

std::string st_header(const CamTable& table, const CamSource& source, std::string_view type,
                      const std::string& extra = {}) {
  const std::string none = "none (a law request, not a plan)";
  std::string h = "(* slosh cam table: IEC 61131-3 structured text, to paste into a PLC project\n";
  h += st_format_line(table);
  h += "   strategy: " + comment_text(source.strategy.empty() ? none : source.strategy) + "\n";
  h += "   recipe key: " + comment_text(source.key.empty() ? none : source.key) + "\n";
  h += "   slosh version: " + comment_text(kVersion) + "\n";
  h += "   law: " + comment_text(source.law_type) + ", stroke " +
       api::number_text(source.stroke * kMmPerM) + " mm, motion time " +
       api::number_text(source.motion_time) + " s\n";
  if (table.axis) h += st_master_line(*table.axis, source);
  h += extra;
  h += "   TYPE " + std::string(type) +
       " is the same in every slosh export: declare it once per project *)\n";
  return h;
}

template <typename Sample>
std::string st_of(const std::string& header, std::string_view type, const StColumns& columns,
                  const std::vector<Sample>& samples, const std::string& name) {
  std::string out = header + "\nTYPE\n  " + std::string(type) + " :\n  STRUCT\n";
  for (const StColumn& c : columns) {
    out += "    " + std::string(c.name) + " : LREAL; (* " + std::string(c.comment) + " *)\n";
  }
  out += "  END_STRUCT;\nEND_TYPE\n\nVAR_GLOBAL CONSTANT\n  " + name + " : ARRAY[0.." +
         std::to_string(samples.size() - 1) + "] OF " + std::string(type) + " := [\n";
  out.reserve(out.size() + samples.size() * row_text_bound(columns, CamFileFormat::kSt));
  const double stroke = samples.empty() ? 0.0 : samples.back().position;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const std::array<double, 5> v = row_values(samples[k], stroke);
    out += "    (";
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i > 0) out += ", ";
      out += std::string(columns[i].name) + " := " + st_real_literal(v[i]);
    }
    out += k + 1 == samples.size() ? ")\n" : "),\n";
  }
  out += "  ];\nEND_VAR\n";
  return out;
}

}  // namespace

const CamOptionNames& cli_option_names() {
  static const CamOptionNames names{"--period-ms",  "--master-period", "--master-start",
                                    "--master-end", "--master-step",   "--st-name"};
  return names;
}

const CamOptionNames& query_option_names() {
  static const CamOptionNames names{"period_ms",  "master_period", "master_start",
                                    "master_end", "master_step",   "st_name"};
  return names;
}

void check_period_ms(double period_ms, const std::string& field) {
  if (period_ms >= kMinPeriodMs && period_ms <= kMaxPeriodMs) return;
  throw invalid(field, field + " = " + master_value_text(period_ms) + " is out of range [" +
                           api::number_text(kMinPeriodMs) + ", " + api::number_text(kMaxPeriodMs) +
                           "] ms");
}

CamOptions parse_cam_query(const CamQuery& query, CamFileFormat format) {
  const CamOptionNames& n = query_option_names();
  const auto number = [](const QueryValues& values, const std::string& name,
                         std::string_view unit) -> std::optional<double> {
    const std::optional<std::string> text = single_query_value(values, name);
    if (!text) return std::nullopt;
    return query_decimal(*text, name, unit);
  };
  CamOptions options;
  options.format = format;
  options.period_ms = number(query.period_ms, n.period_ms, "ms");
  options.master_period = number(query.master_period, n.master_period, "master units");
  options.master_start = number(query.master_start, n.master_start, "master units");
  options.master_end = number(query.master_end, n.master_end, "master units");
  options.master_step = number(query.master_step, n.master_step, "master units");
  options.st_name = single_query_value(query.st_name, n.st_name);  // "" is refused as a name
  return options;
}

CamTableSpec resolve_cam_options(const CamOptions& options, const CamOptionNames& names,
                                 std::size_t max_rows, std::string_view rows_hint) {
  CamTableSpec spec;
  spec.format = options.format;
  spec.master = master_axis_of(options, names);
  if (spec.master) {
    if (options.period_ms) {
      throw invalid(names.period_ms,
                    names.period_ms + " applies to a time-based table: a master-axis table (" +
                        names.master_period + ") has a row every " + names.master_step);
    }
    if (const auto refusal = check_master_axis(*spec.master, max_rows)) {
      throw master_error(*refusal, *spec.master, names, max_rows, rows_hint);
    }
  } else {
    spec.period_ms = options.period_ms.value_or(kDefaultPeriodMs);
    check_period_ms(spec.period_ms, names.period_ms);
  }
  if (options.st_name) {
    if (options.format != CamFileFormat::kSt) {
      throw invalid(names.st_name, names.st_name + " applies to the structured-text format only");
    }
    check_st_name(*options.st_name, names.st_name);
    spec.st_name = *options.st_name;
  }
  return spec;
}

CamTable sample_cam(const MotionLaw& law, double stroke, const CamTableSpec& spec,
                    const CamOptionNames& names) {
  CamTable table;
  table.motion_time = law.duration();
  try {
    if (spec.master) {
      table.axis = spec.master;
      table.master = sample_master_cam_table(law, stroke, *spec.master);
    } else {
      table.period = spec.period_ms * 1e-3;
      table.time = sample_cam_table(law, stroke, table.period);
    }
  } catch (const MasterAxisError& e) {
    throw master_error(e.refusal(), *spec.master, names, kCamMaxSamples, "", table.motion_time);
  } catch (const std::invalid_argument& e) {
    throw invalid(spec.master ? names.master_step : names.period_ms, e.what());
  }
  return table;
}

std::size_t cam_rows(const CamTableSpec& spec, double motion_time, const CamOptionNames& names) {
  if (spec.master) {
    const MasterAxis& a = *spec.master;
    return static_cast<std::size_t>(std::floor(a.period / a.step)) + 1 + kMasterExtraRows;
  }
  try {
    return cam_cycles(motion_time, spec.period_ms * 1e-3) + 1;
  } catch (const std::invalid_argument& e) {
    throw invalid(names.period_ms, e.what());
  }
}

std::size_t cam_export_bytes(const CamTableSpec& spec, std::size_t rows) {
  const StColumns& columns = spec.master ? kMasterColumns : kTimeColumns;
  // The sample, its master position and its text (the file is reserved whole: no regrowth).
  const std::size_t per_row =
      sizeof(MasterCamSample) + sizeof(double) + row_text_bound(columns, spec.format);
  return rows * per_row + kMaxCamHeaderBytes;
}

std::string cam_table_csv(const std::vector<CamSample>& samples) {
  return csv_of(kTimeColumns, samples);
}

std::string master_cam_table_csv(const std::vector<MasterCamSample>& samples) {
  return csv_of(kMasterColumns, samples);
}

std::string cam_table_st(const CamTable& table, const CamSource& source, const std::string& name) {
  if (table.axis) {
    return st_of(st_header(table, source, kStMasterPointType), kStMasterPointType, kMasterColumns,
                 table.master, name);
  }
  return st_of(st_header(table, source, kStTimePointType), kStTimePointType, kTimeColumns,
               table.time, name);
}

std::string cam_st_header(const CamTable& table, const CamSource& source, std::string_view type,
                          const std::string& extra) {
  return st_header(table, source, type, extra);
}

std::string st_declaration(const std::string& header, std::string_view type,
                           const std::vector<CamColumn>& columns,
                           const std::vector<std::vector<double>>& rows, const std::string& name) {
  std::string out = header + "\nTYPE\n  " + std::string(type) + " :\n  STRUCT\n";
  for (const CamColumn& c : columns) {
    out += "    " + std::string(c.name) + " : LREAL; (* " + std::string(c.comment) + " *)\n";
  }
  out += "  END_STRUCT;\nEND_TYPE\n\nVAR_GLOBAL CONSTANT\n  " + name + " : ARRAY[0.." +
         std::to_string(rows.size() - 1) + "] OF " + std::string(type) + " := [\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    out += "    (";
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (i > 0) out += ", ";
      out += std::string(columns[i].name) + " := " + st_real_literal(rows[k][i]);
    }
    out += k + 1 == rows.size() ? ")\n" : "),\n";
  }
  out += "  ];\nEND_VAR\n";
  return out;
}

std::string cam_file(const CamTable& table, const CamSource& source, const CamTableSpec& spec) {
  if (spec.format == CamFileFormat::kSt) return cam_table_st(table, source, spec.st_name);
  return table.axis ? master_cam_table_csv(table.master) : cam_table_csv(table.time);
}

std::vector<std::string> cam_warnings(const CamTable& table) {
  const double motion_time = table.motion_time;
  std::vector<std::string> warnings;
  if (table.axis) {
    const std::vector<std::string> off = off_grid(*table.axis);
    if (!off.empty()) {
      warnings.push_back(joined(off) + (off.size() == 1 ? " is" : " are") + " not a multiple of " +
                         cli_option_names().master_step + " " +
                         master_value_text(table.axis->step) +
                         ": rows are added there, so the rows are not equidistant (load the "
                         "table as a non-equidistant cam)");
    }
    return warnings;
  }
  const double end_time = table.time.back().t;
  if (end_time - motion_time > kCamTimeTolerance) {
    warnings.push_back("the motion time " + api::number_text(motion_time) +
                       " s is not a multiple of the " + api::number_text(table.period * 1e3) +
                       " ms cycle: the law ends " +
                       api::number_text((end_time - motion_time) * 1e3) +
                       " ms before the last sample, which holds the stroke");
  }
  return warnings;
}

}  // namespace slosh::service
