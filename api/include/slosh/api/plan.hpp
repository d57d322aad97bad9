#pragma once
// POST /v1/plans and `slosh plan`: a format + strategy + options -> the plan of SPEC §6-§7.

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "slosh/version.hpp"

namespace slosh::api {

/// Allowed ranges of the plan options (user units), shared by the parser and the OpenAPI
/// document. min_ramp_s (0.001 to T/4) and plateau_min_s (0 to T) depend on the format.
namespace plan_ranges {
inline const Range kPNotch{0.0, 1.0, "", true, true};
inline const Range kWeight{0.0, 1e6, ""};
inline const Range kBand{0.0, 1.0, "", true, true};
inline const Range kTolRel{0.0, 10.0, "", true};
inline const Range kEtaMm{0.0, 10000.0, "mm", true};
inline const Range kRestTime{0.0, 60.0, "s", true};
inline const Range kAMax{0.0, 1000.0, "m/s^2", true};
inline const Range kVMax{0.0, 100.0, "m/s", true};
inline const Range kJMax{0.0, 1e6, "m/s^3", true};
inline const Range kTimeLimit{0.0, 600.0, "s", true};
inline const Range kResidual{0.0, 1.0, "", false, true};
inline const Range kIirTau{1.0, 1000.0, "1/s"};
/// iir_sample_period_s: also <= format.motion_time_s / kIirMinSamples.
inline const Range kIirSamplePeriod{1e-4, 0.01, "s"};
constexpr int kMaxBandPoints = 2001;
/// options.uncertainty: the frequency error (SPEC §10, core kMaxOmegaError) and the viscosities.
inline const Range kOmegaErrorPct{0.0, 50.0, "%"};
inline const Range kViscosityRangePaS{0.0, 1e6, "Pa·s"};
}  // namespace plan_ranges

/// A validated plan request.
struct PlanRequest {
  Format format;
  Strategy strategy{Strategy::kAuto};
  PlanOptions options;
  /// When set, the response carries time series of the planned law at this period [s].
  std::optional<double> sample_period;
  /// format.motion of type arc or path: the law moves along it (format.stroke is its length).
  /// Unset for stroke_mm and for a line motion, which plan as they always have.
  std::optional<SpatialMotion> motion;
};

/// Validates a parsed plan request; throws ApiError(kInvalidValue) naming the field, the value
/// and the allowed range.
/// The options come from `registry` (the built-in one unless a test extends it).
[[nodiscard]] PlanRequest parse_plan_request(
    const nlohmann::json& body, const OptionRegistry& registry = plan_option_registry());

/// The recipe key: hex SHA-256 (first 32 digits) of the canonical JSON of the normalised request
/// (SI values of the format and every option with its default filled in; names, units, field
/// order and the time budget do not enter) and of the slosh version that plans it (`version`,
/// slosh::kVersion unless a test asks for another): identical recipes share one key, and a plan
/// of another version never answers it.
[[nodiscard]] std::string recipe_key(const PlanRequest& request,
                                     const OptionRegistry& registry = plan_option_registry(),
                                     std::string_view version = kVersion);

/// First 32 hex digits of the SHA-256 of `text`: the key of a canonical JSON text (recipe_key,
/// min_time_key).
[[nodiscard]] std::string sha256_key(const std::string& text);

/// The canonical JSON the key is computed from: "format" (SI), "strategy", "options" (the
/// registry's recipe() of the options the request's strategy reads, or with `read_by` those one
/// of these strategies reads), "version" (of the planner's numerics) and "slosh_version"
/// (`version`).
[[nodiscard]] nlohmann::json canonical_recipe(
    const PlanRequest& request, const OptionRegistry& registry = plan_option_registry(),
    std::string_view version = kVersion, std::span<const Strategy> read_by = {});

/// Plans a validated request; throws ApiError(kInvalidValue, "format") when the planner refuses
/// inputs that passed the API's ranges.
[[nodiscard]] PlanResult plan_request(const PlanRequest& request);

/// Runs a validated request and renders the plan response of SPEC §7 (with the series when the
/// request asks for them).
[[nodiscard]] nlohmann::json run_plan(const PlanRequest& request);

/// Renders a plan result without series: what the service caches, whatever series the request
/// asks for.
[[nodiscard]] nlohmann::json plan_json(const PlanRequest& request, const PlanResult& result);

/// Adds the "series" of the plan's law at request.sample_period (nothing when the request asks
/// for none or the plan has no law). A plan from plan_json of the same recipe.
void add_series(const PlanRequest& request, nlohmann::json& plan);

}  // namespace slosh::api
