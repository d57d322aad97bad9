// Calibration through the API, the CLI and the service: options.model in plans
// (recipe key), simulate and its 422s; the calibration request's validation with exact messages;
// `slosh calibrate` on the real binary; POST/GET /v1/calibrations on a real server and a plan
// naming the stored calibration, answered as the inline model.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/response/response.hpp"
#include "support/calibration_body.hpp"
#include "support/plan_errors.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_calibration_api {

using nlohmann::json;

using test::calibration_body;
using test::thesis_format_json;

json plan_body(const json& options) {
  return {{"format", thesis_format_json()}, {"strategy", "shaper"}, {"options", options}};
}

std::string key_of(const json& options) {
  return api::recipe_key(api::parse_plan_request(plan_body(options)));
}

TEST(CalibratedModelOption, KeyedOnlyWhenItChangesTheModel) {
  const json recipe = api::canonical_recipe(api::parse_plan_request(plan_body(json::object())));
  for (const auto& [name, value] : recipe["options"].items()) {
    EXPECT_EQ(name.rfind("model_", 0), std::string::npos) << name;  // old keys unchanged
  }
  const std::string key = key_of(json::object());
  EXPECT_EQ(key, key_of({{"model", {{"omega_scale", 1}, {"height_gain", 1.0}}}}));
  EXPECT_NE(key, key_of({{"model", {{"omega_scale", 1.05}}}}));
  EXPECT_NE(key, key_of({{"model", {{"height_gain", 0.9}}}}));
  // model.alpha and model.zeta set what options.alpha and options.damping set: one key.
  EXPECT_EQ(key_of({{"alpha", 1.2}}), key_of({{"model", {{"alpha", 1.2}}}}));
  EXPECT_EQ(key_of({{"damping", {{"zeta", 0.02}}}}), key_of({{"model", {{"zeta", 0.02}}}}));
}

TEST(CalibratedModelOption, OutOfRangeAndConflictsNameTheField) {
  api::ApiError e = test::plan_parse_error(plan_body({{"model", {{"omega_scale", 0}}}}));
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "options.model.omega_scale");
  EXPECT_STREQ(e.what(), "options.model.omega_scale = 0 is out of range: allowed > 0 and <= 10");
  e = test::plan_parse_error(plan_body({{"model", {{"height_gain", 11}}}}));
  EXPECT_EQ(e.field(), "options.model.height_gain");
  EXPECT_STREQ(e.what(), "options.model.height_gain = 11 is out of range: allowed > 0 and <= 10");
  e = test::plan_parse_error(plan_body({{"alpha", 0.5}, {"model", {{"alpha", 1}}}}));
  EXPECT_EQ(e.field(), "options.model.alpha");
  EXPECT_STREQ(e.what(),
               "options.model.alpha and options.alpha both set the model: give one of them");
  e = test::plan_parse_error(plan_body({{"model", {{"gain", 1}}}}));
  EXPECT_EQ(e.field(), "options.model.gain");
}

TEST(CalibratedModelOption, SimulateUsesTheModel) {
  json body = {
      {"format", thesis_format_json()},
      {"law", {{"type", "modified_trapezoid"}}},
      {"options",
       {{"model", {{"omega_scale", 1.1}, {"zeta", 0.01}, {"alpha", 1.0}, {"height_gain", 0.9}}}}}};
  const json out = api::run_simulate(api::parse_simulate_request(body));
  ModelOptions o;
  o.omega_scale = 1.1;
  o.damping = DampingCorrelation::kExplicit;
  o.explicit_zeta = 0.01;
  o.alpha = 1.0;
  o.height_gain = 0.9;
  const Format f = api::parse_request_format(body);
  const SloshPeaks p =
      NonlinearResponse(make_sloshing_model(f, o), make_modified_trapezoid_law(0.8, 1.0), 1.0)
          .peaks();
  EXPECT_NEAR(out["prediction"]["nonlinear"]["eta_motion_mm"].get<double>(), p.motion.value * 1e3,
              1e-6);
}

api::ApiError calibration_error(const json& body) {
  try {
    (void)api::parse_calibration_request(body);
  } catch (const api::ApiError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted";
  return api::ApiError(api::ErrorCode::kInternal, "", "");
}

TEST(CalibrationRequest, FitsTheSeriesAndReturnsTheModel) {
  const json out = api::run_calibration(api::parse_calibration_request(calibration_body()));
  EXPECT_EQ(out["status"], "converged");
  EXPECT_NEAR(out["model"]["omega_scale"].get<double>(), 1.05, 1e-6);
  EXPECT_NEAR(out["model"]["height_gain"].get<double>(), 0.9, 1e-6);
  EXPECT_EQ(out["parameters"]["alpha"]["state"], "fixed");
  EXPECT_TRUE(out["parameters"]["alpha"]["standard_error"].is_null());
  EXPECT_LT(out["moves"][0]["rms_after_mm"].get<double>(), 1e-4);
  EXPECT_GT(out["moves"][0]["rms_before_mm"].get<double>(), 1.0);
  EXPECT_EQ(out["fit_version"], "calibration-v2");
}

TEST(CalibrationRequest, BadInputNamesTheField) {
  json body = calibration_body();
  body["moves"][0]["series"]["t_s"] = json::array();
  api::ApiError e = calibration_error(body);
  EXPECT_EQ(e.status(), 422);
  EXPECT_EQ(e.field(), "moves[0].series.t_s");
  EXPECT_STREQ(e.what(), "moves[0].series.t_s has 0 samples: a series needs at least 2");

  body = calibration_body();
  body["moves"][0]["series"]["t_s"][2] = 0.01;
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "moves[0].series.t_s[2]");
  EXPECT_STREQ(e.what(),
               "moves[0].series.t_s[2] = 0.01 is not after t_s[1] = 0.02: sample times must "
               "increase");

  body = calibration_body();
  body["moves"][0]["series"]["eta_mm"][1] = "NaN";
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "moves[0].series.eta_mm[1]");
  EXPECT_STREQ(
      e.what(),
      "moves[0].series.eta_mm[1] must be a number, got \"NaN\"; allowed -10000 to 10000 mm");

  body = calibration_body();  // a law of 400 mm on a format of 800 mm
  body["moves"][0]["motion_time_s"] = 1.0;
  body["moves"][0]["law"] = {{"type", "piecewise_linear"},
                             {"breakpoints_s", {0, 0.25, 0.5, 0.75, 1.0}},
                             {"acceleration_m_s2", {0, 3.2, 0, -3.2, 0}}};
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "moves[0].law.acceleration_m_s2");
  EXPECT_STREQ(e.what(),
               "moves[0].law.acceleration_m_s2 integrates to a final velocity of 0 m/s and a final "
               "position of 400 mm: a law must end at rest (|v| <= 1e-6 m/s) at format.stroke_mm "
               "= 800 mm (within 0.001 mm)");

  body = calibration_body();
  body["moves"][0].erase("series");
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "moves[0]");
  EXPECT_STREQ(e.what(), "moves[0] has neither series nor peaks: give what was measured");

  body = calibration_body();
  body["name"] = "bad name!";
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "name");
  EXPECT_STREQ(e.what(),
               "name = \"bad name!\" is not a calibration name: 1 to 64 characters of A-Z a-z 0-9 "
               ". _ -, starting with a letter or digit");

  body = calibration_body();
  body["fit"]["omega_scale"] = {{"min", 1.1}};
  e = calibration_error(body);
  EXPECT_EQ(e.field(), "fit.omega_scale");
  EXPECT_STREQ(e.what(),
               "fit.omega_scale: the model's own value 1 is outside [1.1, 2]: widen min/max or "
               "give fit.omega_scale.initial");
}

TEST(CalibrateCommand, PrintsTheFitAndRefusesBadInput) {
  const test::RunResult ok =
      test::run_slosh({"calibrate", "--request", "-"}, calibration_body().dump());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const json out = json::parse(ok.out);
  EXPECT_NEAR(out["model"]["omega_scale"].get<double>(), 1.05, 1e-6);
  json bad = calibration_body();
  bad["moves"][0]["series"]["t_s"] = json::array();
  const test::RunResult refused = test::run_slosh({"calibrate", "--request", "-"}, bad.dump());
  EXPECT_EQ(refused.exit_code, 2);
  const json envelope = json::parse(refused.err);
  EXPECT_EQ(envelope["error"]["field"], "moves[0].series.t_s");
}

TEST(CalibrationService, StoredCalibrationPlansAsTheInlineModel) {
  test::Server server;
  httplib::Client client = server.client();
  json body = calibration_body();
  body["name"] = "bench-2026-11";
  auto posted = client.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 200) << posted->body;
  const json fit = json::parse(posted->body);
  EXPECT_EQ(fit["name"], "bench-2026-11");
  // The fit ran below the plans (fits at interactive priority starved them).
  const auto metrics = client.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(test::metric(metrics->body, R"(slosh_pool_tasks_started_total{priority="background"})"),
            1);
  EXPECT_EQ(
      test::metric(metrics->body, R"(slosh_pool_tasks_started_total{priority="interactive"})"), 0);
  auto got = client.Get("/v1/calibrations/bench-2026-11");
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_EQ(json::parse(got->body), fit);
  auto missing = client.Get("/v1/calibrations/nope");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);

  auto plan = [&](const json& model) {
    auto r = client.Post("/v1/plans", plan_body({{"model", model}}).dump(), "application/json");
    EXPECT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body);
  };
  const json by_name = plan("bench-2026-11");
  const json inline_model = plan(fit["model"]);
  EXPECT_EQ(by_name["key"], inline_model["key"]);
  EXPECT_EQ(by_name["law"], inline_model["law"]);
  EXPECT_NE(by_name["key"], plan(json::object())["key"]);
  const json batch = {{"requests", json::array({plan_body({{"model", "bench-2026-11"}}),
                                                plan_body({{"model", "nope"}})})}};
  auto batched = client.Post("/v1/plans/batch", batch.dump(), "application/json");
  ASSERT_TRUE(batched);
  ASSERT_EQ(batched->status, 200) << batched->body;
  const json items = json::parse(batched->body);
  EXPECT_EQ(items["results"][0]["plan"]["key"], inline_model["key"]) << batched->body;
  EXPECT_EQ(items["results"][1]["error"]["field"], "requests[1].options.model") << batched->body;
  auto unknown =
      client.Post("/v1/plans", plan_body({{"model", "nope"}}).dump(), "application/json");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(json::parse(unknown->body)["error"]["field"], "options.model");
  server.stop();
}

// Only a fit that converged is stored: one stopped by its iteration cap answers with its numbers
// and "stored": false saying why, and a plan naming it finds no such calibration.
TEST(CalibrationService, AFitThatDidNotConvergeIsNotStored) {
  test::Server server;
  httplib::Client client = server.client();
  json body = calibration_body();
  body["name"] = "capped";
  body["fit"] = {{"max_iterations", 1}};
  auto posted = client.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 200) << posted->body;
  const json fit = json::parse(posted->body);
  ASSERT_EQ(fit["status"], "max_iterations") << posted->body;
  EXPECT_EQ(fit["stored"], false);
  EXPECT_EQ(fit["not_stored"],
            "the fit did not converge (status max_iterations after 1 iterations, sigma " +
                api::number_text(fit["sigma_mm"].get<double>()) +
                " mm): a plan naming it would apply parameters the fit did not settle, so it is "
                "not stored; raise fit.max_iterations or check the moves, then calibrate again");
  auto got = client.Get("/v1/calibrations/capped");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->status, 404);
  auto plan = client.Post("/v1/plans", plan_body({{"model", "capped"}}).dump(), "application/json");
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->status, 404);
  // The same body converged: stored, and said so.
  body.erase("fit");
  auto stored = client.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 200) << stored->body;
  EXPECT_EQ(json::parse(stored->body)["stored"], true);
  EXPECT_TRUE(json::parse(stored->body)["not_stored"].is_null());
  auto now = client.Get("/v1/calibrations/capped");
  ASSERT_TRUE(now);
  EXPECT_EQ(now->status, 200);
  server.stop();
}

// A batch job (POST /v1/batches) names a stored calibration as POST /v1/plans does: its row plans
// with the stored model (the key of the inline model), an unknown name fails its own row only.
TEST(CalibrationService, ABatchJobNamingAStoredCalibrationPlansWithIt) {
  test::Server server;
  httplib::Client client = server.client();
  json body = calibration_body();
  body["name"] = "bench-2026-11";
  auto posted = client.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(posted && posted->status == 200) << (posted ? posted->body : "");
  const json fit = json::parse(posted->body);
  auto inline_plan =
      client.Post("/v1/plans", plan_body({{"model", fit["model"]}}).dump(), "application/json");
  ASSERT_TRUE(inline_plan && inline_plan->status == 200);
  const std::string key = json::parse(inline_plan->body)["key"].get<std::string>();
  const json job = {{"requests", json::array({plan_body({{"model", "bench-2026-11"}}),
                                              plan_body({{"model", "nope"}})})}};
  auto started = client.Post("/v1/batches", job.dump(), "application/json");
  ASSERT_TRUE(started);
  ASSERT_EQ(started->status, 202) << started->body;
  const std::string id = json::parse(started->body)["id"].get<std::string>();
  json record;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  do {
    auto r = client.Get("/v1/batches/" + id);
    ASSERT_TRUE(r && r->status == 200);
    record = json::parse(r->body);
    if (record["state"] == "done") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  } while (std::chrono::steady_clock::now() < deadline);
  ASSERT_EQ(record["state"], "done") << record.dump();
  const json& rows = record["results"]["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["status"], "optimal") << rows[0].dump();
  EXPECT_EQ(rows[0]["key"], key) << rows[0].dump();
  EXPECT_EQ(rows[1]["status"], "error");
  EXPECT_EQ(rows[1]["error_field"], "options.model") << rows[1].dump();
  server.stop();
}

}  // namespace test_calibration_api
}  // namespace slosh
