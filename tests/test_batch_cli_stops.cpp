// `slosh batch --server` (the real binary) when the service answers "not now" or the run stops:
// a results download answered 409 by a replica that does not see yet that the job finished, a
// DELETE refused 503 once and then accepted, a service that keeps a stopped job's rows behind
// `?partial=1`, a replica that stops answering (SIGSTOP) when Ctrl-C comes, Ctrl-C before the
// command line is even read, and an --out that would overwrite --in. A scripted service on
// loopback (an httplib server in this process) gives the answers a cluster only gives by chance;
// the paused replica is a real `slosh serve`.

#include <fcntl.h>
#include <httplib.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <regex>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "support/batch_server_run.hpp"
#include "support/process.hpp"
#include "support/proxy.hpp"
#include "support/redis_server.hpp"
#include "support/replicas.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_batch_cli_stops {

using nlohmann::json;
using test::read_file;
using test::TempDir;
using test::write_file;
using namespace std::chrono_literals;

constexpr const char* kJobId = "fedcba9876543210fedcba9876543210";

std::string row(int n, const std::string& id) {
  return json{{"row", n}, {"recipe_id", id}, {"status", "optimal"}, {"cached", false}}.dump() +
         "\n";
}

std::string envelope(const std::string& code, const std::string& message) {
  return json{{"error", {{"code", code}, {"message", message}, {"field", nullptr}}}}.dump();
}

/// A job of two recipes as a service answers it. The record reads `state` with `done` rows; a
/// DELETE of a running job is answered 503 `delete_503s` times, then accepted (202: the job reads
/// cancelled, its `results` kept); results.jsonl is answered 409 `results_409s` times first, and
/// with `partial_only` the rows of a stopped job only to `?partial=1` (409 without it); with
/// `query_refused` any query parameter is refused 400, as a service whose downloads take none.
struct JobService {
  httplib::Server server;
  std::thread thread;
  int port{0};
  std::mutex mutex;
  std::condition_variable changed;
  std::string state{"running"};
  int done{0};
  int delete_503s{0};
  int results_409s{0};
  bool partial_only{false};
  bool query_refused{false};
  std::string results;
  int posts{0};
  int record_gets{0};
  int deletes{0};
  int results_gets{0};
  int partial_gets{0};

  JobService() {
    const std::string job = "/v1/batches/" + std::string(kJobId);
    server.Post("/v1/batches", [this](const httplib::Request&, httplib::Response& res) {
      const std::lock_guard lock(mutex);
      ++posts;
      res.status = 202;
      res.set_content(record().dump(), "application/json");
    });
    server.Get(job, [this](const httplib::Request&, httplib::Response& res) {
      const std::lock_guard lock(mutex);
      ++record_gets;
      changed.notify_all();
      res.set_content(record().dump(), "application/json");
    });
    server.Get(job + "/results.jsonl", [this](const httplib::Request& req, httplib::Response& res) {
      const std::lock_guard lock(mutex);
      ++results_gets;
      const bool partial = req.has_param("partial");
      partial_gets += partial ? 1 : 0;
      if (query_refused && !req.params.empty()) {
        res.status = 400;
        res.set_content(envelope("invalid_value", "partial is not a query parameter"),
                        "application/json");
      } else if (results_409s > 0 || (partial_only && state != "done" && !partial)) {
        results_409s = std::max(0, results_409s - 1);
        res.status = 409;
        res.set_content(envelope("conflict", "batch job is running"), "application/json");
      } else {
        res.set_content(results, "application/x-ndjson");
      }
    });
    server.Delete(job, [this](const httplib::Request&, httplib::Response& res) {
      const std::lock_guard lock(mutex);
      ++deletes;
      if (delete_503s > 0) {
        --delete_503s;
        res.status = 503;
        res.set_header("Retry-After", "1");
        res.set_content(envelope("unavailable", "the cancel could not be recorded"),
                        "application/json");
        return;
      }
      res.status = state == "running" ? 202 : 200;
      if (state == "running") state = "cancelled";
      res.set_content(record().dump(), "application/json");
    });
    port = server.bind_to_any_port("127.0.0.1");
    thread = std::thread([this] { server.listen_after_bind(); });
    for (int i = 0; i < 10000 && !server.is_running(); ++i) std::this_thread::sleep_for(1ms);
  }
  ~JobService() {
    server.stop();
    thread.join();
  }
  json record() const {
    return {{"id", kJobId},
            {"state", state},
            {"progress", {{"done", done}, {"total", 2}}},
            {"message", nullptr}};
  }
  [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port); }
  /// Waits until the CLI has polled the record `n` times.
  bool wait_polls(int n) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, 30s, [&] { return record_gets >= n; });
  }
};

/// `slosh batch --server` of a two-recipe table into o.jsonl.
using Cli = test::BatchServerRun;

// A replica that does not see yet that the job has finished answers the results download 409
// (through a proxy, the poll that read "done" reached the job's owner): the CLI asks again, as
// after a 503, and writes the whole table (it stopped with exit 1 on the first 409).
TEST(BatchCliStops, AResultsDownloadAnswered409ByALaggingReplicaIsAskedAgain) {
  JobService service;
  service.state = "done";
  service.done = 2;
  service.results_409s = 2;
  service.results = row(1, "a") + row(2, "b");
  Cli cli(service.url());
  const auto code = cli.child->wait_for(60s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << cli.err();
  EXPECT_EQ(read_file(cli.dir / "o.jsonl"), row(1, "a") + row(2, "b"));
  const std::lock_guard lock(service.mutex);
  EXPECT_EQ(service.results_gets, 3);
  EXPECT_EQ(service.deletes, 0);
}

// Ctrl-C: the first DELETE reaches a replica that cannot record the cancel (503), the next one is
// accepted. The run says the job was cancelled (not "could not be cancelled") and the row the
// service finished is in the .partial table, under each way a service may give a stopped job's
// rows: at once, only to `?partial=1`, or after a 409 of a lagging replica from a service that
// takes no query parameter there (its 400 to `?partial=1` is not the end).
TEST(BatchCliStops, ACancelAcceptedOnItsSecondTryIsReportedCancelledWithItsRowsKept) {
  for (const int variant : {0, 1, 2}) {
    SCOPED_TRACE("variant " + std::to_string(variant));
    JobService service;
    service.done = 1;
    service.delete_503s = 1;
    service.results = row(1, "a");
    service.partial_only = variant == 1;
    service.results_409s = variant == 2 ? 1 : 0;
    service.query_refused = variant == 2;
    Cli cli(service.url());
    ASSERT_TRUE(service.wait_polls(1));
    ::kill(cli.child->pid(), SIGINT);
    const auto code = cli.child->wait_for(30s);
    ASSERT_TRUE(code.has_value());
    EXPECT_EQ(*code, 130) << cli.err();
    EXPECT_NE(cli.err().find("slosh batch: stopped after 1 of 2 recipes: interrupted: batch job " +
                             std::string(kJobId) + " cancelled (1 rows written)\n"),
              std::string::npos)
        << cli.err();
    EXPECT_EQ(read_file(cli.dir / "o.jsonl.partial"), row(1, "a")) << cli.err();
    const std::lock_guard lock(service.mutex);
    EXPECT_EQ(service.deletes, 2);
    EXPECT_EQ(service.state, "cancelled");
    // The rows of a stopped job are asked with ?partial=1 once; only a service that refuses the
    // parameter is asked the plain download after it.
    EXPECT_EQ(service.partial_gets, 1);
  }
}

// The replica that runs the job is paused (SIGSTOP) when Ctrl-C comes: the CLI's calls have a
// deadline, so the run ends within the poll's 3 s and the stop's 5 s (it took 30 s), saying
// what is known: the cancel was sent, not confirmed, and the job to check. Once the replica runs
// again it takes the DELETE it had queued: the job ends cancelled.
TEST(BatchCliStops, AnInterruptWhileTheReplicaIsPausedEndsInSecondsNamingTheJobToCheck) {
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (int i = 0; i < 400; ++i) {
    table += "s" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(2.5 + 0.001 * i) +
             ",notch\n";
  }
  write_file(dir / "t.csv", table);
  write_file(dir / "stdin", "");
  test::Server server({"--workers", "1"});
  test::Child cli(
      test::spawn({"batch", "--in", (dir / "t.csv").string(), "--out", (dir / "o.csv").string(),
                   "--server", server.url(), "--progress", "never"},
                  dir / "stdin", dir / "stdout", dir / "stderr"));
  // The CLI polls its job (it has the POST's answer): a poll of the record was answered.
  auto c = server.client();
  const std::string polled = R"(slosh_http_requests_total{route="/v1/batches/{id}",status="200"})";
  for (int i = 0; i < 1000; ++i) {
    const auto r = c.Get("/metrics");
    if (r && test::metric(r->body, polled) >= 1) break;
    std::this_thread::sleep_for(20ms);
  }
  const pid_t replica = server.child().pid();
  ::kill(replica, SIGSTOP);
  struct Resume {
    pid_t pid;
    ~Resume() { ::kill(pid, SIGCONT); }
  } resume{replica};
  std::this_thread::sleep_for(500ms);  // the CLI's next poll is in flight to the paused replica
  const auto interrupted = std::chrono::steady_clock::now();
  ::kill(cli.pid(), SIGINT);
  const auto code = cli.wait_for(40s);
  const auto took = std::chrono::steady_clock::now() - interrupted;
  ASSERT_TRUE(code.has_value()) << "the CLI still runs";
  const std::string err = read_file(dir / "stderr");
  EXPECT_EQ(*code, 130) << err;
  // The documented bounds, 3 s and 5 s, and slack for a loaded machine (it took 30 s).
  EXPECT_LT(took, 15s) << err;
  std::smatch m;
  const std::regex said(
      "interrupted: batch job ([0-9a-f]{32}) was asked to cancel but did not confirm it \\(no "
      "answer to its DELETE within 5 s; last: cannot reach " +
      server.url() + " \\([^)]*\\)\\); it may still run: check it with GET " + server.url() +
      "/v1/batches/([0-9a-f]{32})\n");
  ASSERT_TRUE(std::regex_search(err, m, said)) << err;
  EXPECT_EQ(m[1], m[2]);
  ::kill(replica, SIGCONT);
  json record;
  for (int i = 0; i < 500; ++i) {
    const auto r = c.Get("/v1/batches/" + m[1].str() + "?limit=1");
    if (r && r->status == 200) record = json::parse(r->body);
    if (record.value("state", "") != "running" && record.value("state", "") != "queued") break;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(record.value("state", ""), "cancelled") << record;
}

// Ctrl-C while the command line's configuration is still being read (a --config FIFO that
// nobody has written yet holds the CLI there, before `slosh batch` has started): the interrupt is
// noted from the first instant, so the run ends with exit 130 and its message and posts nothing;
// it was killed by the signal's default action.
TEST(BatchCliStops, AnInterruptBeforeTheCommandLineIsReadEndsWithItsMessageAndPostsNothing) {
  JobService service;
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "config.json").c_str(), 0600), 0);
  Cli cli(service.url(), {"--config", (dir / "config.json").string()});
  // The CLI is blocked opening the FIFO (state S): nothing else it does before blocks.
  const std::string stat_path = "/proc/" + std::to_string(cli.child->pid()) + "/stat";
  for (int i = 0; i < 10000; ++i) {
    const std::string stat = read_file(stat_path);
    const auto paren = stat.rfind(')');
    if (paren != std::string::npos && stat.size() > paren + 2 && stat[paren + 2] == 'S') break;
    std::this_thread::sleep_for(2ms);
  }
  ::kill(cli.child->pid(), SIGINT);
  std::this_thread::sleep_for(100ms);
  const int fifo = ::open((dir / "config.json").c_str(), O_WRONLY | O_NONBLOCK);
  if (fifo >= 0) {
    ASSERT_EQ(::write(fifo, "{}", 2), 2);
    ::close(fifo);
  }
  const auto code = cli.child->wait_for(30s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 130);
  EXPECT_EQ(cli.err(),
            "slosh batch: stopped after 0 of 2 recipes: interrupted before /v1/batches accepted "
            "the table\nslosh batch: the rows written so far are in " +
                (cli.dir / "o.jsonl.partial").string() + " (none: it is empty)\n");
  const std::lock_guard lock(service.mutex);
  EXPECT_EQ(service.posts, 0);
}

// --out naming the --in file (the same path, a relative path to it, a symbolic link to it), or
// an --out whose .partial file is the --in file, is refused before anything is read, posted or
// written: exit 2, a message naming both flags and the file, the recipe table untouched.
TEST(BatchCliStops, AnOutThatWouldOverwriteTheInTableIsRefusedBeforeAnyWork) {
  JobService service;  // a job that would be done at once, so that nothing waits
  service.state = "done";
  service.done = 1;
  service.results = row(1, "a");
  const TempDir dir;
  const std::string recipes =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
      "a,48.5,82,water,800,1.5,notch\n";
  const std::string in = (dir / "t.csv").string();
  write_file(dir / "t.csv", recipes);
  const std::string canonical = std::filesystem::canonical(in).string();
  std::filesystem::create_symlink(in, dir / "link.csv");
  const std::string relative = std::filesystem::relative(in).string();
  const std::vector<std::string> outs{in, relative, (dir / "link.csv").string()};
  for (const std::string& out : outs) {
    SCOPED_TRACE(out);
    const auto r = test::run_slosh({"batch", "--in", in, "--out", out, "--server", service.url()});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err, "slosh batch: --out '" + out + "' is the --in file (" + canonical +
                         "): the plan table would overwrite the recipe table; give --out "
                         "another path\n");
    EXPECT_EQ(read_file(in), recipes);
    EXPECT_FALSE(std::filesystem::exists(in + ".partial"));
  }
  // --out X.csv is written first to X.csv.partial: an --in of that name would be overwritten.
  std::filesystem::rename(dir / "t.csv", dir / "p.csv.partial");
  const std::string partial_in = (dir / "p.csv.partial").string();
  const auto r = test::run_slosh({"batch", "--in", partial_in, "--in-format", "csv", "--out",
                                  (dir / "p.csv").string(), "--cache", ""});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err, "slosh batch: --out '" + (dir / "p.csv").string() + "' is written first to '" +
                       partial_in + "', which is the --in file (" +
                       std::filesystem::canonical(partial_in).string() +
                       "): the recipe table would be overwritten; give --out another path\n");
  EXPECT_EQ(read_file(partial_in), recipes);
  EXPECT_FALSE(std::filesystem::exists(dir / "p.csv"));
  const std::lock_guard lock(service.mutex);
  EXPECT_EQ(service.posts, 0);
}

// The whole topology (redis-server, two replicas sharing it, nginx in front): Ctrl-C through the
// proxy while Redis is paused. The DELETE that reaches the replica that does not run the job is
// refused 503 (it cannot record the cancel), and the CLI said "could not be cancelled" although
// its next DELETE cancelled the job. Sent again within the stop's budget, the DELETE reaches the
// owner, which cancels the job: the run says "cancelled" and the .partial table holds the rows.
TEST(BatchCliStopsCluster, AnInterruptThroughTheProxyWhileRedisIsPausedCancelsTheJob) {
  test::RedisServer redis;
  test::ReplicaSet replicas{2, {"--cache", redis.url(), "--workers", "1"}, "line"};
  test::NginxProxy proxy{replicas.ports(), true};
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  // time_domain (about 15 ms a recipe, 2 s for the table on two workers): the job must still run
  // 300 ms after Redis pauses; a notch table (under 1 ms a recipe) could end before the interrupt.
  for (int i = 0; i < 300; ++i) {
    table += "q" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(2.2 + 0.001 * i) +
             ",time_domain\n";
  }
  write_file(dir / "t.csv", table);
  write_file(dir / "stdin", "");
  test::Child cli(
      test::spawn({"batch", "--in", (dir / "t.csv").string(), "--out", (dir / "o.csv").string(),
                   "--server", proxy.url(), "--progress", "never"},
                  dir / "stdin", dir / "stdout", dir / "stderr"));
  // Some rows are done: the job runs.
  const std::string started = R"(slosh_pool_tasks_started_total{priority="background"})";
  for (int i = 0; i < 1500; ++i) {
    double tasks = 0;
    for (std::size_t r = 0; r < 2; ++r) {
      auto c = replicas[r].client();
      const auto m = c.Get("/metrics");
      if (m) tasks += std::max(0.0, test::metric(m->body, started));
    }
    if (tasks >= 5) break;
    std::this_thread::sleep_for(20ms);
  }
  redis.pause();
  struct Resume {
    const test::RedisServer& redis;
    ~Resume() { redis.resume(); }
  } resume{redis};
  std::this_thread::sleep_for(300ms);
  ::kill(cli.pid(), SIGINT);
  const auto code = cli.wait_for(40s);
  ASSERT_TRUE(code.has_value()) << "the CLI still runs";
  const std::string err = read_file(dir / "stderr");
  EXPECT_EQ(*code, 130) << err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      err, m,
      std::regex("stopped after ([0-9]+) of 300 recipes: interrupted: batch job ([0-9a-f]{32}) "
                 "cancelled \\(([0-9]+) rows written\\)\n")))
      << err;
  EXPECT_EQ(m[1], m[3]);
  const std::string partial = read_file(dir / "o.csv.partial");
  EXPECT_EQ(std::count(partial.begin(), partial.end(), '\n'), std::stoi(m[1]) + 1) << partial;
  redis.resume();
  // Once both replicas reach Redis again, either reads the job cancelled.
  auto c = proxy.client();
  std::string state;
  for (int i = 0; i < 750 && state != "cancelled"; ++i) {
    const auto r = c.Get("/v1/batches/" + m[2].str() + "?limit=1");
    if (r && r->status == 200) state = json::parse(r->body).value("state", "");
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(state, "cancelled");
}

}  // namespace test_batch_cli_stops
}  // namespace slosh
