#pragma once
// POST /v1/simulate and `slosh simulate`: any supported law on a format -> eta peaks and series.

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/api/law_json.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/response/simulation.hpp"

namespace slosh::api {

/// A validated simulate request.
struct SimulateRequest {
  Format format;
  LawType law_type{LawType::kSevenSegment};
  std::optional<Durations> durations;  ///< for kSevenSegment
  MotionLaw law;                       ///< the law, whatever its type
  SimulationOptions options;
  double min_ramp{kDefaultMinRamp};
};

/// Deepest nesting of arrays and objects a request body may have (a SPEC request nests 4 deep).
constexpr int kMaxJsonDepth{64};

/// Parses the request body text; throws ApiError (400 malformed JSON, also when nested deeper than
/// kMaxJsonDepth, 422 invalid value).
[[nodiscard]] nlohmann::json parse_json_body(std::string_view body);

/// Validates a parsed simulate request; throws ApiError(kInvalidValue) naming the field.
[[nodiscard]] SimulateRequest parse_simulate_request(const nlohmann::json& body);

/// The 7-segment law of a validated request, when its law is one (durations or uniform).
[[nodiscard]] std::optional<SevenSegmentLaw> seven_segment_law(const SimulateRequest& request);

/// The law of a validated request.
[[nodiscard]] inline const MotionLaw& build_law(const SimulateRequest& request) {
  return request.law;
}

/// Runs a validated request and renders the response
/// {"law", "kinematics", "model", "prediction", "series"?, "warnings"}.
[[nodiscard]] nlohmann::json run_simulate(const SimulateRequest& request);

/// Optional top-level "sample_period_s" of a request whose series spans `span` seconds; throws
/// ApiError naming the field when out of range or when it would give too many samples.
[[nodiscard]] std::optional<double> parse_sample_period(const nlohmann::json& body, double span);

/// {"eta_motion_mm", "eta_rest_mm", "t_motion_s", "t_rest_s"} of one model's peaks.
[[nodiscard]] nlohmann::json peaks_json(const SloshPeaks& peaks);

/// {"nonlinear", "linear"} peaks: the prediction block of simulations, plans and candidates.
[[nodiscard]] nlohmann::json prediction_json(const SloshPeaks& nonlinear, const SloshPeaks& linear);

/// The prediction block of a simulation.
[[nodiscard]] nlohmann::json prediction_json(const SimulationResult& result);

}  // namespace slosh::api
