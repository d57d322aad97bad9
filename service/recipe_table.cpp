#include "recipe_table.hpp"

#include <csv.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

enum class CellKind { kId, kText, kNumber, kBool, kNumberList, kDamping };

struct InputColumn {
  std::string_view name;
  std::string_view pointer;  // JSON pointer into the plan request
  CellKind kind;
};

constexpr std::array kColumns{
    InputColumn{"recipe_id", "", CellKind::kId},
    InputColumn{"radius_mm", "/format/container/radius_mm", CellKind::kNumber},
    InputColumn{"container_height_mm", "/format/container/height_mm", CellKind::kNumber},
    InputColumn{"fill_height_mm", "/format/fill_height_mm", CellKind::kNumber},
    InputColumn{"fluid", "/format/fluid", CellKind::kText},
    InputColumn{"density_kg_m3", "/format/fluid/density_kg_m3", CellKind::kNumber},
    InputColumn{"viscosity_pa_s", "/format/fluid/viscosity_pa_s", CellKind::kNumber},
    InputColumn{"stroke_mm", "/format/stroke_mm", CellKind::kNumber},
    InputColumn{"motion_time_s", "/format/motion_time_s", CellKind::kNumber},
    InputColumn{"strategy", "/strategy", CellKind::kText},
    InputColumn{"p_notch", "/options/p_notch", CellKind::kNumber},
    InputColumn{"weights", "/options/weights", CellKind::kNumberList},
    InputColumn{"band", "/options/band", CellKind::kNumber},
    InputColumn{"n_band", "/options/n_band", CellKind::kNumber},
    InputColumn{"tol_rel", "/options/tol_rel", CellKind::kNumber},
    InputColumn{"eta_rest_max_mm", "/options/eta_rest_max_mm", CellKind::kNumber},
    InputColumn{"eta_motion_max_mm", "/options/eta_motion_max_mm", CellKind::kNumber},
    InputColumn{"objective", "/options/objective", CellKind::kText},
    InputColumn{"rest_time_s", "/options/rest_time_s", CellKind::kNumber},
    InputColumn{"min_ramp_s", "/options/min_ramp_s", CellKind::kNumber},
    InputColumn{"fix_constant_velocity_zero", "/options/fix_constant_velocity_zero",
                CellKind::kBool},
    InputColumn{"plateau_min_s", "/options/plateau_min_s", CellKind::kNumberList},
    InputColumn{"a_max", "/options/limits/a_max", CellKind::kNumber},
    InputColumn{"v_max", "/options/limits/v_max", CellKind::kNumber},
    InputColumn{"j_max", "/options/limits/j_max", CellKind::kNumber},
    InputColumn{"damping", "/options/damping", CellKind::kDamping},
    InputColumn{"alpha", "/options/alpha", CellKind::kNumber},
    InputColumn{"modes", "/options/modes", CellKind::kNumber},
    InputColumn{"solver", "/options/solver", CellKind::kText},
    InputColumn{"time_limit_s", "/options/time_limit_s", CellKind::kNumber},
    InputColumn{"base", "/options/base", CellKind::kText},
    InputColumn{"shaper", "/options/shaper", CellKind::kText},
    InputColumn{"residual", "/options/residual", CellKind::kNumber},
    InputColumn{"iir_order", "/options/iir_order", CellKind::kNumber},
    InputColumn{"iir_tau", "/options/iir_tau", CellKind::kNumber},
    InputColumn{"iir_sample_period_s", "/options/iir_sample_period_s", CellKind::kNumber},
};

constexpr std::array<std::string_view, 6> kRequired{"recipe_id", "radius_mm",     "fill_height_mm",
                                                    "stroke_mm", "motion_time_s", "strategy"};

const InputColumn* find_column(std::string_view name) {
  const auto it = std::find_if(kColumns.begin(), kColumns.end(),
                               [&](const InputColumn& c) { return c.name == name; });
  return it == kColumns.end() ? nullptr : &*it;
}

// "/format/container/radius_mm" -> "format.container.radius_mm"
std::string dotted(std::string_view pointer) {
  std::string out(pointer.substr(pointer.empty() ? 0 : 1));
  std::replace(out.begin(), out.end(), '/', '.');
  return out;
}

json row_error(const std::string& message, const std::string& field) {
  return {{"code", api::to_string(api::ErrorCode::kInvalidValue)},
          {"message", message},
          {"field", field.empty() ? json(nullptr) : json(field)}};
}

// A cell's problem: names the column, the text and what is expected.
struct CellError {
  std::string column;
  std::string message;
};

std::string quote_text(std::string_view text) {
  return api::show(json(std::string(text)));
}

std::optional<json> parse_number(std::string_view text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  // Integral values stay integers (n_band, modes).
  if (value == std::trunc(value) && std::abs(value) < 9.0e15) {
    return json(static_cast<std::int64_t>(value));
  }
  return json(value);
}

json cell_value(const InputColumn& column, std::string_view text) {
  const std::string name(column.name);
  switch (column.kind) {
    case CellKind::kId:
    case CellKind::kText:
      return std::string(text);
    case CellKind::kNumber:
      if (auto v = parse_number(text)) return *v;
      throw CellError{name, name + " = " + quote_text(text) + " is not a number"};
    case CellKind::kDamping:
      if (auto v = parse_number(text)) return json{{"zeta", *v}};
      return std::string(text);
    case CellKind::kBool: {
      std::string lower(text);
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (lower == "true" || lower == "yes" || lower == "1") return true;
      if (lower == "false" || lower == "no" || lower == "0") return false;
      throw CellError{name, name + " = " + quote_text(text) +
                                " is not a boolean: true, false, yes, no, 1 or 0"};
    }
    case CellKind::kNumberList: {
      json list = json::array();
      std::size_t at = 0;
      while (at < text.size()) {
        const std::size_t end = text.find_first_of("; \t,", at);
        const std::string_view item =
            text.substr(at, end == std::string_view::npos ? end : end - at);
        if (!item.empty()) {
          auto v = parse_number(item);
          if (!v) {
            throw CellError{name, name + " = " + quote_text(text) +
                                      " is not a list of numbers separated by ';'"};
          }
          list.push_back(*v);
        }
        if (end == std::string_view::npos) break;
        at = end + 1;
      }
      return list;
    }
  }
  return nullptr;
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

std::vector<RecipeRow> read_csv(std::string_view text) {
  CsvRecords csv(text);
  auto& records = csv.records();
  if (records.empty()) throw TableError("recipe table: the CSV is empty (no header row)");
  const std::vector<std::string>& header = records.front();
  std::vector<const InputColumn*> columns;
  for (std::size_t c = 0; c < header.size(); ++c) {
    const InputColumn* column = find_column(header[c]);
    if (column == nullptr) {
      throw TableError("recipe table: unknown column " + quote_text(header[c]) + " (column " +
                       std::to_string(c + 1) + " of the header); allowed: " + recipe_columns());
    }
    if (std::find(columns.begin(), columns.end(), column) != columns.end()) {
      throw TableError("recipe table: column " + quote_text(header[c]) + " appears twice");
    }
    columns.push_back(column);
  }
  auto has = [&](std::string_view name) {
    return std::any_of(columns.begin(), columns.end(),
                       [&](const InputColumn* c) { return c->name == name; });
  };
  for (std::string_view name : kRequired) {
    if (!has(name)) {
      throw TableError("recipe table: missing column " + quote_text(name) + "; required: " +
                       "recipe_id, radius_mm, fill_height_mm, fluid (or density_kg_m3 and " +
                       "viscosity_pa_s), stroke_mm, motion_time_s, strategy");
    }
  }
  if (!has("fluid") && !(has("density_kg_m3") && has("viscosity_pa_s"))) {
    throw TableError(
        "recipe table: missing column \"fluid\" (or both density_kg_m3 and viscosity_pa_s)");
  }

  const auto id_column = static_cast<std::size_t>(
      std::find_if(columns.begin(), columns.end(),
                   [](const InputColumn* c) { return c->kind == CellKind::kId; }) -
      columns.begin());
  std::vector<RecipeRow> rows;
  rows.reserve(records.size() - 1);
  for (std::size_t r = 1; r < records.size(); ++r) {
    const std::vector<std::string>& cells = records[r];
    RecipeRow row;
    row.row = r;
    row.csv = true;
    if (id_column < cells.size()) row.recipe_id = cells[id_column];
    if (cells.size() != header.size()) {
      row.error = row_error("row " + std::to_string(r) + " has " + std::to_string(cells.size()) +
                                " cells, the header has " + std::to_string(header.size()),
                            "");
      rows.push_back(std::move(row));
      continue;
    }
    json request = json::object();
    try {
      std::string named_fluid;   // "fluid = ..." when given
      std::string custom_fluid;  // "density_kg_m3 = ..." when given
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].empty()) continue;
        const std::string given = std::string(columns[c]->name) + " = " + quote_text(cells[c]);
        if (columns[c]->name == "fluid") named_fluid = given;
        if (columns[c]->pointer.starts_with("/format/fluid/") && custom_fluid.empty()) {
          custom_fluid = given;
        }
      }
      if (!named_fluid.empty() && !custom_fluid.empty()) {
        throw CellError{"fluid", named_fluid + " and " + custom_fluid +
                                     ": give either fluid or density_kg_m3 and viscosity_pa_s, "
                                     "not both"};
      }
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const InputColumn& column = *columns[c];
        if (column.kind == CellKind::kId || cells[c].empty()) continue;  // empty: the default
        const json::json_pointer pointer{std::string(column.pointer)};
        request[pointer] = cell_value(column, cells[c]);
      }
      row.request = std::move(request);
    } catch (const CellError& e) {
      row.error = row_error(e.message, e.column);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

RecipeRow json_row(std::size_t number, json value) {
  RecipeRow row;
  row.row = number;
  if (value.is_object()) {
    if (const auto id = value.find("recipe_id"); id != value.end()) {
      row.recipe_id = id->is_string() ? id->get<std::string>() : id->dump();
      value.erase(id);
    }
  }
  row.request = std::move(value);
  return row;
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
    const std::size_t number = rows.size() + 1;
    try {
      rows.push_back(json_row(number, api::parse_json_body(line)));
    } catch (const api::ApiError& e) {
      RecipeRow row;
      row.row = number;
      row.error = api::error_envelope(e)["error"];
      row.error["message"] = "line " + std::to_string(line_number) + ": " + e.what();
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

std::vector<RecipeRow> read_json(std::string_view text) {
  json document;
  try {
    document = api::parse_json_body(text);
  } catch (const api::ApiError& e) {
    throw TableError(std::string("recipe table: ") + e.what());
  }
  if (document.is_object() && document.contains("requests")) document = document["requests"];
  if (!document.is_array()) {
    throw TableError(
        "recipe table: a .json table is an array of plan requests or {\"requests\": [...]}");
  }
  std::vector<RecipeRow> rows;
  rows.reserve(document.size());
  for (std::size_t i = 0; i < document.size(); ++i) {
    rows.push_back(json_row(i + 1, std::move(document[i])));
  }
  return rows;
}

}  // namespace

std::string to_string(TableFormat format) {
  switch (format) {
    case TableFormat::kCsv:
      return "csv";
    case TableFormat::kJsonLines:
      return "jsonl";
    case TableFormat::kJson:
      return "json";
  }
  return "csv";
}

TableFormat table_format(const std::string& name, const std::string& path) {
  if (name == "csv") return TableFormat::kCsv;
  if (name == "jsonl") return TableFormat::kJsonLines;
  if (name == "json") return TableFormat::kJson;
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

std::vector<RecipeRow> read_recipe_table(const std::string& text, TableFormat format) {
  std::string_view body = text;
  if (body.starts_with("\xEF\xBB\xBF")) body.remove_prefix(3);  // UTF-8 byte-order mark
  switch (format) {
    case TableFormat::kCsv:
      return read_csv(body);
    case TableFormat::kJsonLines:
      return read_json_lines(body);
    case TableFormat::kJson:
      return read_json(body);
  }
  return {};
}

namespace {

// The column whose request path is the longest prefix of `field` (nullptr when none).
const InputColumn* column_for(const std::string& field) {
  const InputColumn* best = nullptr;
  std::size_t best_length = 0;
  for (const InputColumn& column : kColumns) {
    if (column.pointer.empty()) continue;
    const std::string path = dotted(column.pointer);
    const bool prefix =
        field.rfind(path, 0) == 0 &&
        (field.size() == path.size() || field[path.size()] == '.' || field[path.size()] == '[');
    if (prefix && path.size() > best_length) {
      best = &column;
      best_length = path.size();
    }
  }
  return best;
}

}  // namespace

std::string column_of_field(const std::string& field) {
  const InputColumn* column = column_for(field);
  return column == nullptr ? field : std::string(column->name);
}

std::string in_column_terms(const std::string& field, const std::string& message) {
  const InputColumn* column = column_for(field);
  if (column == nullptr) return message;
  const std::string path = dotted(column->pointer);
  if (message.rfind(path, 0) != 0) return message;
  return std::string(column->name) + message.substr(path.size());
}

std::string recipe_columns() {
  std::string out;
  for (const InputColumn& column : kColumns) {
    if (!out.empty()) out += ", ";
    out += column.name;
  }
  return out;
}

}  // namespace slosh::service
