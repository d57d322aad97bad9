#pragma once
// The rows of a `slosh batch` plan table as they are written, in input order, with the counts the
// summary line reports.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/plan_engine.hpp"
#include "jobs/plan_table.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/plan_table_row.hpp"
#include "slosh/api/plan_view.hpp"

namespace slosh::service::batch_cli {

/// Writes rows in input order and keeps the counts of the summary.
class RowSink {
 public:
  RowSink(PlanTableWriter& writer, std::optional<api::PlanView> view)
      : writer_(writer), view_(view) {}
  void write(const RecipeRow& recipe, const BatchResult& result) {
    write_row(plan_row(recipe, result, view_));
  }
  /// Writes a row made elsewhere (a batch job's, from the service).
  void write_row(const api::PlanTableRow& row) {
    if (row.failed) {
      failed_rows_.push_back(row.number);
    } else {
      ++statuses_[row.status];
    }
    if (row.cached) ++cached_;
    ++written_;
    writer_.write(row);
  }
  [[nodiscard]] std::size_t written() const { return written_; }
  [[nodiscard]] std::size_t cached() const { return cached_; }
  [[nodiscard]] const std::vector<std::size_t>& failed_rows() const { return failed_rows_; }
  /// How many rows have each plan status (the rows that are errors are failed_rows()).
  [[nodiscard]] const std::map<std::string, std::size_t>& statuses() const { return statuses_; }

 private:
  PlanTableWriter& writer_;
  std::optional<api::PlanView> view_;
  std::size_t written_{0};
  std::size_t cached_{0};
  std::vector<std::size_t> failed_rows_;
  std::map<std::string, std::size_t> statuses_;
};

/// The result row of a recipe the table reader could not read (its error).
[[nodiscard]] BatchResult row_error_result(const RecipeRow& row);

}  // namespace slosh::service::batch_cli
