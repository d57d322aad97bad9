#include "slosh/api/min_time_table.hpp"

#include <vector>

#include "slosh/api/csv_cell.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::api {

namespace {

/// An RFC 4180 cell: text quoted when it holds a comma, a quote or a line break, formula-leading
/// text neutralised (csv_cell.hpp); numbers bare.
std::string csv_cell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (!v.is_string()) return dump_json(v);
  return csv_text_cell(v.get_ref<const std::string&>(), false);
}

/// The min_time table's columns (CSV header and JSON members, in order).
std::vector<std::string> min_time_columns() {
  std::vector<std::string> c{"row", "recipe_id", "status", "key"};
  for (Strategy s : default_min_time_strategies()) c.push_back("t_min_" + to_string(s) + "_s");
  for (const char* name : {"winner", "winner_t_min_s", "baseline_t_min_s", "gain_pct",
                           "gain_cycles_per_min", "message", "error_field"}) {
    c.emplace_back(name);
  }
  return c;
}

}  // namespace

MinTimeTableRow min_time_answer_row(std::size_t row, std::string_view recipe_id,
                                    std::string_view answer) {
  nlohmann::json document{{"row", row}, {"recipe_id", recipe_id}, {"status", "ok"}};
  document.update(min_time_row_figures(answer));
  return MinTimeTableRow{std::move(document)};
}

MinTimeTableRow min_time_error_row(std::size_t row, std::string_view recipe_id, bool csv,
                                   const ApiError& error) {
  nlohmann::json document{{"row", row}, {"recipe_id", recipe_id}, {"status", "error"}};
  std::string field = error.field();
  std::string message = error.what();
  if (csv) {  // name the CSV column, as plan tables do
    constexpr std::string_view kMax = "motion_time_max_s";  // the motion_time_s column's value
    if (field == kMax) {
      if (message.rfind(kMax, 0) == 0) message.replace(0, kMax.size(), "motion_time_s");
      field = "motion_time_s";
    } else {
      const std::string text = message;
      message = in_column_terms(field, text);
      field = error_columns(field, text);
    }
  }
  document["message"] = message;
  document["error_field"] = field.empty() ? nlohmann::json(nullptr) : nlohmann::json(field);
  return MinTimeTableRow{std::move(document)};
}

std::string min_time_csv_header() {
  std::string header;
  for (const std::string& c : min_time_columns()) header += (header.empty() ? "" : ",") + c;
  return header;
}

std::string min_time_csv_line(const MinTimeTableRow& row) {
  std::string line;
  bool first = true;
  for (const std::string& c : min_time_columns()) {
    line += (first ? "" : ",") + csv_cell(row.document.value(c, nlohmann::json(nullptr)));
    first = false;
  }
  return line;
}

std::string min_time_json_text(const MinTimeTableRow& row) {
  return dump_json(row.document);
}

}  // namespace slosh::api
