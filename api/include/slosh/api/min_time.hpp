#pragma once
// POST /v1/min-time and `slosh min-time`: a format without motion time, the sloshing and machine
// limits and the strategies to try -> each strategy's minimum motion time (SPEC §9).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/version.hpp"

namespace slosh::api {

/// Allowed ranges of the min-time request members (user units).
namespace min_time_ranges {
inline const Range kMotionTimeMax{0.05, 60.0, "s"};
inline const Range kEtaMm{0.0, 10000.0, "mm", true};
inline const Range kMarginMm{0.0, 10000.0, "mm"};
inline const Range kScanStep{0.001, 1.0, "s"};
constexpr int kMaxPlansLo = 3;
constexpr int kMaxPlansHi = 1000;
inline const Range kCurveFactor{1.0, 10.0, ""};
inline const Range kRefineExcess{1.0, 1000.0, ""};
}  // namespace min_time_ranges

/// A validated min-time request.
struct MinTimeRequest {
  /// The format; its motion_time is motion_time_max (unused by the search).
  Format format;
  /// The strategies in request order (default: every strategy but iir and auto).
  std::vector<Strategy> strategies;
  /// The options; options.path is the motion's path when `motion` is set.
  MinTimeOptions options;
  /// format.motion of type arc or path: the search plans along it (format.stroke is its length).
  /// Unset for stroke_mm and a line motion, which search as they always have.
  std::optional<SpatialMotion> motion;
};

/// The strategies searched when the request names none: every strategy but iir (and auto).
[[nodiscard]] std::vector<Strategy> default_min_time_strategies();

/// Validates a parsed min-time request; throws ApiError(kInvalidValue) naming the field, the
/// value and the allowed range. `budget` caps options.time_limit_s (its default when absent).
[[nodiscard]] MinTimeRequest parse_min_time_request(const nlohmann::json& body, double budget);

/// The cache key: first 32 hex digits of the SHA-256 of the canonical JSON of the normalised
/// request (SI values, defaults filled in, the time budget left out) and of the slosh version that
/// searches (`version`, as recipe_key).
[[nodiscard]] std::string min_time_key(const MinTimeRequest& request,
                                       std::string_view version = kVersion);

/// The response body of a request whose strategies have been searched (results in request
/// order): each strategy's T_min, status, message, plan at T_min, curve; the headline.
[[nodiscard]] nlohmann::json min_time_json(const MinTimeRequest& request,
                                           const std::vector<MinTimeResult>& results,
                                           const std::string& key);

/// The min-time request of a recipe-table row (`slosh batch --mode min_time`): its plan request
/// with format.motion_time_s as motion_time_max_s, options.eta_rest_max_mm and
/// options.eta_motion_max_mm as the search's limits, and no strategy (every strategy but iir is
/// searched); everything else as written, to be validated by parse_min_time_request.
[[nodiscard]] nlohmann::json min_time_body_from_recipe(const nlohmann::json& plan_request);

/// The figures of a min-time answer in a recipe table (`slosh batch --mode min_time`): key,
/// t_min_<strategy>_s, winner, winner_t_min_s, baseline_t_min_s, gain_pct, gain_cycles_per_min,
/// and message (the strategies whose search was not optimal; null when every one was).
/// `answer` is a response body of POST /v1/min-time or a stored answer (stored_min_time), so a
/// local and a remote batch derive their rows alike; throws std::invalid_argument when it is not
/// one.
[[nodiscard]] nlohmann::json min_time_row_figures(std::string_view answer);

/// Throws ApiError(kInvalidValue, "format") when a strategy's search refused its inputs.
void check_min_time_inputs(const MinTimeRequest& request,
                           const std::vector<MinTimeResult>& results);

/// Whether a min-time answer depends only on its request (every search optimal, acceptable or
/// infeasible; a time-limited one depends on the load).
[[nodiscard]] bool is_min_time_cacheable(const std::vector<MinTimeResult>& results);

/// The response as the service keeps it: without the per-reply member `cached`.
[[nodiscard]] std::string stored_min_time(const MinTimeRequest& request,
                                          const std::vector<MinTimeResult>& results,
                                          const std::string& key);

/// The reply body of a stored min-time answer, with `cached` set.
[[nodiscard]] std::string render_min_time_reply(std::string_view stored, bool cached);

/// Runs every strategy of a validated request one after the other and renders the response.
[[nodiscard]] nlohmann::json run_min_time(const MinTimeRequest& request);

}  // namespace slosh::api
