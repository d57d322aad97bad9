// The JSON the service hands to api/: config file members, JSON log lines, batch items read one
// by one, and options.model resolved from stored calibrations. Expected texts are written out by
// hand here (member order, rounding, replacement of invalid UTF-8).

#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "slosh/api/calibration_models.hpp"
#include "slosh/api/config_file.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/log_json.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::api {
namespace test_service_json {

using nlohmann::json;

TEST(ConfigJson, MembersComeInKeyOrderWithTheirKindsAndTexts) {
  const std::vector<ConfigMember> m = parse_config_file(
      "f.json", R"({"port": 80, "host": "a b", "redis_required": true, "x": [1], "t": 0.5})");
  ASSERT_EQ(m.size(), 5u);
  using K = ConfigMember::Type;
  EXPECT_EQ(m[0].key, "host");
  EXPECT_EQ(m[0].type, K::kString);
  EXPECT_EQ(m[0].json, "\"a b\"");
  EXPECT_EQ(m[0].text, "a b");
  EXPECT_EQ(m[1].key, "port");
  EXPECT_EQ(m[1].type, K::kNumber);
  EXPECT_EQ(m[1].json, "80");
  EXPECT_EQ(m[2].key, "redis_required");
  EXPECT_EQ(m[2].type, K::kBoolean);
  EXPECT_EQ(m[2].json, "true");
  EXPECT_EQ(m[3].key, "t");
  EXPECT_EQ(m[3].json, "0.5");
  EXPECT_EQ(m[4].key, "x");
  EXPECT_EQ(m[4].type, K::kOther);
  EXPECT_EQ(m[4].json, "[1]");
  EXPECT_EQ(m[4].text, "[1]");
}

TEST(ConfigJson, RefusesANonObjectAndBrokenJsonNamingTheFile) {
  try {
    (void)parse_config_file("f.json", "[1]");
    FAIL() << "an array was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "config file 'f.json' must hold an object");
  }
  try {
    (void)parse_config_file("g.json", "{\"port\": ");
    FAIL() << "broken JSON was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("config file 'g.json' is not valid JSON: ", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(json_number_text(600.0), "600.0");
  EXPECT_EQ(json_number_text(0.25), "0.25");
}

TEST(LogJson, QuotesInvalidUtf8WithTheReplacementCharacter) {
  EXPECT_EQ(json_quoted(std::string("a\xff") + "\"b\n"),
            std::string("\"a") + "\xEF\xBF\xBD" + "\\\"b\\n\"");
}

TEST(LogJson, RequestObjectHasItsMembersSortedAndMsToTheMicrosecond) {
  LoggedRequest r{"r1",
                  "GET",
                  "/v1/plans/{key}",
                  "/v1/plans/abc",
                  200,
                  1.23456,
                  42,
                  "hit",
                  LoggedPlan{"abc", "zv", "optimal", true}};
  EXPECT_EQ(request_log_object(r),
            R"({"bytes":42,"cache":"hit","cached":true,"method":"GET","ms":1.235,)"
            R"("msg":"request","path":"/v1/plans/abc","plan_key":"abc","plan_status":"optimal",)"
            R"("request_id":"r1","route":"/v1/plans/{key}","status":200,"strategy":"zv"})");
  r.ms.reset();
  r.cache.clear();
  r.plan.reset();
  EXPECT_EQ(request_log_object(r),
            R"({"bytes":42,"method":"GET","ms":null,"msg":"request","path":"/v1/plans/abc",)"
            R"("request_id":"r1","route":"/v1/plans/{key}","status":200})");
}

json plan_body() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150},
               "fill_height_mm": 82, "fluid": "water",
               "stroke_mm": 800, "motion_time_s": 1.0},
    "strategy": "notch"
  })");
}

TEST(BatchItems, EachItemIsReadOnItsOwnAndABadOneCarriesItsError) {
  json with_series = plan_body();
  with_series["sample_period_s"] = 0.001;
  json too_long = plan_body();
  too_long["options"] = {{"time_limit_s", 30}};
  const std::vector<BatchItem> items =
      read_batch_items({plan_body(), with_series, json(42), too_long}, 5.0);
  ASSERT_EQ(items.size(), 4u);
  ASSERT_TRUE(items[0].request.has_value()) << (items[0].error ? items[0].error->what() : "");
  EXPECT_FALSE(items[0].error.has_value());
  EXPECT_EQ(items[0].request->options.time_limit, 5.0);  // the server's budget applied
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_FALSE(items[i].request.has_value()) << i;
    ASSERT_TRUE(items[i].error.has_value()) << i;
    EXPECT_EQ(items[i].error->status(), 422) << i;
  }
  EXPECT_EQ(items[1].error->field(), "sample_period_s");
  EXPECT_EQ(items[3].error->field(), "options.time_limit_s");
}

CalibrationLookup lookup_in(std::map<std::string, std::string> stored) {
  return [stored](const std::string& name) -> std::optional<std::string> {
    const auto it = stored.find(name);
    if (it == stored.end()) return std::nullopt;
    return it->second;
  };
}

TEST(CalibrationModels, ANamedModelIsReplacedByTheStoredOneAndAnUnknownOneIsA404) {
  const auto lookup = lookup_in({{"bench", R"({"model":{"zeta":0.01},"status":"converged"})"},
                                 {"broken", R"({"status":"converged"})"}});
  EXPECT_EQ(resolve_model_names(R"({"format":1,"options":{"model":"bench"}})", lookup),
            R"({"format":1,"options":{"model":{"zeta":0.01}}})");
  const std::string unnamed = R"({ "options" : {"model": {"zeta": 0.02}}})";
  EXPECT_EQ(resolve_model_names(unnamed, lookup), unnamed);  // the same text, not rewritten
  for (const char* name : {"nope", "broken"}) {
    try {
      (void)resolve_model_names(std::string(R"({"options":{"model":")") + name + "\"}}", lookup);
      FAIL() << name << " was resolved";
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status(), 404);
      EXPECT_EQ(e.field(), "options.model");
      EXPECT_EQ(std::string(e.what()),
                std::string("options.model = \"") + name +
                    "\": no stored calibration of that name (POST /v1/calibrations with \"name\" "
                    "stores one)");
    }
  }
  EXPECT_EQ(
      resolve_batch_model_names(
          R"({"requests":[{"options":{"model":"bench"}},{"options":{"model":"nope"}}]})", lookup),
      R"({"requests":[{"options":{"model":{"zeta":0.01}}},{"options":{"model":"nope"}}]})");
}

}  // namespace test_service_json
}  // namespace slosh::api
