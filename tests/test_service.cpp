// The HTTP service end to end: the real `slosh serve` on a free loopback port with a real SQLite
// cache file, talked to over HTTP. Every endpoint, every error class, cache hit after miss and
// across a restart, identical concurrent requests solved once, a full queue answering 503,
// graceful shutdown finishing a solve in flight.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/format_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_service {

using nlohmann::json;
using test::Child;
using test::read_file;
using test::Server;
using test::TempDir;
using test::write_file;

json plan_body(const std::string& strategy, double stroke_mm = 800, double time_s = 1.0) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  body["format"]["stroke_mm"] = stroke_mm;
  body["format"]["motion_time_s"] = time_s;
  return body;
}

json parse(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "not JSON: " << text.substr(0, 300);
  }
  return json::object();
}

using test::metric;

TEST(Service, PlanIsSolvedThenServedFromTheCacheWithAnETag) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  const std::string body = plan_body("multi_notch").dump();
  const auto first = client.Post("/v1/plans", body, "application/json");
  ASSERT_TRUE(first) << httplib::to_string(first.error());
  ASSERT_EQ(first->status, 200) << first->body;
  const json a = parse(first->body);
  EXPECT_EQ(a["cached"], false);
  EXPECT_EQ(a["status"], "optimal");
  EXPECT_EQ(first->get_header_value("ETag"), "\"" + a["key"].get<std::string>() + "\"");
  EXPECT_EQ(first->get_header_value("X-Cache"), "miss");
  // The same JSON as the CLI / in-process API (but the timing).
  json in_process = api::run_plan(api::parse_plan_request(plan_body("multi_notch")));
  EXPECT_EQ(a["durations_s"], in_process["durations_s"]);
  EXPECT_EQ(a["key"], in_process["key"]);

  const auto second = client.Post("/v1/plans", body, "application/json");
  ASSERT_TRUE(second);
  ASSERT_EQ(second->status, 200);
  const json b = parse(second->body);
  EXPECT_EQ(b["cached"], true);
  EXPECT_EQ(second->get_header_value("X-Cache"), "hit");
  EXPECT_EQ(b["durations_s"], a["durations_s"]);
  EXPECT_EQ(b["solver"], a["solver"]);  // the stored plan, not a new solve

  const std::string key = a["key"];
  const auto got = client.Get("/v1/plans/" + key);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->status, 200);
  EXPECT_EQ(parse(got->body), b);
  const auto not_modified = client.Get("/v1/plans/" + key, {{"If-None-Match", "\"" + key + "\""}});
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);

  const std::string metrics = client.Get("/metrics")->body;
  EXPECT_EQ(metric(metrics, R"(slosh_http_requests_total{route="/v1/plans",status="200"})"), 2);
  EXPECT_EQ(metric(metrics, R"(slosh_solve_seconds_count{strategy="multi_notch"})"), 1);
  EXPECT_GE(metric(metrics, R"(slosh_cache_hits_total{level="memory"})"), 2);
  EXPECT_EQ(metric(metrics, "slosh_cache_misses_total"), 1);
  EXPECT_EQ(metric(metrics, "slosh_queue_depth"), 0);
  // One structured log line per request, with its id, route, status and cache outcome.
  ASSERT_EQ(server.stop(), 0);
  EXPECT_TRUE(std::regex_search(
      server.log(),
      std::regex(R"(request id=\d+ method=POST path=/v1/plans status=200 cache=hit)")))
      << server.log();
}

TEST(Service, SimulateFluidsOpenApiHealthAndReadiness) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  json sim = plan_body("x");
  sim.erase("strategy");
  sim["law"] = {{"type", "poly5"}};
  const auto r = client.Post("/v1/simulate", sim.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(parse(r->body), api::run_simulate(api::parse_simulate_request(sim)));
  const auto fluids = client.Get("/v1/fluids");
  ASSERT_TRUE(fluids);
  EXPECT_EQ(parse(fluids->body), api::fluids_json());
  const auto spec = client.Get("/v1/openapi.json");
  ASSERT_TRUE(spec);
  const json doc = parse(spec->body);
  EXPECT_EQ(doc["openapi"], "3.0.3");
  for (const char* path : {"/v1/plans", "/v1/plans/{key}", "/v1/plans/batch", "/v1/simulate",
                           "/v1/fluids", "/healthz", "/readyz", "/metrics"}) {
    EXPECT_TRUE(doc["paths"].contains(path)) << path;
  }
  EXPECT_EQ(client.Get("/healthz")->status, 200);
  const auto ready = client.Get("/readyz");
  EXPECT_EQ(ready->status, 200);
  EXPECT_EQ(parse(ready->body)["status"], "ready");
  EXPECT_EQ(parse(ready->body)["cache"]["persistent"], true);
}

TEST(Service, EveryErrorClassHasTheEnvelope) {
  TempDir dir;
  write_file(dir / "config.json", R"({"max_body_bytes": 4096, "solve_budget_s": 2})");
  Server server({"--config", (dir / "config.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  auto expect_error = [&](const httplib::Result& r, int status, const std::string& code,
                          const json& field) {
    ASSERT_TRUE(r) << httplib::to_string(r.error());
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
    const json e = parse(r->body);
    ASSERT_TRUE(e.contains("error")) << r->body;
    EXPECT_EQ(e["error"]["code"], code) << r->body;
    EXPECT_EQ(e["error"]["field"], field) << r->body;
    EXPECT_FALSE(e["error"]["message"].get<std::string>().empty());
  };
  expect_error(client.Post("/v1/plans", "{\"format\": ", "application/json"), 400, "malformed_json",
               nullptr);
  json bad = plan_body("notch");
  bad["format"]["stroke_mm"] = -5;
  expect_error(client.Post("/v1/plans", bad.dump(), "application/json"), 422, "invalid_value",
               "format.stroke_mm");
  json budget = plan_body("notch");
  budget["options"] = {{"time_limit_s", 3}};
  const auto over = client.Post("/v1/plans", budget.dump(), "application/json");
  expect_error(over, 422, "invalid_value", "options.time_limit_s");
  EXPECT_EQ(parse(over->body)["error"]["message"],
            "options.time_limit_s = 3 is out of range: this server allows at most 2 s");
  // Below the API's own range too, the range said is this server's.
  budget["options"] = {{"time_limit_s", -1}};
  const auto negative = client.Post("/v1/plans", budget.dump(), "application/json");
  expect_error(negative, 422, "invalid_value", "options.time_limit_s");
  EXPECT_EQ(parse(negative->body)["error"]["message"],
            "options.time_limit_s = -1 is out of range: allowed > 0 and <= 2 s (this server's "
            "budget)");
  expect_error(client.Get("/v1/plans/0123456789abcdef0123456789abcdef"), 404, "not_found", "key");
  expect_error(client.Get("/v1/nothing"), 404, "not_found", nullptr);
  expect_error(client.Post("/v1/plans", std::string(5000, ' '), "application/json"), 413,
               "payload_too_large", nullptr);
  // The service still answers after all of them.
  EXPECT_EQ(client.Get("/healthz")->status, 200);
}

TEST(Service, CacheSurvivesARestartOnTheSameSqliteFile) {
  TempDir dir;
  std::string key;
  json first;
  {
    Server a({}, &dir);
    ASSERT_GT(a.port(), 0) << a.log();
    const auto r = a.client().Post("/v1/plans", plan_body("notch").dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200);
    first = parse(r->body);
    key = first["key"];
    ASSERT_EQ(a.stop(), 0);
  }
  Server b({}, &dir);
  ASSERT_GT(b.port(), 0) << b.log();
  const auto got = b.client().Get("/v1/plans/" + key);
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200) << got->body;
  json again = parse(got->body);
  EXPECT_EQ(again["cached"], true);
  again["cached"] = false;
  EXPECT_EQ(again, first);
}

TEST(Service, ACorruptCacheFileIsReportedAndTheServiceAnswersFromMemory) {
  TempDir dir;
  write_file(dir / "plans.sqlite", std::string(4096, 'x'));  // not a database
  Server server({}, &dir);
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  const json ready = parse(client.Get("/readyz")->body);
  EXPECT_EQ(ready["cache"]["persistent"], false);
  EXPECT_NE(ready["cache"]["storage_error"].get<std::string>().find("plans.sqlite"),
            std::string::npos);
  const std::string body = plan_body("notch").dump();
  EXPECT_EQ(parse(client.Post("/v1/plans", body, "application/json")->body)["cached"], false);
  EXPECT_EQ(parse(client.Post("/v1/plans", body, "application/json")->body)["cached"], true);
  EXPECT_EQ(read_file(dir / "plans.sqlite"), std::string(4096, 'x'));  // left untouched
  ASSERT_EQ(server.stop(), 0);
  EXPECT_NE(server.log().find("answering from memory only"), std::string::npos) << server.log();
}

TEST(Service, IdenticalConcurrentRequestsAreSolvedOnce) {
  Server server({"--workers", "2"});
  ASSERT_GT(server.port(), 0) << server.log();
  const std::string body = plan_body("time_domain", 800, 0.9).dump();
  std::vector<std::future<json>> replies;
  for (int i = 0; i < 6; ++i) {
    replies.push_back(std::async(std::launch::async, [&] {
      auto client = server.client();
      const auto r = client.Post("/v1/plans", body, "application/json");
      return r && r->status == 200 ? json::parse(r->body) : json();
    }));
  }
  json durations;
  for (auto& f : replies) {
    const json r = f.get();
    ASSERT_TRUE(r.contains("durations_s"));
    if (durations.is_null()) durations = r["durations_s"];
    EXPECT_EQ(r["durations_s"], durations);
  }
  const std::string metrics = server.client().Get("/metrics")->body;
  EXPECT_EQ(metric(metrics, R"(slosh_solve_seconds_count{strategy="time_domain"})"), 1) << metrics;
}

TEST(Service, AFullQueueAnswers503WithRetryAfter) {
  Server server({"--workers", "1", "--queue", "1"});
  ASSERT_GT(server.port(), 0) << server.log();
  std::vector<std::future<std::pair<int, std::string>>> replies;
  for (int i = 0; i < 6; ++i) {
    replies.push_back(std::async(std::launch::async, [&, i] {
      auto client = server.client();
      const auto r =
          client.Post("/v1/plans", plan_body("auto", 800 + i, 0.9).dump(), "application/json");
      if (!r) return std::pair<int, std::string>{-1, ""};
      const std::string retry = r->get_header_value("Retry-After");
      return std::pair<int, std::string>{r->status, r->status == 503 ? retry + " " + r->body : ""};
    }));
  }
  int ok = 0, refused = 0;
  for (auto& f : replies) {
    const auto [status, detail] = f.get();
    if (status == 200) ++ok;
    if (status == 503) {
      ++refused;
      EXPECT_EQ(detail.substr(0, 2), "1 ") << detail;
      EXPECT_NE(detail.find("\"code\":\"overloaded\""), std::string::npos) << detail;
    }
  }
  EXPECT_GE(ok, 1);
  EXPECT_GE(refused, 1);
  EXPECT_EQ(ok + refused, 6);
}

TEST(Service, ARequestQueuedPastItsWaitAnswers504) {
  TempDir dir;
  write_file(dir / "config.json", R"({"workers": 1, "queue": 8, "queue_wait_s": 0.001})");
  Server server({"--config", (dir / "config.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  // One slow solve occupies the only worker; the next request waits behind it past its budget
  // (0.001 s) plus the allowed queue wait (0.001 s).
  json slow = plan_body("auto", 800, 0.9);
  slow["options"] = {{"rest_time_s", 5}};
  auto first = std::async(std::launch::async, [&] {
    return server.client().Post("/v1/plans", slow.dump(), "application/json");
  });
  // The quick request is sent once the slow solve holds the worker (a fixed 20 ms raced the slow
  // request's arrival on a loaded machine: the quick one then took the worker and answered 200).
  bool solving = false;
  for (int i = 0; i < 1000 && !solving; ++i) {
    const auto m = server.client().Get("/metrics");
    solving = m && m->body.find("\nslosh_busy_workers 0\n") == std::string::npos &&
              m->body.find("\nslosh_busy_workers ") != std::string::npos;
    if (!solving) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(solving) << "the slow plan never reached a worker";
  json quick = plan_body("notch");
  quick["options"] = {{"time_limit_s", 0.001}};
  const auto r = server.client().Post("/v1/plans", quick.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 504) << r->body;
  EXPECT_EQ(parse(r->body)["error"]["code"], "timeout");
  EXPECT_EQ(first.get()->status, 200);
}

TEST(Service, SigtermFinishesTheSolveInFlight) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  json slow = plan_body("auto", 800, 0.9);
  slow["options"] = {{"rest_time_s", 5}};
  auto reply = std::async(std::launch::async, [&] {
    auto client = server.client();
    const auto r = client.Post("/v1/plans", slow.dump(), "application/json");
    return r ? r->status : -1;
  });
  // SIGTERM once the solve runs (a fixed 30 ms raced the request's arrival on a loaded machine).
  bool solving = false;
  for (int i = 0; i < 1000 && !solving; ++i) {
    const auto m = server.client().Get("/metrics");
    solving = m && m->body.find("\nslosh_busy_workers 0\n") == std::string::npos &&
              m->body.find("\nslosh_busy_workers ") != std::string::npos;
    if (!solving) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(solving) << "the plan never reached a worker";
  ::kill(server.child().pid(), SIGTERM);
  EXPECT_EQ(reply.get(), 200);
  EXPECT_EQ(server.child().wait_for(std::chrono::seconds(20)), 0) << server.log();
}

TEST(Service, BatchSolvesEachRecipeAndReportsErrorsPerItem) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  json bad = plan_body("notch");
  bad["format"]["stroke_mm"] = 0;
  const json batch{{"requests", {plan_body("notch"), plan_body("multi_notch", 500, 0.7), bad}}};
  const auto r = server.client().Post("/v1/plans/batch", batch.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json out = parse(r->body);
  ASSERT_EQ(out["results"].size(), 3u);
  EXPECT_EQ(out["results"][0]["index"], 0);
  EXPECT_EQ(out["results"][0]["plan"]["strategy"], "notch");
  EXPECT_EQ(out["results"][1]["plan"]["format"]["stroke_mm"], 500.0);
  EXPECT_EQ(out["results"][2]["error"]["field"], "requests[2].format.stroke_mm");
  // The batch filled the cache: the single request is now a hit.
  const auto hit = server.client().Post("/v1/plans", plan_body("notch").dump(), "application/json");
  EXPECT_EQ(parse(hit->body)["cached"], true);
  const auto empty =
      server.client().Post("/v1/plans/batch", R"({"requests": []})", "application/json");
  EXPECT_EQ(empty->status, 422);
}

}  // namespace test_service
}  // namespace slosh
