#pragma once
// A row of a plan table (`slosh batch`, a batch job's results) as a client holds it: the facts it
// counts, typed, and the row itself, which only the table writer renders.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::api {

/// One plan-table row: its 1-based number, the plan status ("optimal", ..., or "error" for a
/// recipe that could not be planned), whether the plan came from the cache, and the row as the
/// table writer takes it.
struct PlanTableRow {
  /// 1-based recipe number; 0 when the row carries none (or not a whole number).
  std::size_t number{0};
  /// The "row" member as written ("null" when absent), to name a row that is out of place.
  std::string number_text;
  /// The plan status, or "error".
  std::string status;
  /// Whether the recipe could not be planned (status "error").
  bool failed{false};
  bool cached{false};
  /// The whole row, for the table writer.
  nlohmann::json document;
};

/// The typed facts of a row given as JSON (a stored results line).
[[nodiscard]] PlanTableRow table_row_of(nlohmann::json document);

/// Which recipe a row is of: its 1-based number, its recipe_id, and whether it was read from CSV
/// (then an error names the column instead of the request path).
struct RowRecipe {
  std::size_t number{0};
  std::string_view recipe_id;
  bool csv{false};
};

/// The row of a planned recipe: {"row", "recipe_id", "status", "key", "cached", "strategy",
/// "message", "durations_s", "kinematics", "f1_hz", "prediction", "baseline", "reduction_pct",
/// "solve_ms", ...} of `plan` (the rendered plan's JSON text); `view` adds the plan as "plan" in
/// that view (the whole plan, or compact_plan of it).
[[nodiscard]] PlanTableRow planned_row(const RowRecipe& recipe, std::string_view plan, bool cached,
                                       std::optional<PlanView> view);

/// The row of a recipe that could not be planned: {"row", "recipe_id", "status": "error",
/// "message", "error", "error_field"}.
[[nodiscard]] PlanTableRow failed_row(const RowRecipe& recipe, const ApiError& error);

/// The CSV header of plan tables (comma-separated column names).
[[nodiscard]] std::string plan_table_csv_header();

/// The row as a CSV line of those columns (no line break): text cells quoted (RFC 4180) and
/// neutralised when formula-leading (csv_cell.hpp), numbers and booleans bare, absent ones empty.
[[nodiscard]] std::string plan_table_csv_line(const PlanTableRow& row);

/// The row as one JSON object (no line break): a line of JSON-lines tables, an element of JSON
/// ones, a stored results line of a batch job.
[[nodiscard]] std::string table_row_text(const PlanTableRow& row);

/// The rows of a JSON-lines table (a batch job's results.jsonl; blank lines skipped). Throws
/// std::runtime_error naming the line (1-based) that is not a JSON object with a string
/// "status".
[[nodiscard]] std::vector<PlanTableRow> parse_table_rows(std::string_view text);

}  // namespace slosh::api
