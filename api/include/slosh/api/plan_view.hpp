#pragma once
// The views of a plan (SPEC §11): the full plan of SPEC §6-§7, or the compact plan a controller
// needs (`?view=compact` on the plan endpoints, `"view": "compact"` in a batch body, `--view
// compact` on the CLI). The compact plan is derived from the full plan: the view changes neither
// the recipe key nor the cache entry.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace slosh::api {

enum class PlanView {
  kFull,     ///< "full": the whole plan (the default)
  kCompact,  ///< "compact": key, status, strategy, law, kinematics, predictions, warnings, version,
             ///< robustness (interval and worst eta)
};

/// "full", "compact".
[[nodiscard]] std::vector<std::string> plan_view_names();

/// The view named `value`; throws ApiError(kInvalidValue, "view"): view = "value" is not allowed:
/// one of "full", "compact".
[[nodiscard]] PlanView parse_plan_view(std::string_view value);

/// The view of the `view` query parameter given `values` (one per occurrence): full when absent,
/// a 422 naming the field when it is given more than once or names no view.
[[nodiscard]] PlanView parse_view_query(const std::vector<std::string>& values);

/// The view of a batch: the query's (`query_values`, as parse_view_query) and the body's "view"
/// member (`body_view`, nullopt when absent or null); a 422 naming "view" when both are given and
/// differ.
[[nodiscard]] PlanView batch_view(const std::vector<std::string>& query_values,
                                  const std::optional<nlohmann::json>& body_view);

/// Throws ApiError(kInvalidValue, "sample_period_s") when a compact plan is asked with series (a
/// compact plan carries none).
void require_no_series(PlanView view, const std::optional<double>& sample_period);

/// Largest compact plan of a 7-segment law, as the service sends it (unindented JSON) [bytes].
constexpr std::size_t kCompactPlanMaxBytes{1024};

/// The compact plan of a plan reply (a plan JSON with `cached`):
///   view        "compact"
///   key, cached, version, strategy, status   as in the plan
///   law         the plan's law (a 7-segment law: type and durations_s) with the move it makes:
///               stroke_mm and motion_time_s of the format
///   kinematics  a_max (A), a_min (B), v_peak, j_peak
///   prediction  eta_motion_mm and eta_rest_mm of the nonlinear and the linear model
///   warnings    the finding of each warning (its text up to the first ": "; the explanation
///               after it is in the full plan)
///   move_absolute  as in the plan, when it has one
///   robustness  when the plan has a report, on the nonlinear model, in hundredths: holds_pct,
///               the delta interval [%] where the limits hold (null when not at delta = 0), and
///               worst_mm, the largest eta_motion and eta_rest over the sweep [mm]
/// The message (prose that the status, predictions and warnings already carry in numbers) is not
/// in it: the full plan of the same key has it. For a 7-segment law the compact plan is under
/// kCompactPlanMaxBytes (17 numbers, five warnings at most); a general law (shaper, iir, fir_chain
/// without (14)) is as long as its pieces.
[[nodiscard]] nlohmann::json compact_plan(const nlohmann::json& plan);

/// compact_plan of a plan reply's text, as text.
[[nodiscard]] std::string compact_plan_text(std::string_view plan);

/// The codes of a plan's warnings, each once, in order: its warning_codes (the kinds of
/// warning_kinds()); for a plan stored without them, each sentence's finding (its text up to
/// the first ": ").
[[nodiscard]] std::vector<std::string> plan_warning_codes(const nlohmann::json& plan);

}  // namespace slosh::api
