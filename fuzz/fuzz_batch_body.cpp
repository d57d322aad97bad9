// Fuzz target: the body of POST /v1/plans/batch, {"requests": [plan requests]}, through the real
// PlanService::post_batch: parsing, the envelope checks, every item's validation, budget and
// recipe key, the per-item error paths and the rendering of the results. The service is created
// shut down (begin_shutdown), so a valid item is refused ("overloaded") instead of being solved:
// the solver is not what this target fuzzes.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "http/plan_service.hpp"

namespace {

slosh::service::PlanService& shut_down_service() {
  static const std::unique_ptr<slosh::service::PlanService> instance = [] {
    slosh::service::ServerConfig config;
    config.workers = 1;
    config.queue = 1;
    config.cache_path.clear();  // memory only: nothing written to disk
    config.batch_max = 64;      // keeps iterations short; the bound itself is checked too
    auto s = std::make_unique<slosh::service::PlanService>(config);
    s->begin_shutdown();
    return s;
  }();
  return *instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slosh;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const service::Reply reply = shut_down_service().post_batch(text);
  fuzz::require(reply.status == 200 || reply.status == 400 || reply.status == 422,
                "a batch is answered 200, 400 or 422 (never 500)");
  const nlohmann::json body = nlohmann::json::parse(reply.body, nullptr, false);
  fuzz::require(!body.is_discarded(), "the batch reply is valid JSON");
  if (reply.status != 200) {
    fuzz::require(body.contains("error") && body["error"]["message"].is_string(),
                  "an error reply is the envelope");
    return 0;
  }
  fuzz::require(body["results"].is_array() && !body["results"].empty(),
                "a batch reply lists its results");
  for (const nlohmann::json& item : body["results"]) {
    fuzz::require(item.contains("error"), "a shut-down service plans nothing");
    const std::string code = item["error"].value("code", "");
    fuzz::require(code == "invalid_value" || code == "overloaded",
                  "a batch item fails as invalid_value (or is refused), never internal");
  }
  return 0;
}
