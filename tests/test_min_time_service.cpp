// POST /v1/min-time as a service: answers kept in the plan store's own table across a
// restart of a real `slosh serve`, identical concurrent requests merged into one search, a
// refused search that wedges nobody, and `slosh batch --mode min_time` locally (with the store)
// and through --server, row by row equal. Real SQLite files, real processes, loopback only.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/server.hpp"
#include "support/sqlite_query.hpp"

namespace slosh {
namespace test_min_time_service {

using nlohmann::json;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::Server;
using test::TempDir;
using test::write_file;

/// The thesis format with cheap strategies (a few tens of ms per search).
json cheap_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "motion_time_max_s": 2, "eta_rest_max_mm": 3,
    "strategies": ["baseline", "fir_chain", "shaper"]
  })");
}

using test::metric;

double server_metric(const Server& server, const std::string& series) {
  const auto r = server.client().Get("/metrics");
  return r ? metric(r->body, series) : -2.0;
}

using test::query;

/// `body` with its leading `{"cached":true,` turned into `{"cached":false,` (the only member a
/// cached reply may differ in).
std::string as_miss(std::string body) {
  const std::string hit = R"({"cached":true,)";
  if (body.rfind(hit, 0) == 0) body.replace(0, hit.size(), R"({"cached":false,)");
  return body;
}

/// POSTs `body` to /v1/min-time from `n` threads released at once; the results in thread order.
std::vector<httplib::Result> post_concurrently(const Server& server, const std::string& body,
                                               int n) {
  std::mutex mutex;
  std::condition_variable go;
  bool released = false;
  std::vector<std::future<httplib::Result>> futures;
  for (int i = 0; i < n; ++i) {
    futures.push_back(std::async(std::launch::async, [&] {
      auto client = server.client();
      {
        std::unique_lock lock(mutex);
        go.wait(lock, [&] { return released; });
      }
      return client.Post("/v1/min-time", body, "application/json");
    }));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // every thread is waiting
  {
    const std::lock_guard lock(mutex);
    released = true;
  }
  go.notify_all();
  std::vector<httplib::Result> results;
  for (auto& f : futures) results.push_back(f.get());
  return results;
}

TEST(MinTimeService, AnswerSurvivesARestartInItsOwnTableByteForByte) {
  const TempDir dir;
  const std::string body = cheap_request().dump();
  std::string first_body;
  std::string key;
  {
    Server server({}, &dir);
    ASSERT_GT(server.port(), 0) << server.log();
    const auto first = server.client().Post("/v1/min-time", body, "application/json");
    ASSERT_TRUE(first);
    ASSERT_EQ(first->status, 200) << first->body;
    EXPECT_EQ(first->get_header_value("X-Cache"), "miss");
    first_body = first->body;
    key = json::parse(first_body)["key"].get<std::string>();
    EXPECT_EQ(first->get_header_value("ETag"), "\"" + key + "\"");
    ASSERT_EQ(server.stop(), 0) << server.log();
  }
  const std::string file = (dir / "plans.sqlite").string();
  EXPECT_EQ(query(file, "PRAGMA user_version"), "4");
  EXPECT_EQ(query(file, "SELECT count(*) FROM min_times WHERE key = '" + key + "'"), "1");
  EXPECT_EQ(query(file, "SELECT count(*) FROM plans"), "0");

  Server restarted({}, &dir);
  ASSERT_GT(restarted.port(), 0) << restarted.log();
  auto client = restarted.client();
  const auto again = client.Post("/v1/min-time", body, "application/json");
  ASSERT_TRUE(again);
  ASSERT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(again->get_header_value("X-Cache"), "hit");
  EXPECT_EQ(again->get_header_value("ETag"), "\"" + key + "\"");
  EXPECT_TRUE(json::parse(again->body)["cached"].get<bool>());
  EXPECT_EQ(as_miss(again->body), first_body);  // byte for byte but `cached`
  EXPECT_EQ(server_metric(restarted, "slosh_min_time_searches_total"), 0);

  // The tables never answer for each other: a min-time key is no plan.
  const auto as_plan = client.Get("/v1/plans/" + key);
  ASSERT_TRUE(as_plan);
  EXPECT_EQ(as_plan->status, 404);
  EXPECT_EQ(json::parse(as_plan->body)["error"]["message"],
            "no plan with key '" + key + "': POST the recipe to /v1/plans first");
  const auto cam = client.Get("/v1/plans/" + key + "/cam.csv");
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->status, 404);
}

TEST(MinTimeService, IdenticalConcurrentRequestsShareOneSearch) {
  Server server({"--workers", "2"});
  ASSERT_GT(server.port(), 0) << server.log();
  const std::string body = cheap_request().dump();
  constexpr int kClients = 8;
  const auto results = post_concurrently(server, body, kClients);
  std::string reference;
  int misses = 0;
  for (const auto& r : results) {
    ASSERT_TRUE(r) << httplib::to_string(r.error());
    ASSERT_EQ(r->status, 200) << r->body;
    const std::string cache = r->get_header_value("X-Cache");
    // X-Cache and the body's `cached` agree; the ETag names the one body of the key.
    EXPECT_EQ(json::parse(r->body)["cached"].get<bool>(), cache == "hit");
    EXPECT_EQ(r->get_header_value("ETag"),
              "\"" + json::parse(r->body)["key"].get<std::string>() + "\"");
    misses += cache == "miss" ? 1 : 0;
    if (reference.empty()) reference = as_miss(r->body);
    EXPECT_EQ(as_miss(r->body), reference);
  }
  EXPECT_GE(misses, 1);
  EXPECT_EQ(server_metric(server, "slosh_min_time_searches_total"), 1) << server.log();
  const double joins = server_metric(server, "slosh_min_time_joins_total");
  const double hits = server_metric(server, R"(slosh_cache_hits_total{level="memory"})");
  // Every request but the searching one waited for its search (a miss) or came after it (a hit).
  EXPECT_EQ(joins, misses - 1);
  EXPECT_EQ(joins + hits, kClients - 1);
  // One search of each strategy ran.
  EXPECT_EQ(server_metric(server, R"(slosh_solve_seconds_count{strategy="min_time:shaper"})"), 1);
}

/// Polls `server`'s /metrics until `done` holds for it (at most 60 s); whether it did.
template <typename Done>
bool wait_for_metrics(const Server& server, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto r = server.client().Get("/metrics");
    if (r && done(r->body)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

TEST(MinTimeService, ARefusedSearchAnswers503ToEveryWaiterAndWedgesNothing) {
  // One worker and room for two queued tasks: a long search holds the worker and a second one
  // waits in the queue, so a request of two strategies queues one and is refused the other.
  Server server({"--workers", "1", "--queue", "2"});
  ASSERT_GT(server.port(), 0) << server.log();
  auto search_of = [&](const json& strategies) {
    json body = cheap_request();
    body["strategies"] = strategies;
    return std::async(std::launch::async, [&server, body] {
      return server.client().Post("/v1/min-time", body.dump(), "application/json");
    });
  };
  auto running = search_of({"time_domain"});
  ASSERT_TRUE(wait_for_metrics(
      server, [](const std::string& m) { return metric(m, "slosh_busy_workers") == 1; }));
  auto queued = search_of({"min_jerk_band"});
  ASSERT_TRUE(wait_for_metrics(
      server, [](const std::string& m) { return metric(m, "slosh_queue_depth") == 1; }));

  json small = cheap_request();
  small["strategies"] = {"baseline", "shaper"};
  const auto started = std::chrono::steady_clock::now();
  const auto refused = post_concurrently(server, small.dump(), 4);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(server_metric(server, R"(slosh_solve_seconds_count{strategy="min_time:time_domain"})"),
            -1)
      << "the long search ended too soon for this test";
  for (const auto& r : refused) {
    ASSERT_TRUE(r) << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 503) << r->body;
    EXPECT_EQ(r->get_header_value("Retry-After"), "1");
    EXPECT_EQ(json::parse(r->body)["error"]["code"], "overloaded");
  }
  // Answered at once, not after a search or a budget (10 s + 30 s of queueing).
  EXPECT_LT(seconds, 5.0);

  for (auto* f : {&running, &queued}) {
    const auto r = f->get();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;
  }
  // The worker also takes the task queued for the refused search, which skips its strategy.
  ASSERT_TRUE(wait_for_metrics(server, [](const std::string& m) {
    return metric(m, "slosh_busy_workers") == 0 && metric(m, "slosh_queue_depth") == 0;
  }));
  // The refused request was forgotten: asked again it is searched and answered.
  const auto retried = server.client().Post("/v1/min-time", small.dump(), "application/json");
  ASSERT_TRUE(retried);
  EXPECT_EQ(retried->status, 200) << retried->body;
  EXPECT_EQ(retried->get_header_value("X-Cache"), "miss");
  EXPECT_EQ(server_metric(server, "slosh_min_time_searches_total"), 3);  // 2 fillers, the retry
  // One search of baseline ran: the retry's.
  EXPECT_EQ(server_metric(server, R"(slosh_solve_seconds_count{strategy="min_time:baseline"})"), 1);
}

/// JSON lines of recipes (plan requests; the strategies named for a cheap search), a repeated
/// recipe and a bad one.
std::string jsonl_recipes() {
  json thesis = json::parse(R"({"recipe_id": "thesis",
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800, "motion_time_s": 2},
    "options": {"eta_rest_max_mm": 3}, "strategies": ["baseline", "fir_chain", "shaper"]})");
  json narrow = thesis;
  narrow["recipe_id"] = "narrow";
  narrow["format"]["container"]["radius_mm"] = 40;
  narrow["format"]["fill_height_mm"] = 70;
  json again = thesis;
  again["recipe_id"] = "thesis again";
  json bad = thesis;
  bad["recipe_id"] = "bad";
  bad["format"]["stroke_mm"] = -5;
  return thesis.dump() + "\n" + narrow.dump() + "\n" + again.dump() + "\n" + bad.dump() + "\n";
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) rows.push_back(json::parse(line));
  return rows;
}

TEST(MinTimeService, BatchOverServerEqualsTheLocalBatchAndSharesTheStore) {
  const TempDir dir;
  write_file(dir / "recipes.jsonl", jsonl_recipes());
  // The file a server on `dir` uses (test::Server's plans.sqlite).
  const std::string store = (dir / "plans.sqlite").string();
  const RunResult local =
      run_slosh({"batch", "--mode", "min_time", "--in", (dir / "recipes.jsonl").string(), "--out",
                 (dir / "local.csv").string(), "--workers", "2", "--cache", store});
  EXPECT_EQ(local.exit_code, 3) << local.err;
  EXPECT_EQ(local.err, "slosh batch: row 4 could not be searched: see the message of the row\n");
  // Two distinct good recipes: the third row repeats the first (it joined or read its search).
  EXPECT_EQ(query(store, "SELECT count(*) FROM min_times"), "2");
  EXPECT_EQ(query(store, "SELECT count(*) FROM plans"), "0");

  Server server({"--workers", "2"});
  ASSERT_GT(server.port(), 0) << server.log();
  const RunResult remote =
      run_slosh({"batch", "--mode", "min_time", "--in", (dir / "recipes.jsonl").string(), "--out",
                 (dir / "remote.csv").string(), "--server", server.url()});
  EXPECT_EQ(remote.exit_code, 3) << remote.err;
  EXPECT_EQ(remote.err, local.err);
  const std::string table = read_file(dir / "local.csv");
  EXPECT_EQ(read_file(dir / "remote.csv"), table);  // row by row, byte for byte
  EXPECT_EQ(server_metric(server, "slosh_min_time_searches_total"), 2);  // the repeat was a hit
  std::istringstream lines(table);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[1].substr(0, 12), "1,thesis,ok,");
  // JSON rows name the request path (no CSV column to name).
  EXPECT_EQ(rows[4],
            "4,bad,error,,,,,,,,,,,,,,format.stroke_mm = -5 is out of range: allowed 0.01 to "
            "100000 mm,format.stroke_mm");

  // JSON lines out, again through the server: the same figures (a JSON row is the CSV row typed).
  const RunResult jsonl =
      run_slosh({"batch", "--mode", "min_time", "--in", (dir / "recipes.jsonl").string(), "--out",
                 (dir / "remote.jsonl").string(), "--server", server.url()});
  EXPECT_EQ(jsonl.exit_code, 3) << jsonl.err;
  const std::vector<json> typed = json_lines(read_file(dir / "remote.jsonl"));
  ASSERT_EQ(typed.size(), 4u);
  EXPECT_EQ(typed[0]["key"], typed[2]["key"]);
  EXPECT_EQ(typed[0]["t_min_shaper_s"], typed[2]["t_min_shaper_s"]);
  EXPECT_FALSE(typed[0].contains("t_min_notch_s"));  // not searched

  // The local batch's store answers a server started on it: the same request is a hit.
  Server on_local_store({}, &dir);
  ASSERT_GT(on_local_store.port(), 0) << on_local_store.log();
  const auto hit =
      on_local_store.client().Post("/v1/min-time", cheap_request().dump(), "application/json");
  ASSERT_TRUE(hit);
  ASSERT_EQ(hit->status, 200) << hit->body;
  EXPECT_EQ(hit->get_header_value("X-Cache"), "hit");
  EXPECT_EQ(json::parse(hit->body)["key"], typed[0]["key"]);
}

TEST(MinTimeService, BatchOverServerNamesTheCsvColumnOfABadRow) {
  const TempDir dir;
  write_file(dir / "recipes.csv",
             "recipe_id,radius_mm,container_height_mm,fill_height_mm,fluid,stroke_mm,"
             "motion_time_s,strategy,eta_rest_max_mm\n"
             "stroke,48.5,150,82,water,-5,1.5,,\n"
             "radius,-3,150,82,water,800,1.5,,\n"
             "rest,48.5,150,82,water,800,1.5,,0\n"
             "text,abc,150,82,water,800,1.5,,\n"
             "board,48.5,80,82,water,800,1.5,,\n"
             "time,48.5,150,82,water,800,100,,\n");
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const std::vector<std::string> common{"batch",
                                        "--mode",
                                        "min_time",
                                        "--in",
                                        (dir / "recipes.csv").string(),
                                        "--out-format",
                                        "jsonl",
                                        "--out",
                                        "-",
                                        "--cache",
                                        ""};
  std::vector<std::string> with_server = common;
  with_server.insert(with_server.end(), {"--server", server.url()});
  const RunResult remote = run_slosh(with_server);
  EXPECT_EQ(remote.exit_code, 3) << remote.err;
  EXPECT_EQ(remote.err,
            "slosh batch: rows 1, 2, 3, 4, 5, 6 could not be searched: see the message of the "
            "row\n");
  const std::vector<json> rows = json_lines(remote.out);
  ASSERT_EQ(rows.size(), 6u);
  const std::vector<std::pair<std::string, std::string>> expected{
      {"stroke_mm", "stroke_mm = -5 is out of range: allowed 0.01 to 100000 mm"},
      {"radius_mm", "radius_mm = -3 is out of range: allowed 1 to 2000 mm"},
      {"eta_rest_max_mm", "eta_rest_max_mm = 0 is out of range: allowed > 0 and <= 10000 mm"},
      {"radius_mm", "radius_mm must be a number, got \"abc\"; allowed 1 to 2000 mm"},
      {"container_height_mm",
       "container_height_mm = 80 is out of range: allowed > 82 and <= 10000 mm"},
      {"motion_time_s", "motion_time_s = 100 is out of range: allowed 0.05 to 60 s"},
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    SCOPED_TRACE(rows[i].dump());
    EXPECT_EQ(rows[i]["status"], "error");
    EXPECT_EQ(rows[i]["error_field"], expected[i].first);
    EXPECT_EQ(rows[i]["message"], expected[i].second);
  }
  // Locally the same rows, the same texts.
  const RunResult local = run_slosh(common);
  EXPECT_EQ(local.exit_code, 3) << local.err;
  EXPECT_EQ(local.out, remote.out);
  EXPECT_EQ(server_metric(server, "slosh_min_time_searches_total"), 0);
}

TEST(MinTimeService, BatchStopsWhenTheServerIsUnreachable) {
  const TempDir dir;
  write_file(dir / "recipes.jsonl", jsonl_recipes());
  const RunResult r =
      run_slosh({"batch", "--mode", "min_time", "--in", (dir / "recipes.jsonl").string(), "--out",
                 (dir / "out.csv").string(), "--server", "http://127.0.0.1:1"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("slosh batch: stopped: ", 0), 0u) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));
}

}  // namespace test_min_time_service
}  // namespace slosh

namespace slosh {
namespace test_min_time_service {

// Regression: a search still queued when shutdown began answered 200 with every strategy
// "baseline" / time_limit. Queued work answers 503 at once, as queued plan solves do. The test
// waits for what it needs to see in /metrics (the long search running, the second one queued)
// instead of sleeping 150 ms, which raced SIGTERM under load.
TEST(MinTimeService, ASearchStillQueuedAtShutdownAnswers503) {
  test::Server server({"--workers", "1"});
  ASSERT_GT(server.port(), 0) << server.log();
  nlohmann::json slow = cheap_request();
  slow["strategies"] = {"time_domain"};  // about a second on the one worker
  nlohmann::json queued = cheap_request();
  queued["strategies"] = {"baseline"};
  auto post = [&](const nlohmann::json& body) {
    return std::async(std::launch::async, [&server, text = body.dump()] {
      const auto r = server.client().Post("/v1/min-time", text, "application/json");
      return r ? std::make_pair(r->status, r->body) : std::make_pair(-1, std::string());
    });
  };
  auto first = post(slow);
  ASSERT_TRUE(wait_for_metrics(server, [](const std::string& m) {
    return metric(m, "slosh_busy_workers") == 1 && metric(m, "slosh_queue_depth") == 0;
  }));
  auto second = post(queued);
  // One sample shows the long search still running and the second one still queued.
  ASSERT_TRUE(wait_for_metrics(server, [](const std::string& m) {
    return metric(m, "slosh_busy_workers") == 1 && metric(m, "slosh_queue_depth") == 1;
  }));
  ::kill(server.child().pid(), SIGTERM);
  const auto [status, body] = second.get();
  EXPECT_EQ(status, 503) << body;
  const auto error = nlohmann::json::parse(body, nullptr, false);
  ASSERT_TRUE(error.is_object()) << body;
  EXPECT_EQ(error["error"]["code"], "overloaded");
  EXPECT_EQ(error["error"]["message"], "the service is shutting down");
  // The running search stops between two plans and answers the same 503 at once (its answer
  // would be thrown away with the process).
  const auto [first_status, first_body] = first.get();
  EXPECT_EQ(first_status, 503) << first_body;
  EXPECT_EQ(nlohmann::json::parse(first_body, nullptr, false)["error"]["message"],
            "the service is shutting down");
  EXPECT_EQ(server.child().wait_for(std::chrono::seconds(20)), 0) << server.log();
}

}  // namespace test_min_time_service
}  // namespace slosh
