// Work nobody waits for is not done (SPEC §8): a request whose client hung up stops its solve or
// search (the core's PlanOptions::stop, checked wherever the time limit is), a queued solve whose
// client left is never started, identical concurrent robust plans share one solve, and min-time
// searches run at background priority so that plans overtake their queued strategies. Checked on
// a real server over loopback with the pool's and the service's counters, never by wall-clock
// thresholds.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/core/model/format.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/strategy/min_time.hpp"
#include "slosh/core/strategy/path_plan.hpp"
#include "slosh/core/strategy/planner.hpp"
#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_cancellation {

using nlohmann::json;
using namespace std::chrono_literals;

// The thesis format (SPEC §7's example) with `strategy`.
std::string thesis_plan_request(const std::string& strategy) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
                                         "fill_height_mm": 82, "fluid": "water",
                                         "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  return body.dump();
}

// A min-time search on a 1 ms scan up to 5 s with the most plans allowed (1 000) and an eta_motion
// limit (0.01 mm) that no T meets: every one of the 1 000 plans is solved, seconds to a minute of
// work however fast a plan is, far longer than a stop takes; only a stop ends it early.
std::string endless_min_time(const std::string& strategy = "time_domain") {
  json body = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "motion_time_max_s": 5, "eta_rest_max_mm": 3, "eta_motion_max_mm": 0.01,
    "scan_step_s": 0.001, "max_plans": 1000,
    "options": {"time_limit_s": 500}})");
  body["strategies"] = json::array({strategy});
  return body.dump();
}

std::string raw_post(const std::string& path, const std::string& body) {
  return "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n" +
         "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

// A server whose solve budget allows the endless search.
class LongBudgetServer {
 public:
  explicit LongBudgetServer(const std::vector<std::string>& extra) {
    test::write_file(dir_ / "slosh.json", R"({"solve_budget_s": 600})");
    std::vector<std::string> args{"--config", (dir_ / "slosh.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    server_ = std::make_unique<test::Server>(args);
  }
  const test::Server& operator*() const { return *server_; }
  test::Server& server() { return *server_; }

 private:
  test::TempDir dir_;
  std::unique_ptr<test::Server> server_;
};

const std::string kBusy = "slosh_busy_workers";
const std::string kCancelledMinTime = R"(slosh_solves_cancelled_total{kind="min_time"})";
const std::string kCancelledPlan = R"(slosh_solves_cancelled_total{kind="plan"})";
const std::string kBackground = R"(slosh_pool_tasks_started_total{priority="background"})";
const std::string kInteractive = R"(slosh_pool_tasks_started_total{priority="interactive"})";

// Posts min-time request `body`, hangs up once its search runs, and checks the search stopped
// and freed its worker: the `n`-th cancelled search of `server`.
void hang_up_mid_search(const test::Server& server, const std::string& body, int n) {
  {
    test::Raw client(server.port());
    ASSERT_TRUE(client.send(raw_post("/v1/min-time", body)));
    ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
        << server.log();
  }  // the client hangs up mid-search
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == n && test::metric_of(server, kBusy) == 0;
  })) << server.log();
  EXPECT_EQ(test::metric_of(server, "slosh_min_time_searches_total"), n);
}

TEST(Cancellation, AMinTimeSearchWhoseClientHungUpFreesItsWorker) {
  const LongBudgetServer holder({"--workers", "2"});
  const test::Server& server = *holder;
  EXPECT_EQ(test::metric_of(server, kCancelledMinTime), 0);
  hang_up_mid_search(server, endless_min_time(), 1);
  // Nothing half-searched was kept: the same request searches again instead of a cache hit.
  {
    test::Raw again(server.port());
    ASSERT_TRUE(again.send(raw_post("/v1/min-time", endless_min_time())));
    ASSERT_TRUE(test::wait_until([&] {
      return test::metric_of(server, "slosh_min_time_searches_total") == 2 &&
             test::metric_of(server, kBusy) == 1;
    })) << server.log();
  }
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == 2 && test::metric_of(server, kBusy) == 0;
  })) << server.log();
  EXPECT_EQ(test::metric_of(server, R"(slosh_cache_hits_total{level="memory"})"), 0);
}

// The endless search along a rotary table's quarter turn (SPEC §14): a path's search stops with
// its client as the line's does.
TEST(Cancellation, AMinTimeSearchAlongAPathWhoseClientHungUpFreesItsWorker) {
  const LongBudgetServer holder({"--workers", "2"});
  const test::Server& server = *holder;
  json body = json::parse(endless_min_time());
  body["format"].erase("stroke_mm");
  body["format"]["motion"] = {{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  hang_up_mid_search(server, body.dump(), 1);
}

TEST(Cancellation, ASearchTwoClientsWaitForStopsOnlyWhenBothHaveGone) {
  const LongBudgetServer holder({"--workers", "2"});
  const test::Server& server = *holder;
  auto first = std::make_unique<test::Raw>(server.port());
  ASSERT_TRUE(first->send(raw_post("/v1/min-time", endless_min_time())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }));
  auto second = std::make_unique<test::Raw>(server.port());
  ASSERT_TRUE(second->send(raw_post("/v1/min-time", endless_min_time())));
  ASSERT_TRUE(
      test::wait_until([&] { return test::metric_of(server, "slosh_min_time_joins_total") == 1; }));
  first.reset();
  // The first client's departure is seen (within the 100 ms poll) and changes nothing: the
  // search still runs for the second. A plan answered meanwhile proves the service went on.
  auto plan = server.client().Post("/v1/plans", thesis_plan_request("notch"), "application/json");
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->status, 200);
  std::this_thread::sleep_for(500ms);  // longer than the poll: the departure has been seen
  EXPECT_EQ(test::metric_of(server, kCancelledMinTime), 0);
  EXPECT_EQ(test::metric_of(server, kBusy), 1);
  second.reset();
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == 1 && test::metric_of(server, kBusy) == 0;
  })) << server.log();
}

TEST(Cancellation, AQueuedPlanWhoseClientHungUpIsNeverSolved) {
  // One worker, held by a search (background); the plan waits in the interactive queue until
  // that search's strategy ends, which it does only when its own client leaves.
  const LongBudgetServer holder({"--workers", "1"});
  const test::Server& server = *holder;
  auto search = std::make_unique<test::Raw>(server.port());
  ASSERT_TRUE(search->send(raw_post("/v1/min-time", endless_min_time())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }));
  {
    test::Raw plan(server.port());
    ASSERT_TRUE(plan.send(raw_post("/v1/plans", thesis_plan_request("multi_notch"))));
    ASSERT_TRUE(
        test::wait_until([&] { return test::metric_of(server, "slosh_queue_depth") == 1; }));
  }
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kCancelledPlan) == 1; }));
  search.reset();
  ASSERT_TRUE(test::wait_until([&] {
    return test::metric_of(server, kCancelledMinTime) == 1 && test::metric_of(server, kBusy) == 0 &&
           test::metric_of(server, "slosh_queue_depth") == 0;
  })) << server.log();
  // The queued plan's task ran (and was skipped): no multi_notch solve was timed.
  EXPECT_EQ(test::metric_of(server, kInteractive), 1);
  EXPECT_EQ(test::metric_of(server, R"(slosh_solve_seconds_count{strategy="multi_notch"})"), -1);
  // A new request for the recipe solves it afresh, never the stopped flight.
  auto again =
      server.client().Post("/v1/plans", thesis_plan_request("multi_notch"), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(json::parse(again->body).at("status"), "optimal");
  EXPECT_EQ(test::metric_of(server, R"(slosh_solve_seconds_count{strategy="multi_notch"})"), 1);
}

TEST(Cancellation, PlanAndMinTimeEndAtOnceWhenTheirStopIsSet) {
  const Format format = thesis_format();
  std::atomic<bool> stop{true};
  PlanOptions options;
  options.stop = &stop;
  for (const Strategy strategy :
       {Strategy::kNotch, Strategy::kMinJerkBand, Strategy::kTimeDomain}) {
    const PlanResult result = plan(format, strategy, options);
    EXPECT_EQ(result.status, SolveStatus::kTimeLimit) << to_string(strategy);
  }
  MinTimeOptions search;
  search.eta_motion_max = 0.05;  // the thesis format here has no container height
  search.plan.stop = &stop;
  const MinTimeResult result = min_time(format, Strategy::kNotch, search);
  EXPECT_EQ(result.status, SolveStatus::kTimeLimit);
  EXPECT_EQ(result.plans, 0);
  // Along a path too: plan_on_path and a min-time search on the path.
  const PlanarPath arc = PlanarPath::arc(0.3, std::numbers::pi / 2.0, true);
  for (const Strategy strategy : {Strategy::kNotch, Strategy::kTimeDomain}) {
    EXPECT_EQ(plan_on_path(format, arc, strategy, options).status, SolveStatus::kTimeLimit)
        << to_string(strategy);
  }
  search.path = arc;
  const MinTimeResult on_path = min_time(format, Strategy::kTimeDomain, search);
  EXPECT_EQ(on_path.status, SolveStatus::kTimeLimit);
  EXPECT_EQ(on_path.plans, 0);
  // The same calls without the flag set solve as usual.
  stop = false;
  EXPECT_EQ(plan(format, Strategy::kNotch, options).status, SolveStatus::kOptimal);
  EXPECT_NE(plan_on_path(format, arc, Strategy::kNotch, options).status, SolveStatus::kTimeLimit);
}

TEST(Cancellation, IdenticalConcurrentRobustPlansShareOneSolve) {
  test::Server server({"--workers", "2"});
  json body = json::parse(thesis_plan_request("auto"));
  body["options"]["uncertainty"] = {{"omega_error_pct", 5}};
  constexpr int kClients = 4;
  std::vector<std::future<httplib::Result>> replies;
  for (int i = 0; i < kClients; ++i) {
    replies.push_back(std::async(std::launch::async, [&] {
      return server.client().Post("/v1/plans", body.dump(), "application/json");
    }));
  }
  std::string plan;
  for (auto& f : replies) {
    const httplib::Result r = f.get();
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    json p = json::parse(r->body);
    p.erase("cached");
    if (plan.empty()) plan = p.dump();
    EXPECT_EQ(p.dump(), plan);
  }
  // One solve; every other request joined it or found its answer cached.
  EXPECT_EQ(test::metric_of(server, R"(slosh_solve_seconds_count{strategy="auto"})"), 1);
  EXPECT_EQ(test::metric_of(server, "slosh_singleflight_joins_total") +
                test::metric_of(server, R"(slosh_cache_hits_total{level="memory"})"),
            kClients - 1);
}

TEST(MinTimePriority, SearchesRunAtBackgroundPriority) {
  test::Server server({"--workers", "2"});
  json body = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
               "fluid": "water", "stroke_mm": 800},
    "motion_time_max_s": 2, "eta_rest_max_mm": 3,
    "strategies": ["baseline", "fir_chain", "shaper"]})");
  auto r = server.client().Post("/v1/min-time", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(test::metric_of(server, kBackground), 3);  // one task per strategy
  EXPECT_EQ(test::metric_of(server, kInteractive), 0);
}

// A plan posted while a search's strategies wait for the one worker goes ahead of them: while it
// waits, at most the strategy running then finishes and one more starts after it. (Queued first
// in, first out, the plan would wait for at least two of the three queued strategies.)
TEST(MinTimePriority, APlanOvertakesTheQueuedStrategiesOfASearch) {
  const LongBudgetServer holder({"--workers", "1"});
  const test::Server& server = *holder;
  json search = json::parse(endless_min_time());
  search["strategies"] = json::array({"notch", "multi_notch", "min_jerk_band", "fir_chain"});
  test::Raw client(server.port());
  ASSERT_TRUE(client.send(raw_post("/v1/min-time", search.dump())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBackground) == 1; }));
  const double before = test::metric_of(server, kBackground);
  auto plan = server.client().Post("/v1/plans", thesis_plan_request("notch"), "application/json");
  const double after = test::metric_of(server, kBackground);
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->status, 200) << plan->body;
  EXPECT_LE(after - before, 1);
  EXPECT_EQ(test::metric_of(server, kInteractive), 1);
}

// A plan answered 504 (its budget plus queue_wait_s passed while it queued behind a search) has
// nobody waiting for it: its queued solve is stopped at once, as for a client that hung up,
// instead of taking the worker for its whole budget after the search.
TEST(Cancellation, APlanAnswered504IsStoppedNotRunForNobody) {
  test::TempDir dir;
  test::write_file(dir / "slosh.json", R"({"solve_budget_s": 600, "queue_wait_s": 0.2})");
  const test::Server server({"--config", (dir / "slosh.json").string(), "--workers", "1"});
  ASSERT_GT(server.port(), 0) << server.log();
  test::Raw search(server.port());
  ASSERT_TRUE(search.send(raw_post("/v1/min-time", endless_min_time())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  json quick = json::parse(thesis_plan_request("notch"));
  quick["options"] = {{"time_limit_s", 0.3}};
  const auto r = server.client().Post("/v1/plans", quick.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 504) << r->body;
  EXPECT_EQ(json::parse(r->body)["error"]["message"],
            "the plan did not finish within its budget of 0.3 s plus 0.2 s of queueing");
  // Counted under its cause (a 504), not as a client that closed its connection.
  EXPECT_EQ(test::metric_of(server, R"(slosh_solves_timed_out_total{kind="plan"})"), 1);
  EXPECT_EQ(test::metric_of(server, kCancelledPlan), 0);
}

// SIGTERM while a min-time search runs: the search stops between two plans and its client gets
// the shutdown's 503 at once (the search would otherwise run its 500 s budget for an answer
// that is thrown away), and the server exits 0.
TEST(Cancellation, SigtermStopsARunningMinTimeSearchWithTheShutdownReply) {
  LongBudgetServer holder({"--workers", "1"});
  test::Server& server = holder.server();
  test::Raw client(server.port());
  ASSERT_TRUE(client.send(raw_post("/v1/min-time", endless_min_time())));
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, kBusy) == 1; }))
      << server.log();
  ::kill(server.child().pid(), SIGTERM);
  const std::string reply = client.read_all();
  EXPECT_EQ(reply.substr(0, 12), "HTTP/1.1 503") << reply.substr(0, 300);
  EXPECT_NE(reply.find(R"("message":"the service is shutting down")"), std::string::npos)
      << reply.substr(0, 600);
  EXPECT_EQ(server.child().wait_for(std::chrono::seconds(20)), 0) << server.log();
}

}  // namespace test_cancellation
}  // namespace slosh
