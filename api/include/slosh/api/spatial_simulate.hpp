#pragma once
// POST /v1/simulate with format.motion (SPEC §14): both planar models' peaks over the wall.

#include <istream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/api/motion_json.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace slosh::api {

/// {"eta_motion_mm", "eta_rest_mm", "t_motion_s", "t_rest_s", "direction_motion_deg",
/// "direction_rest_deg"}: one planar model's peaks, the directions the wall angles of the peaks
/// (world frame, from +x, counter-clockwise).
[[nodiscard]] nlohmann::json planar_peaks_json(const PlanarPeaks& peaks);

/// A validated simulate request with format.motion.
struct SpatialSimulateRequest {
  /// The format (its stroke the path's length; for a trajectory, placeholders for stroke and
  /// motion time and a placeholder law, none of them used), the law and the options.
  SimulateRequest base;
  SpatialMotion motion;
};

/// Validates a simulate request whose format.motion is given; throws ApiError naming the member.
[[nodiscard]] SpatialSimulateRequest parse_spatial_simulate_request(const nlohmann::json& body);

/// Runs a validated request with a motion and renders the response {"format" (with its
/// motion), "law"? (not for a trajectory), "motion", "model", "prediction", "rest_time_s",
/// "series"? (with sample_period_s: spatial_series.hpp), "warnings"}. Throws ApiError naming
/// format.motion.t_s[i] when a trajectory is sampled too coarsely for the first mode.
[[nodiscard]] nlohmann::json run_spatial_simulate(const SpatialSimulateRequest& request);

/// The POST /v1/simulate answer to a parsed body: the planar models with format.motion, else
/// run_simulate (the straight line, unchanged).
[[nodiscard]] nlohmann::json simulate_response(const nlohmann::json& body);

/// `slosh simulate --trajectory FILE.csv`: the simulate reply (pretty JSON) to `request` (its
/// format without stroke_mm, motion_time_s and motion; no law) with format.motion the trajectory
/// read from `csv` (trajectory_csv.hpp); `source` names the file in messages. ApiError naming
/// --trajectory for an unreadable CSV or a request that gives a motion too.
[[nodiscard]] std::string simulate_trajectory_reply(std::string_view request, std::istream& csv,
                                                    const std::string& source);

}  // namespace slosh::api
