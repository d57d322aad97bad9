#include "cli/batch_job_cancel.hpp"

#include <algorithm>
#include <optional>
#include <thread>

#include "cli/batch_errors.hpp"
#include "cli/batch_retry.hpp"

namespace slosh::service::batch_cli {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

/// The wait between two tries of a stop's call. Short: through a proxy the next try reaches
/// another replica, and the stop's budget bounds the tries anyway.
constexpr milliseconds kStopRetryWait{200};

// The end of a stage of the stop: each call is bounded by what is left of it.
struct Deadline {
  Clock::time_point at;
  [[nodiscard]] bool passed() const { return Clock::now() >= at; }
  void bound(HttpClient& client) const {
    const auto left = std::chrono::duration_cast<milliseconds>(at - Clock::now());
    client.set_timeout(std::clamp(left, milliseconds(100), milliseconds(kStopCallTimeout)));
  }
  void pause() const { std::this_thread::sleep_until(std::min(Clock::now() + kStopRetryWait, at)); }
};

// "Not now" answers: the replica asked cannot reach the shared store (503), or a proxy got no
// answer from the replica it asked (502, 504).
bool transient(int status) {
  return status == 503 || status == 502 || status == 504;
}

// What the service said of the job when the stop began: its record, or why it gave none, and
// whether the last try got no answer at all (a paused replica, or a proxy's 502/504).
struct Seen {
  std::optional<api::JobProgress> progress;
  std::string problem;
  bool silent{false};
};

Seen read_state(HttpClient& client, const RemoteJob& job, const Deadline& d) {
  Seen seen{std::nullopt, "no time was left to ask", false};
  while (!d.passed()) {
    d.bound(client);
    HttpReply reply;
    try {
      reply = client.get(job.path() + "?limit=1");
    } catch (const HttpError& e) {
      // Each such try costs a whole call deadline: go on to the DELETE at once.
      return Seen{std::nullopt, without_hint(e.what()), true};
    }
    if (reply.status == 200) {
      seen.progress = api::parse_job_progress(reply.body);
      if (!seen.progress) seen.problem = job.url() + " answered something that is not a job";
      return seen;
    }
    seen.problem = reply_problem(client, job.path(), reply);
    seen.silent = reply.status != 503;
    if (!transient(reply.status)) return seen;
    d.pause();
  }
  return seen;
}

// The DELETE, repeated on "not now" answers and on no answer until accepted or the deadline.
struct Cancel {
  enum class Result { kAccepted, kEnded, kRefused, kUnanswered } result{Result::kRefused};
  std::string problem;
  std::optional<api::JobProgress> ended;  // kEnded: the job as the DELETE found it (and forgot)
  bool unanswered_once{false};            // a try got no answer: the cancel may have arrived anyway
};

Cancel send_cancel(HttpClient& client, const RemoteJob& job, const Deadline& d) {
  Cancel c{Cancel::Result::kUnanswered, "no time was left to send it", std::nullopt, false};
  while (!d.passed()) {
    d.bound(client);
    HttpReply reply;
    try {
      reply = client.del(job.path());
    } catch (const HttpError& e) {
      c.problem = without_hint(e.what());
      c.unanswered_once = true;
      d.pause();
      continue;
    }
    if (reply.status == 202) return Cancel{Cancel::Result::kAccepted, "", std::nullopt, false};
    if (reply.status == 200) {
      return Cancel{Cancel::Result::kEnded, "", api::parse_job_progress(reply.body), false};
    }
    c.problem = reply_problem(client, job.path(), reply);
    if (reply.status != 503) c.unanswered_once = true;
    if (!transient(reply.status))
      return Cancel{Cancel::Result::kRefused, c.problem, std::nullopt, false};
    d.pause();
  }
  c.result = c.unanswered_once ? Cancel::Result::kUnanswered : Cancel::Result::kRefused;
  return c;
}

// Polls the record until the job has ended or the deadline: its last record, nullopt when it
// was not seen ending.
std::optional<api::JobProgress> wait_ended(HttpClient& client, const RemoteJob& job,
                                           const Deadline& d) {
  while (!d.passed()) {
    d.bound(client);
    try {
      const HttpReply reply = client.get(job.path() + "?limit=1");
      if (reply.status == 200) {
        const auto progress = api::parse_job_progress(reply.body);
        if (progress && api::is_final(progress->state)) return progress;
      }
    } catch (const HttpError&) {  // asked again until the deadline
    }
    d.pause();
  }
  return std::nullopt;
}

// Writes the rows of the ended job to `sink`; empty, or why they could not be fetched. A stopped
// job's rows are asked with `?partial=1` (the service answers its table 409 without it); a
// service that takes no query parameter there refuses that (400), and the plain download is
// asked instead. Every try asks the same way: behind a round-robin proxy, two different
// requests per try would always reach the same two replicas in the same order.
std::string fetch_rows(HttpClient& client, const RemoteJob& job, RowSink& sink, const Deadline& d) {
  const std::string plain = job.path() + "/results.jsonl";
  std::string path = plain + "?partial=1";
  std::string problem = "no time was left to fetch them";
  while (!d.passed()) {
    d.bound(client);
    try {
      HttpReply reply = client.get(path);
      if (reply.status == 400 && path != plain) {
        path = plain;
        continue;
      }
      if (reply.status == 200) {
        for (const api::PlanTableRow& row : job_rows_of(job, reply.body)) sink.write_row(row);
        return {};
      }
      problem = reply_problem(client, path, reply);
      if (!transient(reply.status) && reply.status != 409) return problem;
    } catch (const HttpError& e) {
      problem = without_hint(e.what());
    } catch (const BatchAbort& e) {
      return e.what();
    }
    d.pause();
  }
  return problem;
}

}  // namespace

StopOutcome stop_job(HttpClient& client, const RemoteJob& job, RowSink& sink) {
  const auto start = Clock::now();
  const std::string budget = std::to_string(kStopBudget.count()) + " s";
  const auto not_cancelled = [&](const std::string& why) {
    return StopOutcome{"could not be cancelled (" + why + "); it may still run: DELETE " +
                           job.url() + " once the service answers",
                       false};
  };
  // A job that finished before the stop is not cancelled: a DELETE would forget its rows.
  const Seen seen = read_state(client, job, Deadline{start + kStopBudget / 2});
  std::optional<api::JobProgress> ended;
  if (seen.progress && api::is_final(seen.progress->state)) {
    ended = seen.progress;
  } else if (seen.progress || seen.silent) {
    const Deadline cancelling{start + kStopBudget};
    const Cancel cancel = send_cancel(client, job, cancelling);
    switch (cancel.result) {
      case Cancel::Result::kRefused:
        return not_cancelled(cancel.problem);
      case Cancel::Result::kUnanswered:
        return StopOutcome{
            "was asked to cancel but did not confirm it (no answer to its DELETE "
            "within " +
                budget + "; last: " + cancel.problem + "); it may still run: check it with GET " +
                job.url(),
            false};
      case Cancel::Result::kEnded:
        // It had ended before the DELETE arrived (which then forgot it): as it ended.
        ended = cancel.ended ? *cancel.ended
                             : api::JobProgress{api::JobState::kCancelled, 0, 0, {}, false};
        break;
      case Cancel::Result::kAccepted:
        ended = wait_ended(client, job, cancelling);
        if (!ended) {
          return StopOutcome{"was asked to cancel (its DELETE was accepted) but had not ended " +
                                 budget + " after the stop; check it with GET " + job.url(),
                             false};
        }
        break;
    }
  } else {
    return not_cancelled(seen.problem);
  }
  const std::string state = ended->state == api::JobState::kDone
                                ? "had finished"
                                : std::string(api::to_string(ended->state));
  const std::string missing = fetch_rows(client, job, sink, Deadline{Clock::now() + kStopBudget});
  return StopOutcome{
      state + (missing.empty() ? " (" + std::to_string(sink.written()) + " rows written)"
                               : " (its rows could not be fetched: " + missing + ")"),
      true};
}

}  // namespace slosh::service::batch_cli
