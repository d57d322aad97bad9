#pragma once
// A row of a plan table (`slosh batch`, a batch job's results) as a client holds it: the facts it
// counts, typed, and the row itself, which only the table writer renders.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

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

/// The typed facts of a row made by the table code (plan_row).
[[nodiscard]] PlanTableRow table_row_of(nlohmann::json document);

/// The rows of a JSON-lines table (a batch job's results.jsonl; blank lines skipped). Throws
/// std::runtime_error naming the line (1-based) that is not a JSON object with a string
/// "status".
[[nodiscard]] std::vector<PlanTableRow> parse_table_rows(std::string_view text);

}  // namespace slosh::api
