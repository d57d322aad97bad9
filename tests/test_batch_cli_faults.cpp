// `slosh batch --server` (the real binary) against a scripted service on loopback (an httplib
// server in this process playing the batch jobs API), to reach the moments a real service only
// gives by chance: a SIGINT while the POST that starts the job is in flight (the job accepted,
// its id not yet known to the CLI), a results table with a recipe twice or missing, and 503
// answers with Retry-After while the job is read.

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/batch_server_run.hpp"
#include "support/process.hpp"

namespace slosh {
namespace test_batch_cli_faults {

using nlohmann::json;
using test::read_file;
using test::TempDir;
using test::write_file;
using namespace std::chrono_literals;

constexpr const char* kJobId = "0123456789abcdef0123456789abcdef";

/// The scripted service: POST /v1/batches answers 202 (after `hold_post` is released), GET of
/// the record answers `record_503s` 503s first and then "done", GET results.jsonl answers
/// `results`; DELETEs are counted.
struct ScriptedService {
  httplib::Server server;
  std::thread thread;
  int port{0};
  std::mutex mutex;
  std::condition_variable changed;
  bool post_arrived{false};
  bool hold_post{false};
  bool post_released{false};
  int record_503s{0};
  int post_503s{0};  // POSTs answered 503 with Retry-After: post_retry_after before the 202
  std::string post_retry_after{"30"};
  std::vector<std::chrono::steady_clock::time_point> post_times;  // when each POST arrived
  int posts{0};
  bool forgotten{false};  // a DELETE of the finished job forgets it (its rows too), as the service
  bool record_hangs{false};          // GET of the record answers only when the service is destroyed
  std::string record_state{"done"};  // the job's state until a DELETE ("cancelled" after one)
  int record_gets{0};
  std::string results;
  std::atomic<int> deletes{0};

  ScriptedService() {
    server.Post("/v1/batches", [this](const httplib::Request&, httplib::Response& res) {
      std::unique_lock lock(mutex);
      post_arrived = true;
      post_times.push_back(std::chrono::steady_clock::now());
      changed.notify_all();
      if (posts++ < post_503s) {
        res.status = 503;
        res.set_header("Retry-After", post_retry_after);
        res.set_content(R"({"error":{"code":"unavailable","message":"m"}})", "application/json");
        return;
      }
      changed.wait_for(lock, 30s, [this] { return !hold_post || post_released; });
      res.status = 202;
      res.set_content(json{{"id", kJobId}, {"state", "queued"}}.dump(), "application/json");
    });
    server.Get("/v1/batches/" + std::string(kJobId), [this](const httplib::Request&,
                                                            httplib::Response& res) {
      std::unique_lock lock(mutex);
      if (record_hangs) {
        changed.wait(lock, [this] { return post_released; });
        return;
      }
      if (record_gets++ < record_503s) {
        res.status = 503;
        res.set_header("Retry-After", "1");
        res.set_content(R"({"error":{"code":"unavailable","message":"m"}})", "application/json");
        return;
      }
      const bool cancelled = forgotten && record_state != "done";
      res.set_content(json{{"id", kJobId},
                           {"state", cancelled ? "cancelled" : record_state},
                           {"progress", {{"done", cancelled ? 0 : 2}, {"total", 2}}}}
                          .dump(),
                      "application/json");
    });
    server.Get("/v1/batches/" + std::string(kJobId) + "/results.jsonl",
               [this](const httplib::Request&, httplib::Response& res) {
                 const std::lock_guard lock(mutex);
                 if (forgotten) {
                   res.status = 404;
                   return;
                 }
                 res.set_content(results, "application/x-ndjson");
               });
    server.Delete("/v1/batches/" + std::string(kJobId), [this](const httplib::Request&,
                                                               httplib::Response& res) {
      ++deletes;
      {
        const std::lock_guard lock(mutex);
        forgotten = true;  // a finished job is forgotten; a running one reads cancelled
      }
      res.set_content(json{{"id", kJobId}, {"state", "cancelled"}}.dump(), "application/json");
    });
    port = server.bind_to_any_port("127.0.0.1");
    thread = std::thread([this] { server.listen_after_bind(); });
    // stop() does nothing to a server that is not yet listening, so a service destroyed at once
    // (a CLI interrupted before it connected) would leave its thread in accept() for ever.
    for (int i = 0; i < 10000 && !server.is_running(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  ~ScriptedService() {
    {
      const std::lock_guard lock(mutex);
      post_released = true;
    }
    changed.notify_all();
    server.stop();
    thread.join();
  }
  [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port); }
};

std::string row(int n, const std::string& id) {
  return json{{"row", n}, {"recipe_id", id}, {"status", "optimal"}, {"cached", false}}.dump() +
         "\n";
}

/// `slosh batch --server` of a two-recipe table into o.jsonl.
using Cli = test::BatchServerRun;

// Ctrl-C while the service holds the CLI's POST (hold_post), then the POST answered: the run
// must end with exit 130.
void interrupt_during_held_post(ScriptedService& service, Cli& cli) {
  {
    std::unique_lock lock(service.mutex);
    ASSERT_TRUE(service.changed.wait_for(lock, 30s, [&] { return service.post_arrived; }));
  }
  ::kill(cli.child->pid(), SIGINT);
  std::this_thread::sleep_for(100ms);  // let the signal be taken; the CLI is blocked in the POST
  {
    const std::lock_guard lock(service.mutex);
    service.post_released = true;
  }
  service.changed.notify_all();
  const auto code = cli.child->wait_for(30s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 130) << cli.err();
}

// The job was accepted but the 202 has not reached the CLI when Ctrl-C comes: the CLI still
// learns the id from the answer and DELETEs the job (it is not killed by the default action).
TEST(BatchCliFaults, AnInterruptWhileThePostIsInFlightStillCancelsTheJob) {
  ScriptedService service;
  service.hold_post = true;
  service.record_state = "running";
  Cli cli(service.url());
  ASSERT_NO_FATAL_FAILURE(interrupt_during_held_post(service, cli));
  // Cancelled, then asked for the rows it finished (none here) for the .partial table.
  EXPECT_GE(service.deletes.load(), 1) << cli.err();
  EXPECT_NE(cli.err().find("interrupted: batch job " + std::string(kJobId) + " cancelled"),
            std::string::npos)
      << cli.err();
}

// Ctrl-C after the job finished (here: the 202 is held until the signal has come, and the record
// then reads done): the CLI must not DELETE the finished job before it fetched its rows (the
// service forgets a finished job on DELETE), so the .partial table holds every row, and it says
// what happened: the job had finished (not "cancelled"), its rows are written.
TEST(BatchCliFaults, AnInterruptAfterTheJobFinishedKeepsItsRowsInThePartialTable) {
  ScriptedService service;
  service.hold_post = true;
  service.results = row(1, "a") + row(2, "b");
  Cli cli(service.url());
  ASSERT_NO_FATAL_FAILURE(interrupt_during_held_post(service, cli));
  EXPECT_EQ(read_file(cli.dir / "o.jsonl.partial"), row(1, "a") + row(2, "b")) << cli.err();
  EXPECT_NE(cli.err().find("stopped after 2 of 2 recipes: interrupted: batch job " +
                           std::string(kJobId) + " had finished (2 rows written)"),
            std::string::npos)
      << cli.err();
  EXPECT_EQ(cli.err().find("cancelled"), std::string::npos) << cli.err();
  EXPECT_EQ(service.deletes.load(), 0) << "the finished job was deleted";
}

// Ctrl-C at any moment from the start (here 0 to 3 ms after the process started, before the CLI
// has read its table, and on to 60 ms, while it posts and polls): the run ends with exit 130, and
// a job the service accepted is DELETEd; never ignored (exit 0 with the job run to its end).
TEST(BatchCliFaults, AnInterruptRightAtTheStartEndsTheRunAndCancelsAnyPostedJob) {
  std::vector<int> delays_us;
  for (int us = 0; us <= 3000; us += 250) delays_us.push_back(us);
  for (int us = 5000; us <= 60000; us += 5000) delays_us.push_back(us);
  for (const int delay_us : delays_us) {
    ScriptedService service;
    service.record_state = "running";
    Cli cli(service.url());
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us));
    ::kill(cli.child->pid(), SIGINT);
    const auto code = cli.child->wait_for(30s);
    ASSERT_TRUE(code.has_value()) << delay_us << " us";
    EXPECT_EQ(*code, 130) << delay_us << " us: " << cli.err();
    const std::lock_guard lock(service.mutex);
    if (service.posts > 0) {
      EXPECT_GE(service.deletes.load(), 1) << delay_us << " us: the posted job was not cancelled";
    }
  }
}

// A directory as --in or --out is refused before anything is posted, naming the flag and path.
TEST(BatchCliFaults, ADirectoryAsInOrOutIsRefusedBeforePosting) {
  ScriptedService service;
  TempDir dir;
  write_file(dir / "t.csv",
             "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
             "a,48.5,82,water,800,1.5,notch\n");
  std::filesystem::create_directories(dir / "out.csv");
  const std::string table = (dir / "t.csv").string();
  const std::string out = (dir / "out.csv").string();
  const auto refused_out = test::run_slosh(
      {"batch", "--in", table, "--out", out, "--server", service.url(), "--progress", "never"});
  EXPECT_EQ(refused_out.exit_code, 2);
  EXPECT_EQ(refused_out.err, "slosh batch: --out '" + out +
                                 "' is a directory: give the path of a table file to write (or "
                                 "- for stdout)\n");
  std::filesystem::create_directories(dir / "tables");
  const std::string in = (dir / "tables").string();
  const auto refused_in = test::run_slosh(
      {"batch", "--in", in, "--out", (dir / "o.csv").string(), "--server", service.url()});
  EXPECT_EQ(refused_in.exit_code, 2);
  EXPECT_EQ(refused_in.err, "slosh batch: --in '" + in +
                                "' is a directory: give the path of a table file (or - for "
                                "stdin)\n");
  const std::lock_guard lock(service.mutex);
  EXPECT_EQ(service.posts, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv.partial"));
}

// Ctrl-C while the CLI waits out a 503's Retry-After before posting its job again: the run stops
// at once and nothing is posted after the signal.
TEST(BatchCliFaults, AnInterruptDuringA503WaitStopsBeforeAnotherPost) {
  ScriptedService service;
  service.post_503s = 1;
  Cli cli(service.url());
  {
    std::unique_lock lock(service.mutex);
    ASSERT_TRUE(service.changed.wait_for(lock, 30s, [&] { return service.post_arrived; }));
  }
  std::this_thread::sleep_for(200ms);  // the 503 answered; the CLI waits its 30 s Retry-After
  ::kill(cli.child->pid(), SIGINT);
  const auto code = cli.child->wait_for(20s);
  ASSERT_TRUE(code.has_value()) << "Ctrl-C did not end the 30 s wait";
  EXPECT_EQ(*code, 130) << cli.err();
  const std::lock_guard lock(service.mutex);
  EXPECT_EQ(service.posts, 1) << cli.err();
  EXPECT_NE(cli.err().find("interrupted before /v1/batches accepted the table"), std::string::npos)
      << cli.err();
  // Why it had not been accepted, that nothing runs, and where the (empty) table is.
  EXPECT_NE(cli.err().find("(it answered HTTP 503: m); nothing was started on the service\n"),
            std::string::npos)
      << cli.err();
  EXPECT_NE(cli.err().find(cli.empty_partial_line()), std::string::npos) << cli.err();
  EXPECT_EQ(read_file(cli.dir / "o.jsonl.partial"), "");
}

// A service that refuses the job 503 on every POST (its shared Redis stays down): the CLI posts
// it again after each Retry-After (never sooner), then gives up with exit 1 saying how long it
// tried and that no job was started, and leaves no output file.
TEST(BatchCliFaults, AJobPostRefused503EveryTimeIsRetriedAfterItsRetryAfterThenGivenUp) {
  ScriptedService service;
  service.post_503s = 1000;
  service.post_retry_after = "1";
  Cli cli(service.url(), {"--retries", "5"});
  const auto code = cli.child->wait_for(120s);
  ASSERT_TRUE(code.has_value()) << "the CLI still posts";
  EXPECT_EQ(*code, 1) << cli.err();
  const std::lock_guard lock(service.mutex);
  ASSERT_EQ(service.posts, 6) << cli.err();
  for (std::size_t i = 1; i < service.post_times.size(); ++i) {
    EXPECT_GE(service.post_times[i] - service.post_times[i - 1], 1s) << "POST " << i + 1;
  }
  // The time the CLI reports spans its 6 POSTs: at least the 5 waits between their arrivals.
  const auto waited = std::chrono::duration_cast<std::chrono::seconds>(service.post_times.back() -
                                                                       service.post_times.front());
  const std::string head = "slosh batch: stopped after 0 of 2 recipes: " + service.url() +
                           "/v1/batches answered HTTP 503: m (still 503 after 6 tries over ";
  const std::string tail = " s, each after its Retry-After; no job was started)\n";
  const std::string err = cli.err();
  const auto at = err.find(head);
  ASSERT_NE(at, std::string::npos) << err;
  const auto end = err.find(tail, at);
  ASSERT_NE(end, std::string::npos) << err;
  const std::string seconds = err.substr(at + head.size(), end - at - head.size());
  ASSERT_FALSE(seconds.empty()) << err;
  ASSERT_EQ(seconds.find_first_not_of("0123456789"), std::string::npos) << err;
  EXPECT_GE(std::stoll(seconds), waited.count()) << err;
  EXPECT_LE(std::stoll(seconds), waited.count() + 2) << err;
  EXPECT_NE(err.find(cli.empty_partial_line()), std::string::npos) << err;
  EXPECT_EQ(service.deletes.load(), 0);
  EXPECT_FALSE(std::filesystem::exists(cli.dir / "o.jsonl"));
}

// Ctrl-C while the job's progress is answered 503 (the replica asked cannot reach the replicas'
// Redis): still an interrupt (exit 130), and since the job could not be cancelled the message
// says so, why, and how to cancel it later; and where the (empty) table is.
TEST(BatchCliFaults, AnInterruptWhileTheJobIsAnswered503SaysItCouldNotBeCancelledAndWhy) {
  ScriptedService service;
  service.record_503s = 1000;
  service.record_state = "running";
  Cli cli(service.url());
  // The CLI's first progress poll was answered 503: it waits out the Retry-After.
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  for (;;) {
    {
      const std::lock_guard lock(service.mutex);
      if (service.record_gets >= 1) break;
    }
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << cli.err();
    std::this_thread::sleep_for(20ms);
  }
  ::kill(cli.child->pid(), SIGINT);
  const auto code = cli.child->wait_for(30s);
  ASSERT_TRUE(code.has_value()) << "Ctrl-C did not end the run";
  EXPECT_EQ(*code, 130) << cli.err();
  const std::string path = service.url() + "/v1/batches/" + kJobId;
  EXPECT_NE(cli.err().find("slosh batch: stopped after 0 of 2 recipes: interrupted: batch job " +
                           std::string(kJobId) + " could not be cancelled (" + path +
                           " answered HTTP 503: m); it may still run: DELETE " + path +
                           " once the service answers\n"),
            std::string::npos)
      << cli.err();
  EXPECT_NE(cli.err().find(cli.empty_partial_line()), std::string::npos) << cli.err();
}

// A table with a recipe twice (and so one missing) is never written as complete.
TEST(BatchCliFaults, AResultsTableWithADuplicatedRowIsRefusedNonZero) {
  ScriptedService service;
  service.results = row(1, "a") + row(1, "a");
  Cli cli(service.url());
  const auto code = cli.child->wait_for(30s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 1) << cli.err();
  EXPECT_FALSE(std::filesystem::exists(cli.dir / "o.jsonl"));
  EXPECT_NE(
      cli.err().find("batch job " + std::string(kJobId) + " answered row 1 where row 2 was due"),
      std::string::npos)
      << cli.err();
}

TEST(BatchCliFaults, AShortResultsTableIsRefusedNonZero) {
  ScriptedService service;
  service.results = row(1, "a");
  Cli cli(service.url());
  const auto code = cli.child->wait_for(30s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 1) << cli.err();
  EXPECT_FALSE(std::filesystem::exists(cli.dir / "o.jsonl"));
  EXPECT_NE(cli.err().find("batch job " + std::string(kJobId) + " answered 1 rows for 2 recipes"),
            std::string::npos)
      << cli.err();
}

// 503 with Retry-After while the job is read (Redis paused on the replica asked): the CLI waits
// and asks again instead of stopping (and cancelling its own job).
TEST(BatchCliFaults, A503WithRetryAfterIsRetriedNotFatal) {
  ScriptedService service;
  service.record_503s = 2;
  service.results = row(1, "a") + row(2, "b");
  Cli cli(service.url());
  const auto code = cli.child->wait_for(60s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << cli.err();
  EXPECT_EQ(service.deletes.load(), 0);
  EXPECT_EQ(read_file(cli.dir / "o.jsonl"), row(1, "a") + row(2, "b"));
}

// A replica that accepted the job and then stops answering for good: the CLI's progress polls
// have a deadline and are repeated with backoff for --give-up-after, then it stops with exit 1
// instead of hanging, naming the job and saying its replica stopped answering. It does not DELETE
// the job (a paused replica carries on with it when it runs again).
TEST(BatchCliFaults, AReplicaThatStopsAnsweringStopsTheRunNotHangsIt) {
  ScriptedService service;
  service.record_hangs = true;
  Cli cli(service.url(), {"--give-up-after", "4"});
  const auto code = cli.child->wait_for(120s);
  ASSERT_TRUE(code.has_value()) << "the CLI still hangs";
  EXPECT_EQ(*code, 1) << cli.err();
  EXPECT_FALSE(std::filesystem::exists(cli.dir / "o.jsonl"));
  EXPECT_EQ(service.deletes.load(), 0);
  const std::string err = cli.err();
  EXPECT_NE(err.find("batch job " + std::string(kJobId) +
                     ": the replica that runs it stopped "
                     "answering (no answer for "),
            std::string::npos)
      << err;
  // Silent for at least --give-up-after: counted from the first poll that got no answer, whose
  // own deadline is 3 s, and the last wait of the backoff (0.2 s doubling) is at most 3.2 s more.
  const std::string lead = "(no answer for ";
  const auto at = err.find(lead);
  ASSERT_NE(at, std::string::npos) << err;
  const long silent = std::stol(err.substr(at + lead.size()));
  EXPECT_GE(silent, 4) << err;
  EXPECT_LE(silent, 4 + 3 + 4) << err;
  EXPECT_NE(err.find("the job was not cancelled and may still finish: read it with GET " +
                     service.url() + "/v1/batches/" + kJobId),
            std::string::npos)
      << err;
  EXPECT_EQ(err.find("running there?"), std::string::npos) << err;
}

// The patience flags: their defaults are what docs/batch.md says, and a value outside the range is
// refused with the flag, the value and the range, before anything is read or sent.
TEST(BatchCliFaults, RetriesAndGiveUpAfterSayTheirDefaultsAndRefuseValuesOutsideTheirRange) {
  const test::RunResult help = test::run_slosh({"batch", "--help"});
  ASSERT_EQ(help.exit_code, 0) << help.err;
  for (const char* line :
       {"--retries INT:INT in [0 - 1000]=30", "--give-up-after INT:INT in [1 - 86400]=60"}) {
    EXPECT_NE(help.out.find(line), std::string::npos) << line << "\n" << help.out;
  }
  struct Case {
    const char* flag;
    const char* value;
    const char* range;
  };
  for (const Case& c :
       {Case{"--retries", "-1", "0 to 1000"}, Case{"--retries", "1001", "0 to 1000"},
        Case{"--give-up-after", "0", "1 to 86400"},
        Case{"--give-up-after", "86401", "1 to 86400"}}) {
    const test::RunResult r = test::run_slosh(
        {"batch", "--in", "missing.csv", "--server", "http://127.0.0.1:9", c.flag, c.value});
    EXPECT_EQ(r.exit_code, 2) << c.flag;
    EXPECT_EQ(r.err, std::string(c.flag) + ": Value " + c.value + " not in range " + c.range +
                         "\nRun with --help for more information.\n");
  }
}

}  // namespace test_batch_cli_faults
}  // namespace slosh
