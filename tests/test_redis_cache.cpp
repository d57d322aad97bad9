// The shared cache level on a real redis-server (loopback, started by the test): two caches (two
// replicas) sharing one Redis, promotion into the local levels, version and table isolation,
// tampered values never served, the TTL, and Redis killed mid-run (answers from the local levels,
// degraded readiness, recovery after a restart).

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cache/plan_cache.hpp"
#include "cache/redis_cache.hpp"
#include "config/version.hpp"
#include "http/plan_service.hpp"
#include "slosh/api/plan.hpp"
#include "storage/redis_client.hpp"
#include "support/process.hpp"
#include "support/redis_server.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_redis_cache {

using nlohmann::json;
using service::CacheConfig;
using service::CacheLevel;
using service::CacheTable;
using service::PlanCache;
using service::RedisClient;
using service::RedisReply;
using test::RedisServer;
using namespace std::chrono_literals;

// These tests are about sharing, isolation and a Redis that is gone, never about a slow one: a
// healthy Redis on loopback gets a timeout it always meets. With the product's 200 ms, a loaded
// machine that leaves redis-server (or the test) unscheduled for longer turns one reply into a
// timeout, which marks the client down for its retry interval (as documented): the next commands
// then fail at once and a test would see a miss or no reply where Redis was fine. A Redis that
// was killed refuses at once, so the long timeout never slows the tests that kill it.
constexpr auto kHealthyRedisTimeout = 10s;

std::shared_ptr<RedisClient> client_of(const RedisServer& server) {
  return std::make_shared<RedisClient>(
      service::RedisOptions{.url = service::parse_redis_url(server.url()),
                            .timeout = kHealthyRedisTimeout,
                            .retry_interval = 100ms});
}

/// The reply of `args` on `client`; a Redis that did not answer fails the test and says why
/// (never a dereferenced empty optional).
RedisReply reply_of(RedisClient& client, const std::vector<std::string>& args) {
  auto reply = client.command(args);
  if (!reply) {
    throw std::runtime_error("redis did not answer " + args.front() + " (" + client.state().error +
                             ")");
  }
  return std::move(*reply);
}

/// A replica's plan cache: memory, optionally a SQLite file, and the Redis of `redis`.
CacheConfig replica(std::shared_ptr<RedisClient> redis, const std::string& sqlite = "",
                    CacheTable table = CacheTable::kPlans) {
  CacheConfig config;
  config.path = sqlite;
  config.table = table;
  config.redis = std::move(redis);
  return config;
}

/// The Redis key of plan `key` as the cache documents it (written out independently).
std::string plan_key_in_redis(const std::string& key) {
  return "slosh:v" + std::string(kVersion) + ":plans:" + key;
}

TEST(RedisCacheLevel, APutOnOneReplicaIsAHitOnTheOtherAndIsPromoted) {
  const RedisServer redis;
  const test::TempDir dir;
  PlanCache a(replica(client_of(redis)));
  PlanCache b(replica(client_of(redis), (dir / "b.sqlite").string()));
  a.put("k1", R"({"plan":1})");
  EXPECT_FALSE(b.in_memory("k1"));
  CacheLevel level{};
  EXPECT_EQ(b.get("k1", &level), R"({"plan":1})");
  EXPECT_EQ(level, CacheLevel::kShared);
  // Promoted: the next get is a memory hit, and b's SQLite file holds it (a cache without Redis
  // on that file answers it).
  EXPECT_TRUE(b.in_memory("k1"));
  EXPECT_EQ(b.get("k1", &level), R"({"plan":1})");
  EXPECT_EQ(level, CacheLevel::kMemory);
  PlanCache local_only(CacheConfig{.path = (dir / "b.sqlite").string(), .memory_entries = 0});
  EXPECT_EQ(local_only.get("k1", &level), R"({"plan":1})");
  EXPECT_EQ(level, CacheLevel::kLocal);
  const auto stats = b.stats();
  EXPECT_EQ(stats.shared_hits, 1u);
  EXPECT_EQ(stats.memory_hits, 1u);
  EXPECT_EQ(stats.hits, 2u);
  EXPECT_FALSE(b.get("absent", &level));
  EXPECT_EQ(b.stats().misses, 1u);
  // The key and value as documented: prefix with the version, "slosh1 <digest>\n<body>".
  RedisClient raw({.url = service::parse_redis_url(redis.url()), .timeout = kHealthyRedisTimeout});
  const auto stored = raw.command({"GET", plan_key_in_redis("k1")});
  ASSERT_TRUE(stored);
  const std::string digest = api::sha256_key(plan_key_in_redis("k1") + "\n" + R"({"plan":1})");
  EXPECT_EQ(stored->text, "slosh1 " + digest + "\n" + R"({"plan":1})");
}

TEST(RedisCacheLevel, VersionsAndTablesNeverShareAnswers) {
  const RedisServer redis;
  const auto client = client_of(redis);
  PlanCache current(replica(client));
  CacheConfig older_config = replica(client);
  older_config.version = "0.0.1-older";
  PlanCache older(older_config);
  PlanCache min_times(replica(client, "", CacheTable::kMinTime));
  current.put("same-key", "current answer");
  EXPECT_FALSE(older.get("same-key"));
  EXPECT_FALSE(min_times.get("same-key"));
  older.put("same-key", "older answer");
  min_times.put("same-key", "min-time answer");
  EXPECT_EQ(PlanCache(replica(client)).get("same-key"), "current answer");
  EXPECT_EQ(PlanCache(older_config).get("same-key"), "older answer");
  EXPECT_EQ(PlanCache(replica(client, "", CacheTable::kMinTime)).get("same-key"),
            "min-time answer");
  const auto keys = client->command({"KEYS", "slosh:*"});
  ASSERT_TRUE(keys);
  std::vector<std::string> names;
  for (const RedisReply& k : keys->elements) names.push_back(k.text);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{
                       "slosh:v0.0.1-older:plans:same-key",
                       "slosh:v" + std::string(kVersion) + ":min_times:same-key",
                       "slosh:v" + std::string(kVersion) + ":plans:same-key",
                   }));
}

TEST(RedisCacheLevel, TamperedOrForeignValuesAreNeverServed) {
  const RedisServer redis;
  const auto client = client_of(redis);
  PlanCache writer(replica(client));
  writer.put("good", "the plan");
  writer.put("other", "another plan");
  const std::string good = reply_of(*client, {"GET", plan_key_in_redis("good")}).text;
  const std::string other = reply_of(*client, {"GET", plan_key_in_redis("other")}).text;
  // Body changed (digest kept), digest changed, a foreign value, and a valid value copied under
  // another key: none is served, each is deleted.
  std::string changed_body = good;
  changed_body.back() = 'X';
  std::string changed_digest = good;
  changed_digest[8] = changed_digest[8] == 'a' ? 'b' : 'a';
  const std::vector<std::pair<std::string, std::string>> tampered{
      {"t1", changed_body}, {"t2", changed_digest}, {"t3", "the plan"}, {"t4", other}, {"t5", ""}};
  for (const auto& [key, value] : tampered) {
    ASSERT_TRUE(client->command({"SET", plan_key_in_redis(key), value}));
  }
  PlanCache reader(replica(client));
  for (const auto& [key, value] : tampered) {
    EXPECT_FALSE(reader.get(key)) << key;
    EXPECT_EQ(reply_of(*client, {"EXISTS", plan_key_in_redis(key)}).integer, 0) << key;
  }
  EXPECT_EQ(reader.stats().shared_rejected, tampered.size());
  // The untouched value is served; a value written by hand in the documented form is too.
  EXPECT_EQ(reader.get("good"), "the plan");
  const std::string hand =
      "slosh1 " + api::sha256_key(plan_key_in_redis("hand") + "\n" + "by hand") + "\nby hand";
  ASSERT_TRUE(client->command({"SET", plan_key_in_redis("hand"), hand}));
  EXPECT_EQ(reader.get("hand"), "by hand");
}

TEST(RedisCacheLevel, TheTtlIsSetOnEveryValueWrittenAndNoneByDefault) {
  const RedisServer redis;
  const auto client = client_of(redis);
  CacheConfig with_ttl = replica(client);
  with_ttl.redis_ttl = 3600s;
  PlanCache(with_ttl).put("expiring", "v");
  PlanCache(replica(client)).put("kept", "v");
  const long long expiring = reply_of(*client, {"PTTL", plan_key_in_redis("expiring")}).integer;
  EXPECT_GT(expiring, 3590 * 1000);
  EXPECT_LE(expiring, 3600 * 1000);
  EXPECT_EQ(reply_of(*client, {"PTTL", plan_key_in_redis("kept")}).integer, -1);  // no expiry
}

TEST(RedisCacheLevel, RedisKilledMidRunLeavesTheLocalLevelsAnsweringAndRecovers) {
  RedisServer redis;
  const test::TempDir dir;
  const std::string file = (dir / "local.sqlite").string();
  const auto client = client_of(redis);
  {
    PlanCache cache(replica(client, file));
    cache.put("before", "plan before");
  }
  redis.kill();
  PlanCache cache(replica(client, file));  // a restarted replica: empty memory
  CacheLevel level{};
  EXPECT_EQ(cache.get("before", &level), "plan before");
  EXPECT_EQ(level, CacheLevel::kLocal);
  EXPECT_FALSE(cache.get("unknown"));  // a miss, not an exception or a hang
  cache.put("during", "plan during");  // kept locally
  EXPECT_EQ(cache.get("during"), "plan during");
  EXPECT_FALSE(client->state().up);
  EXPECT_EQ(cache.storage_error(), "");  // the local store is fine
  redis.start();
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!client->state().up && std::chrono::steady_clock::now() < deadline) {
    client->probe();
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_TRUE(client->state().up);
  cache.put("after", "plan after");
  PlanCache other(replica(client_of(redis)));
  EXPECT_EQ(other.get("after"), "plan after");
  EXPECT_FALSE(other.get("during"));  // written while Redis was down: local only (write-through)
}

json plan_body() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 700, "motion_time_s": 1.1},
      "strategy": "multi_notch"})");
}

service::ServerConfig service_config(const RedisServer& redis) {
  service::ServerConfig config;
  config.cache_path = redis.url();
  config.redis_timeout_ms =
      static_cast<std::size_t>(std::chrono::milliseconds(kHealthyRedisTimeout).count());
  config.workers = 1;
  return config;
}

TEST(RedisCacheLevel, TwoPlanServicesShareOneRedis) {
  RedisServer redis;
  service::PlanService a(service_config(redis));
  service::PlanService b(service_config(redis));
  const std::string body = plan_body().dump();
  const auto solved = a.post_plan(body, "");
  ASSERT_EQ(solved.status, 200) << solved.body;
  EXPECT_EQ(json::parse(solved.body)["cached"], false);
  const auto shared = b.post_plan(body, "");
  ASSERT_EQ(shared.status, 200) << shared.body;
  EXPECT_EQ(json::parse(shared.body)["cached"], true);
  EXPECT_EQ(json::parse(shared.body)["durations_s"], json::parse(solved.body)["durations_s"]);
  const std::string metrics = b.metrics_text().body;
  EXPECT_EQ(test::metric(metrics, R"(slosh_cache_hits_total{level="redis"})"), 1);
  EXPECT_EQ(test::metric(metrics, R"(slosh_cache_hits_total{level="memory"})"), 0);
  EXPECT_EQ(test::metric(metrics, "slosh_cache_misses_total"), 0);
  EXPECT_EQ(test::metric(metrics, "slosh_redis_up"), 1);
  const json ready = json::parse(b.ready().body);
  EXPECT_EQ(ready["status"], "ready");
  EXPECT_EQ(ready["cache"]["redis"],
            json({{"url", redis.url()}, {"up", true}, {"required", false}}));
}

TEST(RedisCacheLevel, ReadinessIsDegradedWhileRedisIsDownAndRecovers) {
  RedisServer redis;
  service::PlanService service(service_config(redis));
  service::ServerConfig required_config = service_config(redis);
  required_config.redis_required = true;
  service::PlanService required(required_config);
  const std::string body = plan_body().dump();
  ASSERT_EQ(service.post_plan(body, "").status, 200);
  redis.kill();
  // Answers on: the memory level has the plan; a new recipe is solved.
  const auto cached = service.post_plan(body, "");
  EXPECT_EQ(json::parse(cached.body)["cached"], true);
  json other = plan_body();
  other["format"]["stroke_mm"] = 650;
  EXPECT_EQ(service.post_plan(other.dump(), "").status, 200);
  const auto degraded = service.ready();
  EXPECT_EQ(degraded.status, 200);
  const json d = json::parse(degraded.body);
  EXPECT_EQ(d["status"], "degraded");
  EXPECT_EQ(d["cache"]["redis"]["up"], false);
  const std::string error = d["cache"]["redis"]["error"];
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(d["reason"], "redis " + redis.url() + " is down (" + error +
                             "); answering from the local cache levels");
  EXPECT_EQ(test::metric(service.metrics_text().body, "slosh_redis_up"), 0);
  // The probe of a required Redis may still be waiting for its retry: poll until it saw it down.
  const auto down_by = std::chrono::steady_clock::now() + 5s;
  while (required.ready().status == 200 && std::chrono::steady_clock::now() < down_by) {
    std::this_thread::sleep_for(50ms);
  }
  const auto unready = required.ready();
  EXPECT_EQ(unready.status, 503);
  EXPECT_EQ(json::parse(unready.body)["cache"]["redis"]["required"], true);
  redis.start();
  // No traffic needed: /readyz probes a down Redis once per retry interval (1 s).
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (json::parse(service.ready().body)["status"] != "ready" &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_EQ(json::parse(service.ready().body)["status"], "ready");
  EXPECT_EQ(test::metric(service.metrics_text().body, "slosh_redis_up"), 1);
  while (required.ready().status != 200 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_EQ(required.ready().status, 200);
}

double solves(service::PlanService& service) {
  return std::max(0.0, test::metric(service.metrics_text().body,
                                    R"(slosh_solve_seconds_count{strategy="multi_notch"})"));
}

TEST(RedisCacheLevel, ConcurrentRequestsOnTwoReplicasSolveOnce) {
  RedisServer redis;
  service::PlanService a(service_config(redis));
  service::PlanService b(service_config(redis));
  for (int round = 0; round < 3; ++round) {
    json body = plan_body();
    body["format"]["stroke_mm"] = 600 + 10 * round;
    const std::string text = body.dump();
    auto on_a = std::async(std::launch::async, [&] { return a.post_plan(text, ""); });
    auto on_b = std::async(std::launch::async, [&] { return b.post_plan(text, ""); });
    const auto ra = on_a.get();
    const auto rb = on_b.get();
    ASSERT_EQ(ra.status, 200) << ra.body;
    ASSERT_EQ(rb.status, 200) << rb.body;
    EXPECT_EQ(json::parse(ra.body)["durations_s"], json::parse(rb.body)["durations_s"]);
    // One solve per recipe in all: the other replica waited for it or found it stored.
    EXPECT_EQ(solves(a) + solves(b), round + 1) << "round " << round;
  }
  // No lock is left behind.
  const auto locks = a.redis()->command({"KEYS", "slosh:v*:lock:*"});
  ASSERT_TRUE(locks);
  EXPECT_TRUE(locks->elements.empty());
}

// A lock is a lease renewed while it is held: held past the lease, it stays its holder's; a holder
// that stops renewing it (a replica killed or paused mid-solve) loses it after the lease, and a
// waiter then takes it, instead of waiting out the holder's whole solve budget.
TEST(RedisCacheLevel, ALockIsALeaseRenewedWhileHeldAndTakenOnceItsHolderStopsRenewingIt) {
  RedisServer redis;
  auto client = client_of(redis);
  const std::string name = "slosh:v" + std::string(kVersion) + ":lock:plans:recipe";
  const auto waited_hold = std::chrono::duration_cast<std::chrono::milliseconds>(60s);
  std::string held;
  {
    service::RedisCache holder(client, kVersion, "plans", 0s);
    ASSERT_EQ(holder.lock_or_wait("recipe", waited_hold, held), std::nullopt);
    ASSERT_FALSE(held.empty());
    EXPECT_LE(reply_of(*client, {"PTTL", name}).integer, service::RedisCache::kLockLease.count());
    std::this_thread::sleep_for(service::RedisCache::kLockLease + 1s);
    EXPECT_EQ(reply_of(*client, {"GET", name}).text, held);  // renewed past its lease
    // The holder stops renewing without unlocking, as a killed replica does.
  }
  service::RedisCache waiter(client, kVersion, "plans", 0s);
  std::string taken;
  EXPECT_EQ(waiter.lock_or_wait("recipe", waited_hold, taken), std::nullopt);
  EXPECT_FALSE(taken.empty()) << "the waiter did not get the lock within its hold";
  EXPECT_NE(taken, held);
  waiter.unlock("recipe", taken);
  EXPECT_EQ(reply_of(*client, {"EXISTS", name}).integer, 0);
}

TEST(RedisCacheLevel, ALockOfADeadReplicaExpiresAndTheRecipeIsSolved) {
  RedisServer redis;
  service::PlanService service(service_config(redis));
  const std::string text = plan_body().dump();
  const std::string key = api::recipe_key(api::parse_plan_request(plan_body()));
  const std::string lock = "slosh:v" + std::string(kVersion) + ":lock:plans:" + key;
  // A replica that took the lock and died: the lock expires after its PX.
  ASSERT_TRUE(service.redis()->command({"SET", lock, "dead-replica", "PX", "1500"}));
  const auto reply = service.post_plan(text, "");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(json::parse(reply.body)["cached"], false);
  EXPECT_EQ(solves(service), 1);
  EXPECT_EQ(reply_of(*service.redis(), {"EXISTS", lock}).integer, 0);
  // Our own lock was released, never another's: a lock set by hand now stays.
  ASSERT_TRUE(service.redis()->command({"SET", lock, "other", "PX", "60000"}));
  EXPECT_EQ(service.post_plan(text, "").status, 200);  // a cache hit: no lock involved
  EXPECT_EQ(reply_of(*service.redis(), {"GET", lock}).text, "other");
}

}  // namespace test_redis_cache
}  // namespace slosh
