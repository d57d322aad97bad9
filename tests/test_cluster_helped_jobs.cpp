// A batch job with the default spread ("helpers", SPEC §13): the replica that accepted it runs it
// as "owner" does and the other replicas solve its plans from the table's end into the shared
// plan cache. Every part real and started by the test: a redis-server on a free port and three
// `slosh serve` replicas (one solve worker each) sharing it. A job is worked on by all three
// (each one's slosh_batch_job_items_total and its share in the record) and its table is the file
// `slosh batch` writes, each row once; kill -9 of the accepting replica mid-job leaves the job to
// another, which finishes it complete; Redis stopped mid-job leaves the accepting replica to
// finish and serve it alone, and its rows reach Redis once Redis is back. The tests wait for
// states and counters (polling), never for a fixed time.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "storage/redis_client.hpp"
#include "storage/redis_url.hpp"
#include "support/job_tables.hpp"
#include "support/process.hpp"
#include "support/redis_server.hpp"
#include "support/replicas.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_cluster_helped_jobs {

using nlohmann::json;
using test::csv_cells;
using test::csv_without_timing;
using namespace std::chrono_literals;

/// redis-server and three replicas with the default spread (batch_job_stale_s = 3 s: a silent
/// owner's job is taken over after 1.5 s).
struct HelpedCluster {
  HelpedCluster() : replicas(start(redis)) {}
  static test::ReplicaSet start(const test::RedisServer& redis) {
    ::setenv("SLOSH_BATCH_JOB_STALE_S", "3", 1);  // the replicas read it at start
    test::ReplicaSet set{
        3, {"--cache", redis.url(), "--workers", "1", "--redis-timeout-ms", "10000"}, "line"};
    ::unsetenv("SLOSH_BATCH_JOB_STALE_S");
    return set;
  }
  test::RedisServer redis;
  test::ReplicaSet replicas;
};

/// A CSV recipe table of `n` distinct recipes (the motion time differs: no two share a plan).
std::string table_of(std::size_t n, std::size_t first) {
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (std::size_t i = first; i < first + n; ++i) {
    char time[32];
    std::snprintf(time, sizeof time, "%.3f", 0.9 + 0.001 * static_cast<double>(i));
    table += "r" + std::to_string(i) + ",48.5,82,water,800," + time + ",notch\n";
  }
  return table;
}

/// The table `slosh batch` writes for table_of(n, first) (no cache), without timing cells.
std::vector<std::string> reference_of(std::size_t n, std::size_t first) {
  const test::TempDir dir;
  test::write_file(dir / "t.csv", table_of(n, first));
  const auto r = test::run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                  (dir / "out.csv").string(), "--cache", ""});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return csv_without_timing(test::read_file(dir / "out.csv"));
}

std::string post_table(httplib::Client& c, std::size_t n, std::size_t first) {
  const json body{{"table", table_of(n, first)}, {"table_format", "csv"}, {"format", "csv"}};
  const auto r = c.Post("/v1/batches", body.dump(), "application/json");
  EXPECT_TRUE(r && r->status == 202) << (r ? r->body : "no answer");
  return r && r->status == 202 ? json::parse(r->body).at("id").get<std::string>() : "";
}

json record_of(httplib::Client& c, const std::string& id) {
  const auto r = c.Get("/v1/batches/" + id);
  return r && r->status == 200 ? json::parse(r->body) : json();
}

json wait_finished(httplib::Client& c, const std::string& id) {
  json record;
  test::wait_until([&] { return test::is_final_record(record = record_of(c, id)); });
  return record;
}

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

/// The results.csv of finished job `id` through `c`: every row once, in table order.
std::vector<std::string> whole_table(httplib::Client& c, const std::string& id, std::size_t n) {
  const auto csv = c.Get("/v1/batches/" + id + "/results.csv");
  EXPECT_TRUE(csv && csv->status == 200) << (csv ? csv->body : "no answer");
  if (!csv || csv->status != 200) return {};
  EXPECT_EQ(csv->get_header_value("X-Slosh-Partial"), "false");
  EXPECT_EQ(csv->get_header_value("X-Slosh-Rows"), std::to_string(n));
  const std::vector<std::string> lines = csv_without_timing(csv->body);
  std::set<std::string> numbers;
  for (std::size_t i = 1; i < lines.size(); ++i) numbers.insert(csv_cells(lines[i]).at(0));
  EXPECT_EQ(numbers.size(), n);
  return lines;
}

TEST(HelpedJobs, ADefaultJobIsWorkedOnByEveryReplicaAndItsTableIsSloshBatchs) {
  const std::vector<std::string> reference = reference_of(480, 0);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 480, 0);
  ASSERT_FALSE(id.empty());
  // While it runs, its progress counts the items the helpers solved ahead of its stored rows.
  json ahead;
  test::wait_until([&] {
    ahead = record_of(owner, id);
    return ahead.is_object() &&
           (test::is_final_record(ahead) ||
            ahead.at("progress").value("solved", 0) > ahead.at("progress").value("done", 0));
  });
  EXPECT_EQ(ahead.value("state", ""), "running") << ahead;
  EXPECT_LE(ahead.at("progress").value("solved", 0), 480) << ahead;
  const json done = wait_finished(owner, id);
  EXPECT_EQ(done.at("progress").at("solved"), 480);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  // The shares name every replica and add up to the table: each row counted once.
  const json& shares = done.at("shares");
  std::size_t sum = 0;
  for (const auto& [replica, rows] : shares.items()) sum += rows.get<std::size_t>();
  EXPECT_EQ(sum, 480u) << shares;
  // Each replica counts exactly its share (a plan two replicas solved is counted by the one
  // credited with it).
  for (std::size_t i = 0; i < 3; ++i) {
    const test::Replica& r = cluster.replicas[i];
    EXPECT_GT(shares.value(r.id(), 0), 0) << r.id() << " has no share: " << shares;
    EXPECT_EQ(items_of(r), shares.value(r.id(), 0)) << r.id() << ": " << shares;
  }
  EXPECT_EQ(whole_table(owner, id, 480), reference);
  auto other = cluster.replicas[2].client();
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

TEST(HelpedJobs, KillingTheAcceptingReplicaMidJobLeavesItToAnotherWhichFinishesIt) {
  const std::vector<std::string> reference = reference_of(480, 1000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 480, 1000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(other, id, 100).at("state"), "running");
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 480);
  // The live replicas' counters are their shares in the record, across the takeover.
  for (std::size_t i = 1; i < 3; ++i) {
    const test::Replica& r = cluster.replicas[i];
    EXPECT_EQ(items_of(r), done.at("shares").value(r.id(), 0))
        << r.id() << ": " << done.at("shares");
  }
  EXPECT_EQ(whole_table(other, id, 480), reference);
  auto third = cluster.replicas[2].client();
  EXPECT_EQ(whole_table(third, id, 480), reference);
}

// The replica that took a job over dies right after: the last one takes it over in turn after
// half the stale time, as it would any silent owner, so no replica ever reads the job as failed
// (a client that saw `failed` stops and posts the table again) and it ends done, every row once.
TEST(HelpedJobs, ATakerThatDiesRightAfterItsTakeoverIsTakenOverBeforeTheJobReadsAsFailed) {
  const std::vector<std::string> reference = reference_of(480, 4000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 480, 4000);
  ASSERT_FALSE(id.empty());
  auto watcher = cluster.replicas[2].client();
  ASSERT_EQ(wait_done(watcher, id, 60).at("state"), "running");
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  const std::string took = "batch job " + id + ": its replica line-1 stopped answering";
  std::size_t taker = 0;
  ASSERT_TRUE(test::wait_until(
      [&] {
        for (std::size_t i = 1; i < 3; ++i) {
          if (cluster.replicas[i].log().find(took) != std::string::npos) taker = i;
        }
        return taker != 0;
      },
      60s));
  ASSERT_TRUE(cluster.replicas[taker].kill(SIGKILL));
  auto survivor = cluster.replicas[3 - taker].client();
  // `failed` is final: a survivor that read the job as failed even once ends the wait there.
  const json record = wait_finished(survivor, id);
  EXPECT_EQ(record.at("state"), "done") << record;
  EXPECT_EQ(whole_table(survivor, id, 480), reference);
}

// A graceful stop of the owner (SIGTERM, as a rolling deploy sends) hands its job to the replicas
// that help it: one takes it over at once from the rows stored so far. No replica reads it as
// failed, and it ends done with the whole table, every row once.
TEST(HelpedJobs, ASigtermOfTheOwnerHandsItsJobToTheHelpersWhichFinishIt) {
  const std::vector<std::string> reference = reference_of(480, 5000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 480, 5000);
  ASSERT_FALSE(id.empty());
  auto other = cluster.replicas[1].client();
  ASSERT_EQ(wait_done(other, id, 60).at("state"), "running");
  ASSERT_EQ(cluster.replicas[0].kill(SIGTERM), 0);
  EXPECT_NE(cluster.replicas[0].log().find("handed to the replicas that help it"),
            std::string::npos);
  // `failed` is final: a replica that read the job as failed even once ends the wait there.
  const json record = wait_finished(other, id);
  EXPECT_EQ(record.at("state"), "done") << record;
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

// The owner is stopped gracefully while its worker also helps another replica's job, so the
// solve of its own job's next row is often still queued when the shutdown refuses what is
// queued: that refusal is not stored as the row (the job would end done with a failed row where
// `slosh batch` plans it). The job is handed over before that row, and ends as `slosh batch`.
TEST(HelpedJobs, ASolveTheShutdownRefusedIsNotStoredAsTheRowOfTheHandedOverJob) {
  const std::vector<std::string> reference = reference_of(240, 7000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  auto last = cluster.replicas[2].client();
  for (std::size_t k = 0; k < 3; ++k) ASSERT_FALSE(post_table(other, 240, 7300 + 240 * k).empty());
  const std::string id = post_table(owner, 240, 7000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(last, id, 20).at("state"), "running");
  ASSERT_EQ(cluster.replicas[0].kill(SIGTERM), 0);
  const json record = wait_finished(last, id);
  EXPECT_EQ(record.at("state"), "done") << record;
  EXPECT_EQ(record.at("progress").at("failed"), 0) << record;
  EXPECT_EQ(whole_table(last, id, 240), reference);
}

// The taker of a job handed over by a SIGTERM is itself stopped gracefully right after its
// takeover: it hands the job on together with its adoption lock, so the last replica takes the
// job at its next looks (not once the lock, half of batch_job_stale_s, has run out), and the job
// ends done whole. The last replica is paused until then, so that the taker is the second one
// and still has rows to plan when it is stopped.
TEST(HelpedJobs, ATakerStoppedRightAfterItsTakeoverHandsTheJobOnWithoutItsLock) {
  const std::vector<std::string> reference = reference_of(600, 6000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 600, 6000);
  ASSERT_FALSE(id.empty());
  auto last = cluster.replicas[2].client();
  ASSERT_EQ(wait_done(last, id, 60).at("state"), "running");
  ::kill(cluster.replicas[2].pid(), SIGSTOP);
  ASSERT_EQ(cluster.replicas[0].kill(SIGTERM), 0);
  ASSERT_TRUE(test::wait_until(
      [&] {
        return cluster.replicas[1].log().find("batch job " + id +
                                              ": its replica line-1 stopped answering") !=
               std::string::npos;
      },
      std::chrono::seconds(20)));
  ASSERT_EQ(cluster.replicas[1].kill(SIGTERM), 0);
  ::kill(cluster.replicas[2].pid(), SIGCONT);
  EXPECT_NE(cluster.replicas[1].log().find("handed to the replicas that help it"),
            std::string::npos)
      << cluster.replicas[1].log();
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  const auto lock = redis.command({"GET", "slosh:jobs:" + id + ":adopt"});
  ASSERT_TRUE(lock);
  EXPECT_NE(lock->text, "line-2") << "the stopped taker still holds the adoption lock";
  const json record = wait_finished(last, id);
  EXPECT_EQ(record.at("state"), "done") << record;
  EXPECT_EQ(whole_table(last, id, 600), reference);
}

// Two replicas started with one --replica-id in the default spread: neither would help nor take
// over the other's jobs, and the owner mark cannot tell them apart. Each says so in its log, as in
// the replicas spread.
TEST(HelpedJobs, TwoLiveReplicasWithOneIdSaySoInTheirLogs) {
  test::RedisServer redis;
  test::ReplicaSet first{1, {"--cache", redis.url()}, "same"};
  test::ReplicaSet second{1, {"--cache", redis.url()}, "same"};
  EXPECT_TRUE(test::both_say_their_id_is_shared(first[0], second[0]));
}

TEST(HelpedJobs, RedisStoppedMidJobLeavesTheOwnerToFinishItAloneAndItsRowsReachRedisAfter) {
  const std::vector<std::string> reference = reference_of(480, 2000);
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  const std::string id = post_table(owner, 480, 2000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(owner, id, 60).at("state"), "running");
  cluster.redis.kill();
  const json done = wait_finished(owner, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(whole_table(owner, id, 480), reference);
  cluster.redis.start();  // the same port, empty: the owner publishes the job again
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  EXPECT_TRUE(test::wait_until(
      [&] {
        const auto rows = redis.command({"HLEN", "slosh:jobs:" + id + ":rows"});
        return rows && rows->integer == 480;
      },
      30s));
  auto other = cluster.replicas[1].client();
  EXPECT_TRUE(test::wait_until([&] { return test::is_final_record(record_of(other, id)); }, 30s));
  EXPECT_EQ(whole_table(other, id, 480), reference);
}

// Redis emptied (FLUSHALL) mid-job loses the job's help offer with everything else: the owner
// offers the job again at its next heartbeat (its help offer naming it, its items, its record and
// rows), so that the other replicas help again and one of them takes the job over when the owner
// is then killed: the job ends done, every row once.
TEST(HelpedJobs, AfterRedisIsEmptiedMidJobTheOwnerOffersItAgainAndAnotherTakesItOverWhenItDies) {
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 400, 3000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(owner, id, 10).at("state"), "running");
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  ASSERT_TRUE(redis.command({"FLUSHALL"}));
  const std::string keys = "slosh:jobs:" + id + ":";
  EXPECT_TRUE(test::wait_until(
      [&] {
        const auto help = redis.command({"HGET", keys + "help", "owner"});
        const auto items = redis.command({"XLEN", keys + "items"});
        const auto record = redis.command({"EXISTS", keys + "record"});
        return help && help->text == cluster.replicas[0].id() && items && items->integer == 400 &&
               record && record->integer == 1;
      },
      10s));
  ASSERT_EQ(record_of(owner, id).at("state"), "running");
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  const json done = wait_finished(other, id);
  ASSERT_EQ(done.at("state"), "done") << done;
  EXPECT_EQ(done.at("progress").at("done"), 400);
  (void)whole_table(other, id, 400);
}

// The shared store lost rows of a job while its owner was silent (evicted, or emptied before the
// owner could publish them again): the replica that takes the job over cannot run it on, and ends
// it as failed at once, naming what was lost and keeping the rows before it, instead of handing
// it back and taking it over again forever.
TEST(HelpedJobs, AJobWhoseRowsRedisLostWhileItsOwnerWasSilentFailsNamingThem) {
  HelpedCluster cluster;
  auto owner = cluster.replicas[0].client();
  auto other = cluster.replicas[1].client();
  const std::string id = post_table(owner, 400, 5000);
  ASSERT_FALSE(id.empty());
  ASSERT_EQ(wait_done(owner, id, 10).at("state"), "running");
  ASSERT_EQ(::kill(cluster.replicas[0].pid(), SIGSTOP), 0);  // silent, its rows unchanged
  service::RedisClient redis({service::parse_redis_url(cluster.redis.url())});
  const std::string keys = "slosh:jobs:" + id + ":";
  const auto deleted = redis.command({"HDEL", keys + "rows", "2", "3"});
  ASSERT_TRUE(deleted && deleted->integer == 2);
  ASSERT_TRUE(cluster.replicas[0].kill(SIGKILL));
  const json failed = wait_finished(other, id);
  ASSERT_EQ(failed.value("state", ""), "failed") << failed;
  EXPECT_EQ(failed.at("message"),
            "its replica stopped answering, and the shared job store no longer holds rows 3 and "
            "4 of its results (Redis was emptied, or evicted them, meanwhile): no replica can "
            "run it on; the first 2 of 400 rows are kept; POST the job again (the finished plans "
            "are cached)");
  EXPECT_EQ(failed.at("progress").at("done"), 2);
  // It stays failed: no replica takes it over again.
  std::this_thread::sleep_for(2s);
  EXPECT_EQ(record_of(other, id).value("state", ""), "failed");
  auto third = cluster.replicas[2].client();
  EXPECT_EQ(record_of(third, id).value("state", ""), "failed");
}

}  // namespace test_cluster_helped_jobs
}  // namespace slosh
