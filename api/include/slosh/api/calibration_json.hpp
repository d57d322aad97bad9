#pragma once
// POST /v1/calibrations and `slosh calibrate`: the request (a format, the base model options,
// measured moves, fit settings, an optional name) and the response (fitted values with standard
// errors, residuals before/after per move, identifiability notes and the `model` object that
// options.model of plans, simulate, min-time and batch accept).
//
// Request:
//   {"format": {...as a plan...}, "options": {"modes", "damping", "alpha"} (the base model),
//    "moves": [{"name": "...", "motion_time_s": T (default format.motion_time_s),
//               "orientation_deg": phi (a rectangular container's, default its own),
//               "law": {...as simulate...},
//               "series": {"t_s": [...], "eta_mm": [...], "offset_s": 0, "fit_offset": false,
//                          "max_offset_s": 0.25},
//               "peaks": {"eta_motion_mm": x, "eta_rest_mm": y, "rest_window_s": 1}}],
//    "fit": {"omega_scale": {"fit": true, "initial": 1, "min": 0.5, "max": 2}, "zeta": {...},
//            "alpha": {...}, "height_gain": {...}, "max_iterations": 60},
//    "name": "bench-2026-11"}

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/core/model/calibration.hpp"
#include "slosh/core/model/format.hpp"

namespace slosh::api {

/// Most measured moves of one request, and most samples of one series.
constexpr std::size_t kMaxCalibrationMoves{100};
constexpr std::size_t kMaxSeriesSamples{200000};
/// Calibration names: 1 to 64 characters of [A-Za-z0-9._-], starting with a letter or digit.
constexpr std::size_t kMaxCalibrationName{64};

struct CalibrationRequest {
  Format format;
  ModelOptions base;
  std::vector<MeasuredMove> moves;
  /// A rectangular container's: each move's orientation [deg] (moves[i].orientation_deg, else
  /// format.container.orientation_deg); empty for the cylinder.
  std::vector<double> orientations;
  CalibrationSettings settings;
  std::optional<std::string> name;
};

/// Validates a calibration request; throws ApiError (422) naming the field, the value and the
/// allowed range (an empty series, times not increasing, a law that does not fit the format's
/// stroke, a non-number sample, ...).
[[nodiscard]] CalibrationRequest parse_calibration_request(const nlohmann::json& body);

/// Throws ApiError (422) on `field` unless `name` is a valid calibration name.
void validate_calibration_name(const std::string& name, const std::string& field);

/// {"omega_scale", "zeta", "alpha", "height_gain"} of calibrated model options: what
/// options.model accepts.
[[nodiscard]] nlohmann::json calibrated_model_json(const ModelOptions& model);

/// The numerics of the fit behind an answer, recorded in it ("fit_version") and so in every
/// stored calibration; bumped whenever a fit's numbers change for the same request. v1 (answers
/// without the member) fitted a rectangular container moved along one side on its dominant mode
/// alone; v2 fits every rectangular container on simulate's model, per direction.
inline constexpr std::string_view kCalibrationFitVersion{"calibration-v2"};

/// Runs the fit and renders the response: {"status", "iterations", "sigma_mm", "parameters":
/// {name: {"value", "prior", "standard_error" (null when not fitted), "state", "at_bound"}},
/// "moves": [{"name", "residuals", "rms_before_mm", "rms_after_mm", "offset_s",
/// "offset_standard_error_s"}], "identifiability": [...], "model": {omega_scale, zeta, alpha,
/// height_gain}, "container", "fit_version", "name" (when given)}. A rectangular container is
/// fitted per direction (calibrate_rectangular): its parameters are omega_scale, zeta and
/// height_gain of the one direction its moves drove, and when they drove both, omega_scale and
/// zeta are the length's and width_omega_scale and width_zeta the width's, in "parameters" and
/// "model" alike (no alpha: the depth's); a direction no move drove is named unmeasured in
/// "identifiability" and left out of "container.directions"; moves that cannot tell the
/// directions apart are a 422 on "moves".
[[nodiscard]] nlohmann::json run_calibration(const CalibrationRequest& request);

}  // namespace slosh::api
