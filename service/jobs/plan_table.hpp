#pragma once
// Plan tables written by `slosh batch` and a batch job's results downloads: one row per recipe,
// in input order, as CSV (one column per figure, units in the names), JSON lines or a JSON
// array. The rows and their text are api's (slosh/api/plan_table_row.hpp); this writes them.

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>

#include "engine/plan_engine.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/plan_table_row.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

/// The table row of one recipe: the figures of its plan (api::planned_row; `plan` adds the plan
/// in that view), or, when the recipe could not be planned, its error (api::failed_row).
[[nodiscard]] api::PlanTableRow plan_row(const RecipeRow& recipe, const BatchResult& result,
                                         std::optional<api::PlanView> plan);

/// The CSV header of plan tables (comma-separated column names).
[[nodiscard]] std::string plan_table_header();

/// Streams plan rows to `out` in the chosen format; rows are flushed as they are written.
class PlanTableWriter {
 public:
  PlanTableWriter(std::ostream& out, TableFormat format);
  void write(const api::PlanTableRow& row);
  /// Closes the table (the JSON array's bracket); call once after the last row.
  void finish();

 private:
  std::ostream& out_;
  TableFormat format_;
  std::size_t rows_{0};
};

}  // namespace slosh::service
