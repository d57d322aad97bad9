// Batch jobs of two real `slosh serve` replicas sharing a real redis-server (SPEC §13) when the
// shared store misbehaves or a replica is paused: Redis at maxmemory refusing the job's writes,
// Redis stalling while a replica reads a job's rows (through a relay that holds only the row
// reads), an owner paused (SIGSTOP) when a DELETE comes through the other replica, and the
// downloads of a job that did not finish its rows. Every answer is checked by its exact text.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <regex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "storage/redis_client.hpp"
#include "storage/redis_url.hpp"
#include "support/job_tables.hpp"
#include "support/redis_server.hpp"
#include "support/replicas.hpp"
#include "support/server.hpp"
#include "support/stalling_relay.hpp"

namespace slosh {
namespace test_cluster_store_faults {

using nlohmann::json;
using namespace std::chrono_literals;

json recipe(std::size_t i) {
  return {{"format",
           {{"container", {{"radius_mm", 48.5}}},
            {"fill_height_mm", 82},
            {"fluid", "water"},
            {"stroke_mm", 800},
            {"motion_time_s", 0.9 + 0.001 * static_cast<double>(i)}}},
          {"strategy", "notch"}};
}

json recipes(std::size_t n, std::size_t first) {
  json out = json::array();
  for (std::size_t i = 0; i < n; ++i) out.push_back(recipe(first + i));
  return out;
}

std::string post_job(httplib::Client& c, const json& requests) {
  const auto r = c.Post("/v1/batches", json{{"requests", requests}}.dump(), "application/json");
  EXPECT_TRUE(r && r->status == 202) << (r ? r->body : "no answer");
  return r && r->status == 202 ? json::parse(r->body).at("id").get<std::string>() : "";
}

json get_json(httplib::Client& c, const std::string& path) {
  const auto r = c.Get(path);
  EXPECT_TRUE(r && r->status == 200) << path << ": " << (r ? r->body : "no answer");
  return r && r->status == 200 ? json::parse(r->body) : json();
}

json wait_finished(httplib::Client& c, const std::string& id) {
  json record;
  for (int i = 0; i < 1200; ++i) {
    record = get_json(c, "/v1/batches/" + id);
    if (record.is_null() || test::is_final_record(record)) break;
    std::this_thread::sleep_for(50ms);
  }
  return record;
}

json wait_progress(httplib::Client& c, const std::string& id, std::size_t done) {
  json record;
  for (int i = 0; i < 1200; ++i) {
    record = get_json(c, "/v1/batches/" + id);
    if (record.is_null() || record.at("progress").at("done").get<std::size_t>() >= done) break;
    std::this_thread::sleep_for(20ms);
  }
  return record;
}

/// The error envelope of `r`, which must have `status` (and Retry-After when 503).
json error_of(const httplib::Result& r, int status) {
  EXPECT_TRUE(r);
  if (!r) return json();
  EXPECT_EQ(r->status, status) << r->body;
  if (status == 503) {
    EXPECT_FALSE(r->get_header_value("Retry-After").empty()) << r->body;
  }
  return json::parse(r->body).at("error");
}

int redis_cli(const test::RedisServer& redis, const std::string& args) {
  return std::system(
      ("redis-cli -p " + std::to_string(redis.port()) + " " + args + " >/dev/null").c_str());
}

std::size_t lines_of(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// Polls `attempt` every 50 ms until it returns true or `limit` passes; whether it did.
template <typename Attempt>
bool poll_until(std::chrono::milliseconds limit, Attempt attempt) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    if (attempt()) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
}

/// Two replicas sharing `redis` (one worker each), reading batch_job_stale_s = `stale_s`.
struct Pair {
  /// `spread`: the replicas' batch_job_spread ("" for the default).
  explicit Pair(const test::RedisServer& redis, const char* stale_s = "30", const char* spread = "")
      : replicas(start(redis.url(), redis.url(), stale_s, spread)) {}
  /// `extra`: more arguments of both replicas.
  Pair(const std::string& url_a, const std::string& url_b, const char* stale_s = "30",
       const std::vector<std::string>& extra = {})
      : replicas(start(url_a, url_b, stale_s, "", extra)) {}
  static std::vector<std::unique_ptr<test::Replica>> start(
      const std::string& url_a, const std::string& url_b, const char* stale_s, const char* spread,
      const std::vector<std::string>& extra = {}) {
    ::setenv("SLOSH_BATCH_JOB_STALE_S", stale_s, 1);  // the replicas read it at start
    if (*spread != '\0') ::setenv("SLOSH_BATCH_JOB_SPREAD", spread, 1);
    std::vector<std::unique_ptr<test::Replica>> out;
    for (const auto& [name, url] : {std::pair{"line-1", url_a}, std::pair{"line-2", url_b}}) {
      std::vector<std::string> args{"--cache", url, "--workers", "1"};
      args.insert(args.end(), extra.begin(), extra.end());
      out.push_back(std::make_unique<test::Replica>(name, args));
    }
    ::unsetenv("SLOSH_BATCH_JOB_STALE_S");
    ::unsetenv("SLOSH_BATCH_JOB_SPREAD");
    return out;
  }
  std::vector<std::unique_ptr<test::Replica>> replicas;
  test::Replica& a() { return *replicas[0]; }
  test::Replica& b() { return *replicas[1]; }
};

// Redis at maxmemory with noeviction refuses the job's row and record writes (OOM). The owner
// keeps the rows, retries them at every heartbeat and says so (its record, its log, its
// /readyz naming Redis's refusal); its heartbeat stays alive, so the other replica never reads
// the job as failed, and answers 503 for the results whose rows are not in Redis (never a 200
// with rows missing). Once Redis takes writes again, both serve the same full table.
TEST(ClusterStoreFaults, RowsRedisRefusesStayOnTheOwnerWhichSaysSoAndNoReplicaCallsTheJobFailed) {
  test::RedisServer redis;
  Pair pair(redis, "3");
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(300, 11000));
  ASSERT_FALSE(id.empty());
  // Full from now on: every write that may grow memory is refused with Redis's OOM error.
  ASSERT_EQ(redis_cli(redis, "config set maxmemory-policy noeviction"), 0);
  ASSERT_EQ(redis_cli(redis, "config set maxmemory 1"), 0);
  const std::string refusal = "the shared job store (" + redis.url() +
                              ") refused the write: OOM command not allowed when used memory > "
                              "'maxmemory'.";
  const json own = wait_finished(a, id);
  ASSERT_EQ(own.value("state", ""), "done") << own.dump();
  ASSERT_TRUE(own.contains("unshared")) << own.dump();
  EXPECT_EQ(own["unshared"]["reason"], refusal);
  EXPECT_GT(own["unshared"]["rows"].get<std::size_t>(), 0u) << own.dump();
  EXPECT_NE(pair.a().log().find("batch job " + id + ": " + refusal +
                                "; its rows and record are kept on this replica and sent again "
                                "at every heartbeat"),
            std::string::npos)
      << pair.a().log();
  const json ready = get_json(a, "/readyz");
  EXPECT_EQ(ready.value("status", ""), "degraded") << ready.dump();
  EXPECT_EQ(ready["jobs"]["store_warning"],
            refusal +
                "; 1 batch job's rows or records are kept on this replica only and sent again at "
                "every heartbeat (other replicas cannot serve them until then)");
  const auto full = a.Get("/v1/batches/" + id + "/results.csv");
  ASSERT_TRUE(full && full->status == 200);
  EXPECT_EQ(lines_of(full->body), 301u);
  // Past batch_job_stale_s (3 s) since Redis last took the record: still alive on B.
  std::this_thread::sleep_for(4s);  // the time the fault lasts, not a wait on the product
  const json other = get_json(b, "/v1/batches/" + id);
  EXPECT_NE(other.value("state", ""), "failed") << other.dump();
  ASSERT_TRUE(other.contains("unshared")) << other.dump();
  const std::string alive =
      "the replica running it is alive (its heartbeat in the shared job "
      "store is ";
  EXPECT_EQ(other["unshared"]["reason"].get<std::string>().rfind(alive, 0), 0u) << other.dump();
  const json refused = error_of(b.Get("/v1/batches/" + id + "/results.csv"), 503);
  EXPECT_EQ(refused.value("message", "")
                .rfind("the rows of batch job '" + id +
                           "' are not all in the shared job store "
                           "(Redis): " +
                           alive,
                       0),
            0u)
      << refused.dump();
  // Redis takes writes again: the owner's next heartbeat publishes the rows.
  ASSERT_EQ(redis_cli(redis, "config set maxmemory 0"), 0);
  std::optional<httplib::Response> later;
  ASSERT_TRUE(poll_until(15s, [&] {
    const auto r = b.Get("/v1/batches/" + id + "/results.csv");
    if (r) later = *r;
    return r && r->status == 200;
  })) << (later ? later->body : "no answer");
  EXPECT_EQ(later->body, full->body);
  // The owner clears its warnings once its publishing has returned (just after Redis took it).
  json record;
  json readiness;
  EXPECT_TRUE(poll_until(5s,
                         [&] {
                           record = get_json(a, "/v1/batches/" + id);
                           readiness = get_json(a, "/readyz");
                           return !record.contains("unshared") &&
                                  readiness.value("status", "") == "ready";
                         }))
      << record.dump() << "\n"
      << readiness.dump();
}

// Redis stalls while B reads a job's rows (the relay holds B's HMGET past B's 200 ms timeout):
// a 503 with Retry-After naming the store and its timeout, not "damaged, POST the job again".
TEST(ClusterStoreFaults, AStallWhileReadingRowsIsTheStoreNotAnsweringInTimeNotDamage) {
  test::RedisServer redis;
  test::StallingRelay relay(redis.port());
  Pair pair(redis.url(), relay.url());
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(6, 12000));
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_finished(a, id).value("state", ""), "done");
  const auto own = a.Get("/v1/batches/" + id + "/results.csv");
  ASSERT_TRUE(own && own->status == 200);
  relay.stall_on("HMGET", 600ms);
  const std::string unread =
      "the results of batch job '" + id + "' could not be read: the shared job store (" +
      relay.url() +
      ") did not answer in time: no reply within 200 ms (reading rows 1 to 6); nothing is lost, "
      "retry later";
  EXPECT_EQ(error_of(b.Get("/v1/batches/" + id + "/results.csv"), 503),
            json({{"code", "unavailable"}, {"field", "id"}, {"message", unread}}));
  EXPECT_GE(relay.stalled(), 1);
  relay.stall_on("", 0ms);
  std::optional<httplib::Response> later;
  ASSERT_TRUE(poll_until(10s, [&] {
    const auto r = b.Get("/v1/batches/" + id + "/results.csv");
    if (r) later = *r;
    return r && r->status == 200;
  })) << (later ? later->body : "no answer");
  EXPECT_EQ(later->body, own->body);
}

// A DELETE through B of a job whose owner A is paused (SIGSTOP) is recorded in Redis and
// answered at once (within the Redis timeouts), saying the owner has not answered and stops the
// job when it next reads the store, and what happens if it stays silent under `spread` (the
// end of the note, `then`); once A runs again, it does stop it.
void delete_while_the_owner_is_paused(const char* spread, const std::string& then) {
  test::RedisServer redis;
  Pair pair(redis, "30", spread);
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(300, 13000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  ::kill(pair.a().pid(), SIGSTOP);
  std::this_thread::sleep_for(3s);  // the pause itself (the fault): A's record ages
  const auto asked = std::chrono::steady_clock::now();
  const auto deleted = b.Delete("/v1/batches/" + id);
  const auto took = std::chrono::steady_clock::now() - asked;
  ::kill(pair.a().pid(), SIGCONT);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 202) << deleted->body;
  // Bounded by B's Redis commands (200 ms each), not by A.
  EXPECT_LT(took, 2s);
  const json record = json::parse(deleted->body);
  EXPECT_EQ(record.value("cancel_requested", false), true);
  const std::regex note(
      "the cancel is recorded in the shared job store; the replica running the job has not "
      "answered for [0-9.]+ s \\(paused, stalled or cut off from the store\\): it stops the job "
      "when it next reads the store, " +
      then);
  EXPECT_TRUE(std::regex_match(record.value("cancel_note", ""), note)) << record.dump();
  EXPECT_EQ(wait_finished(a, id).value("state", ""), "cancelled");
}

// With the default "helpers", a silent owner's job is taken over (and so stopped) by another
// replica at half of batch_job_stale_s: it never reads as failed.
TEST(ClusterStoreFaults, ADeleteThroughAnotherReplicaWhileTheOwnerIsPausedIsAnsweredAtOnce) {
  delete_while_the_owner_is_paused(
      "",
      "or another replica takes the job over once it has been silent for half of "
      "batch_job_stale_s = 30 s \\(15 s\\) and stops it then");
}

// With "owner", nothing takes the job over: it reads as failed at batch_job_stale_s.
TEST(ClusterStoreFaults, ADeleteWhileTheOwnerIsPausedSaysTheJobReadsAsFailedWithOwnerSpread) {
  delete_while_the_owner_is_paused(
      "owner", "and the job reads as failed once it has been silent for batch_job_stale_s = 30 s");
}

// With "owner", an owner paused past batch_job_stale_s carries on and says so: a line in its log
// and a note in the job's record (read through either replica), naming how long it did not run.
// (With the default "helpers", another replica takes such a job over: the test below.)
TEST(ClusterStoreFaults, AnOwnerResumedAfterAPauseSaysSoInItsLogAndTheJobsRecord) {
  test::RedisServer redis;
  Pair pair(redis, "1.5", "owner");
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(200, 14000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  ::kill(pair.a().pid(), SIGSTOP);
  std::this_thread::sleep_for(3s);  // the pause itself (the fault), past the stale time
  ::kill(pair.a().pid(), SIGCONT);
  const json done = wait_finished(a, id);
  EXPECT_EQ(done.value("state", ""), "done") << done.dump();
  const std::regex note(
      "this job's replica did not run for ([0-9.]+) s \\(its process was paused or starved\\) and "
      "carried on with the job; other replicas read it as failed meanwhile \\(batch_job_stale_s = "
      "1.5 s\\) until its next record");
  std::smatch m;
  const std::string text = done.value("note", "");
  ASSERT_TRUE(std::regex_match(text, m, note)) << done.dump();
  EXPECT_GE(std::stod(m[1]), 3.0) << text;
  EXPECT_LT(std::stod(m[1]), 30.0) << text;
  EXPECT_NE(pair.a().log().find("batch job " + id + ": " + text), std::string::npos)
      << pair.a().log();
  EXPECT_EQ(get_json(b, "/v1/batches/" + id).value("note", ""), text);
}

// With the default "helpers", a job whose owner is paused past half of batch_job_stale_s is
// taken over by the other replica from its record and rows in Redis and ends done there, each
// row once; the owner, resumed, finds the job is no longer its own, says so and drops its copy
// (it never writes over the new owner's record).
TEST(ClusterStoreFaults, AJobOfAnOwnerPausedPastTheStaleTimeIsTakenOverAndEndsDone) {
  test::RedisServer redis;
  Pair pair(redis, "1.5");
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(200, 15000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  ::kill(pair.a().pid(), SIGSTOP);
  std::this_thread::sleep_for(3s);  // the pause itself (the fault), past the stale time
  ::kill(pair.a().pid(), SIGCONT);
  const json done = wait_finished(b, id);
  EXPECT_EQ(done.value("state", ""), "done") << done.dump();
  EXPECT_EQ(done.at("progress").at("done"), 200);
  std::size_t sum = 0;
  for (const auto& [replica, rows] : done.at("shares").items()) sum += rows.get<std::size_t>();
  EXPECT_EQ(sum, 200u) << done.dump();
  EXPECT_TRUE(test::wait_until(
      [&] {
        return pair.a().log().find("batch job " + id + ": another replica took it over") !=
               std::string::npos;
      },
      std::chrono::seconds(10)))
      << pair.a().log();
  EXPECT_EQ(wait_finished(a, id).value("state", ""), "done");
  const auto csv = a.Get("/v1/batches/" + id + "/results.csv");
  ASSERT_TRUE(csv && csv->status == 200) << (csv ? csv->body : "no answer");
  EXPECT_EQ(csv->get_header_value("X-Slosh-Rows"), "200");
}

/// The stored text of Redis key `key` ("" when absent).
std::string stored(service::RedisClient& redis, const std::string& key) {
  const auto reply = redis.command({"GET", key});
  return reply && reply->type == service::RedisReply::Type::kString ? reply->text : std::string();
}

// An owner paused until after the other replica took its job over and FINISHED it (then, with
// `forget`, after the job was DELETEd too) finds, once it runs again, that the job is no longer
// its own whatever its state: it says so in its log and writes nothing to Redis (the record is
// byte-identical, no rows come back for a forgotten job).
void resumed_owner_of_an_ended_job_writes_nothing(bool forget) {
  test::RedisServer redis;
  Pair pair(redis, "1.5");
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(200, forget ? 18000 : 17000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  ::kill(pair.a().pid(), SIGSTOP);
  const json done = wait_finished(b, id);
  ASSERT_EQ(done.value("state", ""), "done") << done.value("message", "");
  service::RedisClient store({service::parse_redis_url(redis.url())});
  const std::string record_key = "slosh:jobs:" + id + ":record";
  const std::string before = stored(store, record_key);
  if (forget) {
    const auto deleted = b.Delete("/v1/batches/" + id);
    ASSERT_TRUE(deleted && deleted->status == 200) << (deleted ? deleted->body : "no answer");
  }
  ::kill(pair.a().pid(), SIGCONT);
  EXPECT_TRUE(test::wait_until(
      [&] {
        return pair.a().log().find("batch job " + id + ": another replica took it over") !=
               std::string::npos;
      },
      std::chrono::seconds(10)))
      << pair.a().log();
  std::this_thread::sleep_for(1s);  // anything A would still write after its log line
  EXPECT_EQ(pair.a().log().find("carried on with the job"), std::string::npos) << pair.a().log();
  if (forget) {
    EXPECT_EQ(stored(store, record_key), "");
    const auto rows = store.command({"EXISTS", "slosh:jobs:" + id + ":rows"});
    ASSERT_TRUE(rows);
    EXPECT_EQ(rows->integer, 0);
    const auto gone = b.Get("/v1/batches/" + id);
    EXPECT_TRUE(gone && gone->status == 404);
  } else {
    EXPECT_EQ(stored(store, record_key), before);
    const json after = get_json(b, "/v1/batches/" + id);
    EXPECT_EQ(after.value("state", ""), "done");
    EXPECT_EQ(after.at("shares"), done.at("shares"));
  }
}

TEST(ClusterStoreFaults, AnOwnerResumedAfterItsJobWasTakenOverAndFinishedWritesNothing) {
  resumed_owner_of_an_ended_job_writes_nothing(false);
}

TEST(ClusterStoreFaults, AnOwnerResumedAfterItsTakenOverJobWasDeletedWritesNothing) {
  resumed_owner_of_an_ended_job_writes_nothing(true);
}

// Redis stalls for the owner A only (a relay holds every request of A's), past half of
// batch_job_stale_s: B reads A's heartbeat as silent and takes the job over, while A, cut off,
// finishes the job alone. Once A reaches Redis again (its held writes land late, its resync
// publishes what it kept), the job's owner mark names B: A's writes are refused, A drops its
// copy and says so, and both replicas serve B's record and one table (never A's finished record
// on A and B's on B).
TEST(ClusterStoreFaults, AnOwnerThatFinishedItsJobCutOffFromRedisPastItsTakeoverDropsItsCopy) {
  test::RedisServer redis;
  test::StallingRelay relay(redis.port());
  Pair pair(relay.url(), redis.url(), "2");  // taken over once A has been silent for 1 s
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(120, 19000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  relay.stall_on("*", 4000ms);  // every RESP request: A's Redis stalls
  const auto logged = [](test::Replica& r, const std::string& text) {
    return test::wait_until([&] { return r.log().find(text) != std::string::npos; },
                            std::chrono::seconds(30));
  };
  EXPECT_TRUE(logged(pair.b(), "batch job " + id + ": its replica line-1 stopped answering"))
      << pair.b().log();
  EXPECT_TRUE(logged(pair.a(), "batch job " + id + " done: 120 of 120 recipes")) << pair.a().log();
  relay.stall_on("", 0ms);
  const json done = wait_finished(b, id);
  ASSERT_EQ(done.value("state", ""), "done") << done.value("message", "");
  EXPECT_EQ(done.at("progress").at("done"), 120);
  EXPECT_TRUE(logged(pair.a(), "batch job " + id +
                                   ": replica line-2 took it over while this replica could not "
                                   "write to the shared job store; this replica's copy is dropped "
                                   "and the job is served as replica line-2 runs it"))
      << pair.a().log();
  const json via_a = get_json(a, "/v1/batches/" + id);
  EXPECT_EQ(via_a.value("state", ""), "done");
  EXPECT_EQ(via_a.at("shares"), done.at("shares"));
  EXPECT_EQ(via_a.at("finished_at"), done.at("finished_at"));
  EXPECT_GT(done.at("shares").value("line-2", 0), 0) << done.at("shares");
  const auto table_a = a.Get("/v1/batches/" + id + "/results.csv");
  const auto table_b = b.Get("/v1/batches/" + id + "/results.csv");
  ASSERT_TRUE(table_a && table_b);
  ASSERT_EQ(table_a->status, 200) << table_a->body;
  EXPECT_EQ(lines_of(table_a->body), 121u);
  EXPECT_EQ(test::csv_without_timing(table_a->body), test::csv_without_timing(table_b->body));
}

// Redis stalls (paused) past half of batch_job_stale_s while A runs a job: every heartbeat has
// aged by the stall, and B's first look after it reads A as silent (a relay holds A's heartbeat
// writes 0.1 s, so A's first one after the stall lands after that look). A live owner beats again
// at once, and B takes a job over only when its owner was silent at two looks in a row: A keeps
// its job, which ends done on A with every row once, never run again by B.
TEST(ClusterStoreFaults, ARedisStallPastHalfTheStaleTimeIsNotASilentOwner) {
  test::RedisServer redis;
  test::StallingRelay relay(redis.port());
  Pair pair(relay.url(), redis.url(), "2", {"--redis-timeout-ms", "10000"});
  auto a = pair.a().client();
  const std::string id = post_job(a, recipes(160, 23000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  relay.stall_on("alive", 100ms);
  std::this_thread::sleep_for(1s);
  redis.pause();
  std::this_thread::sleep_for(1600ms);  // past 1 s, half of batch_job_stale_s
  redis.resume();
  const json done = wait_finished(a, id);
  relay.stall_on("", 0ms);
  ASSERT_EQ(done.value("state", ""), "done") << done.value("message", "");
  EXPECT_EQ(done.at("progress").at("done"), 160);
  EXPECT_EQ(pair.b().log().find("stopped answering; this replica runs it on"), std::string::npos)
      << pair.b().log();
  EXPECT_EQ(pair.a().log().find("took it over"), std::string::npos) << pair.a().log();
}

// Redis stalls (paused) a little past batch_job_stale_s while A runs a job, and A's first
// heartbeats after it are held back a moment longer (a relay holds them 0.7 s, past A's Redis
// timeout): A's record is older than the stale time when B reads it, but A is alive. B never
// answers the job as failed (a final state a client stops polling at): its first reading of the
// silent record says so in the job's note, and by the time a record still silent would be called
// failed, A has written again (or B, helping, has taken the job over).
TEST(ClusterStoreFaults, ARedisStallPastTheStaleTimeDoesNotFailALiveOwnersJobOnTheOtherReplica) {
  test::RedisServer redis;
  test::StallingRelay relay(redis.port());
  Pair pair(relay.url(), redis.url(), "2");
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(160, 24000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  redis.pause();
  std::this_thread::sleep_for(2300ms);  // past batch_job_stale_s = 2 s
  relay.stall_on("alive", 700ms);
  redis.resume();
  std::thread release([&] {
    std::this_thread::sleep_for(1500ms);
    relay.stall_on("", 0ms);
  });
  bool noted = false;
  json last;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto got = b.Get("/v1/batches/" + id);
    if (got && got->status == 200) {
      last = json::parse(got->body);
      ASSERT_NE(last.value("state", ""), "failed") << last.dump();
      const std::string note =
          last.value("note", json()).is_string() ? last["note"].get<std::string>() : "";
      if (note.find("past batch_job_stale_s") != std::string::npos) {
        noted = true;
        EXPECT_TRUE(std::regex_match(
            note, std::regex("the replica running it has not updated it for [0-9.]+ s, past "
                             "batch_job_stale_s = 2 s \\(paused, stalled or cut off from the "
                             "shared store\\): another replica takes it over, or it reads as "
                             "failed if still silent in [0-9.]+ s")))
            << note;
      }
      if (last.value("state", "") == "done") break;
    }
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_EQ(last.value("state", ""), "done") << last.dump();
  EXPECT_EQ(last.at("progress").at("done"), 160);
  release.join();
  EXPECT_TRUE(noted) << "B never read the silent record";
}

// A DELETE accepted (202) as the owner stored a job's last row, before the owner read the flag
// again, finds the job done: the cancel recorded in Redis then is not dropped. Every replica
// answers the done job with "cancel_requested": true and a note saying the cancel came as it
// finished. (The flag is set here as such a DELETE leaves it, after the job ended.)
TEST(ClusterStoreFaults, ACancelRecordedAsTheJobFinishedIsKeptOnItsDoneRecord) {
  test::RedisServer redis;
  Pair pair(redis);
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(6, 25000));
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_finished(a, id).value("state", ""), "done");
  ASSERT_EQ(redis_cli(redis, "set slosh:jobs:" + id + ":cancel 1"), 0);
  for (auto* client : {&a, &b}) {
    const auto got = client->Get("/v1/batches/" + id);
    ASSERT_TRUE(got && got->status == 200) << (got ? got->body : "no answer");
    const json record = json::parse(got->body);
    EXPECT_EQ(record.value("state", ""), "done") << record.dump();
    EXPECT_EQ(record.at("progress").at("done"), 6);
    EXPECT_EQ(record.value("cancel_requested", false), true) << record.dump();
    EXPECT_EQ(record.value("note", json()),
              "a cancel was asked as its last row was stored: the job had finished, its table is "
              "whole")
        << record.dump();
  }
}

// A job cancelled while its owner is paused, before the other replica takes it over: the taker
// reads the cancel at once and ends the job cancelled, naming the rows the owner had stored
// (never "cancelled before it started" with rows done).
TEST(ClusterStoreFaults, AJobCancelledBeforeItsTakeoverNamesTheRowsItsOwnerHadDone) {
  test::RedisServer redis;
  Pair pair(redis, "4");  // taken over once A has been silent for 2 s
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(300, 16000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 2);
  ::kill(pair.a().pid(), SIGSTOP);
  const auto deleted = b.Delete("/v1/batches/" + id);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 202) << deleted->body;
  const json cancelled = wait_finished(b, id);
  ::kill(pair.a().pid(), SIGCONT);
  EXPECT_EQ(cancelled.value("state", ""), "cancelled") << cancelled.value("message", "");
  const int done = cancelled.at("progress").at("done").get<int>();
  EXPECT_GE(done, 2) << cancelled.at("progress").dump();
  EXPECT_EQ(cancelled.value("message", ""),
            "cancelled after " + std::to_string(done) + " of 300 recipes")
      << cancelled.at("progress").dump();
  EXPECT_TRUE(test::wait_until(
      [&] {
        return pair.b().log().find("batch job " + id + ": its replica line-1 stopped answering") !=
               std::string::npos;
      },
      std::chrono::seconds(10)))
      << pair.b().log();
}

// The table of a job that did not finish its rows (cancelled) is never answered as if it were
// the table: 409 naming the state and the rows done, and with ?partial=1 the done rows marked
// partial by the headers. A finished job's table says it is complete.
TEST(ClusterStoreFaults, ACancelledJobsTableIsRefusedUnlessThePartialTableIsAskedFor) {
  test::RedisServer redis;
  Pair pair(redis);
  auto a = pair.a().client();
  auto b = pair.b().client();
  const std::string id = post_job(a, recipes(300, 15000));
  ASSERT_FALSE(id.empty());
  wait_progress(a, id, 3);
  ASSERT_TRUE(a.Delete("/v1/batches/" + id));
  const json record = wait_finished(a, id);
  ASSERT_EQ(record.value("state", ""), "cancelled");
  const auto done = record["progress"]["done"].get<std::size_t>();
  ASSERT_LT(done, 300u);
  for (auto* c : {&a, &b}) {
    for (const std::string kind : {"csv", "jsonl"}) {
      const std::string path = "/v1/batches/" + id + "/results." + kind;
      EXPECT_EQ(
          error_of(c->Get(path), 409),
          json({{"code", "conflict"},
                {"field", "id"},
                {"message", "batch job " + id + " is cancelled with " + std::to_string(done) +
                                " of 300 recipes done (cancelled after " + std::to_string(done) +
                                " of 300 recipes): its table is "
                                "incomplete; GET " +
                                path + "?partial=1 for the " + std::to_string(done) +
                                " done rows, marked partial (X-Slosh-Partial: true), or POST "
                                "the job again"}}));
      const auto partial = c->Get(path + "?partial=1");
      ASSERT_TRUE(partial && partial->status == 200) << (partial ? partial->body : "");
      EXPECT_EQ(partial->get_header_value("X-Slosh-Partial"), "true");
      EXPECT_EQ(partial->get_header_value("X-Slosh-Rows"), std::to_string(done));
      EXPECT_EQ(partial->get_header_value("X-Slosh-Rows-Total"), "300");
      EXPECT_EQ(partial->get_header_value("X-Slosh-Job-State"), "cancelled");
      EXPECT_EQ(lines_of(partial->body), done + (kind == "csv" ? 1 : 0));
    }
  }
  EXPECT_EQ(get_json(b, "/v1/batches/" + id)["results"]["partial"], true);
  EXPECT_EQ(error_of(a.Get("/v1/batches/" + id + "/results.csv?partial=maybe"), 422),
            json({{"code", "invalid_value"},
                  {"field", "partial"},
                  {"message",
                   "partial = maybe is not allowed: one of \"1\", \"true\", \"0\", \"false\""}}));
  // A job that finished every row: its table, said complete.
  const std::string whole = post_job(a, recipes(4, 15500));
  ASSERT_EQ(wait_finished(a, whole).value("state", ""), "done");
  const auto table = b.Get("/v1/batches/" + whole + "/results.csv");
  ASSERT_TRUE(table && table->status == 200) << (table ? table->body : "");
  EXPECT_EQ(table->get_header_value("X-Slosh-Partial"), "false");
  EXPECT_EQ(table->get_header_value("X-Slosh-Rows"), "4");
  EXPECT_EQ(lines_of(table->body), 5u);
}

}  // namespace test_cluster_store_faults
}  // namespace slosh
