#pragma once
// The rows of a min-time table (`slosh batch --mode min_time`): built from a min-time answer or
// a row's error, rendered as a CSV line or a JSON object. Local and remote batches make their
// rows alike.

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"

namespace slosh::api {

/// One row of a min-time table, ready to render.
struct MinTimeTableRow {
  nlohmann::json document;
};

/// The row of a recipe whose strategies were searched: row, recipe_id, status "ok" and the
/// figures of `answer` (min_time_row_figures; throws std::invalid_argument when `answer` is not a
/// min-time answer).
[[nodiscard]] MinTimeTableRow min_time_answer_row(std::size_t row, std::string_view recipe_id,
                                                  std::string_view answer);

/// The row of a recipe that could not be searched: status "error", its message and field. For a
/// row read from CSV (`csv`) the field and the message name the table's column (motion_time_s
/// for the search's motion_time_max_s), as plan tables do.
[[nodiscard]] MinTimeTableRow min_time_error_row(std::size_t row, std::string_view recipe_id,
                                                 bool csv, const ApiError& error);

/// The CSV header of min-time tables: row, recipe_id, status, key, t_min_<strategy>_s of every
/// default strategy, winner, winner_t_min_s, baseline_t_min_s, gain_pct, gain_cycles_per_min,
/// message, error_field.
[[nodiscard]] std::string min_time_csv_header();

/// The row as a CSV line of those columns (RFC 4180 cells, no line break).
[[nodiscard]] std::string min_time_csv_line(const MinTimeTableRow& row);

/// The row as one JSON object (no line break).
[[nodiscard]] std::string min_time_json_text(const MinTimeTableRow& row);

}  // namespace slosh::api
