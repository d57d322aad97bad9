#include "cli/batch_job_remote.hpp"

#include <chrono>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "cli/batch_errors.hpp"
#include "cli/batch_interrupt.hpp"
#include "cli/batch_retry.hpp"
#include "jobs/batch_job_record.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service::batch_cli {

namespace {

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

// An HttpError's text without its closing hint (": is `slosh serve` running there?"), which
// misleads once the service has accepted the job: it ran, and stopped answering.
std::string without_hint(const std::string& text) {
  const std::size_t hint = text.find(": is `slosh serve` running there?");
  return hint == std::string::npos ? text : text.substr(0, hint);
}

// Polls the job until it has finished, drawing its progress; BatchAbort unless it is done,
// BatchInterrupted on Ctrl-C, JobUnreachable when the service has not answered at all for
// kJobUnreachableLimit (polls that get no answer are repeated with backoff until then).
void wait_for_job(HttpClient& client, const RemoteJob& job, ProgressBar& bar) {
  std::optional<std::chrono::steady_clock::time_point> silent_since;
  std::chrono::milliseconds backoff = kJobPollInterval;
  for (;;) {
    if (interrupt_requested()) throw BatchInterrupted("interrupted");
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
      if (interrupt_requested()) throw BatchInterrupted(e.what());
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

// POSTs the table's text as a batch job (the service reads it as this command does): the job's
// id, or nullopt when the service has no batch jobs (404, 405) or the table is larger than its
// body limit (413). BatchAbort when the service refuses it otherwise.
std::optional<std::string> post_job(const BatchInput& in, const BatchCommandOptions& options,
                                    HttpClient& client) {
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
    return std::nullopt;
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
  return json::parse(posted.body)["id"].get<std::string>();
}

// Waits for `job` to finish, drawing its progress. On a stop: an unreachable service leaves the
// job alone; Ctrl-C or a failure cancels it and writes the rows it finished to `sink` (the
// .partial table then holds what the service did) before the BatchAbort goes on.
void follow_job(HttpClient& client, RemoteJob& job, RowSink& sink, ProgressBar& bar) {
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
}

// Downloads the rows of the finished job `id` (JSON lines) into `sink`; BatchAbort unless they are
// the `recipes` rows of this run's table, in recipe order.
void download_job_rows(HttpClient& client, const std::string& id, std::size_t recipes,
                       RowSink& sink) {
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
  if (sink.written() != recipes) {
    throw BatchAbort("batch job " + id + " answered " + std::to_string(sink.written()) +
                     " rows for " + std::to_string(recipes) + " recipes");
  }
}

}  // namespace

// Runs the table as a batch job of the service: POSTs the table's text (the service reads it as
// this command does), polls the progress, downloads the rows (JSON lines) and writes them in the
// output format. False when the service has no batch jobs (404, 405) or the table is larger
// than its body limit (413): the caller falls back to POST /v1/plans/batch in chunks.
bool run_job_remote(const BatchInput& in, const BatchCommandOptions& options, HttpClient& client,
                    RowSink& sink, ProgressBar& bar) {
  const std::optional<std::string> id = post_job(in, options, client);
  if (!id) return false;
  // A job's calls are short (a record, a cancel): a service that does not answer within this
  // (a paused replica) stops the run instead of holding it, and Ctrl-C, for as long.
  client.set_timeout(kJobCallTimeout);
  RemoteJob job(client, *id);
  follow_job(client, job, sink, bar);
  // Done: nothing to cancel any more (a DELETE would forget the results).
  job.release();
  client.set_timeout(kServerTimeout);
  download_job_rows(client, *id, in.rows.size(), sink);
  return true;
}

}  // namespace slosh::service::batch_cli
