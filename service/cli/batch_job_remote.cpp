#include "cli/batch_job_remote.hpp"

#include <chrono>
#include <iostream>
#include <optional>
#include <string>
#include <thread>

#include "cli/batch_errors.hpp"
#include "cli/batch_interrupt.hpp"
#include "cli/batch_job_calls.hpp"
#include "cli/batch_job_cancel.hpp"
#include "cli/batch_retry.hpp"
#include "slosh/api/batch_job_reply.hpp"

namespace slosh::service::batch_cli {

namespace {

/// Deadline of each progress poll of a started batch job: Ctrl-C waits for a poll in flight at
/// most this long before the stop begins (the results download gets kServerTimeout again).
constexpr std::chrono::seconds kJobCallTimeout{3};
/// How often a batch job's progress is asked for.
constexpr std::chrono::milliseconds kJobPollInterval{200};
/// The waits between the polls of a job whose service does not answer back off from
/// kJobPollInterval to this.
constexpr std::chrono::milliseconds kJobPollBackoffMax{5000};

// The answers of the results download that mean "not now": 409 from a replica that does not see
// yet that the job has finished (its owner's final record reaches the shared store a moment
// later), 503 from one that cannot reach that store, 502 and 504 from a proxy that could not
// reach the replica it asked. Retried as 503s are (retrying_transient).
constexpr std::initializer_list<int> kResultsNotYet{409, 503, 502, 504};

// The job's record, BatchInterrupted when Ctrl-C ended the wait of a 503's Retry-After (e.g. the
// replicas' Redis is down): still an interrupt, so that the job is cancelled if it can be.
api::JobProgress poll_job(HttpClient& client, const RemoteJob& job) {
  try {
    return read_job_progress(client, job);
  } catch (const ServiceUnreachable&) {
    throw;
  } catch (const BatchAbort& e) {
    if (interrupt_requested()) throw BatchInterrupted(e.what());
    throw;
  }
}

// Polls the job until it has finished, drawing its progress; BatchAbort unless it is done,
// BatchInterrupted on Ctrl-C, JobUnreachable when the service has not answered at all for
// `unreachable_limit` (polls that get no answer are repeated with backoff until then).
void wait_for_job(HttpClient& client, const RemoteJob& job, ProgressBar& bar,
                  std::chrono::seconds unreachable_limit) {
  std::optional<std::chrono::steady_clock::time_point> silent_since;
  std::chrono::milliseconds backoff = kJobPollInterval;
  for (;;) {
    if (interrupt_requested()) throw BatchInterrupted("interrupted");
    api::JobProgress progress;
    try {
      progress = poll_job(client, job);
    } catch (const ServiceUnreachable& e) {
      const auto now = std::chrono::steady_clock::now();
      if (!silent_since) silent_since = now;
      const auto silent = std::chrono::duration_cast<std::chrono::seconds>(now - *silent_since);
      if (silent >= unreachable_limit) {
        throw JobUnreachable("batch job " + job.id() + ": the replica that runs it stopped " +
                             "answering (no answer for " + std::to_string(silent.count()) +
                             " s; last: " + without_hint(e.what()) +
                             "); the job was not cancelled and may still finish: read it with "
                             "GET " +
                             job.url());
      }
      sleep_unless_interrupted(backoff);
      backoff = std::min(backoff * 2, kJobPollBackoffMax);
      continue;
    }
    silent_since.reset();
    backoff = kJobPollInterval;
    bar.update(progress.done);
    if (progress.state == api::JobState::kDone) return;
    if (progress.state == api::JobState::kCancelled || progress.state == api::JobState::kFailed) {
      throw BatchAbort("batch job " + job.id() + " " + std::string(api::to_string(progress.state)) +
                       ": " + progress.message);
    }
    std::this_thread::sleep_for(kJobPollInterval);
  }
}

// POSTs the table's text as a batch job (the service reads it as this command does): the job's
// id, or nullopt when the service has no batch jobs (404, 405) or the table is larger than its
// body limit (413). BatchAbort when the service refuses it otherwise.
std::optional<std::string> post_job(const BatchInput& in, const BatchCommandOptions& options,
                                    HttpClient& client) {
  std::optional<std::string> view;
  if (in.view) view = options.full ? std::string("full") : *options.view;
  // Ctrl-C only sets `interrupted` (the handler is installed before the table is read): a job
  // the POST creates is then DELETEd as soon as its id is known.
  const auto posting = std::chrono::steady_clock::now();
  const HttpReply posted = post_retrying_503(
      client, "/v1/batches", api::job_body_text(in.text, to_string(in.in_format), view));
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
                     std::to_string(client.retries() + 1) + " tries over " +
                     std::to_string(waited) +
                     " s, each after its Retry-After; no job was started)");
  }
  if (posted.status != 202) throw BatchAbort(reply_problem(client, "/v1/batches", posted));
  std::optional<std::string> id = api::parse_job_id(posted.body);
  if (!id) throw BatchAbort(client.base_url() + "/v1/batches answered a 202 without a job id");
  return id;
}

// Waits for `job` to finish, drawing its progress. On a stop: an unreachable service leaves the
// job alone; Ctrl-C or a failure cancels it and writes the rows it finished to `sink` (the
// .partial table then holds what the service did) before the BatchAbort goes on. The stop made
// every call it could: the handle is released, so that no DELETE goes out behind its message.
void follow_job(HttpClient& client, RemoteJob& job, RowSink& sink, ProgressBar& bar,
                std::chrono::seconds unreachable_limit) {
  try {
    wait_for_job(client, job, bar, unreachable_limit);
  } catch (const JobUnreachable&) {
    job.release();  // not cancelled: the replica may be paused, and carries on with it
    throw;
  } catch (const BatchInterrupted&) {
    const StopOutcome outcome = stop_job(client, job, sink);
    job.release();
    throw BatchAbort("interrupted: batch job " + job.id() + " " + outcome.text);
  } catch (const BatchAbort&) {
    (void)stop_job(client, job, sink);
    job.release();
    throw;
  }
}

// Downloads the rows of the finished job (JSON lines) into `sink`; BatchAbort unless they are
// the `recipes` rows of this run's table, in recipe order.
void download_job_rows(HttpClient& client, const RemoteJob& job, std::size_t recipes,
                       RowSink& sink) {
  const std::string path = job.path() + "/results.jsonl";
  const HttpReply reply = retrying_transient(
      client, [&] { return client.get(path); }, kResultsNotYet);
  if (reply.status != 200) throw BatchAbort(reply_problem(client, job.path(), reply));
  for (const api::PlanTableRow& row : job_rows_of(job, reply.body)) {
    // Rows come in recipe order, each once: anything else is not the table of this run.
    if (row.number != sink.written() + 1) {
      throw BatchAbort("batch job " + job.id() + " answered row " + row.number_text +
                       " where row " + std::to_string(sink.written() + 1) + " was due");
    }
    sink.write_row(row);
  }
  if (sink.written() != recipes) {
    throw BatchAbort("batch job " + job.id() + " answered " + std::to_string(sink.written()) +
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
  // A job's calls are short (a record): a service that does not answer within this (a paused
  // replica) is asked again with backoff instead of holding the run, and Ctrl-C, for as long.
  client.set_timeout(kJobCallTimeout);
  RemoteJob job(client, *id);
  follow_job(client, job, sink, bar, std::chrono::seconds(options.give_up_after_s));
  // Done: nothing to cancel any more (a DELETE would forget the results).
  job.release();
  client.set_timeout(kServerTimeout);
  download_job_rows(client, job, in.rows.size(), sink);
  return true;
}

}  // namespace slosh::service::batch_cli
