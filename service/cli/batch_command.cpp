#include "cli/batch_command.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "cli/cli_commands.hpp"
#include "cli/http_client.hpp"
#include "cli/io.hpp"
#include "engine/plan_engine.hpp"
#include "engine/worker_pool.hpp"
#include "jobs/batch_job_record.hpp"
#include "jobs/plan_table.hpp"
#include "jobs/recipe_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/recipe_row.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

namespace {

using nlohmann::json;

/// Timeout of one POST /v1/plans/batch chunk in server mode.
constexpr std::chrono::seconds kServerTimeout{600};
/// 503 answers retried per chunk before giving up.
constexpr int kServerRetries = 30;
/// How often the progress bar is refreshed while waiting for a solve.
constexpr std::chrono::milliseconds kPollInterval{100};

/// Stops the run (server unreachable, output not writable): exit kExitFailure.
struct BatchAbort : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The service did not answer a call at all (refused, timed out), as opposed to answering an
/// error: a started job's poll waits and asks again rather than stopping the run.
struct ServiceUnreachable : BatchAbort {
  using BatchAbort::BatchAbort;
};

/// Writes rows in input order and keeps the counts of the summary.
class RowSink {
 public:
  RowSink(PlanTableWriter& writer, std::optional<api::PlanView> view)
      : writer_(writer), view_(view) {}
  void write(const RecipeRow& recipe, const BatchResult& result) {
    write_row(plan_row(recipe, result, view_));
  }
  /// Writes a row made elsewhere (a batch job's, from the service).
  void write_row(const json& row) {
    const std::string status = row["status"].get<std::string>();
    ++statuses_[status];
    if (status == "error") failed_rows_.push_back(row["row"].get<std::size_t>());
    if (row.value("cached", false)) ++cached_;
    ++written_;
    writer_.write(row);
  }
  [[nodiscard]] std::size_t written() const { return written_; }
  [[nodiscard]] std::size_t cached() const { return cached_; }
  [[nodiscard]] const std::vector<std::size_t>& failed_rows() const { return failed_rows_; }
  [[nodiscard]] const std::map<std::string, std::size_t>& statuses() const { return statuses_; }

 private:
  PlanTableWriter& writer_;
  std::optional<api::PlanView> view_;
  std::size_t written_{0};
  std::size_t cached_{0};
  std::vector<std::size_t> failed_rows_;
  std::map<std::string, std::size_t> statuses_;
};

// The recipe table and where its plans go; an exit code after a message when they are unusable.
struct BatchInput {
  std::string text;  // the table as read (sent to the service's batch jobs)
  TableFormat in_format{};
  std::vector<RecipeRow> rows;
  TableFormat out_format{};
  std::optional<api::PlanView> view;  // of the plan added to each JSON row (--full, --view)
  std::unique_ptr<HttpClient> client;
};

BatchResult row_error_result(const RecipeRow& row) {
  BatchResult r;
  r.error = api::error_from_json(row.error);
  return r;
}

void run_local(const std::vector<RecipeRow>& rows, ServerConfig config, RowSink& sink,
               ProgressBar& bar) {
  std::vector<json> requests;
  std::vector<std::size_t> slot(rows.size(), static_cast<std::size_t>(-1));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].error.is_null()) continue;
    slot[i] = requests.size();
    requests.push_back(rows[i].request);
  }
  const std::size_t unreadable = rows.size() - requests.size();
  // Room for the whole table: submission never blocks, so rows are written as they finish.
  config.queue = std::max<std::size_t>(1, requests.size());
  PlanEngine engine(config);
  if (const std::string e = engine.cache().storage_error(); !e.empty()) {
    std::cerr << "slosh batch: warning: " << e << '\n';
  }
  const PendingBatch batch =
      engine.start_batch(api::read_batch_items(requests, engine.config().solve_budget_s));
  // Counting finished solves polls every item: only when the bar is due for a redraw.
  auto refresh = [&] {
    if (bar.due()) bar.update(unreadable + batch.finished());
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (slot[i] == static_cast<std::size_t>(-1)) {
      sink.write(rows[i], row_error_result(rows[i]));
      continue;
    }
    while (!batch.wait_for(slot[i], kPollInterval)) refresh();
    sink.write(rows[i], batch.get(slot[i]));
    refresh();
  }
}

/// Set by SIGINT while an InterruptFlag lives (server mode); never cleared, so that a Ctrl-C at
/// any moment after the handler is in place is seen.
volatile std::sig_atomic_t interrupted = 0;
extern "C" void on_interrupt(int) {
  interrupted = 1;
}

/// SIGINT (Ctrl-C) sets `interrupted` while this lives; the previous action comes back after.
/// Installed first thing in server mode, before the table is read: an interrupt from then on
/// can only stop the run in an orderly way (a job the service accepted is cancelled).
class InterruptFlag {
 public:
  InterruptFlag() {
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a blocking HTTP call finishes; the flag is looked at after
    ::sigaction(SIGINT, &action, &previous_);
  }
  ~InterruptFlag() { ::sigaction(SIGINT, &previous_, nullptr); }
  InterruptFlag(const InterruptFlag&) = delete;
  InterruptFlag& operator=(const InterruptFlag&) = delete;

 private:
  struct sigaction previous_ {};
};

// Makes a call (`call`: one request to `path`), retrying 503 answers after their Retry-After
// (1 to 30 s, 1 s without one) kServerRetries times; the last answer. The waits are sliced so
// that Ctrl-C ends them at once: the 503 is then returned. BatchAbort when the service cannot be
// reached.
HttpReply retrying_503(const std::function<HttpReply()>& call) {
  for (int attempt = 0;; ++attempt) {
    HttpReply reply;
    try {
      reply = call();
    } catch (const HttpError& e) {
      throw ServiceUnreachable(e.what());
    }
    if (reply.status != 503 || attempt >= kServerRetries || interrupted) return reply;
    const int wait =
        reply.retry_after.empty() ? 1 : std::clamp(std::atoi(reply.retry_after.c_str()), 1, 30);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(wait);
    while (!interrupted && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (interrupted) return reply;
  }
}

// POSTs `body` to `path`, retrying 503 answers; nothing is posted after an interrupt.
HttpReply post_retrying_503(HttpClient& client, const std::string& path, const std::string& body) {
  if (interrupted) throw BatchAbort("interrupted before " + path + " accepted the table");
  HttpReply reply = retrying_503([&] { return client.post_json(path, body); });
  if (reply.status == 503 && interrupted) {
    // Say why it had not been accepted (e.g. the replicas' Redis is down) and that nothing runs.
    std::string why = "HTTP 503";
    if (const std::string m = api::envelope_message(reply.body); !m.empty()) why += ": " + m;
    throw BatchAbort("interrupted before " + path + " accepted the table (it answered " + why +
                     "); nothing was started on the service");
  }
  return reply;
}

// POSTs one chunk, retrying 503 answers after their Retry-After.
std::vector<api::BatchItemReply> post_chunk(HttpClient& client,
                                            const std::vector<nlohmann::json>& requests) {
  const HttpReply reply =
      post_retrying_503(client, "/v1/plans/batch", api::batch_body_text(requests));
  auto results = reply.status == 200 ? api::parse_batch_reply(reply.body) : std::nullopt;
  if (!results) {
    std::string message = "HTTP " + std::to_string(reply.status);
    if (const std::string m = api::envelope_message(reply.body); !m.empty()) {
      message += ": " + m;
    }
    throw BatchAbort(client.base_url() + "/v1/plans/batch answered " + message);
  }
  return std::move(*results);
}

void run_remote(const std::vector<RecipeRow>& rows, const BatchCommandOptions& options,
                HttpClient& client, RowSink& sink, ProgressBar& bar) {
  for (std::size_t begin = 0; begin < rows.size(); begin += options.chunk) {
    const std::size_t end = std::min(rows.size(), begin + options.chunk);
    std::vector<nlohmann::json> requests;
    std::vector<std::size_t> sent;
    for (std::size_t i = begin; i < end; ++i) {
      if (rows[i].error.is_null()) {
        requests.push_back(rows[i].request);
        sent.push_back(i);
      }
    }
    const std::vector<api::BatchItemReply> results =
        requests.empty() ? std::vector<api::BatchItemReply>{} : post_chunk(client, requests);
    if (results.size() != sent.size()) {
      throw BatchAbort("the service answered " + std::to_string(results.size()) + " results for " +
                       std::to_string(sent.size()) + " requests");
    }
    std::size_t next = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (next < sent.size() && sent[next] == i) {
        const api::BatchItemReply& item = results[next++];
        BatchResult result;
        result.plan = item.plan;
        result.cached = item.cached;
        result.error = item.error;
        sink.write(rows[i], result);
      } else {
        sink.write(rows[i], row_error_result(rows[i]));
      }
    }
    bar.update(sink.written());
  }
}

// ---- server mode through a batch job (POST /v1/batches) --------------------------------------

/// Deadline of each call about a started batch job (progress, cancel); the results download
/// gets kServerTimeout again.
constexpr std::chrono::seconds kJobCallTimeout{10};
/// How often a batch job's progress is asked for.
constexpr std::chrono::milliseconds kJobPollInterval{200};
/// How long the progress polls of a started job go on while the service does not answer at all
/// (the replica that runs it is paused, restarting, or the network is down) before the run
/// stops: a paused replica carries on with the job when it runs again, so the CLI waits for it
/// (the waits between polls back off from kJobPollInterval to kJobPollBackoffMax). Twice the
/// default batch_job_stale_s (30 s), past which the other replicas call such a job failed.
constexpr std::chrono::seconds kJobUnreachableLimit{60};
constexpr std::chrono::milliseconds kJobPollBackoffMax{5000};

std::string reply_problem(const HttpClient& client, const std::string& path,
                          const HttpReply& reply) {
  std::string message = client.base_url() + path + " answered HTTP " + std::to_string(reply.status);
  if (const std::string m = api::envelope_message(reply.body); !m.empty()) message += ": " + m;
  return message;
}

/// A started batch job: DELETEd (cancelled) unless released, when the run stops on an error or
/// an interrupt.
class RemoteJob {
 public:
  RemoteJob(HttpClient& client, std::string id) : client_(client), id_(std::move(id)) {}
  ~RemoteJob() {
    if (id_.empty()) return;
    try {
      (void)client_.del(path());
    } catch (const HttpError&) {  // the service is gone: nothing to cancel
    }
  }
  RemoteJob(const RemoteJob&) = delete;
  RemoteJob& operator=(const RemoteJob&) = delete;
  [[nodiscard]] std::string path() const { return "/v1/batches/" + id_; }
  [[nodiscard]] const std::string& id() const { return id_; }
  void release() { id_.clear(); }

 private:
  HttpClient& client_;
  std::string id_;
};

// GETs `path`, retrying 503 answers (the shared job store of the replicas cannot answer now).
HttpReply get_retrying_503(HttpClient& client, const std::string& path) {
  return retrying_503([&] { return client.get(path); });
}

// The job's record (its first result row at most); BatchAbort unless the service answers it.
json job_record_of(HttpClient& client, const RemoteJob& job) {
  const HttpReply reply = get_retrying_503(client, job.path() + "?limit=1");
  if (reply.status == 502 || reply.status == 504) {
    // A proxy in front of the replicas that could not reach the one it asked: no answer either.
    throw ServiceUnreachable(reply_problem(client, job.path(), reply));
  }
  if (reply.status != 200) throw BatchAbort(reply_problem(client, job.path(), reply));
  try {
    json record = json::parse(reply.body);
    (void)record.at("state").get<std::string>();
    (void)record.at("progress").at("done").get<std::size_t>();
    return record;
  } catch (const json::exception&) {
    throw BatchAbort(client.base_url() + job.path() + " answered something that is not a job");
  }
}

/// Thrown by wait_for_job on Ctrl-C: the job is stopped and its finished rows saved by the caller.
struct BatchInterrupted : BatchAbort {
  using BatchAbort::BatchAbort;
};

/// Thrown by wait_for_job when the service stopped answering for kJobUnreachableLimit: the job
/// is left alone (it may still finish; a DELETE could not reach it anyway).
struct JobUnreachable : BatchAbort {
  using BatchAbort::BatchAbort;
};

// An HttpError's text without its closing hint (": is `slosh serve` running there?"), which
// misleads once the service has accepted the job: it ran, and stopped answering.
std::string without_hint(const std::string& text) {
  const std::size_t hint = text.find(": is `slosh serve` running there?");
  return hint == std::string::npos ? text : text.substr(0, hint);
}

// Sleeps `wait` in slices, so that Ctrl-C ends it at once.
void sleep_unless_interrupted(std::chrono::milliseconds wait) {
  const auto until = std::chrono::steady_clock::now() + wait;
  while (!interrupted && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// Polls the job until it has finished, drawing its progress; BatchAbort unless it is done,
// BatchInterrupted on Ctrl-C, JobUnreachable when the service has not answered at all for
// kJobUnreachableLimit (polls that get no answer are repeated with backoff until then).
void wait_for_job(HttpClient& client, const RemoteJob& job, ProgressBar& bar) {
  std::optional<std::chrono::steady_clock::time_point> silent_since;
  std::chrono::milliseconds backoff = kJobPollInterval;
  for (;;) {
    if (interrupted) throw BatchInterrupted("interrupted");
    json record;
    try {
      record = job_record_of(client, job);
    } catch (const ServiceUnreachable& e) {
      const auto now = std::chrono::steady_clock::now();
      if (!silent_since) silent_since = now;
      const auto silent = std::chrono::duration_cast<std::chrono::seconds>(now - *silent_since);
      if (silent >= kJobUnreachableLimit) {
        throw JobUnreachable("batch job " + job.id() + ": the replica that runs it stopped " +
                             "answering (no answer for " + std::to_string(silent.count()) +
                             " s; last: " + without_hint(e.what()) +
                             "); the job was not cancelled and may still finish: read it with "
                             "GET " +
                             client.base_url() + job.path());
      }
      sleep_unless_interrupted(backoff);
      backoff = std::min(backoff * 2, kJobPollBackoffMax);
      continue;
    } catch (const BatchInterrupted&) {
      throw;
    } catch (const BatchAbort& e) {
      // Ctrl-C ends the wait of a 503's Retry-After, which then answers the 503 (e.g. the
      // replicas' Redis is down): still an interrupt, so that the job is cancelled if it can be.
      if (interrupted) throw BatchInterrupted(e.what());
      throw;
    }
    silent_since.reset();
    backoff = kJobPollInterval;
    bar.update(record["progress"]["done"].get<std::size_t>());
    const std::string state = record["state"].get<std::string>();
    if (state == "done") return;
    if (state == "cancelled" || state == "failed") {
      throw BatchAbort("batch job " + job.id() + " " + state + ": " +
                       record.value("message", std::string()));
    }
    std::this_thread::sleep_for(kJobPollInterval);
  }
}

// After a stop (Ctrl-C, a failed job): cancels the job unless it has finished, waits a bounded
// time for it to end and writes the rows it finished to `sink`, so that the .partial table holds
// what the service did. Returns what happened, for the message: "cancelled", "had finished" or
// "could not be cancelled (why); it may still run: ..." (the service did not answer, or refused,
// e.g. 503 while the replicas' Redis is down). Any failure leaves the rows written so far.
std::string save_finished_rows(HttpClient& client, const RemoteJob& job, RowSink& sink) {
  const auto not_cancelled = [&](const std::string& why) {
    return "could not be cancelled (" + why + "); it may still run: DELETE " + client.base_url() +
           job.path() + " once the service answers";
  };
  std::string outcome = not_cancelled("no answer");
  try {
    // A job that finished before the stop is not cancelled: a DELETE would forget its rows.
    json record = job_record_of(client, job);
    if (!is_final_state(record["state"].get<std::string>())) {
      const HttpReply deleted = client.del(job.path());
      if (deleted.status != 200 && deleted.status != 202) {
        return not_cancelled(reply_problem(client, job.path(), deleted));
      }
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!is_final_state(record["state"].get<std::string>())) {
      if (std::chrono::steady_clock::now() >= deadline) {
        return not_cancelled("it had not stopped 10 s after its DELETE was accepted");
      }
      std::this_thread::sleep_for(kJobPollInterval);
      record = job_record_of(client, job);
    }
    // A job that finished all its rows before the cancel reached it reads done: it had finished.
    outcome = record["state"] == "done" ? "had finished" : record["state"].get<std::string>();
    const HttpReply rows = client.get(job.path() + "/results.jsonl");
    if (rows.status != 200) return outcome;
    std::istringstream lines(rows.body);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) sink.write_row(json::parse(line));
    }
  } catch (const std::exception& e) {
    if (outcome.rfind("could not be cancelled", 0) == 0)
      outcome = not_cancelled(without_hint(e.what()));
  }
  return outcome;
}

// Runs the table as a batch job of the service: POSTs the table's text (the service reads it as
// this command does), polls the progress, downloads the rows (JSON lines) and writes them in the
// output format. False when the service has no batch jobs (404, 405) or the table is larger
// than its body limit (413): the caller falls back to POST /v1/plans/batch in chunks.
bool run_job_remote(const BatchInput& in, const BatchCommandOptions& options, HttpClient& client,
                    RowSink& sink, ProgressBar& bar) {
  json body{{"table", in.text}, {"table_format", to_string(in.in_format)}, {"format", "jsonl"}};
  if (in.view) body["view"] = options.full ? std::string("full") : *options.view;
  // Ctrl-C only sets `interrupted` (the handler is installed before the table is read): a job
  // the POST creates is then DELETEd as soon as its id is known.
  const auto posting = std::chrono::steady_clock::now();
  const HttpReply posted = post_retrying_503(client, "/v1/batches", api::dump_json(body));
  if (posted.status == 404 || posted.status == 405 || posted.status == 413) {
    if (posted.status == 413) {
      std::cerr << "slosh batch: the table is larger than the service's body limit: sending it in "
                   "chunks of "
                << options.chunk << " to /v1/plans/batch\n";
    }
    return false;
  }
  if (posted.status == 503) {
    // Still refused after every retry (e.g. the replicas' shared Redis is down: a job is only
    // accepted once every replica can find it). Nothing was started on the service.
    const auto waited =
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - posting)
            .count();
    throw BatchAbort(reply_problem(client, "/v1/batches", posted) + " (still 503 after " +
                     std::to_string(kServerRetries + 1) + " tries over " + std::to_string(waited) +
                     " s, each after its Retry-After; no job was started)");
  }
  if (posted.status != 202) throw BatchAbort(reply_problem(client, "/v1/batches", posted));
  // A job's calls are short (a record, a cancel): a service that does not answer within this
  // (a paused replica) stops the run instead of holding it, and Ctrl-C, for as long.
  client.set_timeout(kJobCallTimeout);
  RemoteJob job(client, json::parse(posted.body)["id"].get<std::string>());
  try {
    wait_for_job(client, job, bar);
  } catch (const JobUnreachable&) {
    job.release();  // not cancelled: the replica may be paused, and carries on with it
    throw;
  } catch (const BatchInterrupted&) {
    const std::string outcome = save_finished_rows(client, job, sink);
    const std::string id = job.id();
    if (outcome == "had finished") job.release();  // its rows are saved: nothing to cancel
    throw BatchAbort("interrupted: batch job " + id + " " + outcome +
                     (outcome == "had finished"
                          ? " (" + std::to_string(sink.written()) + " rows written)"
                          : ""));
  } catch (const BatchAbort&) {
    (void)save_finished_rows(client, job, sink);
    throw;
  }
  // Done: nothing to cancel any more (a DELETE would forget the results).
  const std::string id = job.id();
  job.release();
  client.set_timeout(kServerTimeout);
  const HttpReply rows = get_retrying_503(client, "/v1/batches/" + id + "/results.jsonl");
  if (rows.status != 200) throw BatchAbort(reply_problem(client, "/v1/batches/" + id, rows));
  std::size_t at = 0;
  while (at < rows.body.size()) {
    const std::size_t end = rows.body.find('\n', at);
    const json row = json::parse(rows.body.substr(at, end - at));
    // Rows come in recipe order, each once: anything else is not the table of this run.
    if (row.value("row", std::size_t{0}) != sink.written() + 1) {
      throw BatchAbort("batch job " + id + " answered row " + api::dump_json(row["row"]) +
                       " where row " + std::to_string(sink.written() + 1) + " was due");
    }
    sink.write_row(row);
    at = end == std::string::npos ? rows.body.size() : end + 1;
  }
  if (sink.written() != in.rows.size()) {
    throw BatchAbort("batch job " + id + " answered " + std::to_string(sink.written()) +
                     " rows for " + std::to_string(in.rows.size()) + " recipes");
  }
  return true;
}

std::string count(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string summary(const RowSink& sink, double seconds, const std::string& out) {
  std::string text = "slosh batch: " + count(sink.written(), "recipe") + ", " +
                     std::to_string(sink.written() - sink.failed_rows().size()) + " planned (" +
                     std::to_string(sink.cached()) + " from cache";
  for (const auto& [status, n] : sink.statuses()) {
    if (status != "error") text += ", " + std::to_string(n) + " " + status;
  }
  char timing[32];
  std::snprintf(timing, sizeof timing, ", %.1f s", seconds);
  text += "), " + count(sink.failed_rows().size(), "error") + timing;
  if (out != "-") text += " -> " + out;
  return text;
}

std::string failed_rows_text(const std::vector<std::size_t>& rows) {
  std::string text;
  for (std::size_t k = 0; k < rows.size() && k < 20; ++k) {
    text += (k == 0 ? "" : ", ") + std::to_string(rows[k]);
  }
  if (rows.size() > 20) text += ", ...";
  return text;
}

// ---- min_time mode ---------------------------------------------------------------------------

/// An RFC 4180 cell: text quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (!v.is_string()) return api::dump_json(v);
  const std::string text = v.get<std::string>();
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// The min_time table's columns (CSV header and JSON members, in order).
std::vector<std::string> min_time_columns() {
  std::vector<std::string> c{"row", "recipe_id", "status", "key"};
  for (Strategy s : api::default_min_time_strategies()) c.push_back("t_min_" + to_string(s) + "_s");
  for (const char* name : {"winner", "winner_t_min_s", "baseline_t_min_s", "gain_pct",
                           "gain_cycles_per_min", "message", "error_field"}) {
    c.emplace_back(name);
  }
  return c;
}

/// Writes the min_time rows in the table format.
class MinTimeWriter {
 public:
  MinTimeWriter(std::ostream& out, TableFormat format) : out_(out), format_(format) {
    if (format_ == TableFormat::kCsv) {
      std::string header;
      for (const std::string& c : min_time_columns()) header += (header.empty() ? "" : ",") + c;
      out_ << header << '\n';
    } else if (format_ == TableFormat::kJson) {
      out_ << '[';
    }
  }
  void write(const json& row) {
    if (format_ == TableFormat::kCsv) {
      std::string line;
      bool first = true;
      for (const std::string& c : min_time_columns()) {
        line += (first ? "" : ",") + csv_cell(row.value(c, json(nullptr)));
        first = false;
      }
      out_ << line << '\n';
    } else if (format_ == TableFormat::kJson) {
      out_ << (rows_ == 0 ? "\n" : ",\n") << api::dump_json(row);
    } else {
      out_ << api::dump_json(row) << '\n';
    }
    ++rows_;
    out_.flush();
  }
  void finish() {
    if (format_ == TableFormat::kJson) out_ << (rows_ == 0 ? "]\n" : "\n]\n");
    out_.flush();
  }

 private:
  std::ostream& out_;
  TableFormat format_;
  std::size_t rows_{0};
};

json min_time_error_row(const RecipeRow& recipe, const api::ApiError& e) {
  json row{{"row", recipe.row}, {"recipe_id", recipe.recipe_id}, {"status", "error"}};
  std::string field = e.field();
  std::string message = e.what();
  if (recipe.csv) {  // name the CSV column, as plan tables do
    constexpr std::string_view kMax = "motion_time_max_s";  // the motion_time_s column's value
    if (field == kMax) {
      if (message.rfind(kMax, 0) == 0) message.replace(0, kMax.size(), "motion_time_s");
      field = "motion_time_s";
    } else {
      message = api::in_column_terms(field, message);
      field = api::column_of_field(field);
    }
  }
  row["message"] = message;
  row["error_field"] = field.empty() ? json(nullptr) : json(field);
  return row;
}

/// A min-time row on its way: its answer from the cache or a search, or the row's error.
struct MinTimeJob {
  std::optional<api::ApiError> error;
  PendingMinTime pending;
};

// Parses a row's min-time request and starts it on `engine`: from the plan store, joined to the
// search of an identical earlier row, or queued (waiting for queue room).
MinTimeJob start_min_time_row(const RecipeRow& row, double budget, PlanEngine& engine) {
  MinTimeJob job;
  if (!row.error.is_null()) {
    job.error = api::error_from_json(row.error);
    return job;
  }
  try {
    job.pending = engine.start_min_time(
        api::parse_min_time_request(api::min_time_body_from_recipe(row.request), budget), true);
  } catch (const api::ApiError& e) {
    job.error = e;
  }
  return job;
}

// Writes the row of an answer (a stored or replied min-time response) or of its error; false for
// an error row.
bool write_min_time_row(const RecipeRow& recipe, const SolveOutcome& outcome,
                        MinTimeWriter& writer) {
  if (outcome.error) {
    writer.write(min_time_error_row(recipe, *outcome.error));
    return false;
  }
  json row{{"row", recipe.row}, {"recipe_id", recipe.recipe_id}, {"status", "ok"}};
  row.update(api::min_time_row_figures(outcome.body));
  writer.write(row);
  return true;
}

// Searches every row on a local PlanEngine (the cache file of `config`, `config.workers`, one
// task per row and strategy) and writes the rows in input order; the 1-based numbers of the rows
// in error.
std::vector<std::size_t> run_min_time_local(const std::vector<RecipeRow>& rows, ServerConfig config,
                                            MinTimeWriter& writer) {
  config.queue = 1024;
  PlanEngine engine(config);
  if (const std::string e = engine.min_time_cache().storage_error(); !e.empty()) {
    std::cerr << "slosh batch: warning: " << e << '\n';
  }
  std::vector<MinTimeJob> jobs;
  jobs.reserve(rows.size());
  for (const RecipeRow& row : rows) {
    jobs.push_back(start_min_time_row(row, config.solve_budget_s, engine));
  }
  std::vector<std::size_t> failed;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const MinTimeJob& job = jobs[i];
    const SolveOutcome outcome = job.error            ? SolveOutcome{{}, job.error}
                                 : job.pending.cached ? SolveOutcome{*job.pending.cached, {}}
                                                      : job.pending.search.get();
    if (!write_min_time_row(rows[i], outcome, writer)) failed.push_back(rows[i].row);
  }
  return failed;
}

// POSTs one row's min-time request, retrying 503 answers after their Retry-After: the answer, or
// the error the service answered; BatchAbort when it answered no envelope.
SolveOutcome post_min_time_row(HttpClient& client, const std::string& body) {
  HttpReply reply = post_retrying_503(client, "/v1/min-time", body);
  if (reply.status == 200) return SolveOutcome{std::move(reply.body), std::nullopt};
  if (api::envelope_message(reply.body).empty()) {
    throw BatchAbort(client.base_url() + "/v1/min-time answered HTTP " +
                     std::to_string(reply.status));
  }
  return SolveOutcome{{}, api::error_from_text(reply.body)};
}

// POSTs every readable row to the service's /v1/min-time, one after the other (each request's
// strategies run in parallel on the service's pool), and writes the rows as they return.
std::vector<std::size_t> run_min_time_remote(const std::vector<RecipeRow>& rows, HttpClient& client,
                                             MinTimeWriter& writer) {
  std::vector<std::size_t> failed;
  for (const RecipeRow& row : rows) {
    const SolveOutcome outcome =
        row.error.is_null()
            ? post_min_time_row(client, api::dump_json(api::min_time_body_from_recipe(row.request)))
            : SolveOutcome{{}, api::error_from_json(row.error)};
    try {
      if (!write_min_time_row(row, outcome, writer)) failed.push_back(row.row);
    } catch (const std::invalid_argument& e) {
      throw BatchAbort(client.base_url() + "/v1/min-time: " + e.what());
    }
  }
  return failed;
}

}  // namespace

namespace {

// The view of the plan each JSON row carries: --view, or full with --full (both: the same view);
// nullopt for none. Throws TableError for an unknown view or two different ones.
std::optional<api::PlanView> row_plan_view(const BatchCommandOptions& options) {
  std::optional<api::PlanView> view;
  if (options.view) {
    try {
      view = api::parse_plan_view(*options.view);
    } catch (const api::ApiError& e) {
      throw TableError(std::string("--") + e.what());
    }
  }
  if (options.full && view && *view != api::PlanView::kFull) {
    throw TableError("--full adds the whole plan but --view " + *options.view +
                     " the compact one: give one of them");
  }
  return options.full ? std::optional(api::PlanView::kFull) : view;
}

std::optional<int> read_batch_input(const BatchCommandOptions& options, BatchInput& in) {
  try {
    // Refused before anything is posted: a directory as --out would only fail once the job is
    // done, when the table is renamed into place.
    for (const auto& [flag, path] : {std::pair{"--in", &options.in}, {"--out", &options.out}}) {
      std::error_code ec;
      if (*path != "-" && std::filesystem::is_directory(*path, ec)) {
        throw TableError(std::string(flag) + " '" + *path +
                         "' is a directory: give the path of a table file" +
                         (std::string(flag) == "--in" ? "" : " to write") + " (or - for " +
                         (std::string(flag) == "--in" ? "stdin" : "stdout") + ")");
      }
    }
    in.in_format = table_format(options.in_format, options.in);
    in.out_format = table_format(options.out_format, options.out);
    try {
      in.text = read_request_text(options.in);
    } catch (const std::exception&) {
      throw TableError("cannot read the recipe table '" + options.in + "'");
    }
    in.rows = read_recipe_table(in.text, in.in_format);
    in.view = row_plan_view(options);
    if (in.view && in.out_format == TableFormat::kCsv) {
      throw TableError(
          std::string(options.full ? "--full adds the whole plan" : "--view adds the plan") +
          " to JSON rows: use a .json or .jsonl output");
    }
    if (!options.server.empty() && options.chunk == 0) {
      throw TableError("--chunk must be at least 1");
    }
    if (!options.server.empty()) {
      in.client = std::make_unique<HttpClient>(options.server, kServerTimeout);  // checks the URL
    }
  } catch (const std::exception& e) {
    std::cerr << "slosh batch: " << e.what() << '\n';
    return kExitInvalidInput;
  }
  if (options.mode == "min_time" && in.view) {
    std::cerr << "slosh batch: " << (options.full ? "--full" : "--view")
              << " is for plan tables, not --mode min_time\n";
    return kExitInvalidInput;
  }
  return std::nullopt;
}

// The output table: written to <out>.partial and renamed when complete (stdout for "-").
class BatchOutput {
 public:
  explicit BatchOutput(const std::string& out) : out_(out), partial_(out + ".partial") {
    if (to_stdout()) return;
    errno = 0;
    file_.open(partial_, std::ios::binary | std::ios::trunc);
    if (!file_) open_error_ = errno != 0 ? std::strerror(errno) : "it cannot be opened";
  }
  [[nodiscard]] bool to_stdout() const { return out_ == "-"; }
  [[nodiscard]] bool opened() const { return to_stdout() || static_cast<bool>(file_); }
  /// Why the partial file could not be created (the OS's reason), when !opened().
  [[nodiscard]] const std::string& open_error() const { return open_error_; }
  [[nodiscard]] const std::string& out() const { return out_; }
  [[nodiscard]] const std::string& partial() const { return partial_; }
  std::ostream& stream() { return to_stdout() ? std::cout : file_; }
  /// Closes and renames the partial file; false (after a message) when it cannot.
  bool commit() {
    if (to_stdout()) return true;
    file_.close();
    if (!file_ || std::rename(partial_.c_str(), out_.c_str()) != 0) {
      std::cerr << "slosh batch: cannot write '" << out_ << "' (the table is in " << partial_
                << ")\n";
      return false;
    }
    return true;
  }

 private:
  std::string out_;
  std::string partial_;
  std::ofstream file_;
  std::string open_error_;
};

int run_min_time_mode(const BatchCommandOptions& options, BatchInput& in, BatchOutput& output) {
  std::vector<std::size_t> failed;
  try {
    MinTimeWriter writer(output.stream(), in.out_format);
    failed = in.client ? run_min_time_remote(in.rows, *in.client, writer)
                       : run_min_time_local(in.rows, options.config, writer);
    writer.finish();
  } catch (const std::exception& e) {
    std::cerr << "slosh batch: stopped: " << e.what() << '\n';
    return interrupted ? kExitInterrupted : kExitFailure;
  }
  if (!output.commit()) return kExitFailure;
  if (!failed.empty()) {
    std::cerr << "slosh batch: " << (failed.size() == 1 ? "row " : "rows ")
              << failed_rows_text(failed) << " could not be searched: see the message of the row\n";
    return kExitSomeRowsFailed;
  }
  return kExitOk;
}

int run_plan_mode(const BatchCommandOptions& options, BatchInput& in, BatchOutput& output,
                  std::chrono::steady_clock::time_point started) {
  PlanTableWriter writer(output.stream(), in.out_format);
  RowSink sink(writer, in.view);
  const bool draw = progress_enabled(options.progress);
  ProgressBar bar(std::cerr, in.rows.size(), draw);
  bar.update(0);
  try {
    if (options.server.empty()) {
      run_local(in.rows, options.config, sink, bar);
    } else if (!run_job_remote(in, options, *in.client, sink, bar)) {
      run_remote(in.rows, options, *in.client, sink, bar);
    }
    writer.finish();
  } catch (const std::exception& e) {
    bar.stop(sink.written());
    std::cerr << "slosh batch: stopped after " << sink.written() << " of " << in.rows.size()
              << " recipes: " << e.what() << '\n';
    if (!output.to_stdout()) {
      std::cerr << "slosh batch: the rows written so far are in " << output.partial();
      if (sink.written() == 0) {
        std::cerr << (in.out_format == TableFormat::kCsv ? " (none: it holds the header only)"
                                                         : " (none: it is empty)");
      }
      std::cerr << '\n';
    }
    return interrupted ? kExitInterrupted : kExitFailure;
  }
  bar.finish();
  if (!output.commit()) return kExitFailure;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (draw || !sink.failed_rows().empty()) std::cerr << summary(sink, seconds, options.out) << '\n';
  if (!sink.failed_rows().empty()) {
    std::cerr << "slosh batch: " << (sink.failed_rows().size() == 1 ? "row " : "rows ")
              << failed_rows_text(sink.failed_rows())
              << " could not be planned: see the message of the row\n";
    return kExitSomeRowsFailed;
  }
  return kExitOk;
}

}  // namespace

int run_batch_command(const BatchCommandOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::optional<InterruptFlag> interrupt;
  if (!options.server.empty()) interrupt.emplace();
  BatchInput in;
  if (auto exit_code = read_batch_input(options, in)) return *exit_code;
  // Before any plan is solved or posted: a table that cannot be written is not computed.
  BatchOutput output(options.out);
  if (!output.opened()) {
    std::cerr << "slosh batch: cannot write the output table '" << output.out() << "': creating '"
              << output.partial()
              << "' (where it is written before it is renamed) failed: " << output.open_error()
              << "; nothing was planned\n";
    return kExitFailure;
  }
  return options.mode == "min_time" ? run_min_time_mode(options, in, output)
                                    : run_plan_mode(options, in, output, started);
}

}  // namespace slosh::service
