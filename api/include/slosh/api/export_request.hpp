#pragma once
// The request of `slosh export`: a simulate request with a "law" (that law is exported as given,
// along format.motion when it is an arc or a path) or a plan request (its plan is solved or read
// from the cache, then exported).

#include <optional>
#include <string_view>

#include "slosh/api/motion_json.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

/// A law request to export: the law over the format's stroke, and the path it moves along when
/// format.motion is an arc or a path (its length is the stroke); no path for the straight line
/// (stroke_mm, or a motion of type line, exported as today).
struct ExportLawRequest {
  SimulateRequest request;
  std::optional<PlanarPath> path;
  MotionType motion_type{MotionType::kLine};
};

/// `text` read as the body of `slosh export --request`: the law request when the body is an
/// object with a "law" member; nullopt for a plan request, which is checked here (its errors name
/// its fields) and handed on as text. ApiError for invalid JSON or an invalid request; a
/// trajectory motion is refused naming format.motion (its samples are the motion: there is no
/// law to sample).
[[nodiscard]] std::optional<ExportLawRequest> parse_export_request(std::string_view text);

/// The path of a plan answer along an arc or a path (its echoed format.motion), for the pose
/// columns of its cam table; nullopt for a plan along a straight line (no motion, or a line).
/// Defined with the motion parser (motion_json.cpp).
[[nodiscard]] std::optional<SpatialMotion> plan_path_motion(std::string_view plan_text);

}  // namespace slosh::api
