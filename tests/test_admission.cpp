// Admission to the solve pool (docs/service.md, "Worker pool"): an idle pool admits workers +
// queue solves at once (the tasks the woken workers are about to take are not queued), a
// synchronous batch's items run below interactive plans so that an HMI's plan overtakes them
// instead of finding the queue full, and a min-time request of more strategies than an idle pool
// admits runs them one after the other instead of a false "busy" 503. Real pool, real server on
// loopback; decided by counters and statuses, never by wall-clock thresholds.

#include <httplib.h>

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <future>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "engine/worker_pool.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_admission {

using nlohmann::json;
using namespace std::chrono_literals;

// Tasks that hold their worker until `gate` opens are submitted at once, as fast as a burst of
// requests arrives: workers + queue of them fit, the next one does not.
TEST(Admission, AnIdlePoolAdmitsWorkersPlusQueueTasksAtOnce) {
  service::WorkerPool pool(2, 1);
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(pool.try_submit([gate] { gate.wait(); })) << i;
  EXPECT_FALSE(pool.try_submit([gate] { gate.wait(); }));
  // Background tasks count only the idle workers the interactive ones leave (none here).
  EXPECT_TRUE(pool.try_submit([] {}, service::TaskPriority::kBackground));
  EXPECT_FALSE(pool.try_submit([] {}, service::TaskPriority::kBackground));
  release.set_value();
}

json thesis_plan(const std::string& strategy, double stroke_mm) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}})");
  body["strategy"] = strategy;
  body["format"]["stroke_mm"] = stroke_mm;
  return body;
}

// The batch fills its queue as fast as the one worker drains it; an interactive plan sent while
// the batch still has queued items is admitted (200, not 503) and answered before the batch.
TEST(Admission, AnInteractivePlanOvertakesASynchronousBatch) {
  test::Server server({"--workers", "1", "--queue", "2", "--cache", ""});
  ASSERT_GT(server.port(), 0) << server.log();
  json requests = json::array();
  for (int i = 0; i < 40; ++i) requests.push_back(thesis_plan("auto", 500 + i));
  auto batch = std::async(std::launch::async, [&] {
    return server.client().Post("/v1/plans/batch", json{{"requests", requests}}.dump(),
                                "application/json");
  });
  ASSERT_TRUE(test::wait_until([&] { return test::metric_of(server, "slosh_queue_depth") >= 2; }))
      << server.log();
  const auto plan =
      server.client().Post("/v1/plans", thesis_plan("notch", 321).dump(), "application/json");
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->status, 200) << plan->body;
  EXPECT_EQ(batch.wait_for(0s), std::future_status::timeout) << "the batch ended first";
  const auto done = batch.get();
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, 200);
}

// Four strategies on 1 worker + a queue of 1: more tasks than an idle pool admits. The search
// runs them two by two (one task each for half of them) and answers.
TEST(Admission, AMinTimeOfMoreStrategiesThanThePoolAdmitsRunsThemInTurn) {
  test::Server server({"--workers", "1", "--queue", "1", "--cache", ""});
  ASSERT_GT(server.port(), 0) << server.log();
  const json request = json::parse(R"({"format": {"container": {"radius_mm": 48.5,
      "height_mm": 150}, "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800},
      "strategies": ["notch", "multi_notch", "baseline", "shaper"]})");
  const auto r = server.client().Post("/v1/min-time", request.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json answer = json::parse(r->body);
  ASSERT_EQ(answer.at("strategies").size(), 4u) << r->body.substr(0, 400);
  EXPECT_EQ(test::metric_of(server, R"(slosh_pool_tasks_started_total{priority="background"})"), 2);
}

}  // namespace test_admission
}  // namespace slosh
