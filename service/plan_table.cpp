#include "plan_table.hpp"

#include <csv.h>

#include <array>
#include <string_view>
#include <vector>

#include "slosh/api/error.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

struct OutputColumn {
  std::string_view name;
  std::string_view pointer;  // into plan_row()
};

constexpr std::array kOutputColumns{
    OutputColumn{"row", "/row"},
    OutputColumn{"recipe_id", "/recipe_id"},
    OutputColumn{"status", "/status"},
    OutputColumn{"key", "/key"},
    OutputColumn{"cached", "/cached"},
    OutputColumn{"strategy", "/strategy"},
    OutputColumn{"law_type", "/law_type"},
    OutputColumn{"T1_s", "/durations_s/0"},
    OutputColumn{"T2_s", "/durations_s/1"},
    OutputColumn{"T3_s", "/durations_s/2"},
    OutputColumn{"T4_s", "/durations_s/3"},
    OutputColumn{"T5_s", "/durations_s/4"},
    OutputColumn{"T6_s", "/durations_s/5"},
    OutputColumn{"T7_s", "/durations_s/6"},
    OutputColumn{"A_m_s2", "/kinematics/a_max"},
    OutputColumn{"B_m_s2", "/kinematics/a_min"},
    OutputColumn{"v_peak_m_s", "/kinematics/v_peak"},
    OutputColumn{"j_peak_m_s3", "/kinematics/j_peak"},
    OutputColumn{"f1_hz", "/f1_hz"},
    OutputColumn{"eta_motion_nonlinear_mm", "/prediction/nonlinear/eta_motion_mm"},
    OutputColumn{"eta_rest_nonlinear_mm", "/prediction/nonlinear/eta_rest_mm"},
    OutputColumn{"eta_motion_linear_mm", "/prediction/linear/eta_motion_mm"},
    OutputColumn{"eta_rest_linear_mm", "/prediction/linear/eta_rest_mm"},
    OutputColumn{"baseline_eta_motion_nonlinear_mm", "/baseline/nonlinear/eta_motion_mm"},
    OutputColumn{"baseline_eta_rest_nonlinear_mm", "/baseline/nonlinear/eta_rest_mm"},
    OutputColumn{"reduction_motion_pct", "/reduction_pct/motion"},
    OutputColumn{"reduction_rest_pct", "/reduction_pct/rest"},
    OutputColumn{"solve_ms", "/solve_ms"},
    OutputColumn{"message", "/message"},
    OutputColumn{"error_field", "/error_field"},
};

json member_or_null(const json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? json(nullptr) : *it;
}

// RFC 4180 cell: text quoted by libcsv (doubling inner quotes), numbers and booleans bare.
void write_cell(std::ostream& out, const json& value) {
  if (value.is_null()) return;
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    std::vector<char> buffer(2 * text.size() + 2);
    const std::size_t n = csv_write(buffer.data(), buffer.size(), text.data(), text.size());
    out.write(buffer.data(), static_cast<std::streamsize>(n));
    return;
  }
  out << api::dump_json(value);
}

}  // namespace

json plan_row(const RecipeRow& recipe, const BatchResult& result, bool full) {
  json row{{"row", recipe.row}, {"recipe_id", recipe.recipe_id}};
  if (!result.ok()) {
    json error = api::error_envelope(*result.error)["error"];
    const json& field = error["field"];
    std::string where = field.is_string() ? field.get<std::string>() : "";
    json message = member_or_null(error, "message");
    if (recipe.csv && !where.empty()) {
      if (message.is_string()) message = in_column_terms(where, message.get<std::string>());
      where = column_of_field(where);
    }
    row["status"] = "error";
    row["message"] = std::move(message);
    row["error"] = std::move(error);
    row["error_field"] = where.empty() ? json(nullptr) : json(where);
    return row;
  }
  const json plan = json::parse(result.plan);
  row["status"] = member_or_null(plan, "status");
  row["key"] = member_or_null(plan, "key");
  row["cached"] = result.cached;
  row["strategy"] = member_or_null(plan, "strategy");
  row["message"] = member_or_null(plan, "message");
  row["law_type"] = plan.contains("law") ? member_or_null(plan["law"], "type") : json();
  row["durations_s"] = member_or_null(plan, "durations_s");
  row["kinematics"] = member_or_null(plan, "kinematics");
  const json f_hz = plan.contains("model") ? member_or_null(plan["model"], "f_hz") : json();
  row["f1_hz"] = f_hz.is_array() && !f_hz.empty() ? f_hz[0] : json(nullptr);
  row["prediction"] = member_or_null(plan, "prediction");
  row["baseline"] = member_or_null(plan, "baseline");
  row["reduction_pct"] = member_or_null(plan, "reduction_pct");
  row["solve_ms"] = plan.contains("solver") ? member_or_null(plan["solver"], "solve_ms") : json();
  if (full) row["plan"] = plan;
  return row;
}

std::string plan_table_header() {
  std::string out;
  for (const OutputColumn& column : kOutputColumns) {
    if (!out.empty()) out += ',';
    out += column.name;
  }
  return out;
}

PlanTableWriter::PlanTableWriter(std::ostream& out, TableFormat format)
    : out_(out), format_(format) {
  if (format_ == TableFormat::kCsv) out_ << plan_table_header() << '\n';
  if (format_ == TableFormat::kJson) out_ << "[";
  out_.flush();
}

void PlanTableWriter::write(const json& row) {
  switch (format_) {
    case TableFormat::kCsv: {
      bool first = true;
      for (const OutputColumn& column : kOutputColumns) {
        if (!first) out_ << ',';
        first = false;
        const json::json_pointer pointer{std::string(column.pointer)};
        write_cell(out_, row.contains(pointer) ? row[pointer] : json(nullptr));
      }
      out_ << '\n';
      break;
    }
    case TableFormat::kJsonLines:
      out_ << api::dump_json(row) << '\n';
      break;
    case TableFormat::kJson:
      out_ << (rows_ == 0 ? "\n" : ",\n") << api::dump_json(row);
      break;
  }
  ++rows_;
  out_.flush();
}

void PlanTableWriter::finish() {
  if (format_ == TableFormat::kJson) out_ << (rows_ == 0 ? "]\n" : "\n]\n");
  out_.flush();
}

}  // namespace slosh::service
