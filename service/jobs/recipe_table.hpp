#pragma once
// Recipe tables for `slosh batch`: CSV (one recipe per row, named columns) or JSON (one plan
// request per line, or an array) -> one plan request per recipe.
//
// CSV columns (header row, any order; an empty cell means "the default"):
//   required  recipe_id, radius_mm, fill_height_mm, stroke_mm, motion_time_s, strategy, and
//             fluid (a catalogue name) or density_kg_m3 + viscosity_pa_s (a custom fluid)
//   optional  container_height_mm, every plan option of the option registry by its JSON name
//             (slosh/api/option_registry.hpp) and the limits by theirs: a_max, v_max, j_max.
// List cells (weights, plateau_min_s) separate numbers by ';' (or spaces); damping is a name or
// a number (the explicit zeta); booleans are true/false, yes/no or 1/0. Cells follow RFC 4180
// (quotes, doubled quotes, line breaks inside quotes) except that spaces around unquoted cells
// are trimmed (libcsv's default); quote a cell to keep them.

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/api/recipe_row.hpp"
#include "slosh/core/enum_names.hpp"

namespace slosh::service {

/// File formats of recipe and plan tables.
enum class TableFormat { kCsv, kJsonLines, kJson };

}  // namespace slosh::service

namespace slosh {
template <>
struct EnumNames<service::TableFormat> {
  static constexpr std::array<EnumName<service::TableFormat>, 3> table{{
      {service::TableFormat::kCsv, "csv"},
      {service::TableFormat::kJsonLines, "jsonl"},
      {service::TableFormat::kJson, "json"},
  }};
};
}  // namespace slosh

namespace slosh::service {

[[nodiscard]] std::string to_string(TableFormat format);

/// The format named by `name` ("csv", "jsonl", "json"), or, when `name` is "auto", the one of the
/// path's extension (.csv; .jsonl or .ndjson; .json), CSV for "-". Throws TableError otherwise.
[[nodiscard]] TableFormat table_format(const std::string& name, const std::string& path);

/// A problem with the table as a whole (unreadable, bad header): nothing is planned.
class TableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One recipe of a table.
struct RecipeRow {
  std::size_t row{};           ///< 1-based recipe number (the CSV header is not counted)
  std::string recipe_id;       ///< as given (may be empty; empty when the id itself is refused)
  api::RecipeRequest request;  ///< the plan request, read by api (null when `error` is set)
  std::optional<api::ApiError> error;  ///< set when the row cannot be read
  bool csv{false};                     ///< read from CSV: error fields are reported as column names
};

/// Reads a whole table. Row-level problems (a non-numeric cell, a wrong cell count, a line that
/// is not JSON, a recipe_id with a control character) become the row's `error`; table-level ones
/// throw TableError. The CSV columns and cells are api's (slosh/api/recipe_row.hpp); their options
/// come from `registry`.
[[nodiscard]] std::vector<RecipeRow> read_recipe_table(
    const std::string& text, TableFormat format,
    const api::OptionRegistry& registry = api::plan_option_registry());

/// The CSV column a request field path ("format.container.radius_mm", "options.weights[1]")
/// comes from; the path itself when no column maps to it.
[[nodiscard]] std::string column_of_field(const std::string& field);

/// `message` with a leading request path replaced by its column ("format.container.radius_mm =
/// -3 is out of range ..." -> "radius_mm = -3 is out of range ...").
[[nodiscard]] std::string in_column_terms(const std::string& field, const std::string& message);

/// The accepted CSV column names, comma-separated (for messages and --help).
[[nodiscard]] std::string recipe_columns();

}  // namespace slosh::service
