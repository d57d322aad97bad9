// Batch jobs as resources (SPEC §13) against a real `slosh serve` on loopback: the
// lifecycle (202 + Location, progress to the total, results row by row equal to POST
// /v1/plans/batch), paging, the CSV and JSON lines downloads equal to the files of `slosh batch`,
// cancelling mid-run (no more solves after), the 404/405/422 texts, a bad recipe as a failed row,
// an interactive plan overtaking a running 1000-recipe job in the pool, staleness of a record
// whose replica stopped, and `slosh batch --server` through the jobs API (also interrupted).

#include <httplib.h>
#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/batch_job_record.hpp"
#include "slosh/api/job_record.hpp"
#include "support/job_tables.hpp"
#include "support/process.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_batch_jobs {

using nlohmann::json;
using test::csv_without_timing;
using test::read_file;
using test::run_slosh;
using test::Server;
using test::TempDir;
using test::write_file;
using namespace std::chrono_literals;

// A plan request of a distinct recipe per `i` (the motion time differs): never a cache hit of
// another i.
json recipe(std::size_t i, const std::string& strategy = "notch") {
  return {{"format",
           {{"container", {{"radius_mm", 48.5}}},
            {"fill_height_mm", 82},
            {"fluid", "water"},
            {"stroke_mm", 800},
            {"motion_time_s", 0.9 + 0.001 * static_cast<double>(i)}}},
          {"strategy", strategy}};
}

std::vector<json> recipes(std::size_t n, std::size_t first = 0) {
  std::vector<json> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(recipe(first + i));
  return out;
}

json post_job(httplib::Client& c, const json& body, std::string* location = nullptr) {
  auto r = c.Post("/v1/batches", body.dump(), "application/json");
  EXPECT_TRUE(r);
  if (!r) return json();
  EXPECT_EQ(r->status, 202) << r->body;
  if (location != nullptr) *location = r->get_header_value("Location");
  return json::parse(r->body);
}

json get_json(httplib::Client& c, const std::string& path, int status = 200) {
  auto r = c.Get(path);
  EXPECT_TRUE(r) << path;
  if (!r) return json();
  EXPECT_EQ(r->status, status) << path << ": " << r->body;
  return json::parse(r->body);
}

// Polls until the job has finished (waits, never asserts a duration); the last record.
json wait_finished(httplib::Client& c, const std::string& id) {
  json record;
  for (int i = 0; i < 1200; ++i) {
    record = get_json(c, "/v1/batches/" + id);
    if (record.value("state", "") != "queued" && record.value("state", "") != "running") break;
    std::this_thread::sleep_for(50ms);
  }
  return record;
}

// Every row of a finished job through the pages of `limit` rows (following next_offset).
std::vector<json> all_pages(httplib::Client& c, const std::string& id, std::size_t limit) {
  std::vector<json> rows;
  std::size_t offset = 0;
  for (int pages = 0; pages < 10000; ++pages) {
    const json page = get_json(c, "/v1/batches/" + id + "?offset=" + std::to_string(offset) +
                                      "&limit=" + std::to_string(limit));
    const json& results = page.at("results");
    EXPECT_EQ(results.at("offset"), offset);
    EXPECT_LE(results.at("rows").size(), limit);
    for (const json& row : results.at("rows")) rows.push_back(row);
    if (results.at("next_offset").is_null()) break;
    offset = results.at("next_offset").get<std::size_t>();
  }
  return rows;
}

json without_timing(json row) {
  row.erase("cached");
  row.erase("solve_ms");
  return row;
}

TEST(BatchJobs, LifecycleResultsEqualThePlansBatchRowByRow) {
  Server server({"--workers", "2"});
  auto c = server.client();
  std::vector<json> requests = recipes(12);
  requests.insert(requests.begin() + 5, json{{"recipe_id", "bad"}, {"strategy", "nope"}});
  requests[2]["recipe_id"] = "R-2";
  std::string location;
  const json accepted = post_job(c, {{"requests", requests}}, &location);
  const std::string id = accepted.at("id");
  EXPECT_TRUE(std::regex_match(id, std::regex("[0-9a-f]{32}"))) << id;
  EXPECT_EQ(location, "/v1/batches/" + id);
  EXPECT_EQ(accepted.at("progress").at("total"), 13);
  EXPECT_TRUE(accepted.at("state") == "queued" || accepted.at("state") == "running");
  const json done = wait_finished(c, id);
  ASSERT_EQ(done.at("state"), "done") << done.dump();
  EXPECT_EQ(done.at("progress").at("done"), 13);
  EXPECT_EQ(done.at("progress").at("failed"), 1);  // the bad recipe is a failed row
  EXPECT_TRUE(done.at("message").is_null());
  EXPECT_FALSE(done.at("finished_at").is_null());
  const std::vector<json> rows = all_pages(c, id, 100);
  ASSERT_EQ(rows.size(), 13u);
  // The same recipes through POST /v1/plans/batch (now cached: the same plans).
  std::vector<json> plain = requests;
  for (json& r : plain) r.erase("recipe_id");
  auto batch = c.Post("/v1/plans/batch", json{{"requests", plain}}.dump(), "application/json");
  ASSERT_TRUE(batch);
  const json results = json::parse(batch->body).at("results");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(rows[i].at("row"), i + 1);
    if (results[i].contains("error")) {
      EXPECT_EQ(rows[i].at("status"), "error");
      EXPECT_EQ(rows[i].at("recipe_id"), "bad");
      // The batch reads the paths inside it (requests[i].format); a job's row names its own.
      const std::string prefix = "requests[" + std::to_string(i) + "].";
      std::string inside = results[i]["error"]["message"];
      ASSERT_EQ(inside.rfind(prefix, 0), 0U) << inside;
      EXPECT_EQ(rows[i].at("error").at("message"), inside.substr(prefix.size()));
      continue;
    }
    const json& plan = results[i].at("plan");
    EXPECT_EQ(rows[i].at("key"), plan.at("key"));
    EXPECT_EQ(rows[i].at("status"), plan.at("status"));
    EXPECT_EQ(rows[i].at("durations_s"), plan.at("law").at("durations_s"));
  }
  EXPECT_EQ(rows[2].at("recipe_id"), "R-2");
}

TEST(BatchJobs, PagesFollowNextOffsetAndAnOffsetPastTheEndIsEmpty) {
  Server server({"--workers", "2"});
  auto c = server.client();
  const json accepted = post_job(c, {{"requests", recipes(9)}});
  const std::string id = accepted.at("id");
  ASSERT_EQ(wait_finished(c, id).at("state"), "done");
  const std::vector<json> whole = all_pages(c, id, 1000);
  const std::vector<json> paged = all_pages(c, id, 4);  // pages of 4, 4 and 1
  ASSERT_EQ(whole.size(), 9u);
  EXPECT_EQ(paged, whole);
  const json first = get_json(c, "/v1/batches/" + id + "?limit=4");
  EXPECT_EQ(first.at("results").at("next_offset"), 4);
  const json past = get_json(c, "/v1/batches/" + id + "?offset=50");
  EXPECT_EQ(past.at("results").at("rows"), json::array());
  EXPECT_TRUE(past.at("results").at("next_offset").is_null());
}

std::vector<json> jsonl_without_timing(const std::string& text) {
  std::vector<json> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) rows.push_back(without_timing(json::parse(line)));
  return rows;
}

TEST(BatchJobs, DownloadsAreTheFilesOfSloshBatch) {
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (int i = 0; i < 8; ++i) {
    table += "r" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(0.9 + 0.01 * i) +
             ",notch\n";
  }
  table += "\"bad, quoted\",48.5,-5,water,800,1,notch\n";  // fill height out of range
  table += "short,48.5\n";                                 // an unreadable row
  write_file(dir / "t.csv", table);
  const auto local_csv = run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                    (dir / "local.csv").string(), "--cache", ""});
  const auto local_jsonl = run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                      (dir / "local.jsonl").string(), "--cache", ""});
  ASSERT_EQ(local_csv.exit_code, 3) << local_csv.err;
  ASSERT_EQ(local_jsonl.exit_code, 3) << local_jsonl.err;
  Server server({"--workers", "2"});
  auto c = server.client();
  const json accepted = post_job(c, {{"table", table}, {"table_format", "csv"}, {"format", "csv"}});
  const std::string id = accepted.at("id");
  EXPECT_EQ(accepted.at("results_csv"), "/v1/batches/" + id + "/results.csv");
  ASSERT_EQ(wait_finished(c, id).at("state"), "done");
  auto csv = c.Get("/v1/batches/" + id + "/results.csv");
  auto jsonl = c.Get("/v1/batches/" + id + "/results.jsonl");
  ASSERT_TRUE(csv && jsonl);
  EXPECT_EQ(csv->status, 200);
  EXPECT_EQ(csv->get_header_value("Content-Type"), "text/csv; charset=utf-8");
  EXPECT_EQ(csv->get_header_value("Content-Disposition"),
            "attachment; filename=\"batch-" + id + ".csv\"");
  const std::vector<std::string> remote_lines = csv_without_timing(csv->body);
  const std::vector<std::string> local_lines = csv_without_timing(read_file(dir / "local.csv"));
  ASSERT_EQ(remote_lines.size(), 11u);  // header + 10 rows
  EXPECT_EQ(remote_lines, local_lines);
  EXPECT_EQ(jsonl_without_timing(jsonl->body),
            jsonl_without_timing(read_file(dir / "local.jsonl")));
}

TEST(BatchJobs, CancelMidRunStopsTheSolves) {
  Server server({"--workers", "1"});
  auto c = server.client();
  const json accepted = post_job(c, {{"requests", recipes(400, 1000)}});
  const std::string id = accepted.at("id");
  // Queued behind the running job, with one worker: it cannot start before that one has ended,
  // which takes a DELETE (below) or all of its 400 solves. Its DELETEs are the idempotency check:
  // a running job's second DELETE races with its runner stopping it (then it is forgotten: 200).
  const std::string queued = post_job(c, {{"requests", recipes(2, 5000)}}).at("id");
  json record;
  for (int i = 0; i < 1200; ++i) {  // wait until it has made some progress
    record = get_json(c, "/v1/batches/" + id);
    if (record.at("progress").at("done").get<int>() >= 3) break;
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_EQ(record.at("state"), "running");
  for (int i = 0; i < 2; ++i) {  // idempotent while it has not stopped
    auto again = c.Delete("/v1/batches/" + queued);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 202) << again->body;
    EXPECT_EQ(json::parse(again->body).at("cancel_requested"), true);
  }
  auto deleted = c.Delete("/v1/batches/" + id);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 202) << deleted->body;
  EXPECT_EQ(json::parse(deleted->body).at("cancel_requested"), true);
  EXPECT_EQ(wait_finished(c, queued).at("message"), "cancelled before it started");
  const json cancelled = wait_finished(c, id);
  ASSERT_EQ(cancelled.at("state"), "cancelled");
  const int done = cancelled.at("progress").at("done").get<int>();
  EXPECT_LT(done, 400);
  EXPECT_EQ(cancelled.at("message"), "cancelled after " + std::to_string(done) + " of 400 recipes");
  EXPECT_EQ(cancelled.at("results").at("rows").size(), std::min(done, 100));
  // No more solves: the background tasks started stay where they are once the (at most one)
  // item in flight has finished.
  std::this_thread::sleep_for(1s);
  const double started =
      test::metric_of(server, "slosh_pool_tasks_started_total{priority=\"background\"}");
  std::this_thread::sleep_for(1s);
  EXPECT_EQ(test::metric_of(server, "slosh_pool_tasks_started_total{priority=\"background\"}"),
            started);
  EXPECT_LE(started, done + 2);  // the window: at most `workers` items beyond the rows kept
  EXPECT_EQ(test::metric_of(server, "slosh_batch_jobs_active"), 0);
  // A finished job's DELETE forgets it.
  auto forget = c.Delete("/v1/batches/" + id);
  ASSERT_TRUE(forget);
  EXPECT_EQ(forget->status, 200);
  EXPECT_EQ(json::parse(forget->body).at("deleted"), true);
  get_json(c, "/v1/batches/" + id, 404);
}

// A DELETE of a job still queued behind another is recorded at once: its record says
// cancel_requested before the runner takes it (it then ends cancelled without a solve).
TEST(BatchJobs, AQueuedJobsDeleteShowsInItsRecordAtOnce) {
  Server server({"--workers", "1"});
  auto c = server.client();
  const std::string running = post_job(c, {{"requests", recipes(400, 3000)}}).at("id");
  const std::string queued = post_job(c, {{"requests", recipes(3, 3500)}}).at("id");
  const auto deleted = c.Delete("/v1/batches/" + queued);
  ASSERT_TRUE(deleted);
  ASSERT_EQ(deleted->status, 202) << deleted->body;
  const json record = get_json(c, "/v1/batches/" + queued);
  ASSERT_EQ(record.at("state"), "queued") << record;
  EXPECT_EQ(record.at("cancel_requested"), true) << record;
  // Still so after a heartbeat of the running job rewrote the queued job's record.
  std::this_thread::sleep_for(1200ms);  // two heartbeats (the product's period), not a timing
  const json later = get_json(c, "/v1/batches/" + queued);
  if (later.at("state") == "queued") {
    EXPECT_EQ(later.at("cancel_requested"), true) << later;
  }
  c.Delete("/v1/batches/" + running);
  EXPECT_EQ(wait_finished(c, queued).at("state"), "cancelled");
}

TEST(BatchJobs, ErrorTexts) {
  Server server({"--workers", "1"});
  auto c = server.client();
  auto message = [](const httplib::Result& r) {
    return json::parse(r->body).at("error").at("message").get<std::string>();
  };
  auto unknown = c.Get("/v1/batches/0123");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(message(unknown),
            "no batch job with id '0123' is known to this service: it never existed, was "
            "deleted, was lost with a restart of the replica that ran it (without a shared "
            "store), expired or was forgotten to make room (finished jobs are kept for "
            "batch_job_ttl_s = 3600 s, at most batch_jobs_kept = 100 of them within "
            "batch_jobs_bytes = 268435456 bytes)");
  EXPECT_EQ(c.Delete("/v1/batches/0123")->status, 404);
  EXPECT_EQ(c.Get("/v1/batches/0123/results.csv")->status, 404);
  auto wrong = c.Delete("/v1/batches");
  EXPECT_EQ(wrong->status, 405);
  EXPECT_EQ(wrong->get_header_value("Allow"), "POST");
  auto post_on_job = c.Post("/v1/batches/0123", "{}", "application/json");
  EXPECT_EQ(post_on_job->status, 405);
  EXPECT_EQ(post_on_job->get_header_value("Allow"), "GET, HEAD, DELETE");
  const std::vector<std::pair<json, std::string>> bodies = {
      {json{{"requests", json::array()}},
       "requests must be an array of 1 to 100000 plan requests (batch_job_max), got 0 requests"},
      {json{{"requests", recipes(1)}, {"format", "xml"}},
       "format = \"xml\" is not allowed: one of \"csv\", \"jsonl\""},
      {json{{"requests", recipes(1)}, {"table", "x"}},
       "give either requests (plan requests) or table (a recipe table's text), not both"},
      {json{{"table", "radius_mm\n1\n"}},
       "recipe table: missing column \"recipe_id\"; required: recipe_id, radius_mm, "
       "fill_height_mm, fluid (or density_kg_m3 and viscosity_pa_s), stroke_mm, motion_time_s, "
       "strategy"},
  };
  for (const auto& [body, text] : bodies) {
    auto r = c.Post("/v1/batches", body.dump(), "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << body.dump();
    EXPECT_EQ(message(r), text);
  }
  const std::string id = post_job(c, {{"requests", recipes(1)}}).at("id");
  for (const auto& [query, text] : std::vector<std::pair<std::string, std::string>>{
           {"?limit=0", "limit = 0 is not allowed: a whole number from 1 to 1000"},
           {"?limit=1001", "limit = 1001 is not allowed: a whole number from 1 to 1000"},
           {"?offset=-1", "offset = -1 is not allowed: a whole number from 0 to 100000"},
           {"?limit=5&limit=6",
            "limit is given twice (5 and 6): give each query parameter once"}}) {
    auto r = c.Get("/v1/batches/" + id + query);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << query;
    EXPECT_EQ(message(r), text) << query;
    EXPECT_EQ(json::parse(r->body)["error"]["field"], query.substr(1, query.find('=') - 1));
  }
}

TEST(BatchJobs, LimitsAreRefusedNamingTheirSetting) {
  const TempDir dir;
  write_file(dir / "limits.json", R"({"batch_job_max": 3, "batch_jobs_max": 1})");
  Server limited({"--workers", "1", "--config", (dir / "limits.json").string()});
  auto c = limited.client();
  auto big = c.Post("/v1/batches", json{{"requests", recipes(4)}}.dump(), "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 422);
  EXPECT_EQ(json::parse(big->body)["error"]["message"],
            "requests must be an array of 1 to 3 plan requests (batch_job_max), got 4 requests");
  // One job holds the replica's only slot while it runs: a second is refused with 503.
  post_job(c, {{"requests", recipes(3, 2000)}});
  auto second = c.Post("/v1/batches", json{{"requests", recipes(1)}}.dump(), "application/json");
  ASSERT_TRUE(second);
  if (second->status == 202) GTEST_SKIP() << "the first job finished before the second POST";
  EXPECT_EQ(second->status, 503);
  EXPECT_EQ(second->get_header_value("Retry-After"), "1");
  EXPECT_EQ(json::parse(second->body)["error"]["message"],
            "1 batch jobs are queued or running here, the limit (batch_jobs_max); retry after one "
            "has finished");
}

// An interactive plan posted while a 1000-recipe job runs on the one worker goes through the pool
// ahead of the job's items: while it waits, at most the job's window (1 item per worker) plus the
// item running start. Counted with the pool's counters, not by wall-clock thresholds.
TEST(BatchJobs, AnInteractivePlanOvertakesARunningJob) {
  Server server({"--workers", "1"});
  auto c = server.client();
  const std::string id = post_job(c, {{"requests", recipes(1000, 3000)}}).at("id");
  for (int i = 0; i < 1200; ++i) {
    if (get_json(c, "/v1/batches/" + id).at("progress").at("done").get<int>() >= 2) break;
    std::this_thread::sleep_for(20ms);
  }
  const std::string background = "slosh_pool_tasks_started_total{priority=\"background\"}";
  for (int k = 0; k < 3; ++k) {
    const double before = test::metric_of(server, background);
    auto r =
        c.Post("/v1/plans", recipe(9000 + static_cast<std::size_t>(k)).dump(), "application/json");
    const double after = test::metric_of(server, background);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(r->get_header_value("X-Cache"), "miss");
    // The running item, the window's one queued item, and one each side of the metric reads.
    EXPECT_LE(after - before, 4) << "k = " << k;
  }
  const json record = get_json(c, "/v1/batches/" + id);
  EXPECT_EQ(record.at("state"), "running");
  EXPECT_LT(record.at("progress").at("done").get<int>(), 1000);
  EXPECT_LE(test::metric_of(server, "slosh_pool_background_queue_depth"), 1);
  c.Delete("/v1/batches/" + id);
}

// SIGTERM while a job runs: the service stops (exit 0) and the job ends as failed with a message
// (logged; with a shared store, other replicas read it).
TEST(BatchJobs, ShutdownEndsTheRunningJobAsFailed) {
  Server server({"--workers", "1"});
  auto c = server.client();
  const std::string id = post_job(c, {{"requests", recipes(500, 5000)}}).at("id");
  for (int i = 0; i < 1200; ++i) {
    if (get_json(c, "/v1/batches/" + id).at("progress").at("done").get<int>() >= 1) break;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(server.stop(), 0);
  const std::string log = server.log();
  EXPECT_TRUE(std::regex_search(
      log, std::regex("batch job " + id +
                      " failed: [0-9]+ of 500 recipes \\([0-9]+ failed\\): the service shut down "
                      "after [0-9]+ of 500 recipes; POST the job again \\(the finished plans are "
                      "cached\\)")))
      << log;
}

TEST(BatchJobs, ARecordItsReplicaStoppedRewritingReadsAsFailed) {
  service::JobStatus status;
  status.id = "abc";
  status.state = service::JobState::kRunning;
  status.total = 10;
  status.done = 4;
  status.created_ms = 1'000'000;
  status.started_ms = 1'000'000;
  const std::string text = api::job_record_text(status, 1'002'000);
  const json rendered = json::parse(text);
  EXPECT_EQ(rendered["progress"]["rate_per_s"], 2.0);  // 4 rows in 2 s
  EXPECT_EQ(rendered["progress"]["eta_s"], 3.0);       // 6 rows left at 2 rows/s
  auto record = api::parse_job_record(text);
  ASSERT_TRUE(record);
  EXPECT_FALSE(service::mark_if_stale(*record, 1'002'000 + 30'000, 30));
  EXPECT_EQ(json::parse(api::job_record_text(*record))["state"], "running");
  EXPECT_TRUE(service::mark_if_stale(*record, 1'002'000 + 31'000, 30));
  EXPECT_EQ(record->state, service::JobState::kFailed);
  const json stale = json::parse(api::job_record_text(*record));
  EXPECT_EQ(stale["state"], "failed");
  EXPECT_EQ(stale["message"],
            "the replica running it stopped: no update for 31 s (batch_job_stale_s = 30 s); POST "
            "the job again (its plans are cached)");
  status.state = service::JobState::kDone;
  auto finished = api::parse_job_record(api::job_record_text(status, 1'002'000));
  ASSERT_TRUE(finished);
  EXPECT_FALSE(service::mark_if_stale(*finished, 9'000'000'000, 30));  // final states stay
  EXPECT_EQ(api::iso_time(1'795'566'103'512), "2026-11-25T00:21:43.512Z");
}

// A job several replicas work on counts the items its helpers solved ahead of its stored rows:
// "solved" is the stored rows plus those, and the rate and ETA are of it; once the job has ended
// only the stored rows count. A job one replica runs (no shares) renders no "solved".
TEST(BatchJobs, AHelpedJobsProgressCountsTheItemsItsHelpersSolvedAheadOfItsRows) {
  service::JobStatus status;
  status.id = "abc";
  status.state = service::JobState::kRunning;
  status.total = 20;
  status.done = 4;
  status.solved_ahead = 6;
  status.shares = {{"line-1", 4}};
  status.created_ms = 1'000'000;
  status.started_ms = 1'000'000;
  json rendered = json::parse(api::job_record_text(status, 1'002'000));
  EXPECT_EQ(rendered["progress"]["done"], 4);
  EXPECT_EQ(rendered["progress"]["solved"], 10);
  EXPECT_EQ(rendered["progress"]["rate_per_s"], 5.0);  // 10 items in 2 s
  EXPECT_EQ(rendered["progress"]["eta_s"], 2.0);       // 10 items left at 5 items/s
  status.solved_ahead = 30;                            // never more than the table
  rendered = json::parse(api::job_record_text(status, 1'002'000));
  EXPECT_EQ(rendered["progress"]["solved"], 20);
  EXPECT_EQ(rendered["progress"]["eta_s"], 0.0);
  status.state = service::JobState::kCancelled;
  status.finished_ms = 1'002'000;
  rendered = json::parse(api::job_record_text(status, 1'002'000));
  EXPECT_EQ(rendered["progress"]["solved"], 4);
  EXPECT_EQ(rendered["progress"]["rate_per_s"], 2.0);
  status.shares.clear();
  status.state = service::JobState::kRunning;
  rendered = json::parse(api::job_record_text(status, 1'002'000));
  EXPECT_FALSE(rendered["progress"].contains("solved"));
}

// A replica of the previous version shares Redis: the records it stored (this text is one, byte
// for byte, as it wrote it) are read, judged and answered unchanged, and this version stores the
// same text for the same job.
TEST(BatchJobs, ARecordInThePreviousStoredFormIsReadAndAnsweredByteForByte) {
  const std::string stored =
      R"({"cancel_requested":false,"created_at":"1970-01-01T00:16:40.000Z","finished_at":null,)"
      R"("format":"jsonl","id":"abc","message":null,"note":null,"progress":{"done":4,"eta_s":3.0,)"
      R"("failed":1,"rate_per_s":2.0,"total":10},"results_csv":"/v1/batches/abc/results.csv",)"
      R"("results_jsonl":"/v1/batches/abc/results.jsonl","started_at":"1970-01-01T00:16:40.000Z",)"
      R"("state":"running","updated_at":"1970-01-01T00:16:42.000Z","updated_unix_ms":1002000,)"
      R"("view":"compact"})";
  service::JobStatus status;
  status.id = "abc";
  status.state = service::JobState::kRunning;
  status.format = "jsonl";
  status.view = "compact";
  status.total = 10;
  status.done = 4;
  status.failed = 1;
  status.created_ms = 1'000'000;
  status.started_ms = 1'000'000;
  EXPECT_EQ(api::job_record_text(status, 1'002'000), stored);

  auto record = api::parse_job_record(stored);
  ASSERT_TRUE(record);
  EXPECT_EQ(record->state, service::JobState::kRunning);
  EXPECT_EQ(record->done, 4u);
  EXPECT_EQ(record->total, 10u);
  EXPECT_EQ(record->updated_unix_ms, 1'002'000);
  EXPECT_FALSE(record->cancel_requested);
  EXPECT_EQ(record->message, "");
  EXPECT_EQ(api::job_record_text(*record), stored);  // answered as stored
  api::mark_cancel_requested(*record);
  std::string cancelled = stored;
  cancelled.replace(cancelled.find("false"), 5, "true");
  EXPECT_EQ(api::job_record_text(*record), cancelled);

  // Not job records: 503 "damaged" for these, never a crash or a guess.
  for (const char* damaged : {"", "[]", "{}", R"({"state":"running"})",
                              R"({"state":"paused","progress":{"done":1,"total":2}})",
                              R"({"state":"done","progress":{"done":"1","total":2}})",
                              R"({"state":3,"progress":{"done":1,"total":2}})"}) {
    EXPECT_FALSE(api::parse_job_record(damaged)) << damaged;
  }
}

// `slosh batch --server` runs the table as a job (POST /v1/batches, GET for progress, the
// results download) and writes what the local run writes.
TEST(BatchJobsCli, ServerModeRunsAJobAndWritesTheLocalTable) {
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (int i = 0; i < 6; ++i) {
    table += "c" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(1.0 + 0.01 * i) +
             ",notch\n";
  }
  table += "x,48.5,82,water,800,1,nope\n";
  write_file(dir / "t.csv", table);
  Server server({"--workers", "2"});
  const auto remote = run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                 (dir / "remote.jsonl").string(), "--server", server.url()});
  const auto local = run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                (dir / "local.jsonl").string(), "--cache", ""});
  EXPECT_EQ(remote.exit_code, 3) << remote.err;
  EXPECT_EQ(local.exit_code, 3) << local.err;
  EXPECT_NE(remote.err.find("slosh batch: 7 recipes, 6 planned (0 from cache, 6 optimal), 1 error"),
            std::string::npos)
      << remote.err;
  EXPECT_NE(
      remote.err.find("slosh batch: row 7 could not be planned: see the message of the row\n"),
      std::string::npos)
      << remote.err;
  EXPECT_EQ(jsonl_without_timing(read_file(dir / "remote.jsonl")),
            jsonl_without_timing(read_file(dir / "local.jsonl")));
  EXPECT_EQ(
      test::metric_of(server, "slosh_http_requests_total{route=\"/v1/batches\",status=\"202\"}"),
      1);
  EXPECT_EQ(test::metric_of(server,
                            "slosh_http_requests_total{route=\"/v1/plans/batch\",status=\"200\"}"),
            -1);
}

// Ctrl-C (SIGINT) during a remote job cancels the job on the service (DELETE). The signal is sent
// at the earliest point the job is observable on the server, which may be before the CLI has read
// the POST's answer: the handler is installed before the POST, so every trial cancels.
TEST(BatchJobsCli, InterruptCancelsTheRemoteJob) {
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (int i = 0; i < 500; ++i) {
    table += "i" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(2.0 + 0.001 * i) +
             ",notch\n";
  }
  write_file(dir / "t.csv", table);
  write_file(dir / "stdin", "");
  Server server({"--workers", "1"});
  for (int trial = 0; trial < 8; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    test::Child cli(
        test::spawn({"batch", "--in", (dir / "t.csv").string(), "--out", (dir / "o.csv").string(),
                     "--server", server.url(), "--progress", "never"},
                    dir / "stdin", dir / "stdout", dir / "stderr"));
    for (int i = 0; i < 1200 && test::metric_of(server, "slosh_batch_jobs_active") != 1; ++i) {
      std::this_thread::sleep_for(10ms);
    }
    ASSERT_EQ(test::metric_of(server, "slosh_batch_jobs_active"), 1) << server.log();
    ::kill(cli.pid(), SIGINT);
    const auto code = cli.wait_for(30s);
    ASSERT_TRUE(code.has_value());
    EXPECT_EQ(*code, 130);
    EXPECT_NE(read_file(dir / "stderr").find("interrupted: batch job "), std::string::npos)
        << read_file(dir / "stderr");
    for (int i = 0; i < 600 && test::metric_of(server, "slosh_batch_jobs_active") != 0; ++i) {
      std::this_thread::sleep_for(10ms);
    }
    ASSERT_EQ(test::metric_of(server, "slosh_batch_jobs_active"), 0);
  }
  // The access log is written in batches: the line follows within milliseconds.
  EXPECT_TRUE(test::wait_until(
      [&] { return server.log().find("method=DELETE path=/v1/batches/") != std::string::npos; },
      std::chrono::seconds(10)))
      << server.log();
}

// Interrupted once the service has finished some of the job's rows, the CLI cancels the job and
// the .partial table holds those rows (1..k, in order), and the bar is not drawn as complete.
TEST(BatchJobsCli, AnInterruptedRunKeepsTheRowsTheServiceFinishedInThePartialTable) {
  const TempDir dir;
  std::string table = "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n";
  for (int i = 0; i < 300; ++i) {
    table += "p" + std::to_string(i) + ",48.5,82,water,800," + std::to_string(3.0 + 0.001 * i) +
             ",notch\n";
  }
  write_file(dir / "t.csv", table);
  write_file(dir / "stdin", "");
  Server server({"--workers", "1"});
  test::Child cli(
      test::spawn({"batch", "--in", (dir / "t.csv").string(), "--out", (dir / "o.csv").string(),
                   "--server", server.url(), "--progress", "always"},
                  dir / "stdin", dir / "stdout", dir / "stderr"));
  // With one worker, the 5th item started means at least 3 rows are finished.
  const std::string started = R"(slosh_pool_tasks_started_total{priority="background"})";
  for (int i = 0; i < 3000 && test::metric_of(server, started) < 5; ++i) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_GE(test::metric_of(server, started), 5) << server.log();
  ::kill(cli.pid(), SIGINT);
  const auto code = cli.wait_for(60s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 130);
  const std::string err = read_file(dir / "stderr");
  std::istringstream partial(read_file(dir / "o.csv.partial"));
  std::string line;
  std::getline(partial, line);  // header
  std::size_t rows = 0;
  while (std::getline(partial, line)) {
    ++rows;
    EXPECT_EQ(line.rfind(std::to_string(rows) + ",\"p" + std::to_string(rows - 1) + "\",", 0), 0u)
        << line;
  }
  EXPECT_GE(rows, 3u) << err;
  EXPECT_NE(err.find("stopped after " + std::to_string(rows) + " of 300 recipes: interrupted"),
            std::string::npos)
      << err;
  EXPECT_EQ(err.find("300/300"), std::string::npos) << err;
}

// Kept results have a byte budget (batch_jobs_bytes): a job whose own rows pass it stops as
// failed naming the setting (never an allocation failure), and a later job's rows make room by
// forgetting the least recently written finished job.
TEST(BatchJobs, KeptResultsStayWithinTheirByteBudget) {
  const TempDir dir;
  write_file(dir / "budget.json", R"({"batch_jobs_bytes": 65536})");
  Server server({"--workers", "1", "--config", (dir / "budget.json").string()});
  auto c = server.client();
  // ~1.5 KB a row: 200 rows pass 64 KiB.
  const std::string big = post_job(c, {{"requests", recipes(200, 7000)}}).at("id");
  const json failed = wait_finished(c, big);
  ASSERT_EQ(failed.at("state"), "failed") << failed;
  const auto done = failed.at("progress").at("done").get<std::size_t>();
  EXPECT_LT(done, 200u);
  EXPECT_EQ(failed.at("message"),
            "its results passed the memory kept for batch jobs, batch_jobs_bytes = 65536 bytes, "
            "after " +
                std::to_string(done) +
                " of 200 recipes: split the table into smaller jobs, ask for a smaller view, or "
                "raise batch_jobs_bytes");
  // Each of these fits; together they do not: the oldest is forgotten first.
  const std::string first = post_job(c, {{"requests", recipes(25, 8000)}}).at("id");
  ASSERT_EQ(wait_finished(c, first).at("state"), "done");
  const std::string second = post_job(c, {{"requests", recipes(25, 8100)}}).at("id");
  ASSERT_EQ(wait_finished(c, second).at("state"), "done");
  const std::string third = post_job(c, {{"requests", recipes(25, 8200)}}).at("id");
  ASSERT_EQ(wait_finished(c, third).at("state"), "done");
  EXPECT_EQ(all_pages(c, third, 100).size(), 25u);
  const auto gone = c.Get("/v1/batches/" + first);
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->status, 404) << gone->body;
  EXPECT_NE(gone->body.find("batch_jobs_bytes = 65536 bytes"), std::string::npos) << gone->body;
}

}  // namespace test_batch_jobs
}  // namespace slosh
