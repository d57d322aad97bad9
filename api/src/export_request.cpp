#include "slosh/api/export_request.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/motion_json.hpp"
#include "slosh/api/plan.hpp"

namespace slosh::api {

std::optional<SimulateRequest> parse_export_request(std::string_view text) {
  const nlohmann::json body = parse_json_body(text);
  if (body.is_object() && body.contains("law")) {
    // The cam of a law along a path (s plus x, y, theta) is not exported yet: a line's is the
    // stroke's, any other motion is refused rather than exported as a straight move.
    if (const std::optional<nlohmann::json> line = straight_line_body(body)) {
      return parse_simulate_request(*line);
    }
    return parse_simulate_request(body);
  }
  (void)parse_plan_request(body);
  return std::nullopt;
}

}  // namespace slosh::api
