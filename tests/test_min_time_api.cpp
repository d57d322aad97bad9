// POST /v1/min-time against a real `slosh serve` and `slosh min-time` as a real process:
// the JSON equals the in-process API, the cache, and the exact texts of bad input.

#include <httplib.h>

#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_min_time_api {

using nlohmann::json;
using test::run_slosh;
using test::RunResult;

json thesis_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001, "name": "thesis_water"},
               "stroke_mm": 800},
    "free_board_margin_mm": 0, "eta_rest_max_mm": 3,
    "strategies": ["baseline", "shaper"]
  })");
}

/// The response without its wall-clock figures (search_ms, solve_ms), which differ run to run.
json without_timings(json j) {
  if (j.is_object()) {
    j.erase("search_ms");
    j.erase("solve_ms");
    for (auto& [key, value] : j.items()) value = without_timings(value);
  } else if (j.is_array()) {
    for (auto& value : j) value = without_timings(value);
  }
  return j;
}

json in_process(const json& body) {
  return api::run_min_time(api::parse_min_time_request(body, 600.0));
}

/// (field, message) of the 422 the parser gives `body`.
std::pair<std::string, std::string> refusal(const json& body) {
  try {
    (void)api::parse_min_time_request(body, 10.0);
  } catch (const api::ApiError& e) {
    return {e.field(), e.what()};
  }
  return {"", "accepted"};
}

TEST(MinTimeApi, ResponseCarriesEachStrategyAndTheHeadline) {
  const json r = in_process(thesis_request());
  ASSERT_EQ(r["strategies"].size(), 2u);
  const json& base = r["strategies"][0];
  const json& shaper = r["strategies"][1];
  EXPECT_EQ(base["strategy"], "baseline");
  // At the uniform law's T_min the linear model's wave in motion is over the 68 mm free board
  // (the limit holds on the nonlinear model): its plan spills, so baseline is acceptable, saying
  // why, and the headline goes to the strategy whose T_min plan is optimal (SPEC §5).
  const bool base_spills =
      base["plan"]["prediction"]["linear"]["eta_motion_mm"].get<double>() > 68.0;
  const bool shaper_spills =
      shaper["plan"]["prediction"]["linear"]["eta_motion_mm"].get<double>() > 68.0;
  ASSERT_TRUE(base_spills);
  EXPECT_EQ(base["status"], "acceptable");
  EXPECT_TRUE(base["message"].get<std::string>().starts_with(
      "not optimal: the plan at T_min is not (the predicted sloshing exceeds the free board "
      "(liquid will spill)"))
      << base["message"];
  EXPECT_EQ(shaper["status"], shaper_spills ? "acceptable" : "optimal") << shaper["message"];
  // The plan at T_min is the plan of that motion time, and the curve is the planned T's.
  const double t = shaper["t_min_s"];
  EXPECT_NEAR(shaper["plan"]["format"]["motion_time_s"].get<double>(), t, 1e-12);
  EXPECT_EQ(shaper["plan"]["strategy"], "shaper");
  EXPECT_EQ(shaper["curve"]["t_s"].size(), shaper["plans"].get<std::size_t>());
  EXPECT_NEAR(r["limits"]["eta_motion_max_mm"].get<double>(), 68.0, 1e-9);
  const double tb = base["t_min_s"];
  const double tw = shaper_spills ? std::min(t, tb) : t;
  EXPECT_EQ(r["headline"]["winner"], tw == t ? "shaper" : "baseline");
  EXPECT_EQ(r["headline"]["not_optimal"].is_null(), !shaper_spills);
  EXPECT_NEAR(r["headline"]["gain_pct"].get<double>(), 100.0 * (tb - tw) / tb, 1e-9);
  EXPECT_NEAR(r["headline"]["gain_cycles_per_min"].get<double>(), 60.0 / tw - 60.0 / tb, 1e-9);
  EXPECT_FALSE(r.contains("format") && r["format"].contains("motion_time_s"));
}

TEST(MinTimeApi, KeyIgnoresSpellingAndBudgetButNotTheLimits) {
  json a = thesis_request();
  json b = thesis_request();
  b["options"] = {{"time_limit_s", 3}};
  b["eta_rest_max_mm"] = 3.0;
  EXPECT_EQ(api::min_time_key(api::parse_min_time_request(a, 10.0)),
            api::min_time_key(api::parse_min_time_request(b, 10.0)));
  b["eta_rest_max_mm"] = 2.5;
  EXPECT_NE(api::min_time_key(api::parse_min_time_request(a, 10.0)),
            api::min_time_key(api::parse_min_time_request(b, 10.0)));
}

TEST(MinTimeApi, BadInputIsRefusedNamingFieldValueAndRange) {
  struct Case {
    json patch;  // merged into the thesis request
    std::string field, message;
  };
  const std::vector<Case> cases{
      {{{"format", {{"motion_time_s", 1.0}}}},
       "format.motion_time_s",
       "format.motion_time_s is not part of a min-time request: the search finds the motion "
       "time; bound it with motion_time_max_s (default 5 s)"},
      {{{"strategies", {"auto"}}},
       "strategies[0]",
       "strategies[0] = \"auto\" is not allowed: one of \"baseline\", \"notch\", "
       "\"multi_notch\", \"min_jerk_band\", \"time_domain\", \"fir_chain\", \"shaper\", \"iir\" "
       "(auto is not searched: the response compares the strategies)"},
      {{{"strategies", {"shaper", "shaper"}}},
       "strategies[1]",
       "strategies[1] = \"shaper\" is listed twice"},
      {{{"eta_rest_max_mm", -1}},
       "eta_rest_max_mm",
       "eta_rest_max_mm = -1 is out of range: allowed > 0 and <= 10000 mm"},
      {{{"motion_time_max_s", 100}},
       "motion_time_max_s",
       "motion_time_max_s = 100 is out of range: allowed 0.05 to 60 s"},
      {{{"free_board_margin_mm", 70}},
       "free_board_margin_mm",
       "free_board_margin_mm = 70 leaves no eta_motion_max: the free board (height_mm - "
       "fill_height_mm) is 68 mm; allowed below it, or give eta_motion_max_mm"},
      {{{"limit_model", "quadratic"}},
       "limit_model",
       "limit_model = \"quadratic\" is not allowed: one of \"nonlinear\", \"linear\", \"both\""},
      {{{"max_plans", 2}},
       "max_plans",
       "max_plans = 2 is out of range: allowed an integer from 3 to 1000"},
      {{{"options", {{"eta_rest_max_mm", 2}}}},
       "options.eta_rest_max_mm",
       "options.eta_rest_max_mm is not an option of a min-time request: give the limit as "
       "eta_rest_max_mm at the top level"},
      {{{"options", {{"time_limit_s", 20}}}},
       "options.time_limit_s",
       "options.time_limit_s = 20 is out of range: this server allows at most 10 s"},
      {{{"options", {{"min_ramp_s", 16}}}},
       "options.min_ramp_s",
       "options.min_ramp_s = 16 is out of range: allowed 0.001 to 15 s (the upper bound is the "
       "longest motion time a search plans (60 s) / 4: four ramps must fit)"},
      {{{"options", {{"time_limit_s", 0}}}},
       "options.time_limit_s",
       "options.time_limit_s = 0 is out of range: allowed > 0 and <= 10 s (this server's "
       "budget)"},
      {{{"options", {{"limits", {{"a_max", 0}}}}}},
       "options.limits.a_max",
       "options.limits.a_max = 0 is out of range: allowed > 0 and <= 1000 m/s^2"},
  };
  for (const Case& c : cases) {
    json body = thesis_request();
    body.merge_patch(c.patch);
    SCOPED_TRACE(c.patch.dump());
    const auto [field, message] = refusal(body);
    EXPECT_EQ(field, c.field);
    EXPECT_EQ(message, c.message);
  }
  json no_height = thesis_request();
  no_height["format"]["container"].erase("height_mm");
  EXPECT_EQ(refusal(no_height).second,
            "eta_motion_max_mm is required when format.container.height_mm is not given (its "
            "default is the free board: height_mm - fill_height_mm - free_board_margin_mm)");
  no_height["eta_motion_max_mm"] = 40;
  EXPECT_EQ(refusal(no_height).second, "accepted");
}

TEST(MinTimeApi, RealServerAnswersAsTheApiCachesAndRefusesBadInput) {
  test::Server server;
  auto client = server.client();
  const json body = thesis_request();
  const auto first = client.Post("/v1/min-time", body.dump(), "application/json");
  ASSERT_TRUE(first) << httplib::to_string(first.error()) << "\n" << server.log();
  ASSERT_EQ(first->status, 200) << first->body;
  EXPECT_EQ(first->get_header_value("X-Cache"), "miss");
  const json j = json::parse(first->body);
  EXPECT_EQ(without_timings(j), without_timings(in_process(body)));
  const auto second = client.Post("/v1/min-time", body.dump(), "application/json");
  ASSERT_TRUE(second);
  EXPECT_EQ(second->get_header_value("X-Cache"), "hit");
  json cached = json::parse(second->body);
  EXPECT_TRUE(cached["cached"].get<bool>());
  cached["cached"] = false;
  EXPECT_EQ(cached, j);
  httplib::Headers tag{{"If-None-Match", first->get_header_value("ETag")}};
  const auto not_modified = client.Post("/v1/min-time", tag, body.dump(), "application/json");
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);

  json bad = body;
  bad["eta_rest_max_mm"] = 0;
  const auto refused = client.Post("/v1/min-time", bad.dump(), "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 422);
  EXPECT_EQ(json::parse(refused->body),
            json::parse(R"({"error": {"code": "invalid_value", "field": "eta_rest_max_mm",
              "message": "eta_rest_max_mm = 0 is out of range: allowed > 0 and <= 10000 mm"}})"));
  const auto budget = client.Post(
      "/v1/min-time", json::parse(R"({"format": {}, "options": {"time_limit_s": 11}})").dump(),
      "application/json");
  ASSERT_TRUE(budget);
  EXPECT_EQ(budget->status, 422);
}

TEST(MinTimeApi, FullQueueAnswers503WithRetryAfter) {
  // One worker and room for one queued task: a search of two strategies that no T satisfies
  // (eta_motion <= 0.01 mm, up to 1 000 plans each) holds both while a second search arrives.
  // (An idle pool would run a search of more strategies than workers + queue in turns: only a
  // busy pool answers 503.)
  test::Server server({"--workers", "1", "--queue", "1"});
  json busy = thesis_request();
  busy["strategies"] = {"time_domain", "multi_notch"};
  busy["eta_motion_max_mm"] = 0.01;
  busy["max_plans"] = 1000;
  busy["scan_step_s"] = 0.001;
  test::Raw holder(server.port());
  const std::string text = busy.dump();
  ASSERT_TRUE(
      holder.send("POST /v1/min-time HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                  "application/json\r\nContent-Length: " +
                  std::to_string(text.size()) + "\r\n\r\n" + text));
  bool holding = false;
  for (int i = 0; i < 6000 && !holding; ++i) {
    const auto m = server.client().Get("/metrics");
    holding = m && test::metric(m->body, "slosh_busy_workers") == 1 &&
              test::metric(m->body, "slosh_queue_depth") == 1;
    if (!holding) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(holding) << server.log();
  auto client = server.client();
  const auto r = client.Post("/v1/min-time", thesis_request().dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 503) << r->body;
  EXPECT_EQ(r->get_header_value("Retry-After"), "1");
  EXPECT_EQ(json::parse(r->body)["error"]["code"], "overloaded");
}

// More strategies than workers + queue on an idle pool: run in turns, never a 503 that no retry
// could cure.
TEST(MinTimeApi, MoreStrategiesThanThePoolHoldsRunInTurns) {
  test::Server server({"--workers", "1", "--queue", "1"});
  json body = thesis_request();
  body.erase("strategies");  // every strategy but iir: seven tasks
  const auto r = server.client().Post("/v1/min-time", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
  EXPECT_EQ(json::parse(r->body)["strategies"].size(), 7u);
}

TEST(MinTimeApi, CliPrintsTheResponseFromAFileAndStdinAndRefusesBadInput) {
  const test::TempDir dir;
  json body = thesis_request();
  body["strategies"] = {"shaper"};
  test::write_file(dir / "request.json", body.dump());
  const RunResult from_file = run_slosh({"min-time", "--request", (dir / "request.json").string()});
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  const json j = json::parse(from_file.out);
  EXPECT_EQ(without_timings(j), without_timings(in_process(body)));
  const RunResult from_stdin = run_slosh({"min-time", "--request", "-"}, body.dump());
  ASSERT_EQ(from_stdin.exit_code, 0) << from_stdin.err;
  EXPECT_EQ(without_timings(json::parse(from_stdin.out)), without_timings(j));

  body["format"]["motion_time_s"] = 1.0;
  const RunResult bad = run_slosh({"min-time", "--request", "-"}, body.dump());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(json::parse(bad.err),
            json::parse(R"j({"error": {"code": "invalid_value", "field": "format.motion_time_s",
              "message": "format.motion_time_s is not part of a min-time request: the search finds the motion time; bound it with motion_time_max_s (default 5 s)"}})j"));
  EXPECT_TRUE(bad.out.empty());
}

}  // namespace test_min_time_api
}  // namespace slosh

namespace slosh {
namespace test_min_time_api {

TEST(MinTimeApi, BatchMinTimeModeWritesTMinPerStrategyWinnerAndGainPerRecipe) {
  const test::TempDir dir;
  test::write_file(dir / "recipes.csv",
                   "recipe_id,radius_mm,container_height_mm,fill_height_mm,fluid,stroke_mm,"
                   "motion_time_s,strategy,eta_rest_max_mm\n"
                   "thesis,48.5,150,82,water,800,2,,3\n"
                   "bad,48.5,150,82,water,-5,1.5,,\n");
  // The budget of the in-process reference: the searches finish on a slow (sanitizer) build too,
  // so both sides compare finished searches.
  test::write_file(dir / "slosh.json", R"({"solve_budget_s": 600})");
  const RunResult r =
      run_slosh({"batch", "--mode", "min_time", "--in", (dir / "recipes.csv").string(), "--out",
                 (dir / "out.jsonl").string(), "--workers", "2", "--config",
                 (dir / "slosh.json").string(), "--cache", (dir / "plans.sqlite").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.err, "slosh batch: row 2 could not be searched: see the message of the row\n");
  std::vector<json> rows;
  std::istringstream lines(test::read_file(dir / "out.jsonl"));
  for (std::string line; std::getline(lines, line);) rows.push_back(json::parse(line));
  ASSERT_EQ(rows.size(), 2u);
  // The good row equals the in-process search of the equivalent min-time request.
  const json reference = in_process(json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "motion_time_max_s": 2, "eta_rest_max_mm": 3})"));
  const json& good = rows[0];
  EXPECT_EQ(good["status"], "ok");
  EXPECT_EQ(good["recipe_id"], "thesis");
  EXPECT_EQ(good["key"], reference["key"]);
  ASSERT_EQ(reference["strategies"].size(), 7u);
  for (const json& s : reference["strategies"]) {
    EXPECT_EQ(good["t_min_" + s["strategy"].get<std::string>() + "_s"], s["t_min_s"])
        << s["strategy"];
  }
  EXPECT_EQ(good["winner"], reference["headline"]["winner"]);
  EXPECT_EQ(good["gain_pct"], reference["headline"]["gain_pct"]);
  EXPECT_EQ(good["gain_cycles_per_min"], reference["headline"]["gain_cycles_per_min"]);
  const json& bad = rows[1];
  EXPECT_EQ(bad["status"], "error");
  EXPECT_EQ(bad["message"], "stroke_mm = -5 is out of range: allowed 0.01 to 100000 mm");
  EXPECT_EQ(bad["error_field"], "stroke_mm");
}

}  // namespace test_min_time_api
}  // namespace slosh

namespace slosh {
namespace test_min_time_api {

// Regression: an in-range motion_time_max_s shorter than the ramps was a 422 on "options".
TEST(MinTimeApi, ASearchRangeShorterThanTheRampsIsAnInfeasibleAnswerNotA422) {
  nlohmann::json body = thesis_request();
  body["motion_time_max_s"] = 0.05;
  const nlohmann::json r = in_process(body);
  ASSERT_EQ(r["strategies"].size(), 2u);
  for (const auto& s : r["strategies"]) {
    EXPECT_EQ(s["status"], "infeasible");
    EXPECT_EQ(s["plans"], 0);
    EXPECT_NE(s["message"].get<std::string>().find("needs at least 0.200 s"), std::string::npos);
  }
  // A plan option that is wrong at every T is still refused naming it.
  body["options"] = {{"plateau_min_s", {-1, 0}}};
  try {
    (void)api::parse_min_time_request(body, 10.0);
    ADD_FAILURE() << "no error";
  } catch (const api::ApiError& e) {
    EXPECT_EQ(e.field(), "options.plateau_min_s[0]");
  }
}

}  // namespace test_min_time_api
}  // namespace slosh

namespace slosh {
namespace test_min_time_api {

// Regression: the default free board came out as 67.99999999999999 mm (metres subtracted),
// so it did not share the key of the same explicit limit.
TEST(MinTimeApi, TheDefaultFreeBoardIsTheExplicitLimitInMillimetres) {
  nlohmann::json by_default = thesis_request();
  by_default["free_board_margin_mm"] = 0;
  by_default.erase("eta_motion_max_mm");
  nlohmann::json explicit_limit = by_default;
  explicit_limit.erase("free_board_margin_mm");
  explicit_limit["eta_motion_max_mm"] = 150 - 82;
  const api::MinTimeRequest a = api::parse_min_time_request(by_default, 10.0);
  const api::MinTimeRequest b = api::parse_min_time_request(explicit_limit, 10.0);
  EXPECT_EQ(*a.options.eta_motion_limit(a.format), 68e-3);
  EXPECT_EQ(api::min_time_key(a), api::min_time_key(b));
  by_default["free_board_margin_mm"] = 5;  // 150 - 82 - 5
  const api::MinTimeRequest c = api::parse_min_time_request(by_default, 10.0);
  EXPECT_EQ(*c.options.eta_motion_limit(c.format), 63e-3);
}

}  // namespace test_min_time_api
}  // namespace slosh

namespace slosh {
namespace test_min_time_api {

// Hostile re-test: explicit ramp options were checked at motion_time_max_s (a 422 citing
// format.motion_time_s), non-integer free boards missed the explicit limit's key, and a 100 m
// stroke with limit_model linear still put the diverged nonlinear model into the curve (a 500).
TEST(MinTimeApi, ExplicitRampsLongerThanTheSearchRangeAreAnInfeasibleAnswer) {
  nlohmann::json body = thesis_request();
  body["motion_time_max_s"] = 1;
  body["options"] = {{"plateau_min_s", {2, 0}}};
  const nlohmann::json plateaus = in_process(body);  // kept: the loop refers into it
  for (const auto& s : plateaus["strategies"]) {
    EXPECT_EQ(s["status"], "infeasible");
    EXPECT_NE(s["message"].get<std::string>().find("needs at least 2.200 s"), std::string::npos)
        << s["message"];
  }
  body["motion_time_max_s"] = 0.1;
  body["options"] = {{"min_ramp_s", 0.05}};
  const nlohmann::json ramps = in_process(body);
  for (const auto& s : ramps["strategies"]) {
    EXPECT_NE(s["message"].get<std::string>().find("needs at least 0.200 s"), std::string::npos)
        << s["message"];
  }
}

TEST(MinTimeApi, ADefaultFreeBoardWithRoundOffSharesTheExplicitLimitsKey) {
  nlohmann::json by_default = thesis_request();
  by_default["format"]["container"]["height_mm"] = 150.3;
  by_default["format"]["fill_height_mm"] = 82.1;
  by_default["free_board_margin_mm"] = 5.7;
  by_default.erase("eta_motion_max_mm");
  nlohmann::json explicit_limit = by_default;
  explicit_limit.erase("free_board_margin_mm");
  explicit_limit["eta_motion_max_mm"] = 62.5;
  const api::MinTimeRequest a = api::parse_min_time_request(by_default, 10.0);
  const api::MinTimeRequest b = api::parse_min_time_request(explicit_limit, 10.0);
  EXPECT_EQ(*a.options.eta_motion_limit(a.format), *b.options.eta_motion_limit(b.format));
  EXPECT_EQ(api::min_time_key(a), api::min_time_key(b));
}

TEST(MinTimeApi, ADivergingModelLeavesNoNonFiniteNumberWhateverTheLimitModel) {
  nlohmann::json body = thesis_request();
  body["format"]["stroke_mm"] = 100000;
  body["limit_model"] = "linear";
  body["motion_time_max_s"] = 0.5;
  body["strategies"] = {"shaper"};
  const nlohmann::json r = in_process(body);  // rendering throws on a non-finite number
  const auto& s = r["strategies"][0];
  EXPECT_LT(s["curve"]["t_s"].size(), s["plans"].get<std::size_t>());
}

}  // namespace test_min_time_api
}  // namespace slosh
