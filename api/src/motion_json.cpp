#include "slosh/api/motion_json.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "slosh/api/error.hpp"
#include "slosh/api/export_request.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/motion/invalid_motion.hpp"

namespace slosh::api {

namespace {

using json = nlohmann::json;

// Bound on the relative rounding of a path's length summed over its segments (at most
// kMaxPathSegments terms, each rounding by 2^-53).
constexpr double kPathLengthRounding{1e-11};
const std::string kMotion{"format.motion"};

using motion_ranges::kAngleDeg;
using motion_ranges::kArcRadiusMm;
using motion_ranges::kHeadingDeg;
using motion_ranges::kMaxTrajectorySamples;
using motion_ranges::kMaxTrajectorySpanS;
// Sample values: any finite number a log holds (1e9 mm is 1000 km).
const Range kSampleValue{-1e9, 1e9, ""};

MotionType parse_type(const json& m) {
  const std::string tpath = join_path(kMotion, "type");
  const json* type = given_member(m, "type");
  if (type == nullptr) {
    invalid(tpath, tpath + " is required: one of \"line\", \"arc\", \"path\", \"trajectory\"");
  }
  const std::string name = type->is_string() ? type->get<std::string>() : std::string();
  if (name == "line") return MotionType::kLine;
  if (name == "arc") return MotionType::kArc;
  if (name == "path") return MotionType::kPath;
  if (name == "trajectory") return MotionType::kTrajectory;
  invalid(tpath, tpath + " = " + show(*type) +
                     " is not allowed: one of \"line\", \"arc\", \"path\", \"trajectory\"");
}

// A value that passed its range but is not a normal double once scaled to SI (5e-324 mm is 0 m,
// 1e-310 deg a subnormal radian): refused naming the member and the value sent, since the core
// would see 0 or compute with a few bits.
void require_normal_scaled(double value, double scale, const std::string& field,
                           const Range& range) {
  if (value == 0.0 || std::isnormal(value * scale)) return;
  invalid(field, field + " = " + number_text(value) + " is too small to compute with: allowed " +
                     range.describe() + " and at least " +
                     number_text(std::numeric_limits<double>::min() / scale) + " " +
                     std::string(range.unit) + " in magnitude");
}

// A non-zero angle: an arc that turns through nothing is not an arc.
double arc_angle_deg(const json& arc, const std::string& path) {
  const double angle = required_number(arc, path, "angle_deg", kAngleDeg);
  const std::string field = join_path(path, "angle_deg");
  if (angle == 0.0) {
    invalid(field, field + " = 0 is not allowed: an arc turns, allowed " + kAngleDeg.describe() +
                       " except 0 (signed, left positive)");
  }
  require_normal_scaled(angle, kRadPerDeg, field, kAngleDeg);
  return angle;
}

// An arc's radius [m] from radius_mm.
double arc_radius_m(const json& arc, const std::string& path) {
  const double radius = required_number(arc, path, "radius_mm", kArcRadiusMm);
  require_normal_scaled(radius, 1e-3, join_path(path, "radius_mm"), kArcRadiusMm);
  return radius * 1e-3;
}

// A start heading in (-180, 180] deg: headings a turn apart are one motion (one recipe key, one
// echo); fmod is exact.
double normal_heading_deg(double deg) {
  double h = std::fmod(deg, 360.0);
  if (h <= -180.0) h += 360.0;
  if (h > 180.0) h -= 360.0;
  return h + 0.0;  // -0 (from -0 or -360) is 0: one echo, one recipe key
}

// The start heading of an arc or a path [rad], normalised.
double start_heading_rad(const json& m) {
  return normal_heading_deg(optional_number(m, kMotion, "start_heading_deg", kHeadingDeg, 0.0)) *
         kRadPerDeg;
}

// An arc or a path as answers echo it, from what was parsed: every member given (defaults
// filled in), in the request's units, the optional heading checks of the segments left out. A
// cached plan shows the motion of its recipe key, never one client's spelling of it to another.
json canonical_echo(MotionType type, const PlanarPath& path) {
  const std::vector<PathElement>& elements = path.elements();
  auto arc_json = [](const PathElement& e) {
    return json{{"radius_mm", mm_of(e.radius)}, {"angle_deg", deg_of(e.angle)}};
  };
  json out{{"type", type == MotionType::kArc ? "arc" : "path"}};
  if (type == MotionType::kArc) {
    out.update(arc_json(elements.front()));
  } else {
    json segments = json::array();
    for (const PathElement& e : elements) {
      segments.push_back(e.kind == PathElement::Kind::kLine ? json{{"line_mm", mm_of(e.length)}}
                                                            : json{{"arc", arc_json(e)}});
    }
    out["segments"] = std::move(segments);
  }
  out["start_heading_deg"] = deg_of(path.start_heading());
  out["container_turns"] = path.container_turns();
  return out;
}

std::optional<double> optional_heading(const json& object, const std::string& path,
                                       std::string_view key) {
  if (given_member(object, key) == nullptr) return std::nullopt;
  return required_number(object, path, key, kHeadingDeg) * kRadPerDeg;
}

PlanarPath checked_path(std::vector<PathElement> elements, double start_heading, bool turns) {
  try {
    return PlanarPath(std::move(elements), start_heading, turns);
  } catch (const InvalidMotion& e) {
    motion_refusal(e.member(), e.what());
  }
}

PathElement parse_segment(const json& segment, const std::string& path) {
  require_object(segment, path);
  reject_unknown_fields(segment, path, {"line_mm", "arc", "heading_deg"});
  const bool line = given_member(segment, "line_mm") != nullptr;
  const bool arc = given_member(segment, "arc") != nullptr;
  if (line == arc) {
    invalid(path, path +
                      " must have one of \"line_mm\" (a line's length) or \"arc\" "
                      "({\"radius_mm\", \"angle_deg\"}), got " +
                      show(segment));
  }
  const std::optional<double> heading = optional_heading(segment, path, "heading_deg");
  if (line)
    return PathElement::line(required_number(segment, path, "line_mm", ranges::kStrokeMm) * 1e-3,
                             heading);
  const std::string apath = join_path(path, "arc");
  const json& a = segment["arc"];
  require_object(a, apath);
  reject_unknown_fields(a, apath, {"radius_mm", "angle_deg"});
  const double radius = arc_radius_m(a, apath);
  const double angle = arc_angle_deg(a, apath) * kRadPerDeg;
  // A segment is at least as long as a line may be: an arc shorter than that is a corner the
  // container cannot follow (its normal acceleration grows as 1 / radius).
  const double length_mm = mm_of(radius * std::abs(angle));
  if (!ranges::kStrokeMm.contains(length_mm)) {
    invalid(apath, apath + " is " + number_text(length_mm) +
                       " mm long (radius_mm × angle); allowed " + ranges::kStrokeMm.describe());
  }
  return PathElement::arc(radius, angle, heading);
}

PlanarPath parse_path(const json& m) {
  reject_unknown_fields(m, kMotion, {"type", "segments", "start_heading_deg", "container_turns"});
  const std::string spath = join_path(kMotion, "segments");
  const json* segments = given_member(m, "segments");
  if (segments == nullptr || !segments->is_array() || segments->empty()) {
    invalid(spath, spath +
                       " must be a non-empty array of {\"line_mm\"} and {\"arc\": "
                       "{\"radius_mm\", \"angle_deg\"}}, got " +
                       (segments == nullptr ? std::string("nothing") : show(*segments)));
  }
  if (segments->size() > motion_ranges::kMaxPathSegments) {
    invalid(spath, spath + " has " + std::to_string(segments->size()) +
                       " segments; allowed at most " +
                       std::to_string(motion_ranges::kMaxPathSegments));
  }
  std::vector<PathElement> elements;
  for (std::size_t i = 0; i < segments->size(); ++i) {
    elements.push_back(parse_segment((*segments)[i], spath + "[" + std::to_string(i) + "]"));
  }
  const bool turns = optional_bool(m, kMotion, "container_turns", false);
  return checked_path(std::move(elements), start_heading_rad(m), turns);
}

// A sample column in user units, scaled to SI; empty when optional and absent.
std::vector<double> sample_column(const json& m, std::string_view key, double scale,
                                  bool required) {
  const std::string cpath = join_path(kMotion, key);
  const json* column = given_member(m, key);
  if (column == nullptr) {
    if (required) invalid(cpath, cpath + " is required: an array of numbers, one per sample");
    return {};
  }
  if (!column->is_array())
    invalid(cpath, cpath + " must be an array of numbers, got " + show(*column));
  if (column->size() > kMaxTrajectorySamples) {
    invalid(cpath, cpath + " has " + std::to_string(column->size()) + " samples; allowed at most " +
                       std::to_string(kMaxTrajectorySamples));
  }
  std::vector<double> out;
  out.reserve(column->size());
  for (std::size_t i = 0; i < column->size(); ++i) {
    const std::string field = cpath + "[" + std::to_string(i) + "]";
    out.push_back(checked_number(&(*column)[i], field, kSampleValue) * scale);
  }
  return out;
}

// A heading log wrapped to (-180, 180] deg (as robots log it), unwrapped: each sample is taken
// at the turn nearest the previous one, as the quaternion reader does, so a wrap is not a turn
// of -360 deg in one interval. Samples that do not wrap are kept exactly.
std::vector<double> unwrapped(std::vector<double> theta) {
  constexpr double kTurn{2.0 * std::numbers::pi};
  double offset = 0.0;
  for (std::size_t i = 1; i < theta.size(); ++i) {
    const double step = theta[i] + offset - theta[i - 1];
    offset -= kTurn * std::round(step / kTurn);
    if (offset != 0.0) theta[i] += offset;
  }
  return theta;
}

SampledTrajectory parse_trajectory(const json& m) {
  reject_unknown_fields(m, kMotion, {"type", "t_s", "x_mm", "y_mm", "z_mm", "theta_deg"});
  TrajectorySamples s;
  s.t = sample_column(m, "t_s", 1.0, true);
  s.x = sample_column(m, "x_mm", 1e-3, true);
  s.y = sample_column(m, "y_mm", 1e-3, true);
  s.z = sample_column(m, "z_mm", 1e-3, false);
  s.theta = unwrapped(sample_column(m, "theta_deg", kRadPerDeg, false));
  try {
    SampledTrajectory trajectory(std::move(s));
    const double span = trajectory.end_time() - trajectory.start_time();
    if (span > kMaxTrajectorySpanS) {
      const std::string field = join_path(kMotion, "t_s");
      invalid(field, field + " spans " + number_text(span) + " s; allowed at most " +
                         number_text(kMaxTrajectorySpanS) + " s");
    }
    return trajectory;
  } catch (const InvalidMotion& e) {
    motion_refusal(e.member(), e.what());
  }
}

// The JSON name of a core member: "t[12]" -> "t_s[12]", "segments[2]" as it is.
std::string json_member(const std::string& member) {
  const std::size_t bracket = member.find('[');
  const std::string head = member.substr(0, bracket);
  const std::string tail = bracket == std::string::npos ? std::string() : member.substr(bracket);
  static const std::pair<std::string_view, std::string_view> kNames[] = {
      {"t", "t_s"},  {"x", "x_mm"},          {"y", "y_mm"},
      {"z", "z_mm"}, {"theta", "theta_deg"}, {"start_heading", "start_heading_deg"}};
  for (const auto& [core, api] : kNames) {
    if (head == core) return std::string(api) + tail;
  }
  return member;
}

SpatialMotion parse_motion(const json& m, bool trajectory_allowed) {
  require_object(m, kMotion);
  SpatialMotion out;
  out.type = parse_type(m);
  out.echo = m;
  switch (out.type) {
    case MotionType::kLine: {
      reject_unknown_fields(m, kMotion, {"type", "length_mm", "direction_deg"});
      const double length = required_number(m, kMotion, "length_mm", ranges::kStrokeMm);
      const double direction = optional_number(m, kMotion, "direction_deg", kHeadingDeg, 0.0);
      out.path = checked_path({PathElement::line(length * 1e-3)}, direction * kRadPerDeg, false);
      break;
    }
    case MotionType::kArc: {
      reject_unknown_fields(
          m, kMotion, {"type", "radius_mm", "angle_deg", "container_turns", "start_heading_deg"});
      const double radius = arc_radius_m(m, kMotion);
      const double angle = arc_angle_deg(m, kMotion) * kRadPerDeg;
      const bool turns = optional_bool(m, kMotion, "container_turns", true);
      out.path = checked_path({PathElement::arc(radius, angle)}, start_heading_rad(m), turns);
      out.echo = canonical_echo(out.type, *out.path);
      break;
    }
    case MotionType::kPath:
      out.path = parse_path(m);
      out.echo = canonical_echo(out.type, *out.path);
      break;
    case MotionType::kTrajectory:
      if (!trajectory_allowed) break;  // refused by the caller
      out.trajectory = parse_trajectory(m);
      break;
  }
  return out;
}

}  // namespace

void motion_refusal(const std::string& member, const std::string& message) {
  // The core's sentence starts with its member: it is renamed to the JSON member.
  const std::string field = join_path(kMotion, json_member(member));
  std::string text = message;
  if (text.rfind(member, 0) == 0) {
    text = field + text.substr(member.size());
  } else {
    text = field + ": " + text;
  }
  invalid(field, text);
}

const nlohmann::json* given_motion(const nlohmann::json& body) {
  if (!body.is_object()) return nullptr;
  const json* format = given_member(body, "format");
  if (format == nullptr || !format->is_object()) return nullptr;
  return given_member(*format, "motion");
}

SpatialFormat parse_spatial_format(const nlohmann::json& body, bool trajectory_allowed) {
  const json& format = body.at("format");
  SpatialFormat out;
  out.motion = parse_motion(format.at("motion"), trajectory_allowed);
  json plain = format;
  plain.erase("motion");
  if (out.motion.type == MotionType::kTrajectory) {
    for (const char* key : {"stroke_mm", "motion_time_s"}) {
      if (given_member(format, key) != nullptr) {
        const std::string field = join_path("format", key);
        invalid(field, field +
                           " is not part of a trajectory motion: its samples give the path "
                           "and the times; leave " +
                           field + " out");
      }
    }
    // Placeholders for the members a trajectory replaces (the echo leaves them out).
    plain["stroke_mm"] = 1.0;
    plain["motion_time_s"] = 1.0;
    out.format = parse_format(plain, "format");
    return out;
  }
  if (given_member(format, "stroke_mm") != nullptr) {
    invalid("format.stroke_mm",
            "format.stroke_mm and format.motion both give the move: give one of them (stroke_mm "
            "is the short form of a motion of type \"line\")");
  }
  double length_mm = out.motion.type == MotionType::kLine
                         ? format["motion"]["length_mm"].get<double>()
                         : out.motion.path->length() * 1e3;
  // A path's length is a sum of its segments': segments that add up to the limit exactly may
  // exceed it by the sum's rounding, which is not the client's length.
  if (out.motion.path && length_mm > ranges::kStrokeMm.hi &&
      length_mm <= ranges::kStrokeMm.hi * (1.0 + kPathLengthRounding)) {
    length_mm = ranges::kStrokeMm.hi;
  }
  if (!ranges::kStrokeMm.contains(length_mm)) {
    invalid(kMotion, kMotion + " is " + number_text(length_mm) +
                         " mm long (the length the law moves along it); allowed " +
                         ranges::kStrokeMm.describe());
  }
  plain["stroke_mm"] = length_mm;
  out.format = parse_format(plain, "format");
  return out;
}

std::optional<nlohmann::json> straight_line_body(const nlohmann::json& body) {
  const json* m = given_motion(body);
  if (m == nullptr) {
    // "motion": null is absent, as every optional member.
    const json* format = body.is_object() ? given_member(body, "format") : nullptr;
    if (format == nullptr || !format->is_object() || find_member(*format, "motion") == nullptr) {
      return std::nullopt;
    }
    json out = body;
    out["format"].erase("motion");
    return out;
  }
  require_object(*m, kMotion);
  const MotionType type = parse_type(*m);
  if (type != MotionType::kLine) {
    invalid(kMotion, kMotion + " of type " + show((*m)["type"]) +
                         ": min-time moves the container along a \"line\", an \"arc\" or a "
                         "\"path\" (a trajectory is simulated, POST /v1/simulate)");
  }
  static_cast<void>(parse_motion(*m, false));  // validates the line
  const json& format = body["format"];
  if (given_member(format, "stroke_mm") != nullptr) {
    invalid("format.stroke_mm",
            "format.stroke_mm and format.motion both give the move: give one of them (stroke_mm "
            "is the short form of a motion of type \"line\")");
  }
  json out = body;
  out["format"].erase("motion");
  out["format"]["stroke_mm"] = (*m)["length_mm"];
  return out;
}

std::optional<SpatialFormat> planned_path_format(const nlohmann::json& body) {
  const json* m = given_motion(body);
  if (m == nullptr) return std::nullopt;
  require_object(*m, kMotion);
  const MotionType type = parse_type(*m);
  if (type == MotionType::kLine) return std::nullopt;
  if (type == MotionType::kTrajectory) {
    const std::string field = join_path(kMotion, "type");
    invalid(field, field +
                       " = \"trajectory\" is not allowed in a plan: a plan moves the container "
                       "along a \"line\", an \"arc\" or a \"path\" (a trajectory is simulated, "
                       "POST /v1/simulate)");
  }
  return parse_spatial_format(body, false);
}

nlohmann::json canonical_motion(const SpatialMotion& motion) {
  json elements = json::array();
  for (const PathElement& e : motion.path->elements()) {
    if (e.kind == PathElement::Kind::kLine) {
      elements.push_back({{"line_m", e.length}});
    } else {
      elements.push_back({{"arc_radius_m", e.radius}, {"arc_angle_rad", e.angle}});
    }
  }
  return {{"type", motion.type == MotionType::kArc ? "arc" : "path"},
          {"elements", elements},
          {"start_heading_rad", motion.path->start_heading()},
          {"container_turns", motion.path->container_turns()}};
}

std::optional<SpatialMotion> plan_path_motion(std::string_view plan_text) {
  const json plan = parse_json_body(plan_text);
  const json* format = plan.is_object() ? given_member(plan, "format") : nullptr;
  const json* motion =
      format != nullptr && format->is_object() ? given_member(*format, "motion") : nullptr;
  if (motion == nullptr) return std::nullopt;
  SpatialMotion m = parse_motion(*motion, false);
  if (m.type == MotionType::kLine) return std::nullopt;
  return m;
}

nlohmann::json trajectory_motion_json(const TrajectorySamples& samples) {
  auto scaled = [](const std::vector<double>& v, double scale) {
    std::vector<double> out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] * scale;
    return out;
  };
  json m{{"type", "trajectory"},
         {"t_s", samples.t},
         {"x_mm", scaled(samples.x, 1e3)},
         {"y_mm", scaled(samples.y, 1e3)}};
  if (!samples.z.empty()) m["z_mm"] = scaled(samples.z, 1e3);
  if (!samples.theta.empty()) m["theta_deg"] = scaled(samples.theta, 1.0 / kRadPerDeg);
  return m;
}

}  // namespace slosh::api
