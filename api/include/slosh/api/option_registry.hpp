#pragma once
// The plan options, each declared once: its name, kind, range, names, default, unit and one line
// of documentation, and how it reads and writes PlanOptions. The registry drives the request
// parser (parse_plan_request), the recipe key (canonical_recipe), the OpenAPI option schemas and
// the columns of CSV recipe tables. Adding an option = one entry here + the PlanOptions field +
// its use in core.

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh::api {

/// How an option is spelled in JSON (and in a CSV cell).
enum class OptionKind {
  kNumber,          ///< a number within `range`
  kOptionalNumber,  ///< a number within `range`; unset (null in the recipe) by default
  kInteger,         ///< an integer within `range`
  kBool,            ///< true or false
  kEnum,            ///< one of `names`
  kNumberArray,     ///< exactly `size` numbers, each within `range`
  kDamping,         ///< a correlation name or {"zeta": z} (a number in CSV cells)
};

/// One plan option. Values pass between the parser, the accessors and the recipe as JSON in SI
/// units (user value x `scale`): a number, an integer, a bool, a name, an array, or null (unset).
struct OptionSpec {
  std::string_view name;  ///< member of "options" (or of options.<group>), e.g. "eta_rest_max_mm"
  std::string_view
      recipe_name;  ///< member of the canonical recipe's options, e.g. "eta_rest_max_m"
  OptionKind kind{OptionKind::kNumber};
  /// Allowed values in user units (for kInteger its bounds). The widest range when `range_for`
  /// narrows it for a format: the OpenAPI document states this one.
  Range range{0.0, 0.0, ""};
  /// The allowed range for a format, when it depends on it (min_ramp_s, plateau_min_s, ...).
  std::function<Range(const Format&)> range_for;
  /// Appended to every message about the option (e.g. where a format-dependent bound comes from).
  std::string message_note;
  /// Replaces range.describe() in the OpenAPI description (a format-dependent range in words).
  std::string allowed_text;
  std::vector<std::string> names;  ///< kEnum: the allowed names (EnumNames order)
  std::size_t size{0};             ///< kNumberArray: number of items
  std::string item_doc;            ///< kNumberArray: description of one item (empty: none)
  double scale{1.0};               ///< user unit -> SI (mm -> m: 1e-3)
  std::string_view group;          ///< "" or the object of "options" it sits in ("limits")
  std::string doc;                 ///< one line, without unit or range (the schema adds them)
  /// The current value in SI (null when unset).
  std::function<nlohmann::json(const PlanOptions&)> get;
  /// Stores a validated value in SI.
  std::function<void(PlanOptions&, const nlohmann::json&)> set;
  /// Further check of a validated value in user units; throws ApiError (e.g. weights not all 0).
  std::function<void(const nlohmann::json&)> check;
  /// Parse rank: lower first, then registry order. The model options (modes, alpha, damping)
  /// are read first, as simulate reads them, so a request's first error stays the same.
  int parse_rank{0};
  /// Keyed only when its value differs from the default: an option added after plans were keyed
  /// (drive_profile) leaves the keys of the requests without it as they were.
  bool keyed_when_set{false};
  /// When set, keyed only when it returns true as well (sample_points: only with a range).
  std::function<bool(const PlanOptions&)> keyed_only_if;
  /// The strategies whose plans read the option; empty: every strategy. A strategy that does
  /// not read it leaves it out of its recipe key, so that requests differing only there share
  /// one plan (sample_points: only time_domain and auto, which runs it, read it).
  std::vector<Strategy> read_by;

  /// Whether a plan of one of `strategies` reads the option.
  [[nodiscard]] bool read_by_any(std::span<const Strategy> strategies) const;
};

/// An object of "options" holding several options ("limits", "uncertainty").
struct OptionGroup {
  std::string_view name;         ///< "limits"
  std::string_view schema_name;  ///< OpenAPI component, "MachineLimits"
  std::string doc;
  /// Put before its members' names in CSV recipe columns ("uncertainty_": its fill_height_mm
  /// column is not the format's).
  std::string_view column_prefix{};
};

/// The plan options in the order the API lists them (the allowed keys of "options", the CSV
/// columns). Copy the built-in one and add() to extend it (tests do).
class OptionRegistry {
 public:
  OptionRegistry() = default;
  OptionRegistry(std::vector<OptionSpec> options, std::vector<OptionGroup> groups);

  /// Appends an option (after the others).
  void add(OptionSpec option);

  [[nodiscard]] std::span<const OptionSpec> options() const { return options_; }
  [[nodiscard]] std::span<const OptionGroup> groups() const { return groups_; }
  [[nodiscard]] const OptionSpec* find(std::string_view name) const;
  [[nodiscard]] const OptionGroup* group(std::string_view name) const;

  /// The members "options" accepts, in order: each option outside a group, each group once.
  [[nodiscard]] std::vector<std::string_view> option_keys() const;
  /// The members of options.<group>.
  [[nodiscard]] std::vector<std::string_view> group_keys(std::string_view group) const;

  /// Parses the "options" object of a request for `format` into `options` (absent and null
  /// members keep their value). Messages name the field, the value and the allowed range.
  void parse(const nlohmann::json& json_options, const Format& format, PlanOptions& options) const;

  /// {recipe_name: SI value} of every keyed option (those keyed_when_set only when they differ
  /// from their default, those with keyed_only_if only when it holds, those with read_by only
  /// when one of `strategies` reads them): the "options" of the canonical recipe.
  [[nodiscard]] nlohmann::json recipe(const PlanOptions& options,
                                      std::span<const Strategy> strategies) const;

 private:
  std::vector<OptionSpec> options_;
  std::vector<OptionGroup> groups_;
};

/// The built-in registry of every plan option.
[[nodiscard]] const OptionRegistry& plan_option_registry();

/// The value of one option read from `options` (a JSON object) into user units, validated
/// against `range` (the caller resolves range_for); nullopt when absent or null.
[[nodiscard]] std::optional<nlohmann::json> parse_option(const OptionSpec& option,
                                                         const nlohmann::json& options,
                                                         const std::string& path,
                                                         const Range& range);

/// The OpenAPI schema of one option: type, minimum/maximum (exclusive), enum, items, default
/// (from a default PlanOptions) and the description with unit and allowed range.
[[nodiscard]] nlohmann::json option_schema(const OptionSpec& option);

}  // namespace slosh::api
