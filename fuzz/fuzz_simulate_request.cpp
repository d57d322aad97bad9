// Fuzz target: the body of POST /v1/simulate and `slosh simulate` (api::parse_json_body +
// api::parse_simulate_request). A valid request that is cheap to simulate is also run and
// rendered: SPEC §7 promises that in-range input never yields a 500 or a null where a number
// belongs. Expensive valid requests (long windows, many pieces, long series) are only parsed so
// that an iteration stays in the millisecond range.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"

namespace {

/// Simulated window (motion + rest) [s], law pieces and series samples of a "cheap" request.
constexpr double kCheapWindowS = 3.0;
constexpr std::size_t kCheapPieces = 64;
constexpr double kCheapSamples = 4000.0;

bool cheap(const slosh::api::SimulateRequest& r) {
  const double window = r.format.motion_time + r.options.rest_time;
  if (window > kCheapWindowS) return false;
  if (r.law.pieces().size() > kCheapPieces) return false;
  return !r.options.sample_period || window / *r.options.sample_period <= kCheapSamples;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slosh;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const api::SimulateRequest request = api::parse_simulate_request(api::parse_json_body(text));
    if (!cheap(request)) return 0;
    const nlohmann::json response = api::run_simulate(request);
    fuzz::require(fuzz::all_finite(response), "a simulate response has only finite numbers");
    (void)api::dump_json(response);
  } catch (const api::ApiError& e) {
    fuzz::check_envelope(e);
  }
  return 0;
}
