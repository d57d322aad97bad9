#pragma once
// Recipe and plan tables (`slosh batch`), the JSON side: the cells of a CSV recipe row -> its plan
// request, a rendered plan -> the figures of its table row. The service only moves bytes (reads
// CSV/JSON text, writes cells).
//
// CSV input columns: recipe_id, the format's (radius_mm, container_height_mm, fill_height_mm,
// fluid or density_kg_m3 + viscosity_pa_s, stroke_mm, motion_time_s), the motion's (motion_type,
// arc_radius_mm, arc_angle_deg, container_turns, path_json: recipe_motion.hpp), strategy, then
// every plan option of the registry by its JSON name (the limits by theirs: a_max, v_max, j_max;
// the members of options.uncertainty prefixed: uncertainty_omega_error_pct,
// uncertainty_fill_height_mm, uncertainty_viscosity_pa_s, uncertainty_sample_points).

#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/option_registry.hpp"

namespace slosh::api {

struct BatchItem;       // slosh/api/service_bodies.hpp
struct MinTimeRequest;  // slosh/api/min_time.hpp

/// How a CSV cell is read.
enum class CellKind {
  kId,          ///< recipe_id: not part of the request
  kText,        ///< as written
  kNumber,      ///< a number (integral values stay integers)
  kBool,        ///< true/false, yes/no, 1/0
  kNumberList,  ///< numbers separated by ';', ',' or spaces
  kDamping,     ///< a number (the explicit zeta) or a correlation name
  kJson,        ///< a JSON value (a path's segments)
};

/// One input column of CSV recipe tables.
struct RecipeColumn {
  std::string name;
  std::string pointer;  ///< JSON pointer into the plan request ("" for recipe_id)
  CellKind kind{CellKind::kText};
};

/// Every input column: recipe_id, the format's, strategy, then one per option of `registry`.
[[nodiscard]] std::vector<RecipeColumn> recipe_columns(
    const OptionRegistry& registry = plan_option_registry());

/// The input column names, comma-separated (for messages and --help).
[[nodiscard]] std::string recipe_column_names(
    const OptionRegistry& registry = plan_option_registry());

/// A table that cannot be read as a whole (a CSV header with unknown, repeated or missing columns;
/// a .json document that is not a list of requests): nothing is planned.
class RecipeTableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A cell that cannot be read: names the column, the text and what is expected.
struct CellError {
  std::string column;
  std::string message;
};

/// The plan request of one recipe as its table gave it: the CSV cells as request members, or the
/// JSON value of a line without its recipe_id. Only api reads it (as a batch item, a min-time
/// request or a member of a POST /v1/plans/batch body), so the service moves it as a value.
class RecipeRequest {
 public:
  RecipeRequest() = default;
  explicit RecipeRequest(nlohmann::json body) : body_(std::move(body)) {}
  /// The request as JSON (null for a recipe whose row could not be read).
  [[nodiscard]] const nlohmann::json& body() const { return body_; }

 private:
  nlohmann::json body_;
};

/// One recipe as a table gave it: its recipe_id and its request, or the error of its row.
struct ReadRecipe {
  /// As given; empty when the row has none or when the id itself is refused (a control
  /// character would cut or forge the lines of the table it is written into).
  std::string recipe_id;
  RecipeRequest request;
  std::optional<ApiError> error;  ///< set when the row cannot be read (then `request` is null)
};

/// The recipe_id of a row, or an ApiError (invalid_value, field "recipe_id") when it holds a
/// control character (U+0000 to U+001F, U+007F): "recipe_id must not hold control characters
/// (NUL, tab, line breaks, ...), got \"a\nb\"".
void check_recipe_id(std::string_view recipe_id);

/// The columns of one CSV recipe table, from its header row.
class RecipeHeader {
 public:
  /// Throws RecipeTableError for an unknown or repeated column or a missing required one.
  explicit RecipeHeader(const std::vector<std::string>& names,
                        const OptionRegistry& registry = plan_option_registry());

  [[nodiscard]] std::size_t size() const { return columns_.size(); }
  /// Index of the recipe_id column.
  [[nodiscard]] std::size_t id_index() const { return id_index_; }

  /// The plan request of a row of size() cells (an empty cell means "the default"); throws
  /// CellError.
  [[nodiscard]] RecipeRequest request(const std::vector<std::string>& cells) const;

  /// The recipe of CSV record `number` (1-based, the header not counted): its recipe_id and
  /// request, or the row's error (a wrong cell count, a refused id, a cell that cannot be read),
  /// never a throw.
  [[nodiscard]] ReadRecipe recipe(std::size_t number, const std::vector<std::string>& cells) const;

 private:
  std::vector<RecipeColumn> columns_;
  std::size_t id_index_{0};
};

/// One line of a JSON-lines table (its recipe_id taken out of the request); `line_number`
/// (1-based) prefixes the message of its error.
[[nodiscard]] ReadRecipe json_line_recipe(std::string_view line, std::size_t line_number);

/// The recipes of a .json table: an array of plan requests or {"requests": [...]}. Throws
/// RecipeTableError.
[[nodiscard]] std::vector<ReadRecipe> json_document_recipes(std::string_view text);

/// A recipe's request as JSON text ("null" for a row that could not be read), and back (a text
/// that is not JSON reads as null), for work items kept outside the process (a Redis stream).
[[nodiscard]] std::string recipe_request_text(const RecipeRequest& request);
[[nodiscard]] RecipeRequest recipe_request_of_text(std::string_view text);
/// A row's error as its envelope's text (empty when the row was read), and back.
[[nodiscard]] std::string recipe_error_text(const std::optional<ApiError>& error);
[[nodiscard]] std::optional<ApiError> recipe_error_of_text(std::string_view text);

/// A recipe's plan request read as a batch item (read_batch_item: never throws).
[[nodiscard]] BatchItem batch_item_of(const RecipeRequest& request, double budget);

/// A recipe's min-time request (`slosh batch --mode min_time`: min_time_body_from_recipe, then
/// parse_min_time_request with `budget`); throws ApiError.
[[nodiscard]] MinTimeRequest min_time_request_of(const RecipeRequest& request, double budget);

/// The body of POST /v1/min-time for a recipe (min_time_body_from_recipe, as JSON text).
[[nodiscard]] std::string min_time_body_text(const RecipeRequest& request);

/// The CSV column a request field path ("format.container.radius_mm", "options.weights[1]")
/// comes from; the path itself when no column maps to it.
[[nodiscard]] std::string column_of_field(const std::string& field,
                                          const OptionRegistry& registry = plan_option_registry());

/// `message` with every request path a column maps replaced by its column
/// ("format.container.radius_mm = -3 is out of range ..." -> "radius_mm = -3 is out of range
/// ..."; "give format.container.shape = ..." -> "give container_shape = ..."), whether or not
/// `field` itself maps to one (a refusal of two members names their group, "options").
[[nodiscard]] std::string in_column_terms(const std::string& field, const std::string& message,
                                          const OptionRegistry& registry = plan_option_registry());

/// The column(s) a CSV row's refusal names in its `error_field`: the column of `field`, or, for
/// a group that has none (a refusal of two members names their group: "options",
/// "options.uncertainty", "format.container"), the columns of its members that `message` (the
/// refusal's own text, in request paths) names by their paths or by their paths in the group, in
/// its order, joined by ';'; `field` itself when it names none.
[[nodiscard]] std::string error_columns(const std::string& field, const std::string& message,
                                        const OptionRegistry& registry = plan_option_registry());

/// One output column of CSV plan tables: a JSON pointer into the row of plan_row_figures.
struct PlanColumn {
  std::string_view name;
  std::string_view pointer;
};

/// Every output column, in order.
[[nodiscard]] std::span<const PlanColumn> plan_columns();

/// The output column names, comma-separated (the CSV header of plan tables).
[[nodiscard]] std::string plan_column_names();

/// The figures of a rendered plan a table row shows: status, key, version, strategy, message,
/// law_type, durations_s, kinematics, f1_hz, prediction, baseline, reduction_pct, solve_ms and
/// of its robustness report holds_from_pct, holds_to_pct and worst_eta_rest_mm (nonlinear model;
/// null without the report), and its motion (motion_row_figures, recipe_motion.hpp).
[[nodiscard]] nlohmann::json plan_row_figures(const nlohmann::json& plan);

/// The row of a recipe that failed: status "error", message, error and error_field; `csv` rows
/// name the column instead of the request path.
[[nodiscard]] nlohmann::json error_row_figures(const nlohmann::json& error, bool csv);

}  // namespace slosh::api
