#include "jobs/plan_table.hpp"

#include <csv.h>

#include <string_view>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/recipe_row.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

// RFC 4180 cell: text quoted by libcsv (doubling inner quotes), numbers and booleans bare.
void write_cell(std::ostream& out, const json& value) {
  if (value.is_null()) return;
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    std::vector<char> buffer(2 * text.size() + 2);
    const std::size_t n = csv_write(buffer.data(), buffer.size(), text.data(), text.size());
    out.write(buffer.data(), static_cast<std::streamsize>(n));
    return;
  }
  out << api::dump_json(value);
}

}  // namespace

json plan_row(const RecipeRow& recipe, const BatchResult& result,
              std::optional<api::PlanView> view) {
  json row{{"row", recipe.row}, {"recipe_id", recipe.recipe_id}};
  if (!result.ok()) {
    row.update(api::error_row_figures(api::error_envelope(*result.error)["error"], recipe.csv));
    return row;
  }
  const json plan = json::parse(result.plan);
  row.update(api::plan_row_figures(plan));
  row["cached"] = result.cached;
  if (view) row["plan"] = *view == api::PlanView::kCompact ? api::compact_plan(plan) : plan;
  return row;
}

std::string plan_table_header() {
  return api::plan_column_names();
}

PlanTableWriter::PlanTableWriter(std::ostream& out, TableFormat format)
    : out_(out), format_(format) {
  if (format_ == TableFormat::kCsv) out_ << plan_table_header() << '\n';
  if (format_ == TableFormat::kJson) out_ << "[";
  out_.flush();
}

void PlanTableWriter::write(const json& row) {
  switch (format_) {
    case TableFormat::kCsv: {
      bool first = true;
      for (const api::PlanColumn& column : api::plan_columns()) {
        if (!first) out_ << ',';
        first = false;
        const json::json_pointer pointer{std::string(column.pointer)};
        write_cell(out_, row.contains(pointer) ? row[pointer] : json(nullptr));
      }
      out_ << '\n';
      break;
    }
    case TableFormat::kJsonLines:
      out_ << api::dump_json(row) << '\n';
      break;
    case TableFormat::kJson:
      out_ << (rows_ == 0 ? "\n" : ",\n") << api::dump_json(row);
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
