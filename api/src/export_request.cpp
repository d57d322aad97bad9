#include "slosh/api/export_request.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/plan.hpp"

namespace slosh::api {

std::optional<SimulateRequest> parse_export_request(std::string_view text) {
  const nlohmann::json body = parse_json_body(text);
  if (body.is_object() && body.contains("law")) return parse_simulate_request(body);
  (void)parse_plan_request(body);
  return std::nullopt;
}

}  // namespace slosh::api
