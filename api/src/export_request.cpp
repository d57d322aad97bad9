#include "slosh/api/export_request.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/spatial_simulate.hpp"

namespace slosh::api {

namespace {

bool has_type(const nlohmann::json& motion, const char* type) {
  if (!motion.is_object()) return false;
  const auto it = motion.find("type");
  return it != motion.end() && *it == type;
}

}  // namespace

std::optional<ExportLawRequest> parse_export_request(std::string_view text) {
  const nlohmann::json body = parse_json_body(text);
  const nlohmann::json* motion = body.is_object() ? given_motion(body) : nullptr;
  // Before the plan's parse: a simulate request with a trajectory has no law either.
  if (motion != nullptr && has_type(*motion, "trajectory")) {
    invalid(join_path("format", "motion"),
            "format.motion: a trajectory cannot be exported: its samples are the motion already "
            "(export a law along a line, an arc or a path)");
  }
  if (!body.is_object() || !body.contains("law")) {
    (void)parse_plan_request(body);
    return std::nullopt;
  }
  if (motion == nullptr || has_type(*motion, "line")) {
    // The straight line: its cam is the stroke's, exported as it always was.
    const std::optional<nlohmann::json> line = straight_line_body(body);
    return ExportLawRequest{parse_simulate_request(line ? *line : body), std::nullopt,
                            MotionType::kLine};
  }
  SpatialSimulateRequest spatial = parse_spatial_simulate_request(body);
  return ExportLawRequest{std::move(spatial.base), std::move(spatial.motion.path),
                          spatial.motion.type};
}

}  // namespace slosh::api
