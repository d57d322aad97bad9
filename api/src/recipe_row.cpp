#include "slosh/api/recipe_row.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>

#include "slosh/api/control_characters.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/recipe_motion.hpp"
#include "slosh/api/robustness_json.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

/// The columns before the options: recipe_id, the format, the strategy.
const std::array kRequestColumns{
    RecipeColumn{"recipe_id", "", CellKind::kId},
    RecipeColumn{"radius_mm", "/format/container/radius_mm", CellKind::kNumber},
    RecipeColumn{"container_shape", "/format/container/shape", CellKind::kText},
    RecipeColumn{"length_mm", "/format/container/length_mm", CellKind::kNumber},
    RecipeColumn{"width_mm", "/format/container/width_mm", CellKind::kNumber},
    RecipeColumn{"orientation_deg", "/format/container/orientation_deg", CellKind::kNumber},
    RecipeColumn{"container_height_mm", "/format/container/height_mm", CellKind::kNumber},
    RecipeColumn{"fill_height_mm", "/format/fill_height_mm", CellKind::kNumber},
    RecipeColumn{"fluid", "/format/fluid", CellKind::kText},
    RecipeColumn{"density_kg_m3", "/format/fluid/density_kg_m3", CellKind::kNumber},
    RecipeColumn{"viscosity_pa_s", "/format/fluid/viscosity_pa_s", CellKind::kNumber},
    RecipeColumn{"stroke_mm", "/format/stroke_mm", CellKind::kNumber},
    RecipeColumn{"motion_time_s", "/format/motion_time_s", CellKind::kNumber},
    RecipeColumn{"strategy", "/strategy", CellKind::kText},
};

// (radius_mm, or length_mm and width_mm for rectangular containers: container_sides.)
constexpr std::array<std::string_view, 6> kRequired{"recipe_id", "radius_mm",     "fill_height_mm",
                                                    "stroke_mm", "motion_time_s", "strategy"};

CellKind cell_kind(OptionKind kind) {
  switch (kind) {
    case OptionKind::kNumber:
    case OptionKind::kOptionalNumber:
    case OptionKind::kInteger:
      return CellKind::kNumber;
    case OptionKind::kBool:
      return CellKind::kBool;
    case OptionKind::kEnum:
      return CellKind::kText;
    case OptionKind::kNumberArray:
      return CellKind::kNumberList;
    case OptionKind::kDamping:
      return CellKind::kDamping;
  }
  return CellKind::kText;
}

template <class Names>
std::string comma_list(const Names& items) {
  std::string out;
  for (const auto& item : items) {
    if (!out.empty()) out += ", ";
    out += item.name;
  }
  return out;
}

std::string quote_text(std::string_view text) {
  return show(json(std::string(text)));
}

/// A table of rectangular containers (a length_mm or width_mm column) needs both sides instead
/// of radius_mm; a row gives one shape or the other (the request parser names a row's mix).
bool rectangular_table(const std::function<bool(std::string_view)>& has) {
  if (!has("length_mm") && !has("width_mm")) return false;
  for (std::string_view side : {"length_mm", "width_mm"}) {
    if (!has(side)) {
      throw RecipeTableError("recipe table: missing column " + quote_text(side) +
                             "; a table of rectangular containers has both length_mm and "
                             "width_mm (and radius_mm only for its round ones)");
    }
  }
  return true;
}

// "/format/container/radius_mm" -> "format.container.radius_mm"
std::string dotted(std::string_view pointer) {
  std::string out(pointer.substr(pointer.empty() ? 0 : 1));
  std::replace(out.begin(), out.end(), '/', '.');
  return out;
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

json bool_cell(const std::string& name, std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "true" || lower == "yes" || lower == "1") return true;
  if (lower == "false" || lower == "no" || lower == "0") return false;
  throw CellError{
      name, name + " = " + quote_text(text) + " is not a boolean: true, false, yes, no, 1 or 0"};
}

json number_list_cell(const std::string& name, std::string_view text) {
  json list = json::array();
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = text.find_first_of("; \t,", at);
    const std::string_view item = text.substr(at, end == std::string_view::npos ? end : end - at);
    if (!item.empty()) {
      auto v = parse_number(item);
      if (!v) {
        throw CellError{
            name, name + " = " + quote_text(text) + " is not a list of numbers separated by ';'"};
      }
      list.push_back(*v);
    }
    if (end == std::string_view::npos) break;
    at = end + 1;
  }
  return list;
}

json cell_value(const RecipeColumn& column, std::string_view text) {
  switch (column.kind) {
    case CellKind::kId:
    case CellKind::kText:
      return std::string(text);
    case CellKind::kNumber:
      // A cell that is not a number goes to the request as the text it is, so that the request's
      // parser refuses it with the member's allowed range, as it refuses such a JSON value.
      if (auto v = parse_number(text)) return *v;
      return std::string(text);
    case CellKind::kDamping:
      if (auto v = parse_number(text)) return json{{"zeta", *v}};
      return std::string(text);
    case CellKind::kBool:
      return bool_cell(column.name, text);
    case CellKind::kNumberList:
      return number_list_cell(column.name, text);
    case CellKind::kJson: {
      json value = json::parse(text, nullptr, false);
      if (value.is_discarded()) {
        throw CellError{column.name, column.name + " = " + quote_text(text) + " is not JSON"};
      }
      return value;
    }
  }
  return nullptr;
}

// The column whose request path is the longest prefix of `field` (none when no column maps).
std::optional<RecipeColumn> column_for(const std::string& field, const OptionRegistry& registry) {
  std::optional<RecipeColumn> best;
  std::size_t best_length = 0;
  for (RecipeColumn& column : recipe_columns(registry)) {
    if (column.pointer.empty()) continue;
    const std::string path = dotted(column.pointer);
    const bool prefix =
        field.rfind(path, 0) == 0 &&
        (field.size() == path.size() || field[path.size()] == '.' || field[path.size()] == '[');
    if (prefix && path.size() > best_length) {
      best = std::move(column);
      best_length = path.size();
    }
  }
  return best;
}

}  // namespace

std::vector<RecipeColumn> recipe_columns(const OptionRegistry& registry) {
  std::vector<RecipeColumn> columns(kRequestColumns.begin(), kRequestColumns.end() - 1);
  const std::vector<RecipeColumn>& motion = motion_recipe_columns();
  columns.insert(columns.end(), motion.begin(), motion.end());
  columns.push_back(kRequestColumns.back());  // strategy
  for (const OptionSpec& o : registry.options()) {
    std::string pointer = "/options/";
    std::string name(o.name);
    if (!o.group.empty()) {
      pointer += std::string(o.group) + "/";
      if (const OptionGroup* group = registry.group(o.group)) {
        name = std::string(group->column_prefix) + name;
      }
    }
    columns.push_back(RecipeColumn{name, pointer + std::string(o.name), cell_kind(o.kind)});
  }
  return columns;
}

std::string recipe_column_names(const OptionRegistry& registry) {
  return comma_list(recipe_columns(registry));
}

RecipeHeader::RecipeHeader(const std::vector<std::string>& names, const OptionRegistry& registry) {
  const std::vector<RecipeColumn> known = recipe_columns(registry);
  for (std::size_t c = 0; c < names.size(); ++c) {
    const auto it = std::find_if(known.begin(), known.end(),
                                 [&](const RecipeColumn& k) { return k.name == names[c]; });
    if (it == known.end()) {
      throw RecipeTableError("recipe table: unknown column " + quote_text(names[c]) + " (column " +
                             std::to_string(c + 1) +
                             " of the header); allowed: " + comma_list(known));
    }
    if (std::any_of(columns_.begin(), columns_.end(),
                    [&](const RecipeColumn& k) { return k.name == it->name; })) {
      throw RecipeTableError("recipe table: column " + quote_text(names[c]) + " appears twice");
    }
    if (it->kind == CellKind::kId) id_index_ = c;
    columns_.push_back(*it);
  }
  auto has = [&](std::string_view name) {
    return std::any_of(columns_.begin(), columns_.end(),
                       [&](const RecipeColumn& k) { return k.name == name; });
  };
  const bool rectangular = rectangular_table(has);
  for (std::string_view name : kRequired) {
    // A table with motion_type may move its rows along arcs and paths (their length the stroke).
    if (name == "stroke_mm" && has("motion_type")) continue;
    if (!has(name) && !(rectangular && name == "radius_mm")) {
      // A rectangular table names its sides instead of a radius.
      const std::string container = rectangular ? "length_mm, width_mm" : "radius_mm";
      // A table with neither a radius nor sides may be of rectangular containers.
      const std::string or_sides =
          name == "radius_mm" ? " (or length_mm and width_mm for rectangular containers)" : "";
      throw RecipeTableError("recipe table: missing column " + quote_text(name) + or_sides +
                             "; required: " + "recipe_id, " + container +
                             ", fill_height_mm, fluid (or density_kg_m3 and " +
                             "viscosity_pa_s), stroke_mm, motion_time_s, strategy");
    }
  }
  if (!has("fluid") && !(has("density_kg_m3") && has("viscosity_pa_s"))) {
    throw RecipeTableError(
        "recipe table: missing column \"fluid\" (or both density_kg_m3 and viscosity_pa_s)");
  }
}

RecipeRequest RecipeHeader::request(const std::vector<std::string>& cells) const {
  std::string named_fluid;   // "fluid = ..." when given
  std::string custom_fluid;  // "density_kg_m3 = ..." when given
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].empty()) continue;
    const std::string given = columns_[c].name + " = " + quote_text(cells[c]);
    if (columns_[c].name == "fluid") named_fluid = given;
    if (columns_[c].pointer.starts_with("/format/fluid/") && custom_fluid.empty()) {
      custom_fluid = given;
    }
  }
  if (!named_fluid.empty() && !custom_fluid.empty()) {
    throw CellError{"fluid", named_fluid + " and " + custom_fluid +
                                 ": give either fluid or density_kg_m3 and viscosity_pa_s, "
                                 "not both"};
  }
  json request = json::object();
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const RecipeColumn& column = columns_[c];
    if (column.kind == CellKind::kId || cells[c].empty()) continue;  // empty: the default
    request[json::json_pointer(column.pointer)] = cell_value(column, cells[c]);
  }
  // A row with sides and no radius is a rectangular container without saying so.
  const json::json_pointer container("/format/container");
  if (request.contains(container)) {
    json& c = request[container];
    if (!c.contains("shape") && !c.contains("radius_mm") &&
        (c.contains("length_mm") || c.contains("width_mm"))) {
      c["shape"] = "rectangular";
    }
  }
  complete_row_motion(request);
  return RecipeRequest(std::move(request));
}

ReadRecipe RecipeHeader::recipe(std::size_t number, const std::vector<std::string>& cells) const {
  ReadRecipe recipe;
  try {
    if (id_index_ < cells.size()) {
      check_recipe_id(cells[id_index_]);
      recipe.recipe_id = cells[id_index_];
    }
    if (cells.size() != size()) {
      throw ApiError(ErrorCode::kInvalidValue, "",
                     "row " + std::to_string(number) + " has " + std::to_string(cells.size()) +
                         " cells, the header has " + std::to_string(size()));
    }
    recipe.request = request(cells);
  } catch (const ApiError& e) {
    recipe.error = e;
  } catch (const CellError& e) {
    recipe.error = ApiError(ErrorCode::kInvalidValue, e.column, e.message);
  }
  return recipe;
}

void check_recipe_id(std::string_view recipe_id) {
  refuse_control_characters("recipe_id", recipe_id);
}

namespace {

ReadRecipe json_recipe(json value) {
  ReadRecipe recipe;
  if (value.is_object()) {
    if (const auto id = value.find("recipe_id"); id != value.end()) {
      std::string text = id->is_string() ? id->get<std::string>() : id->dump();
      value.erase(id);
      try {
        check_recipe_id(text);
      } catch (const ApiError& e) {
        recipe.error = e;
        return recipe;
      }
      recipe.recipe_id = std::move(text);
    }
  }
  recipe.request = RecipeRequest(std::move(value));
  return recipe;
}

}  // namespace

ReadRecipe json_line_recipe(std::string_view line, std::size_t line_number) {
  try {
    return json_recipe(parse_json_body(line));
  } catch (const ApiError& e) {
    ReadRecipe recipe;
    recipe.error =
        ApiError(e.code(), e.field(), "line " + std::to_string(line_number) + ": " + e.what());
    return recipe;
  }
}

std::vector<ReadRecipe> json_document_recipes(std::string_view text) {
  json document;
  try {
    document = parse_json_body(text);
  } catch (const ApiError& e) {
    throw RecipeTableError(std::string("recipe table: ") + e.what());
  }
  if (document.is_object() && document.contains("requests")) document = document["requests"];
  if (!document.is_array()) {
    throw RecipeTableError(
        "recipe table: a .json table is an array of plan requests or {\"requests\": [...]}");
  }
  std::vector<ReadRecipe> recipes;
  recipes.reserve(document.size());
  for (json& value : document) recipes.push_back(json_recipe(std::move(value)));
  return recipes;
}

BatchItem batch_item_of(const RecipeRequest& request, double budget) {
  return read_batch_item(request.body(), budget);
}

MinTimeRequest min_time_request_of(const RecipeRequest& request, double budget) {
  return parse_min_time_request(min_time_body_from_recipe(request.body()), budget);
}

std::string min_time_body_text(const RecipeRequest& request) {
  return dump_json(min_time_body_from_recipe(request.body()));
}

std::string column_of_field(const std::string& field, const OptionRegistry& registry) {
  const std::optional<RecipeColumn> column = column_for(field, registry);
  return column ? column->name : field;
}

namespace {

// Where `path` occurs in `text` from `from` as a whole member name, outside a value the text
// echoes in quotes; npos when nowhere.
std::size_t find_path_in(const std::string& text, const std::string& path, std::size_t from) {
  auto member_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.';
  };
  for (std::size_t at = text.find(path, from); at != std::string::npos;
       at = text.find(path, at + path.size())) {
    const std::size_t end = at + path.size();
    const bool whole =
        (at == 0 || !member_char(text[at - 1])) && (end == text.size() || !member_char(text[end]));
    if (whole && !inside_json_string(text, at)) return at;
  }
  return std::string::npos;
}

}  // namespace

// (The field is not needed: a refusal of two members names their group, "options", which has no
// column, while the members it names do.)
std::string in_column_terms(const std::string& /*field*/, const std::string& message,
                            const OptionRegistry& registry) {
  // Every request path the message names that a column maps, not only its first: a refusal
  // naming two members ("... and ... are both given", "give ... = ...") reads in one language.
  // Longest paths first, each replaced only as a whole member name.
  std::vector<RecipeColumn> columns = recipe_columns(registry);
  std::sort(columns.begin(), columns.end(), [](const RecipeColumn& a, const RecipeColumn& b) {
    return a.pointer.size() > b.pointer.size();
  });
  std::string out = message;
  for (const RecipeColumn& column : columns) {
    if (column.pointer.empty()) continue;
    const std::string path = dotted(column.pointer);
    for (std::size_t at = find_path_in(out, path, 0); at != std::string::npos;
         at = find_path_in(out, path, at + column.name.size())) {
      out.replace(at, path.size(), column.name);
    }
  }
  return out;
}

std::string error_columns(const std::string& field, const std::string& message,
                          const OptionRegistry& registry) {
  if (const std::optional<RecipeColumn> own = column_for(field, registry)) {
    return std::string(own->name);
  }
  std::vector<std::pair<std::size_t, std::string>> named;  // where the message names each
  for (const RecipeColumn& column : recipe_columns(registry)) {
    if (column.pointer.empty()) continue;
    const std::string path = dotted(column.pointer);
    if (!field.empty() && path.rfind(field + ".", 0) != 0) continue;
    // A member is named by its path, or within its group's sentence by its path in the group
    // ("options.min_ramp_s = ... and plateau_min_s = ...").
    std::size_t at = find_path_in(message, path, 0);
    if (at == std::string::npos && !field.empty()) {
      at = find_path_in(message, path.substr(field.size() + 1), 0);
    }
    if (at != std::string::npos) named.emplace_back(at, std::string(column.name));
  }
  if (named.empty()) return field;
  std::sort(named.begin(), named.end());
  std::string out;
  for (const auto& [at, name] : named) {
    if (out.find(name) != std::string::npos) continue;
    out += (out.empty() ? "" : ";") + name;
  }
  return out;
}

// ---- plan tables -------------------------------------------------------------------------------

namespace {

constexpr std::array kPlanColumns{
    PlanColumn{"row", "/row"},
    PlanColumn{"recipe_id", "/recipe_id"},
    PlanColumn{"status", "/status"},
    PlanColumn{"key", "/key"},
    PlanColumn{"cached", "/cached"},
    PlanColumn{"strategy", "/strategy"},
    PlanColumn{"law_type", "/law_type"},
    PlanColumn{"T1_s", "/durations_s/0"},
    PlanColumn{"T2_s", "/durations_s/1"},
    PlanColumn{"T3_s", "/durations_s/2"},
    PlanColumn{"T4_s", "/durations_s/3"},
    PlanColumn{"T5_s", "/durations_s/4"},
    PlanColumn{"T6_s", "/durations_s/5"},
    PlanColumn{"T7_s", "/durations_s/6"},
    PlanColumn{"A_m_s2", "/kinematics/a_max"},
    PlanColumn{"B_m_s2", "/kinematics/a_min"},
    PlanColumn{"v_peak_m_s", "/kinematics/v_peak"},
    PlanColumn{"j_peak_m_s3", "/kinematics/j_peak"},
    PlanColumn{"f1_hz", "/f1_hz"},
    PlanColumn{"f1_length_hz", "/f1_length_hz"},
    PlanColumn{"f1_width_hz", "/f1_width_hz"},
    PlanColumn{"eta_motion_nonlinear_mm", "/prediction/nonlinear/eta_motion_mm"},
    PlanColumn{"eta_rest_nonlinear_mm", "/prediction/nonlinear/eta_rest_mm"},
    PlanColumn{"eta_motion_linear_mm", "/prediction/linear/eta_motion_mm"},
    PlanColumn{"eta_rest_linear_mm", "/prediction/linear/eta_rest_mm"},
    PlanColumn{"baseline_eta_motion_nonlinear_mm", "/baseline/nonlinear/eta_motion_mm"},
    PlanColumn{"baseline_eta_rest_nonlinear_mm", "/baseline/nonlinear/eta_rest_mm"},
    PlanColumn{"reduction_motion_pct", "/reduction_pct/motion"},
    PlanColumn{"reduction_rest_pct", "/reduction_pct/rest"},
    PlanColumn{"solve_ms", "/solve_ms"},
    PlanColumn{"message", "/message"},
    PlanColumn{"error_field", "/error_field"},
    PlanColumn{"version", "/version"},
    PlanColumn{"holds_from_pct", "/holds_from_pct"},
    PlanColumn{"holds_to_pct", "/holds_to_pct"},
    PlanColumn{"worst_eta_rest_mm", "/worst_eta_rest_mm"},
    PlanColumn{"container_shape", "/container_shape"},
    PlanColumn{"length_mm", "/length_mm"},
    PlanColumn{"width_mm", "/width_mm"},
    PlanColumn{"orientation_deg", "/orientation_deg"},
    PlanColumn{"motion_type", "/motion_type"},
    PlanColumn{"arc_radius_mm", "/arc_radius_mm"},
    PlanColumn{"arc_angle_deg", "/arc_angle_deg"},
    PlanColumn{"container_turns", "/container_turns"},
    PlanColumn{"path_length_mm", "/path_length_mm"},
    PlanColumn{"path_json", "/path_json"},
    PlanColumn{"warnings", "/warnings"},
};

/// object[key], null when absent (or when `object` is not an object).
json value_or_null(const json& object, std::string_view key) {
  const json* value = find_member(object, key);
  return value == nullptr ? json(nullptr) : *value;
}

/// object[outer][inner], null when either is absent.
json nested_or_null(const json& object, std::string_view outer, std::string_view inner) {
  const json* value = find_member(object, outer);
  return value == nullptr ? json(nullptr) : value_or_null(*value, inner);
}

/// The codes of the plan's warnings (the compact view's), "; "-separated; null when it has
/// none, so a row that reads `optimal` with a warning shows it in the table.
json warning_findings(const json& plan) {
  std::string out;
  for (const std::string& code : plan_warning_codes(plan)) {
    out += (out.empty() ? "" : "; ") + code;
  }
  return out.empty() ? json(nullptr) : json(out);
}

}  // namespace

std::span<const PlanColumn> plan_columns() {
  return kPlanColumns;
}

std::string plan_column_names() {
  std::string out;
  for (const PlanColumn& column : kPlanColumns) {
    if (!out.empty()) out += ',';
    out += column.name;
  }
  return out;
}

json plan_row_figures(const json& plan) {
  json row = json::object();
  for (std::string_view key : {"status", "key", "version", "strategy", "message", "durations_s",
                               "kinematics", "prediction", "baseline", "reduction_pct"}) {
    row[std::string(key)] = value_or_null(plan, key);
  }
  row["law_type"] = nested_or_null(plan, "law", "type");
  const json f_hz = nested_or_null(plan, "model", "f_hz");
  row["f1_hz"] = f_hz.is_array() && !f_hz.empty() ? f_hz[0] : json(nullptr);
  // A rectangular tank's first frequency along each side (f1_hz is its most excited
  // direction's): a turned tank sloshes at both. Null for a cylinder.
  const json rectangular = nested_or_null(plan, "model", "rectangular");
  for (const char* side : {"length", "width"}) {
    const json side_f = nested_or_null(rectangular, side, "f_hz");
    row[std::string("f1_") + side + "_hz"] =
        side_f.is_array() && !side_f.empty() ? side_f[0] : json(nullptr);
  }
  // Which container the row planned: a table of tanks reads back each one's sides and turn
  // (empty for a cylinder, whose radius stays its input row's).
  const json container = nested_or_null(plan, "format", "container");
  row["container_shape"] =
      container.is_object() ? container.value("shape", json("cylinder")) : json(nullptr);
  for (const char* member : {"length_mm", "width_mm", "orientation_deg"}) {
    row[member] = value_or_null(container, member);
  }
  row["solve_ms"] = nested_or_null(plan, "solver", "solve_ms");
  row.update(robustness_row_figures(find_member(plan, "robustness")));
  row.update(motion_row_figures(plan));
  row["warnings"] = warning_findings(plan);
  return row;
}

json error_row_figures(const json& failure, bool csv) {
  json error = failure;
  const json field = error["field"];  // the row's error always names its field, null when none
  std::string where = field.is_string() ? field.get<std::string>() : "";
  json message = value_or_null(error, "message");
  if (csv && !where.empty()) {
    const std::string text = message.is_string() ? message.get<std::string>() : std::string();
    if (message.is_string()) message = in_column_terms(where, text);
    where = error_columns(where, text);
  }
  return {{"status", "error"},
          {"message", std::move(message)},
          {"error", std::move(error)},
          {"error_field", where.empty() ? json(nullptr) : json(where)}};
}

}  // namespace slosh::api
