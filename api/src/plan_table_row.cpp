#include "slosh/api/plan_table_row.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "slosh/api/csv_cell.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::api {

PlanTableRow table_row_of(nlohmann::json document) {
  PlanTableRow row;
  const auto number = document.find("row");
  row.number_text = number == document.end() ? "null" : dump_json(*number);
  if (number != document.end() && number->is_number_unsigned()) {
    row.number = number->get<std::size_t>();
  }
  row.status = document.at("status").get<std::string>();
  row.failed = row.status == "error";
  const auto cached = document.find("cached");
  row.cached = cached != document.end() && cached->is_boolean() && cached->get<bool>();
  row.document = std::move(document);
  return row;
}

namespace {

nlohmann::json row_head(const RowRecipe& recipe) {
  return {{"row", recipe.number}, {"recipe_id", recipe.recipe_id}};
}

}  // namespace

PlanTableRow planned_row(const RowRecipe& recipe, std::string_view plan, bool cached,
                         std::optional<PlanView> view) {
  nlohmann::json row = row_head(recipe);
  const nlohmann::json parsed = nlohmann::json::parse(plan);
  row.update(plan_row_figures(parsed));
  row["cached"] = cached;
  if (view) row["plan"] = *view == PlanView::kCompact ? compact_plan(parsed) : parsed;
  return table_row_of(std::move(row));
}

PlanTableRow failed_row(const RowRecipe& recipe, const ApiError& error) {
  nlohmann::json row = row_head(recipe);
  row.update(error_row_figures(error_envelope(error)["error"], recipe.csv));
  return table_row_of(std::move(row));
}

std::string plan_table_csv_header() {
  return plan_column_names();
}

std::string plan_table_csv_line(const PlanTableRow& row) {
  std::string line;
  bool first = true;
  for (const PlanColumn& column : plan_columns()) {
    if (!first) line += ',';
    first = false;
    const nlohmann::json::json_pointer pointer{std::string(column.pointer)};
    if (!row.document.contains(pointer)) continue;
    const nlohmann::json& value = row.document[pointer];
    if (value.is_string()) {
      line += csv_text_cell(value.get_ref<const std::string&>(), true);
    } else if (!value.is_null()) {
      line += dump_json(value);
    }
  }
  return line;
}

std::string table_row_text(const PlanTableRow& row) {
  return dump_json(row.document);
}

std::vector<PlanTableRow> parse_table_rows(std::string_view text) {
  std::vector<PlanTableRow> rows;
  std::size_t line = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view cells = text.substr(at, end - at);
    at = end + 1;
    ++line;
    if (cells.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    nlohmann::json document = nlohmann::json::parse(cells, nullptr, false);
    if (document.is_discarded() || !document.is_object() || !document.contains("status") ||
        !document["status"].is_string()) {
      throw std::runtime_error("line " + std::to_string(line) +
                               " of the results is not a plan-table row");
    }
    rows.push_back(table_row_of(std::move(document)));
  }
  return rows;
}

}  // namespace slosh::api
