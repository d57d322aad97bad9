// Fuzz target: the body of POST /v1/plans and `slosh plan` (api::parse_json_body +
// api::parse_plan_request), then what the service computes from a valid request before solving:
// the canonical recipe and its key. Invalid input must be an ApiError (400/422) with a valid
// envelope; anything else escaping is a finding (the service would answer 500).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slosh;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const nlohmann::json body = api::parse_json_body(text);
    const api::PlanRequest request = api::parse_plan_request(body);
    const nlohmann::json canonical = api::canonical_recipe(request);
    fuzz::require(fuzz::all_finite(canonical), "the canonical recipe has only finite numbers");
    const std::string key = api::recipe_key(request);
    fuzz::require(key.size() == 32, "a recipe key is 32 hex digits");
    fuzz::require(api::recipe_key(api::parse_plan_request(body)) == key,
                  "parsing the same body twice gives the same key");
  } catch (const api::ApiError& e) {
    fuzz::check_envelope(e);
  }
  return 0;
}
