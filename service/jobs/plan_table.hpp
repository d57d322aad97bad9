#pragma once
// Plan tables written by `slosh batch`: one row per recipe, in input order, as CSV (one column
// per figure, units in the names), JSON lines or a JSON array.

#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/plan_engine.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service {

/// The table row of one recipe: {"row", "recipe_id", "status", "key", "cached", "strategy",
/// "message", "durations_s", "kinematics", "f1_hz", "prediction", "baseline", "reduction_pct",
/// "solve_ms"} of its plan, or {"row", "recipe_id", "status": "error", "message", "error",
/// "error_field"} when the recipe could not be planned. `plan` adds the plan as "plan" in that
/// view (the whole plan, or api::compact_plan of it).
[[nodiscard]] nlohmann::json plan_row(const RecipeRow& recipe, const BatchResult& result,
                                      std::optional<api::PlanView> plan);

/// The CSV header of plan tables (comma-separated column names).
[[nodiscard]] std::string plan_table_header();

/// Streams plan rows to `out` in the chosen format; rows are flushed as they are written.
class PlanTableWriter {
 public:
  PlanTableWriter(std::ostream& out, TableFormat format);
  void write(const nlohmann::json& row);
  /// Closes the table (the JSON array's bracket); call once after the last row.
  void finish();

 private:
  std::ostream& out_;
  TableFormat format_;
  std::size_t rows_{0};
};

}  // namespace slosh::service
