// RedisJobStore (service/jobs/redis_job_store.hpp) against a real redis-server on loopback:
// records, rows in item order with paging, the cancel flag, removal, the time to live of a job's
// keys, two replicas' stores seeing the same jobs, and a Redis that is down.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "jobs/job_store.hpp"
#include "jobs/redis_job_store.hpp"
#include "storage/redis_client.hpp"
#include "support/redis_server.hpp"

namespace test_redis_job_store {

using slosh::service::JobStore;
using slosh::service::JobTraces;
using slosh::service::RedisClient;
using slosh::service::RedisJobStore;
using slosh::test::RedisServer;
using namespace std::chrono_literals;
using Rows = std::vector<std::string>;

std::shared_ptr<RedisClient> client_of(const RedisServer& server) {
  return std::make_shared<RedisClient>(slosh::service::RedisOptions{
      .url = slosh::service::parse_redis_url(server.url()), .timeout = 200ms});
}

TEST(RedisJobStore, RecordsRowsAndCancelRoundTrip) {
  const RedisServer redis;
  RedisJobStore redis_store(client_of(redis), 3600s);
  JobStore& store = redis_store;
  EXPECT_FALSE(store.record("j1"));
  EXPECT_FALSE(store.rows("j1", 0, 10));
  ASSERT_TRUE(store.put_record("j1", R"({"state":"running","done":0})"));
  EXPECT_EQ(store.record("j1"), R"({"state":"running","done":0})");
  EXPECT_EQ(store.rows("j1", 0, 10), Rows{});
  ASSERT_TRUE(store.put_rows("j1", 0, {"r0", "r1,\"quoted\"", ""}));
  ASSERT_TRUE(store.put_rows("j1", 3, {}));
  ASSERT_TRUE(store.put_rows("j1", 3, {"r3", "r4"}));
  ASSERT_TRUE(store.put_record("j1", R"({"state":"done","done":5})"));
  EXPECT_EQ(store.record("j1"), R"({"state":"done","done":5})");
  EXPECT_EQ(store.rows("j1", 0, 100), (Rows{"r0", "r1,\"quoted\"", "", "r3", "r4"}));
  EXPECT_EQ(store.rows("j1", 1, 2), (Rows{"r1,\"quoted\"", ""}));
  EXPECT_EQ(store.rows("j1", 4, 2), (Rows{"r4"}));
  EXPECT_EQ(store.rows("j1", 5, 2), Rows{});
  EXPECT_EQ(store.rows("j1", 0, 0), Rows{});
  EXPECT_EQ(store.rows("j1", static_cast<std::size_t>(-1), static_cast<std::size_t>(-1)), Rows{});
  EXPECT_FALSE(store.cancel_requested("j1"));
  ASSERT_TRUE(store.request_cancel("j1"));
  EXPECT_TRUE(store.cancel_requested("j1"));
  EXPECT_FALSE(store.cancel_requested("j2"));
  EXPECT_TRUE(store.remove("j1"));
  EXPECT_FALSE(store.record("j1"));
  EXPECT_FALSE(store.rows("j1", 0, 10));
  // Removed: an owner still running it (its record read as stale elsewhere) cancels it, and a
  // record it writes again stays unread.
  EXPECT_TRUE(store.cancel_requested("j1"));
  ASSERT_TRUE(store.put_record("j1", R"({"state":"running","done":1})"));
  EXPECT_EQ(store.lookup_record("j1").text, std::nullopt);
  EXPECT_TRUE(store.lookup_record("j1").answered);
  EXPECT_EQ(store.removed_among({"j0", "j1", "j2"}), std::vector<std::string>{"j1"});
}

// A write that timed out in the client may still have landed in Redis; the owner writes the same
// rows again. Keyed by index, the second write replaces them (an appended list held them twice),
// and a write that never landed leaves its indexes missing: reading stops there.
TEST(RedisJobStore, RowsAreKeyedByIndexSoARetriedWriteCannotDuplicateAndALostOneShowsAsAGap) {
  const RedisServer redis;
  RedisJobStore store(client_of(redis), 3600s);
  ASSERT_TRUE(store.put_record("j", "running"));
  ASSERT_TRUE(store.put_rows("j", 0, {"r0", "r1"}));
  ASSERT_TRUE(store.put_rows("j", 0, {"r0", "r1"}));  // the retry of a write that landed
  ASSERT_TRUE(store.put_rows("j", 1, {"r1", "r2"}));  // overlapping
  EXPECT_EQ(store.rows("j", 0, 10), (Rows{"r0", "r1", "r2"}));
  ASSERT_TRUE(store.put_rows("j", 4, {"r4", "r5"}));  // row 3 was lost
  EXPECT_EQ(store.rows("j", 0, 10), (Rows{"r0", "r1", "r2"}));
  EXPECT_EQ(store.rows("j", 4, 10), (Rows{"r4", "r5"}));
  ASSERT_TRUE(store.put_rows("j", 3, {"r3"}));
  EXPECT_EQ(store.rows("j", 0, 10), (Rows{"r0", "r1", "r2", "r3", "r4", "r5"}));
  EXPECT_EQ(store.rows("j", 2, 3), (Rows{"r2", "r3", "r4"}));
}

TEST(RedisJobStore, EveryWriteRenewsTheTtlOfTheJobsKeys) {
  const RedisServer redis;
  const auto client = client_of(redis);
  RedisJobStore store(client, 120s);
  ASSERT_TRUE(store.put_record("j", "r"));
  ASSERT_TRUE(store.put_rows("j", 0, {"a"}));
  ASSERT_TRUE(store.request_cancel("j"));
  for (const char* part : {"record", "rows", "cancel"}) {
    EXPECT_EQ(store.key("j", part), std::string("slosh:jobs:j:") + part);
    const long long ttl = client->command({"PTTL", store.key("j", part)})->integer;
    EXPECT_GT(ttl, 110 * 1000) << part;
    EXPECT_LE(ttl, 120 * 1000) << part;
  }
  // A shorter store's write (another replica configured with 30 s) renews all three to 30 s.
  RedisJobStore other(client, 30s);
  ASSERT_TRUE(other.put_record("j", "r2"));
  for (const char* part : {"record", "rows", "cancel"}) {
    EXPECT_LE(client->command({"PTTL", store.key("j", part)})->integer, 30 * 1000) << part;
  }
}

TEST(RedisJobStore, TwoReplicasSeeTheSameJobs) {
  const RedisServer redis;
  RedisJobStore runner(client_of(redis), 3600s);
  RedisJobStore reader(client_of(redis), 3600s);
  ASSERT_TRUE(runner.put_record("shared", "running"));
  ASSERT_TRUE(runner.put_rows("shared", 0, {"row 0"}));
  EXPECT_EQ(reader.record("shared"), "running");
  EXPECT_EQ(reader.rows("shared", 0, 5), Rows{"row 0"});
  ASSERT_TRUE(reader.request_cancel("shared"));  // DELETE through the other replica
  EXPECT_TRUE(runner.cancel_requested("shared"));
}

// A record Redis did not answer for (stalled, slow, or every connection busy) is not a record
// Redis said it lacks: the job may run on another replica, so it must not be answered as 404.
TEST(RedisJobStore, ARecordRedisDidNotAnswerForIsNotReadAsMissing) {
  RedisServer redis;
  RedisJobStore store(client_of(redis), 3600s);
  ASSERT_TRUE(store.put_record("j", "r"));
  const JobStore::RecordLookup missing = store.lookup_record("absent");
  EXPECT_TRUE(missing.answered);
  EXPECT_FALSE(missing.text);
  const JobStore::RecordLookup found = store.lookup_record("j");
  EXPECT_TRUE(found.answered);
  EXPECT_EQ(found.text, "r");
  redis.pause();
  const JobStore::RecordLookup stalled = store.lookup_record("j");
  redis.resume();
  EXPECT_FALSE(stalled.answered);
  EXPECT_FALSE(stalled.text);
}

// A job is created only when Redis takes its first record: a stalled Redis (SIGSTOP) or one
// refusing writes (maxmemory reached, noeviction) makes create() name the store and why, and a
// Redis that answers creates it.
TEST(RedisJobStore, ACreateRedisDoesNotTakeIsRefusedNamingTheStoreAndWhy) {
  RedisServer redis({"--maxmemory-policy", "noeviction"});
  RedisJobStore store(client_of(redis), 3600s);
  EXPECT_EQ(store.create("j", "r"), std::nullopt);
  EXPECT_EQ(store.record("j"), "r");
  redis.pause();
  const std::optional<std::string> stalled = store.create("k", "r");
  redis.resume();
  EXPECT_EQ(stalled,
            "the shared job store (" + redis.url() + ") is unavailable: no reply within 200 ms");
  // Redis at its memory limit refuses the write inside MULTI: its own error is the reason.
  auto admin = client_of(redis);
  std::optional<slosh::service::RedisReply> set;
  for (int i = 0; i < 50 && !(set && set->type == slosh::service::RedisReply::Type::kStatus); ++i) {
    std::this_thread::sleep_for(100ms);  // the client probes again after its retry interval
    set = admin->command({"CONFIG", "SET", "maxmemory", "1"});
  }
  ASSERT_TRUE(set && set->type == slosh::service::RedisReply::Type::kStatus);
  std::optional<std::string> full;
  for (int i = 0; i < 50; ++i) {  // store's client: up again after its retry interval
    full = store.create("m", "r");
    if (full && full->find("no reply") == std::string::npos) break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(full, "the shared job store (" + redis.url() +
                      ") is unavailable: Redis refused the write: OOM command not allowed when "
                      "used memory > 'maxmemory'.");
  (void)admin->command({"CONFIG", "SET", "maxmemory", "0"});
}

// Only a nil reply means "no such record". A WRONGTYPE error (the key holds a hash) is not read
// as missing (it would be answered 404 for a job that exists), nor as Redis being unreachable:
// Redis answered, and the job's stored state is damaged.
TEST(RedisJobStore, ARecordReadRedisAnsweredWithAnErrorIsNotReadAsMissing) {
  const RedisServer redis;
  const auto client = client_of(redis);
  RedisJobStore store(client, 3600s);
  ASSERT_TRUE(client->command({"HSET", store.key("j", "record"), "f", "v"}));
  const JobStore::RecordLookup lookup = store.lookup_record("j");
  EXPECT_FALSE(lookup.text);
  EXPECT_TRUE(lookup.answered);
  EXPECT_TRUE(lookup.damaged);
}

// A record key gone while the job's rows are there (evicted, deleted): the job has traces and
// its record is missing; row_slots names every missing index instead of stopping at the first.
TEST(RedisJobStore, ALostRecordLeavesTracesAndRowSlotsShowEveryGap) {
  const RedisServer redis;
  const auto client = client_of(redis);
  RedisJobStore store(client, 3600s);
  ASSERT_TRUE(store.put_rows("j", 0, {"a", "b", "c", "d"}));
  ASSERT_TRUE(store.put_record("j", "r"));
  ASSERT_TRUE(store.put_record("k", "r"));
  ASSERT_TRUE(client->command({"HDEL", store.key("j", "rows"), "1"}));
  const auto slots = store.row_slots("j", 0, 4);
  ASSERT_TRUE(slots);
  EXPECT_EQ(*slots, (std::vector<std::optional<std::string>>{"a", std::nullopt, "c", "d"}));
  EXPECT_TRUE(store.records_missing_among({"j", "k"}).empty());
  ASSERT_TRUE(client->command({"DEL", store.key("j", "record")}));
  EXPECT_EQ(store.records_missing_among({"j", "k"}), std::vector<std::string>{"j"});
  EXPECT_EQ(store.traces("j"), JobTraces::kRows);
  EXPECT_EQ(store.traces("unknown"), JobTraces::kNone);
  // A cancel flag alone (a DELETE sent again after an emptying) is a trace only while a
  // replica's heartbeat of the job lives: then that replica writes the record back.
  ASSERT_TRUE(store.request_cancel("c"));
  EXPECT_EQ(store.traces("c"), JobTraces::kNone);
  ASSERT_TRUE(store.put_record("c", "r"));  // sets the heartbeat with the record
  ASSERT_TRUE(client->command({"DEL", store.key("c", "record")}));
  EXPECT_EQ(store.traces("c"), JobTraces::kLiveCancel);
  ASSERT_TRUE(client->command({"DEL", store.key("c", "alive")}));
  EXPECT_EQ(store.traces("c"), JobTraces::kNone);
  // A removed job is neither missing (its owner must not publish it again) nor traced.
  ASSERT_TRUE(store.remove("k"));
  EXPECT_TRUE(store.records_missing_among({"k"}).empty());
  EXPECT_EQ(store.traces("k"), JobTraces::kNone);
}

TEST(RedisJobStore, ADownRedisFailsEveryCallWithoutThrowing) {
  RedisServer redis;
  RedisJobStore store(client_of(redis), 3600s);
  ASSERT_TRUE(store.put_record("j", "r"));
  redis.kill();
  EXPECT_FALSE(store.put_record("j", "r2"));
  EXPECT_FALSE(store.record("j"));
  EXPECT_FALSE(store.put_rows("j", 0, {"x"}));
  EXPECT_FALSE(store.rows("j", 0, 1));
  EXPECT_FALSE(store.request_cancel("j"));
  EXPECT_FALSE(store.cancel_requested("j"));
  EXPECT_NO_THROW(store.remove("j"));
}

}  // namespace test_redis_job_store

namespace test_redis_job_store {

// Redis at maxmemory (noeviction) refuses the record and the rows with its OOM error, and the
// store says so naming Redis; the heartbeat (PEXPIRE of <id>:alive) is still taken, so the job's
// heartbeat age stays young while its record ages. Its age is the time to live it was given less
// the time left, checked against a clock in the test.
TEST(RedisJobStore, AFullRedisRefusesTheRecordButTakesTheHeartbeat) {
  const RedisServer redis;
  RedisJobStore store(client_of(redis), 3600s, "slosh:jobs:", 10000ms);
  EXPECT_EQ(store.heartbeat_age_ms("j"), std::nullopt);
  ASSERT_TRUE(store.put_record("j", "r1"));
  const auto written = std::chrono::steady_clock::now();
  const auto fresh = store.heartbeat_age_ms("j");
  ASSERT_TRUE(fresh);
  EXPECT_LE(*fresh, 100);
  ASSERT_EQ(std::system(("redis-cli -p " + std::to_string(redis.port()) +
                         " config set maxmemory-policy noeviction >/dev/null && redis-cli -p " +
                         std::to_string(redis.port()) + " config set maxmemory 1 >/dev/null")
                            .c_str()),
            0);
  EXPECT_FALSE(store.put_record("j", "r2"));
  EXPECT_FALSE(store.put_rows("j", 0, {"row"}));
  EXPECT_EQ(store.last_write_failure(),
            "the shared job store (" + redis.url() +
                ") refused the write: OOM command not allowed when used memory > 'maxmemory'.");
  std::this_thread::sleep_for(300ms);  // the record ages (the time that passes, not a wait)
  const auto before = store.heartbeat_age_ms("j");
  const auto aged_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::steady_clock::now() - written)
                           .count();
  ASSERT_TRUE(before);
  EXPECT_GE(*before, 250);
  EXPECT_LE(*before, aged_ms + 50);  // the write took place before `written`
  ASSERT_TRUE(store.touch("j"));
  const auto after = store.heartbeat_age_ms("j");
  ASSERT_TRUE(after);
  EXPECT_LE(*after, 100);
  EXPECT_EQ(store.record("j"), "r1");  // the record Redis took last
}

}  // namespace test_redis_job_store
