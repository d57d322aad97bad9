#pragma once
// The container a calibration was fitted on: recorded in the calibration's answer (and so in
// the stored copy), and compared with the container of a request that names the calibration.
// A fitted frequency scale, wall-height gain or damping belongs to the tank and the direction
// it was measured on; on another tank they would be another tank's numbers, silently.

#include <nlohmann/json.hpp>
#include <string>

#include "slosh/core/model/format.hpp"

namespace slosh::api {

/// `{"shape": "cylinder", "radius_mm"}` or `{"shape": "rectangular", "length_mm", "width_mm",
/// "directions": ["length"] or ["width"]}` (the direction the calibration moves drove) for the
/// format a calibration was fitted on. The fill height, free board and stroke are not part of
/// it: a calibration of a container holds at its other fills and moves.
[[nodiscard]] nlohmann::json fitted_container_json(const Format& format);

/// Throws ApiError 422 on options.model when the stored calibration `stored` (its answer, with
/// "container") was fitted on another container than `body`'s format.container, or, for a
/// rectangular tank, when the request moves a direction the calibration did not measure. A
/// stored calibration without "container" (stored by an older release) and a body whose
/// container cannot be read (its endpoint refuses it) pass unchecked.
void check_calibrated_container(const nlohmann::json& stored, const nlohmann::json& body,
                                const std::string& name);

}  // namespace slosh::api
