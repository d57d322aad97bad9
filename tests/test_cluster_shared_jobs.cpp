// A batch job shared out to every replica through Redis (SPEC §13, batch_job_spread =
// "replicas"), every part real and started by the test: a redis-server on a free port, three
// `slosh serve` replicas (one solve worker each) sharing it, and nginx in front. A job posted
// through the proxy is worked on by all three (each one's slosh_batch_job_items_total and its
// share in the record), and its table is the file `slosh batch` writes for the same recipes,
// also after a replica was killed (-9) at a third of it and after Redis was restarted empty
// mid-job; a cancel through a replica that did not take the job stops every replica's items; a
// job much larger than every replica's queue runs to its end while interactive plans are
// answered. A calibration stored through one replica plans on another (calibrations live in Redis
// too). The tests wait for states and counters (polling), never for a fixed time.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/batch_job_record.hpp"
#include "jobs/recipe_table.hpp"
#include "jobs/shared_job_queue.hpp"
#include "storage/redis_client.hpp"
#include "storage/redis_url.hpp"
#include "support/calibration_body.hpp"
#include "support/job_tables.hpp"
#include "support/process.hpp"
#include "support/proxy.hpp"
#include "support/redis_server.hpp"
#include "support/replicas.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_cluster_shared_jobs {

using nlohmann::json;
using test::csv_cells;
using test::csv_without_timing;
using namespace std::chrono_literals;

/// The item take-over time of these clusters (batch_job_stale_s) [s]: a killed replica's items
/// are solved by the others this long after it stopped renewing them.
constexpr const char* kStaleS = "3";

/// redis-server, three replicas sharing jobs through it (one worker each, `queue` solves may wait
/// on each, Redis timeout `redis_timeout_ms`) and nginx in front.
struct SharedCluster {
  explicit SharedCluster(const char* queue = "64", const char* redis_timeout_ms = "10000")
      : replicas(start(redis, queue, redis_timeout_ms)) {}
  static test::ReplicaSet start(const test::RedisServer& redis, const char* queue,
                                const char* redis_timeout_ms) {
    ::setenv("SLOSH_BATCH_JOB_SPREAD", "replicas", 1);  // the replicas read them at start
    ::setenv("SLOSH_BATCH_JOB_STALE_S", kStaleS, 1);
    test::ReplicaSet set{3,
                         {"--cache", redis.url(), "--workers", "1", "--queue", queue,
                          "--redis-timeout-ms", redis_timeout_ms},
                         "line"};
    ::unsetenv("SLOSH_BATCH_JOB_SPREAD");
    ::unsetenv("SLOSH_BATCH_JOB_STALE_S");
    return set;
  }
  test::RedisServer redis;
  test::ReplicaSet replicas;
  test::NginxProxy proxy{replicas.ports(), true};
};

/// A CSV recipe table of `n` distinct recipes (the motion time differs: no two share a plan).
std::string table_of(std::size_t n) {
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (std::size_t i = 0; i < n; ++i) {
    char time[32];
    std::snprintf(time, sizeof time, "%.3f", 0.9 + 0.001 * static_cast<double>(i));
    table += "r" + std::to_string(i) + ",48.5,82,water,800," + time + ",notch\n";
  }
  return table;
}

/// The table `slosh batch` writes for table_of(n) (no cache), without timing cells.
std::vector<std::string> reference_of(std::size_t n) {
  const test::TempDir dir;
  test::write_file(dir / "t.csv", table_of(n));
  const auto r = test::run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                  (dir / "out.csv").string(), "--cache", ""});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return csv_without_timing(test::read_file(dir / "out.csv"));
}

/// The reference of the 480-recipe table, computed once for the tests that use it.
const std::vector<std::string>& reference_480() {
  static const std::vector<std::string> reference = reference_of(480);
  return reference;
}

std::string post_table(httplib::Client& c, std::size_t n) {
  const json body{{"table", table_of(n)}, {"table_format", "csv"}, {"format", "csv"}};
  const auto r = c.Post("/v1/batches", body.dump(), "application/json");
  EXPECT_TRUE(r && r->status == 202) << (r ? r->body : "no answer");
  return r && r->status == 202 ? json::parse(r->body).at("id").get<std::string>() : "";
}

/// The record of job `id` through `c`; null while it answers anything but 200 (e.g. 503 while
/// Redis restarts).
json record_of(httplib::Client& c, const std::string& id) {
  const auto r = c.Get("/v1/batches/" + id);
  return r && r->status == 200 ? json::parse(r->body) : json();
}

/// Polls job `id` through `c` until it has finished; the last record.
json wait_finished(httplib::Client& c, const std::string& id) {
  json record;
  test::wait_until([&] { return test::is_final_record(record = record_of(c, id)); });
  return record;
}

/// Polls job `id` through `c` until at least `done` rows are stored; the last record.
json wait_done(httplib::Client& c, const std::string& id, int done) {
  json record;
  test::wait_until([&] {
    record = record_of(c, id);
    return record.is_object() && record.at("progress").at("done").get<int>() >= done;
  });
  return record;
}

double items_of(const test::Replica& replica) {
  auto c = replica.client();
  const auto r = c.Get("/metrics");
  return r ? test::metric(r->body, "slosh_batch_job_items_total") : -1.0;
}

/// The items counters of the running replicas of `cluster` once their sum is `rows`: a replica
/// counts a row just after Redis took it, so the last count may follow the job's final record by
/// a moment; a sum that never reaches `rows` (a row stored twice or never) is reported as it is.
std::vector<double> counters_once_at(SharedCluster& cluster, double rows) {
  std::vector<double> items(3, 0.0);
  test::wait_until(
      [&] {
        double sum = 0;
        for (std::size_t i = 0; i < 3; ++i) {
          items[i] = cluster.replicas[i].running() ? items_of(cluster.replicas[i]) : 0.0;
          sum += items[i];
        }
        return sum == rows;
      },
      std::chrono::seconds(10));
  return items;
}

/// The results.csv of a finished job `id` through `c`, checked whole: every row number once.
std::vector<std::string> whole_table(httplib::Client& c, const std::string& id, std::size_t n) {
  const auto csv = c.Get("/v1/batches/" + id + "/results.csv");
  EXPECT_TRUE(csv && csv->status == 200) << (csv ? csv->body : "no answer");
  if (!csv || csv->status != 200) return {};
  EXPECT_EQ(csv->get_header_value("X-Slosh-Partial"), "false");
  EXPECT_EQ(csv->get_header_value("X-Slosh-Rows"), std::to_string(n));
  return csv_without_timing(csv->body);
}

TEST(SharedJobs, AJobIsWorkedOnByEveryReplicaAndItsTableIsSloshBatchs) {
  const std::vector<std::string>& reference = reference_480();
  SharedCluster cluster;
  auto proxy = cluster.proxy.client();
  const std::string id = post_table(proxy, 480);
  ASSERT_FALSE(id.empty());
  const json done = wait_finished(proxy, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  EXPECT_EQ(done.at("progress").at("failed"), 0);
  // Each replica stored a share, its counter says the same, and the shares add up to the table.
  const std::vector<double> items = counters_once_at(cluster, 480);
  double sum = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const test::Replica& r = cluster.replicas[i];
    EXPECT_GT(items[i], 0) << r.id() << " took no item: " << done;
    EXPECT_EQ(done.at("shares").value(r.id(), -1.0), items[i]) << done;
    sum += items[i];
  }
  EXPECT_EQ(sum, 480);
  EXPECT_EQ(whole_table(proxy, id, 480), reference);
  // Every replica answers the same record (the status and body are shown when one does not).
  for (std::size_t i = 0; i < 3; ++i) {
    auto c = cluster.replicas[i].client();
    const auto r = c.Get("/v1/batches/" + id);
    ASSERT_TRUE(r) << cluster.replicas[i].id();
    ASSERT_EQ(r->status, 200) << cluster.replicas[i].id() << ": " << r->body;
    EXPECT_EQ(json::parse(r->body).at("shares"), done.at("shares")) << cluster.replicas[i].id();
  }
}

TEST(SharedJobs, KillingAReplicaAtAThirdLosesNoRowAndDuplicatesNone) {
  const std::vector<std::string>& reference = reference_480();
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 480);
  ASSERT_FALSE(id.empty());
  // The replica that accepted the job dies at ~30 %, holding an item it took (pending in the
  // stream's group: it is solving it), which another replica must take over.
  const json third = wait_done(other, id, 144);
  ASSERT_EQ(third.at("state"), "running") << third;
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  ASSERT_TRUE(test::wait_until([&] {
    const auto held = redis.command(
        {"XPENDING", "slosh:jobs:" + id + ":items", "workers", "-", "+", "10", "line-1"});
    return held && !held->elements.empty();
  }));
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  const json& shares = done.at("shares");
  std::size_t sum = 0;
  for (const auto& [replica, rows] : shares.items()) sum += rows.get<std::size_t>();
  EXPECT_EQ(sum, 480) << shares;  // each row stored once
  const std::vector<double> items = counters_once_at(cluster, 480 - shares.value("line-1", 0.0));
  EXPECT_EQ(items[1] + items[2] + shares.value("line-1", 0.0), 480);
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

// A replica stopped gracefully mid-job: the solves still queued on it are refused by its
// shutdown, and such a refusal is not a recipe's row (the job would end done with failed rows
// where `slosh batch` plans them). Its items stay pending in the stream; the others plan them.
TEST(SharedJobs, AReplicaStoppedGracefullyMidJobStoresNoRefusalAsARow) {
  const std::vector<std::string>& reference = reference_480();
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 480);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(other, id, 144).at("state"), "running");
  ASSERT_EQ(cluster.replicas[0].kill(SIGTERM), 0);
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("failed"), 0) << done;
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

TEST(SharedJobs, ARedisRestartedEmptyMidJobStillEndsWithTheWholeTable) {
  const std::vector<std::string>& reference = reference_480();
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[2].client();
  const std::string id = post_table(owner, 480);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(other, id, 120).at("state"), "running");
  cluster.redis.kill();
  cluster.redis.start();  // the same port, empty: the owner publishes the job again
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

TEST(SharedJobs, ACancelThroughAnotherReplicaStopsEveryReplicasItems) {
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto third = cluster.replicas[2].client();
  const std::string id = post_table(owner, 3000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(third, id, 30).at("state"), "running");
  const auto deleted = third.Delete("/v1/batches/" + id);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 202) << deleted->body;
  auto second = cluster.replicas[1].client();
  const json cancelled = wait_finished(second, id);
  ASSERT_EQ(cancelled.at("state"), "cancelled") << cancelled;
  const int rows = cancelled.at("progress").at("done").get<int>();
  EXPECT_LT(rows, 3000);
  EXPECT_EQ(cancelled.at("message"),
            "cancelled after " + std::to_string(rows) + " of 3000 recipes");
  // No replica stored a row after the cancel: the rows stored are the record's, and the partial
  // table holds each of them once.
  const std::vector<double> items = counters_once_at(cluster, rows);
  EXPECT_EQ(items[0] + items[1] + items[2], rows);
  const auto csv = second.Get("/v1/batches/" + id + "/results.csv?partial=1");
  ASSERT_TRUE(csv && csv->status == 200) << (csv ? csv->body : "no answer");
  EXPECT_EQ(csv->get_header_value("X-Slosh-Rows"), std::to_string(rows));
  const std::vector<std::string> lines = csv_without_timing(csv->body);
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(rows) + 1);
  std::set<std::string> numbers;
  for (std::size_t i = 1; i < lines.size(); ++i) numbers.insert(csv_cells(lines[i]).at(0));
  EXPECT_EQ(numbers.size(), static_cast<std::size_t>(rows));
  // The replicas' pools run no more of its items: every replica is idle again.
  EXPECT_TRUE(test::wait_until([&] {
    for (std::size_t i = 0; i < 3; ++i) {
      auto c = cluster.replicas[i].client();
      const auto m = c.Get("/metrics");
      if (!m || test::metric(m->body, "slosh_pool_background_queue_depth") > 0) return false;
    }
    return true;
  }));
}

TEST(SharedJobs, AJobLargerThanEveryQueueRunsToItsEndWhileInteractivePlansAreAnswered) {
  // Each replica lets 2 solves wait: the 600 items never crowd out a plan (the job keeps at most
  // one item per worker in flight), and a plan posted meanwhile is answered, not refused.
  SharedCluster cluster{"2"};
  auto proxy = cluster.proxy.client();
  const std::string id = post_table(proxy, 600);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(proxy, id, 30).at("state"), "running");
  for (int i = 0; i < 3; ++i) {  // distinct recipes: each one solved, none a cache hit
    const std::string plan = json{
        {"format",
         {{"container", {{"radius_mm", 48.5}}},
          {"fill_height_mm", 82},
          {"fluid", "water"},
          {"stroke_mm", 800},
          {"motion_time_s", 2.5 + 0.1 * i}}},
        {"strategy", "notch"}}.dump();
    const auto r = proxy.Post("/v1/plans", plan, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;
  }
  const json done = wait_finished(proxy, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 600);
  std::size_t sum = 0;
  for (const auto& [replica, rows] : done.at("shares").items()) sum += rows.get<std::size_t>();
  EXPECT_EQ(sum, 600);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_GT(items_of(cluster.replicas[i]), 0);
}

/// The keys of the Redis of `cluster` matching `pattern` (KEYS), sorted; empty when it does not
/// answer.
std::vector<std::string> keys_of(const SharedCluster& cluster, const std::string& pattern) {
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  std::vector<std::string> out;
  if (const auto reply = redis.command({"KEYS", pattern})) {
    for (const auto& key : reply->elements) out.push_back(key.text);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Redis full (maxmemory, noeviction) mid-job refuses the rows and the record, but the replicas
// still renew the job's heartbeat (a PEXPIRE, which a full Redis takes): past batch_job_stale_s
// another replica reads the job as alive and behind, never as failed, and the job ends with the
// whole table once Redis takes writes: each replica kept the rows Redis refused (renewing its
// hold of their items, so none is taken over as if its replica had died) and stores them then.
TEST(SharedJobs, AFullRedisMidJobLeavesItAliveAndItEndsWithTheWholeTableOnceWritesAreTaken) {
  const std::vector<std::string>& reference = reference_480();
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 480);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(other, id, 60).at("state"), "running");
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  ASSERT_TRUE(redis.command({"CONFIG", "SET", "maxmemory-policy", "noeviction"}));
  ASSERT_TRUE(redis.command({"CONFIG", "SET", "maxmemory", "1"}));
  std::this_thread::sleep_for(5s);  // the fault lasts past batch_job_stale_s (3 s)
  const json behind = record_of(other, id);
  // Its stored record is the last one Redis took (queued or running), not failed.
  const std::string state = behind.value("state", "");
  EXPECT_TRUE(state == "queued" || state == "running") << behind;
  ASSERT_TRUE(behind.contains("unshared")) << behind;
  const std::regex reason(
      "the replicas working on it are alive \\(its heartbeat in the shared job store is "
      "[0-9.]+ s old\\) but could not update its record there for [0-9.]+ s: the shared store "
      "refuses or fails their writes \\(their /readyz says why\\); each replica keeps the rows "
      "it refused and stores them once it takes writes");
  EXPECT_TRUE(std::regex_match(behind["unshared"].value("reason", ""), reason)) << behind;
  ASSERT_TRUE(redis.command({"CONFIG", "SET", "maxmemory", "0"}));
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

// A job POSTed while Redis is stalled (SIGSTOP) past the replicas' 200 ms timeout is refused 503;
// the publishing writes that timed out land once Redis runs again, and the replica that refused
// the job marks it removed, so no replica takes an item of a job that nobody owns and nothing of
// it but the mark is left.
TEST(SharedJobs, AJobRefusedWhileRedisIsStalledIsClosedForEveryReplica) {
  SharedCluster cluster{"64", "200"};
  auto owner = cluster.replicas[0].client();
  cluster.redis.pause();
  const json body{{"table", table_of(30)}, {"table_format", "csv"}, {"format", "csv"}};
  const auto refused = owner.Post("/v1/batches", body.dump(), "application/json");
  cluster.redis.resume();
  ASSERT_TRUE(refused);
  ASSERT_EQ(refused->status, 503) << refused->body;
  EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
  ASSERT_TRUE(test::wait_until([&] { return !keys_of(cluster, "slosh:jobs:*:removed").empty(); },
                               std::chrono::seconds(20)));
  ASSERT_EQ(keys_of(cluster, "slosh:jobs:*:removed").size(), 1u);
  for (const char* part : {"spec", "items", "record", "rows", "counts"}) {
    EXPECT_TRUE(keys_of(cluster, std::string("slosh:jobs:*:") + part).empty()) << part;
  }
  for (std::size_t i = 0; i < 3; ++i) EXPECT_LE(items_of(cluster.replicas[i]), 0);
}

// Redis killed mid-job: the replica that accepted the job still answers for it with its last view
// of the job's progress (saying why), not 503, and takes a DELETE, which it records in Redis once
// Redis runs again (restarted empty: it publishes the job again, cancelled).
TEST(SharedJobs, WhileRedisIsDownTheAcceptingReplicaAnswersForItsJobAndTakesItsCancel) {
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 3000);
  ASSERT_FALSE(id.empty());
  const int seen = wait_done(owner, id, 30).at("progress").at("done").get<int>();
  cluster.redis.kill();
  const json view = record_of(owner, id);
  ASSERT_TRUE(view.is_object()) << "no 200 from the accepting replica";
  EXPECT_EQ(view.value("state", ""), "running") << view;
  EXPECT_GE(view.at("progress").at("done").get<int>(), seen) << view;
  EXPECT_EQ(view["unshared"].value("reason", ""),
            "the shared job store (Redis) cannot be reached now: this is the job's progress over "
            "all replicas as the replica that accepted it last read it; its items wait until the "
            "store answers again")
      << view;
  const auto deleted = owner.Delete("/v1/batches/" + id);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 202) << deleted->body;
  cluster.redis.start();
  const json cancelled = wait_finished(owner, id);
  EXPECT_EQ(cancelled.value("state", ""), "cancelled") << cancelled;
}

/// Replicas sharing jobs through `redis` (one worker each), started with the settings `env`
/// (name, value) besides batch_job_spread = "replicas" and batch_job_stale_s = 2.
test::ReplicaSet sharing_replicas(const test::RedisServer& redis, std::size_t n,
                                  const std::vector<std::pair<const char*, const char*>>& env,
                                  const char* name) {
  ::setenv("SLOSH_BATCH_JOB_SPREAD", "replicas", 1);
  ::setenv("SLOSH_BATCH_JOB_STALE_S", "2", 1);
  for (const auto& [key, value] : env) ::setenv(key, value, 1);
  test::ReplicaSet set{
      n, {"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "10000"}, name};
  ::unsetenv("SLOSH_BATCH_JOB_SPREAD");
  ::unsetenv("SLOSH_BATCH_JOB_STALE_S");
  for (const auto& [key, value] : env) ::unsetenv(key);
  return set;
}

/// Publishes a job of table_of(n) in `redis` as a replica that accepted it would, and returns
/// its id; no replica runs yet.
std::string publish_job(const test::RedisServer& redis, const std::string& id, std::size_t n) {
  auto client = std::make_shared<service::RedisClient>(
      service::RedisOptions{service::parse_redis_url(redis.url())});
  service::SharedQueueOptions options;
  options.replica = "publisher";
  service::SharedJobQueue queue(client, options);
  service::JobStatus status;
  status.id = id;
  status.total = n;
  status.created_ms = service::unix_ms_now();
  const auto published =
      queue.publish(status, service::read_recipe_table(table_of(n), service::TableFormat::kCsv));
  EXPECT_FALSE(published) << *published;
  return id;
}

/// Hands the first item of job `id` out `takes` times to consumers that never store it (as
/// replicas that died while solving it would); its delivery count is then `takes`.
void take_first_item(service::RedisClient& redis, const std::string& id, int takes) {
  const std::string stream = "slosh:jobs:" + id + ":items";
  const auto read = redis.command(
      {"XREADGROUP", "GROUP", "workers", "ghost-1", "COUNT", "1", "STREAMS", stream, ">"});
  ASSERT_TRUE(read && !read->elements.empty()) << "no item to take";
  const std::string entry = read->elements[0].elements[1].elements[0].elements[0].text;
  for (int i = 2; i <= takes; ++i) {
    ASSERT_TRUE(
        redis.command({"XCLAIM", stream, "workers", "ghost-" + std::to_string(i), "0", entry}));
  }
  const auto pending = redis.command({"XPENDING", stream, "workers", entry, entry, "1"});
  ASSERT_TRUE(pending && pending->elements.size() == 1);
  ASSERT_EQ(pending->elements[0].elements[3].integer, takes);
}

// An item whose takers all stopped before storing its row (it may be what kills them) is handed
// out batch_job_max_takes times at most: the next replica that takes it over records its row
// failed, naming the setting, instead of solving it again; an item taken as often as the limit
// allows is still solved.
TEST(SharedJobs, AnItemTakenMoreThanMaxTakesWithoutARowIsRecordedFailedNotHandedOutForever) {
  test::RedisServer redis;
  service::RedisClient client({service::parse_redis_url(redis.url())});
  const std::string at_limit = publish_job(redis, "00000000000000000000000000000a11", 6);
  const std::string past = publish_job(redis, "00000000000000000000000000000b22", 6);
  take_first_item(client, at_limit, 2);  // the replica's take over is the 3rd: still solved
  take_first_item(client, past, 3);      // the replica's take over is the 4th: recorded failed
  test::ReplicaSet replicas =
      sharing_replicas(redis, 1, {{"SLOSH_BATCH_JOB_MAX_TAKES", "3"}}, "take");
  auto c = replicas[0].client();
  const json solved = wait_finished(c, at_limit);
  ASSERT_EQ(solved.at("state"), "done") << solved;
  EXPECT_EQ(solved.at("progress").at("failed"), 0) << solved;
  const json dead = wait_finished(c, past);
  ASSERT_EQ(dead.at("state"), "done") << dead;
  EXPECT_EQ(dead.at("progress").at("done"), 6);
  EXPECT_EQ(dead.at("progress").at("failed"), 1) << dead;
  const json& rows = dead.at("results").at("rows");
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].at("status"), "error") << rows[0];
  EXPECT_EQ(rows[0].at("message"),
            "this recipe was taken 3 times by replicas that never stored its row (each stopped, "
            "crashed or was cut off from Redis while solving it): it is not handed out again past "
            "batch_job_max_takes = 3; plan it alone (POST /v1/plans) to see what it does");
  for (std::size_t i = 1; i < 6; ++i) EXPECT_NE(rows[i].at("status"), "error") << rows[i];
  // The same recipe in the other job was solved: it is a good recipe, only its takers died.
  EXPECT_NE(solved.at("results").at("rows")[0].at("status"), "error");
}

// batch_jobs_bytes bounds a shared job's rows in Redis as it bounds a job run on one replica: the
// row that passes it is the job's last and the job ends failed naming the setting; Redis holds
// exactly the rows counted, their sizes summed just past the bound.
TEST(SharedJobs, ASharedJobsRowsInRedisAreBoundedByBatchJobsBytes) {
  test::RedisServer redis;
  test::ReplicaSet replicas =
      sharing_replicas(redis, 2, {{"SLOSH_BATCH_JOBS_BYTES", "65536"}}, "bytes");
  auto c = replicas[0].client();
  const std::string id = post_table(c, 600);
  ASSERT_FALSE(id.empty());
  auto other = replicas[1].client();
  const json failed = wait_finished(other, id);
  ASSERT_EQ(failed.at("state"), "failed") << failed;
  const int done = failed.at("progress").at("done").get<int>();
  EXPECT_LT(done, 600);
  EXPECT_EQ(failed.at("message"),
            "its results passed the memory kept for batch jobs, batch_jobs_bytes = 65536 bytes, "
            "after " +
                std::to_string(done) +
                " of 600 recipes: split the table into smaller "
                "jobs, ask for a smaller view, or raise batch_jobs_bytes");
  service::RedisClient client({service::parse_redis_url(redis.url())});
  const auto values = client.command({"HVALS", "slosh:jobs:" + id + ":rows"});
  ASSERT_TRUE(values);
  ASSERT_EQ(values->elements.size(), static_cast<std::size_t>(done));
  std::size_t bytes = 0;
  std::size_t largest = 0;
  for (const auto& v : values->elements) {
    bytes += v.text.size();
    largest = std::max(largest, v.text.size());
  }
  EXPECT_GT(bytes, 65536u);
  EXPECT_LE(bytes - largest, 65536u);  // no row stored past the one that passed the bound
  const auto csv = other.Get("/v1/batches/" + id + "/results.csv?partial=1");
  ASSERT_TRUE(csv && csv->status == 200) << (csv ? csv->body : "no answer");
  EXPECT_EQ(csv->get_header_value("X-Slosh-Rows"), std::to_string(done));
}

// A finished job survives Redis restarted empty, as a job run on one replica does: the replica
// that accepted it kept a copy of its record and rows and publishes it again, so every replica
// answers its record and its whole table (before, every replica answered 404 a moment later).
TEST(SharedJobs, AFinishedJobIsStillReadAndDownloadedAfterRedisRestartedEmpty) {
  const std::vector<std::string> reference = reference_of(90);
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[2].client();
  const std::string id = post_table(owner, 90);
  ASSERT_FALSE(id.empty());
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  // The accepting replica counts the job as its own until it has kept its copy.
  ASSERT_TRUE(test::wait_until([&] {
    auto c = cluster.replicas[0].client();
    const auto m = c.Get("/metrics");
    return m && test::metric(m->body, "slosh_batch_jobs_active") == 0;
  }));
  cluster.redis.kill();
  cluster.redis.start();  // the same port, empty
  json again;
  ASSERT_TRUE(test::wait_until(
      [&] {
        again = record_of(other, id);
        return test::is_final_record(again);
      },
      std::chrono::seconds(30)))
      << "the job was not published again";
  EXPECT_EQ(again.at("state"), "done") << again;
  EXPECT_EQ(again.at("progress").at("done"), 90);
  EXPECT_EQ(again.at("shares"), done.at("shares"));
  EXPECT_EQ(whole_table(other, id, 90), reference);
}

// A job is paged to its end through any replica, also one whose own batch_job_max is smaller
// than the job (settings changed one replica at a time); an offset past such a job is refused
// naming the job's size. Before, that replica refused every offset past its own batch_job_max.
TEST(SharedJobs, AJobLargerThanAReplicasBatchJobMaxIsPagedThroughIt) {
  test::RedisServer redis;
  test::ReplicaSet wide = sharing_replicas(redis, 1, {}, "wide");
  test::ReplicaSet narrow = sharing_replicas(redis, 1, {{"SLOSH_BATCH_JOB_MAX", "100"}}, "narrow");
  auto a = wide[0].client();
  auto b = narrow[0].client();
  const std::string id = post_table(a, 150);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_finished(b, id).at("state"), "done");
  const auto page = b.Get("/v1/batches/" + id + "?offset=120&limit=5");
  ASSERT_TRUE(page);
  ASSERT_EQ(page->status, 200) << page->body;
  const json rows = json::parse(page->body).at("results").at("rows");
  ASSERT_EQ(rows.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(rows[i].at("row"), 121 + i) << rows[i];
  const auto past = b.Get("/v1/batches/" + id + "?offset=151");
  ASSERT_TRUE(past);
  EXPECT_EQ(past->status, 422) << past->body;
  EXPECT_EQ(json::parse(past->body).at("error").at("message"),
            "offset = 151 is not allowed: a whole number from 0 to 150");
}

// A Redis stall past the replicas' timeout in the middle of a job does not hold the job for the
// take-over time: a row whose write timed out is stored again by the replica that solved it, and
// the items Redis handed out in a take whose reply was lost are found again in that replica's
// pending list. With one replica and batch_job_stale_s = 30 nothing else could take them over:
// before, the job stood one row short until 30 s after the stall.
TEST(SharedJobs, ARedisStallMidJobDoesNotHoldTheJobForTheTakeOverTime) {
  test::RedisServer redis;
  ::setenv("SLOSH_BATCH_JOB_SPREAD", "replicas", 1);
  ::setenv("SLOSH_BATCH_JOB_STALE_S", "30", 1);
  test::ReplicaSet one{
      1, {"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "200"}, "stall"};
  ::unsetenv("SLOSH_BATCH_JOB_SPREAD");
  ::unsetenv("SLOSH_BATCH_JOB_STALE_S");
  auto c = one[0].client();
  const std::string id = post_table(c, 400);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(c, id, 40).at("state"), "running");
  redis.pause();
  std::this_thread::sleep_for(1s);  // the stall itself (the fault), five times the timeout
  redis.resume();
  json record;
  EXPECT_TRUE(test::wait_until([&] { return test::is_final_record(record = record_of(c, id)); },
                               std::chrono::seconds(20)))
      << "the job did not end within 20 s of the stall: " << record;
  EXPECT_EQ(record.value("state", ""), "done") << record;
  EXPECT_EQ(whole_table(c, id, 400).size(), 401u);
}

// Two replicas started with one --replica-id (or none, on one host) would merge their consumer
// names and shares without a word: each says so in its log.
TEST(SharedJobs, TwoLiveReplicasWithOneIdSaySoInTheirLogs) {
  test::RedisServer redis;
  test::ReplicaSet first = sharing_replicas(redis, 1, {}, "same");
  test::ReplicaSet second = sharing_replicas(redis, 1, {}, "same");
  EXPECT_TRUE(test::both_say_their_id_is_shared(first[0], second[0]));
}

// A cancelled job lost with an emptying of Redis (the replica that accepted it, the only one
// that could publish it again, was killed): the replica that took its DELETE sends the cancel
// flag again, which alone says nothing lives. Once the emptying's settling time has passed,
// every replica answers 404 for GET and DELETE, never a 503 promising a publication that cannot
// come; before that, a 503 that says only what is true.
TEST(SharedJobs, ACancelledJobLostWithAnEmptyingIsUnknownOnceTheEmptyingHasSettled) {
  SharedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto second = cluster.replicas[1].client();
  auto third = cluster.replicas[2].client();
  const std::string id = post_table(owner, 3000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(second, id, 30).at("state"), "running");
  const auto deleted = second.Delete("/v1/batches/" + id);
  ASSERT_TRUE(deleted);
  ASSERT_EQ(deleted->status, 202) << deleted->body;
  ASSERT_EQ(wait_finished(second, id).at("state"), "cancelled");
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  ASSERT_TRUE(redis.command({"FLUSHALL"}));
  // The replica that took the DELETE records it again after the emptying (never lost).
  ASSERT_TRUE(test::wait_until([&] {
    const auto cancel = redis.command({"EXISTS", "slosh:jobs:" + id + ":cancel"});
    return cancel && cancel->integer == 1;
  }));
  for (auto* c : {&second, &third}) {
    int last = 0;
    ASSERT_TRUE(test::wait_until(
        [&] {
          const auto r = c->Get("/v1/batches/" + id);
          last = r ? r->status : 0;
          if (last == 503) {
            const std::string message = json::parse(r->body).value("message", "");
            EXPECT_EQ(message.find("its results are there"), std::string::npos) << message;
          }
          return last == 404;
        },
        std::chrono::seconds(20)))
        << "still " << last;
    const auto again = c->Delete("/v1/batches/" + id);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 404) << again->body;
  }
}

// With a Redis cache, a calibration stored through one replica is in Redis: another replica
// plans with it by name (before, it answered 404 on options.model), with the same plan as the
// fitted model given inline.
TEST(SharedCalibrations, ACalibrationStoredThroughOneReplicaPlansOnAnother) {
  test::RedisServer redis;
  test::ReplicaSet replicas{
      2, {"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "10000"}, "cal"};
  auto a = replicas[0].client();
  auto b = replicas[1].client();
  json body = test::calibration_body();
  body["name"] = "line-7-2026";
  const auto posted = a.Post("/v1/calibrations", body.dump(), "application/json");
  ASSERT_TRUE(posted && posted->status == 200) << (posted ? posted->body : "no answer");
  const json fit = json::parse(posted->body);
  const auto got = b.Get("/v1/calibrations/line-7-2026");
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200) << got->body;
  EXPECT_EQ(json::parse(got->body), fit);
  auto plan = [&](const json& model) {
    const json request{{"format", test::thesis_format_json()},
                       {"strategy", "shaper"},
                       {"options", {{"model", model}}}};
    const auto r = b.Post("/v1/plans", request.dump(), "application/json");
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no answer");
    return r && r->status == 200 ? json::parse(r->body) : json();
  };
  const json by_name = plan("line-7-2026");
  const json inline_model = plan(fit.at("model"));
  ASSERT_TRUE(by_name.is_object() && inline_model.is_object());
  EXPECT_EQ(by_name.at("key"), inline_model.at("key"));
  EXPECT_EQ(by_name.at("law"), inline_model.at("law"));
}

}  // namespace test_cluster_shared_jobs
}  // namespace slosh
