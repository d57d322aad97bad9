#include "jobs/recipe_table.hpp"

#include <csv.h>

#include <algorithm>
#include <cctype>
#include <string_view>

#include "slosh/api/fields.hpp"
#include "slosh/api/recipe_row.hpp"
#include "slosh/api/text_preview.hpp"

namespace slosh::service {

namespace {

std::string quote_text(std::string_view text) {
  return api::show_text(text);
}

// Collects the records of a CSV text with libcsv (RFC 4180: quoted cells, doubled quotes,
// line breaks inside quotes, CRLF).
class CsvRecords {
 public:
  explicit CsvRecords(std::string_view text) {
    csv_parser parser{};
    if (csv_init(&parser, CSV_STRICT | CSV_STRICT_FINI) != 0) {
      throw TableError("recipe table: cannot initialise the CSV parser");
    }
    const std::size_t parsed =
        csv_parse(&parser, text.data(), text.size(), on_cell, on_record, this);
    const bool ok = parsed == text.size() && csv_fini(&parser, on_cell, on_record, this) == 0;
    const std::string reason = csv_strerror(csv_error(&parser));
    csv_free(&parser);
    if (!ok) {
      throw TableError("recipe table: the CSV is malformed after " +
                       std::to_string(records_.size()) + " complete record(s) (" + reason +
                       "): a quote inside an unquoted cell, or a quoted cell never closed");
    }
  }
  std::vector<std::vector<std::string>>& records() { return records_; }

 private:
  static void on_cell(void* data, std::size_t size, void* self) {
    auto* me = static_cast<CsvRecords*>(self);
    me->current_.emplace_back(static_cast<const char*>(data), size);
  }
  static void on_record(int /*terminator*/, void* self) {
    auto* me = static_cast<CsvRecords*>(self);
    me->records_.push_back(std::move(me->current_));
    me->current_.clear();
  }
  std::vector<std::vector<std::string>> records_;
  std::vector<std::string> current_;
};

api::RecipeHeader read_header(const std::vector<std::string>& names,
                              const api::OptionRegistry& registry) {
  try {
    return api::RecipeHeader(names, registry);
  } catch (const api::RecipeTableError& e) {
    throw TableError(e.what());
  }
}

// A recipe as api read it, numbered.
RecipeRow recipe_row(std::size_t number, api::ReadRecipe recipe, bool csv) {
  RecipeRow row;
  row.row = number;
  row.recipe_id = std::move(recipe.recipe_id);
  row.request = std::move(recipe.request);
  row.error = std::move(recipe.error);
  row.csv = csv;
  return row;
}

std::vector<RecipeRow> read_csv(std::string_view text, const api::OptionRegistry& registry) {
  CsvRecords csv(text);
  auto& records = csv.records();
  if (records.empty()) throw TableError("recipe table: the CSV is empty (no header row)");
  const api::RecipeHeader header = read_header(records.front(), registry);
  std::vector<RecipeRow> rows;
  rows.reserve(records.size() - 1);
  for (std::size_t r = 1; r < records.size(); ++r)
    rows.push_back(recipe_row(r, header.recipe(r, records[r]), true));
  return rows;
}

std::vector<RecipeRow> read_json_lines(std::string_view text) {
  std::vector<RecipeRow> rows;
  std::size_t at = 0;
  std::size_t line_number = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    rows.push_back(recipe_row(rows.size() + 1, api::json_line_recipe(line, line_number), false));
  }
  return rows;
}

std::vector<RecipeRow> read_json(std::string_view text) {
  std::vector<api::ReadRecipe> recipes;
  try {
    recipes = api::json_document_recipes(text);
  } catch (const api::RecipeTableError& e) {
    throw TableError(e.what());
  }
  std::vector<RecipeRow> rows;
  rows.reserve(recipes.size());
  for (api::ReadRecipe& recipe : recipes)
    rows.push_back(recipe_row(rows.size() + 1, std::move(recipe), false));
  return rows;
}

}  // namespace

std::string to_string(TableFormat format) {
  return std::string(name_of(format));
}

TableFormat table_format(const std::string& name, const std::string& path) {
  if (const auto format = enum_from_name<TableFormat>(name)) return *format;
  if (name != "auto") {
    throw TableError("table format " + quote_text(name) +
                     " is not allowed: one of auto, csv, jsonl, json");
  }
  if (path == "-") return TableFormat::kCsv;
  auto ends_with = [&](std::string_view suffix) {
    if (path.size() < suffix.size()) return false;
    return std::equal(suffix.rbegin(), suffix.rend(), path.rbegin(), [](char a, char b) {
      return std::tolower(static_cast<unsigned char>(a)) == b;
    });
  };
  if (ends_with(".csv")) return TableFormat::kCsv;
  if (ends_with(".jsonl") || ends_with(".ndjson")) return TableFormat::kJsonLines;
  if (ends_with(".json")) return TableFormat::kJson;
  throw TableError("cannot tell the table format of " + quote_text(path) +
                   " from its extension: use .csv, .jsonl, .ndjson or .json, or give the format");
}

std::vector<RecipeRow> read_recipe_table(const std::string& text, TableFormat format,
                                         const api::OptionRegistry& registry) {
  std::string_view body = text;
  if (body.starts_with("\xEF\xBB\xBF")) body.remove_prefix(3);  // UTF-8 byte-order mark
  switch (format) {
    case TableFormat::kCsv:
      return read_csv(body, registry);
    case TableFormat::kJsonLines:
      return read_json_lines(body);
    case TableFormat::kJson:
      return read_json(body);
  }
  return {};
}

std::string column_of_field(const std::string& field) {
  return api::column_of_field(field);
}

std::string in_column_terms(const std::string& field, const std::string& message) {
  return api::in_column_terms(field, message);
}

std::string recipe_columns() {
  return api::recipe_column_names();
}

}  // namespace slosh::service
