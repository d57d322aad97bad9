// Two real `slosh serve` replicas (build/slosh) on loopback sharing a real redis-server started by
// the test: a plan solved by one is a cache hit on the other; killing Redis leaves both answering
// with /readyz degraded (or 503 with --redis-required), and restarting it recovers by itself.

#include <httplib.h>

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/redis_server.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_redis_replicas {

using nlohmann::json;
using test::metric;
using test::RedisServer;
using test::Server;
using namespace std::chrono_literals;

std::string plan_body(double stroke_mm) {
  json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
      "strategy": "multi_notch"})");
  body["format"]["stroke_mm"] = stroke_mm;
  return body.dump();
}

/// POSTs a plan; its "cached" member (nullopt on a failure, reported).
std::optional<bool> post_cached(const Server& server, const std::string& body) {
  auto client = server.client();
  const auto r = client.Post("/v1/plans", body, "application/json");
  if (!r || r->status != 200) {
    ADD_FAILURE() << "POST /v1/plans on " << server.url() << ": "
                  << (r ? r->body : httplib::to_string(r.error()));
    return std::nullopt;
  }
  return json::parse(r->body)["cached"].get<bool>();
}

/// Polls /readyz until its status is `status` (at most 10 s); the last answer.
std::pair<int, json> ready_until(const Server& server, const std::string& status) {
  auto client = server.client();
  std::pair<int, json> last{-1, json()};
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  do {
    if (const auto r = client.Get("/readyz")) last = {r->status, json::parse(r->body)};
    if (last.second.is_object() && last.second["status"] == status) break;
    std::this_thread::sleep_for(50ms);
  } while (std::chrono::steady_clock::now() < deadline);
  return last;
}

TEST(RedisReplicas, APlanSolvedByOneIsAHitOnTheOtherAndRedisOutagesAreSurvived) {
  RedisServer redis;
  Server a({"--cache", redis.url(), "--workers", "1"});
  Server b({"--cache", redis.url(), "--workers", "1"});
  ASSERT_GT(a.port(), 0) << a.log();
  ASSERT_GT(b.port(), 0) << b.log();
  EXPECT_EQ(post_cached(a, plan_body(800)), false);
  EXPECT_EQ(post_cached(b, plan_body(800)), true);
  EXPECT_EQ(metric(b.client().Get("/metrics")->body, R"(slosh_cache_hits_total{level="redis"})"),
            1);
  EXPECT_EQ(ready_until(b, "ready").first, 200);

  redis.kill();
  // Both keep answering: from memory, and by solving what they do not have.
  EXPECT_EQ(post_cached(b, plan_body(800)), true);
  EXPECT_EQ(post_cached(a, plan_body(750)), false);
  for (const Server* s : {&a, &b}) {
    const auto [status, body] = ready_until(*s, "degraded");
    EXPECT_EQ(status, 200);
    EXPECT_EQ(body["status"], "degraded") << body;
    EXPECT_EQ(body["cache"]["redis"]["up"], false);
    EXPECT_TRUE(
        body["reason"].get<std::string>().starts_with("redis " + redis.url() + " is down ("))
        << body;
    EXPECT_EQ(metric(s->client().Get("/metrics")->body, "slosh_redis_up"), 0);
  }

  redis.start();  // empty: nothing was persisted
  for (const Server* s : {&a, &b}) {
    const auto [status, body] = ready_until(*s, "ready");
    EXPECT_EQ(status, 200);
    EXPECT_EQ(body["status"], "ready") << body;
    EXPECT_EQ(body["cache"]["redis"]["up"], true);
  }
  EXPECT_EQ(post_cached(b, plan_body(700)), false);
  EXPECT_EQ(post_cached(a, plan_body(700)), true);  // shared again
  // One log line per change of state, not one per request.
  for (const Server* s : {&a, &b}) {
    const std::string log = s->log();
    std::size_t downs = 0;
    for (auto at = log.find("is down ("); at != std::string::npos;
         at = log.find("is down (", at + 1)) {
      ++downs;
    }
    EXPECT_EQ(downs, 1u) << log;
    EXPECT_NE(log.find("redis " + redis.url() + " is up again"), std::string::npos) << log;
  }
}

TEST(RedisReplicas, RedisRequiredTakesTheReplicaOutOfRotationWhileRedisIsDown) {
  RedisServer redis;
  Server server({"--cache", redis.url(), "--redis-required", "--redis-timeout-ms", "100"});
  ASSERT_GT(server.port(), 0) << server.log();
  EXPECT_EQ(ready_until(server, "ready").first, 200);
  redis.kill();
  const auto [status, body] = ready_until(server, "degraded");
  EXPECT_EQ(status, 503) << body;
  EXPECT_EQ(body["cache"]["redis"]["required"], true);
  EXPECT_EQ(post_cached(server, plan_body(800)), false);  // it still answers a direct request
  redis.start();
  EXPECT_EQ(ready_until(server, "ready").first, 200);
}

TEST(RedisReplicas, AStoppedRedisCostsARequestAtMostItsTimeoutAndIsSaidInReadyz) {
  RedisServer redis;
  Server a({"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "100"});
  Server b({"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "100"});
  ASSERT_GT(a.port(), 0) << a.log();
  ASSERT_GT(b.port(), 0) << b.log();
  auto client_a = a.client();
  const auto solved = client_a.Post("/v1/plans", plan_body(800), "application/json");
  ASSERT_TRUE(solved && solved->status == 200);
  const std::string key = json::parse(solved->body)["key"];
  // GET by key on the other replica: found in Redis.
  const auto got = b.client().Get("/v1/plans/" + key);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->status, 200);
  EXPECT_EQ(json::parse(got->body)["cached"], true);
  redis.pause();                                     // accepts connections, answers nothing
  EXPECT_EQ(post_cached(a, plan_body(800)), true);   // memory
  EXPECT_EQ(post_cached(b, plan_body(650)), false);  // solved; Redis timed out once
  const auto [status, body] = ready_until(b, "degraded");
  EXPECT_EQ(status, 200);
  EXPECT_EQ(body["cache"]["redis"]["error"], "no reply within 100 ms") << body;
  redis.resume();
  // Both wait to see Redis again: a's job worker also asked the paused Redis (its idle poll), so
  // a may be backing off too, and while it does it fails Redis commands fast and solves.
  for (const Server* s : {&a, &b}) EXPECT_EQ(ready_until(*s, "ready").first, 200);
  // (The plan b solved meanwhile may or may not be in Redis now: a write that timed out is still
  // applied by a stopped server once it continues. Either way it is a correct, digest-checked
  // value.) Sharing works again:
  EXPECT_EQ(post_cached(b, plan_body(600)), false);
  EXPECT_EQ(post_cached(a, plan_body(600)), true);
}

TEST(RedisReplicas, ServeRefusesABadRedisUrlNamingIt) {
  const auto r =
      test::run_slosh({"serve", "--port", "0", "--cache", "redis://:pw@127.0.0.1:99999/0"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "slosh serve: --cache = redis://:***@127.0.0.1:99999/0 is not a Redis URL: the port "
            "'99999' is not a number from 1 to 65535 (expected redis://host:port/db or "
            "redis://:password@host:port/db)\n");
  const auto local = test::run_slosh({"serve", "--port", "0", "--cache-local", "x.sqlite"});
  EXPECT_EQ(local.exit_code, 2);
  EXPECT_NE(local.err.find("cache_local = x.sqlite needs a Redis cache"), std::string::npos)
      << local.err;
}

}  // namespace test_redis_replicas
}  // namespace slosh
