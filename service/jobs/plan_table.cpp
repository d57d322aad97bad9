#include "jobs/plan_table.hpp"

namespace slosh::service {

api::PlanTableRow plan_row(const RecipeRow& recipe, const BatchResult& result,
                           std::optional<api::PlanView> view) {
  const api::RowRecipe which{recipe.row, recipe.recipe_id, recipe.csv};
  if (!result.ok()) return api::failed_row(which, *result.error);
  return api::planned_row(which, result.plan, result.cached, view);
}

std::string plan_table_header() {
  return api::plan_table_csv_header();
}

PlanTableWriter::PlanTableWriter(std::ostream& out, TableFormat format)
    : out_(out), format_(format) {
  if (format_ == TableFormat::kCsv) out_ << plan_table_header() << '\n';
  if (format_ == TableFormat::kJson) out_ << "[";
  out_.flush();
}

void PlanTableWriter::write(const api::PlanTableRow& row) {
  switch (format_) {
    case TableFormat::kCsv:
      out_ << api::plan_table_csv_line(row) << '\n';
      break;
    case TableFormat::kJsonLines:
      out_ << api::table_row_text(row) << '\n';
      break;
    case TableFormat::kJson:
      out_ << (rows_ == 0 ? "\n" : ",\n") << api::table_row_text(row);
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
