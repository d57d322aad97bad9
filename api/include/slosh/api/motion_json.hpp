#pragma once
// format.motion (SPEC §14): a line, an arc, a path of lines and arcs, or (simulate only) a
// sampled trajectory, parsed into the core's PlanarPath or SampledTrajectory. The request speaks
// mm, degrees and s; the core SI and radians. A motion the core refuses (InvalidMotion) becomes a
// 422 naming the JSON member (`format.motion.segments[2]`, `format.motion.t_s[13]`).

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/fields.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh::api {

/// Allowed ranges of the motion members (user units).
namespace motion_ranges {
/// An arc's radius: > 0 (a table or a track curve of any size).
inline const Range kArcRadiusMm{0.0, 100000.0, "mm", true};
/// An arc's angle, signed (left positive), non-zero: up to ten turns either way.
inline const Range kAngleDeg{-3600.0, 3600.0, "deg"};
/// Directions and headings.
inline const Range kHeadingDeg{-360.0, 360.0, "deg"};
/// A trajectory spans at most a minute (what a simulation is asked for) [s].
constexpr double kMaxTrajectorySpanS{60.0};
/// Most samples of a trajectory.
constexpr std::size_t kMaxTrajectorySamples{200000};
/// Most segments of a path: a track of many modules plans in seconds (each segment joins the
/// drive's pieces and the planner's sensitivities), 10 000 keeps a plan within its budget.
constexpr std::size_t kMaxPathSegments{10000};
}  // namespace motion_ranges

/// The motion types of format.motion.
enum class MotionType { kLine, kArc, kPath, kTrajectory };

/// A validated format.motion.
struct SpatialMotion {
  MotionType type{MotionType::kLine};
  std::optional<PlanarPath> path;               ///< line, arc and path
  std::optional<SampledTrajectory> trajectory;  ///< trajectory
  /// The motion as answers echo it: a line or a trajectory as given; an arc or a path canonical
  /// (every member with its default filled in, start_heading_deg in (-180, 180], the segments'
  /// optional heading_deg checks left out, numbers as the request's units read them back), so
  /// the echo is a function of the recipe key (canonical_motion).
  nlohmann::json echo;
};

/// A format with its motion: the format's stroke is the path's length (a trajectory's format
/// has neither stroke nor motion time: `format` then holds placeholders the echo leaves out).
struct SpatialFormat {
  Format format;
  SpatialMotion motion;
};

/// The request's format.motion when given (null counts as absent).
[[nodiscard]] const nlohmann::json* given_motion(const nlohmann::json& body);

/// Parses the format of a request whose format.motion is given; `trajectory_allowed` for
/// simulate. A path motion replaces format.stroke_mm (both given are refused); a trajectory
/// replaces stroke_mm and motion_time_s.
[[nodiscard]] SpatialFormat parse_spatial_format(const nlohmann::json& body,
                                                 bool trajectory_allowed);

/// The straight line of the planning endpoints (plans, min-time, export), which take arcs and
/// paths first (planned_path_format): nullopt when the body has no format.motion; the body
/// without it when it is null; the body with a `line` motion written as its short form stroke_mm
/// (the line's direction does not change the wave of an axisymmetric container); any other
/// motion (a trajectory) is refused with a 422 naming format.motion.
[[nodiscard]] std::optional<nlohmann::json> straight_line_body(const nlohmann::json& body);

/// For POST /v1/plans: the format of a request whose format.motion is an arc or a path (its
/// stroke the path length; parse_spatial_format's refusals); nullopt without a motion or for a
/// line (straight_line_body's). A trajectory is refused naming format.motion.type.
[[nodiscard]] std::optional<SpatialFormat> planned_path_format(const nlohmann::json& body);

/// The motion as the recipe key holds it: the path's elements in SI (lengths in m, angles in
/// rad), its start heading (normalised to (-180, 180] deg) and container_turns; the same path
/// written twice the same way (an arc or a path of one arc) gives the same key only when its
/// type is the same.
[[nodiscard]] nlohmann::json canonical_motion(const SpatialMotion& motion);

/// Throws ApiError (422) for a core refusal of a motion, its member as the JSON member.
[[noreturn]] void motion_refusal(const std::string& member, const std::string& message);

/// The samples of format.motion of type trajectory in user units (t_s, x_mm, y_mm, z_mm?,
/// theta_deg?) from SI samples: what `slosh simulate --trajectory` puts in the request.
[[nodiscard]] nlohmann::json trajectory_motion_json(const TrajectorySamples& samples);

}  // namespace slosh::api
