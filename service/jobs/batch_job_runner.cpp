// The runner of the batch jobs (BatchJobs): takes the queued jobs in order, runs each one's items
// on the solve pool at background priority, stores their rows and record at every heartbeat and
// ends them done, cancelled or failed.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include "jobs/batch_job_record.hpp"
#include "jobs/batch_job_state.hpp"
#include "jobs/batch_jobs.hpp"
#include "jobs/job_messages.hpp"
#include "jobs/plan_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/plan_table_row.hpp"
#include "slosh/api/service_bodies.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

/// How often the runner stores rows and rewrites the record (the heartbeat), and polls the
/// store's cancel flag, while a job runs.
constexpr std::chrono::milliseconds kHeartbeat{500};

/// A gap between two turns of a running job's loop longer than this [s]: the process did not
/// run (paused, starved), which its record and log then say.
constexpr double kPauseNoteS = 2.0;

// The index below which the helpers skip a job's items, at a heartbeat of its runner that starts
// item `next` and started `at_beat` at the last one: about as many items as since then are
// started before the next heartbeat. Sets `at_beat` to `next`.
std::size_t front_of(std::size_t next, std::size_t& at_beat) {
  const std::size_t front = next + (next - at_beat) + 2;
  at_beat = next;
  return front;
}

// One more row of `status` solved by `replica`.
void add_share(JobStatus& status, const std::string& replica) {
  for (auto& [name, rows] : status.shares) {
    if (name == replica) {
      ++rows;
      return;
    }
  }
  status.shares.emplace_back(replica, 1);
}

}  // namespace

void BatchJobs::run_jobs() {
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      // Idle, the runner still wakes every heartbeat to give the shared store what it missed
      // (finished jobs' rows and records, or everything after it was emptied).
      wake_.wait_for(lock, kHeartbeat, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) {
        if (stopping_) return;  // stopping, nothing left
        lock.unlock();
        store_.resync();
        continue;
      }
      job = queue_.front();
      queue_.pop_front();
    }
    try {
      run(*job);
    } catch (const std::exception& e) {
      finish(*job, JobState::kFailed, std::string("the job failed: ") + e.what());
    }
    const std::lock_guard lock(mutex_);
    active_.erase(job->status.id);
  }
}

bool BatchJobs::cancelled(Job& job, bool ask_store) {
  // The store is asked at most once a heartbeat (it may be Redis); a DELETE on this replica sets
  // the job's own flag at once.
  if (!job.cancel && ask_store && store_.cancel_requested(job.status.id)) job.cancel = true;
  job.status.cancel_requested = job.cancel;
  return job.cancel;
}

bool BatchJobs::stopping() const {
  const std::lock_guard lock(mutex_);
  return stopping_;
}

std::size_t BatchJobs::fill_window(Job& job, std::size_t next, std::deque<StartedItem>& window) {
  // At most `workers` of this job's solves are queued or running: the background queue stays
  // short, so interactive plans (which workers take first) never wait behind the job's items.
  const std::size_t max_in_flight = service_.workers();
  auto in_flight = [&] {
    return static_cast<std::size_t>(
        std::count_if(window.begin(), window.end(), [](const StartedItem& s) {
          return s.pending.valid() &&
                 s.pending.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
        }));
  };
  while (next < job.rows.size() && in_flight() < max_in_flight &&
         window.size() < 4 * max_in_flight + 64) {
    const RecipeRow& row = job.rows[next++];
    if (row.error) {  // an unreadable row: its error is its result
      StartedItem item;
      item.result.error = row.error;
      window.push_back(std::move(item));
      continue;
    }
    window.push_back(service_.start_batch_item(
        api::batch_item_of(row.request, service_.engine().config().solve_budget_s),
        TaskPriority::kBackground));
  }
  return next;
}

void BatchJobs::flush(Job& job, std::vector<std::string>& rows) {
  // The buffered rows are rows done - size ... done - 1; on a failed write they stay buffered and
  // are written again (same indexes) at the next heartbeat.
  if (!rows.empty()) {
    if (store_.put_rows(job.status.id, job.status.done - rows.size(), rows)) {
      rows.clear();
    } else {
      spdlog::warn("batch job {}: the job store did not take {} rows", job.status.id, rows.size());
    }
  }
  // What the shared store missed first (this job's rows and record after a failed write, every
  // job after an emptying): each row and record is sent once, after the rows it counts. The
  // record after that: written before, it would announce to the other replicas rows an emptying
  // took (one that took the job over from here would find its table damaged).
  store_.resync();
  write_record(job);
  // The queued jobs' heartbeat: they are alive, only waiting.
  std::vector<std::shared_ptr<Job>> queued;
  {
    const std::lock_guard lock(mutex_);
    queued.assign(queue_.begin(), queue_.end());
  }
  for (const auto& q : queued) write_record(*q);
}

bool BatchJobs::note_if_paused(Job& job, std::chrono::steady_clock::time_point& last_turn) {
  const auto now = std::chrono::steady_clock::now();
  const double gap = std::chrono::duration<double>(now - last_turn).count();
  last_turn = now;
  if (gap <= kPauseNoteS) return true;
  if (helped_) {
    // Another replica may have taken the job over meanwhile, and even finished or forgotten it:
    // its record must not be written over.
    const auto owner = helped_->owner_of(job.status.id);
    if (owner && !owner->empty() && *owner != helped_->replica()) return false;
  }
  job.status.note = resumed_note(gap, service_.config().batch_job_stale_s);
  spdlog::warn("batch job {}: {}", job.status.id, job.status.note);
  write_record(job);  // at once: other replicas may have read it as failed meanwhile
  return true;
}

void BatchJobs::finish(Job& job, JobState state, const std::string& message) {
  job.status.state = state;
  job.status.message = message;
  job.status.finished_ms = unix_ms_now();
  write_record(job);
  spdlog::info("batch job {} {}: {} of {} recipes ({} failed){}{}", job.status.id,
               api::to_string(state), job.status.done, job.status.total, job.status.failed,
               message.empty() ? "" : ": ", message);
}

std::optional<BatchJobs::RunStop> BatchJobs::stop_before_row(
    Job& job, std::chrono::steady_clock::time_point& last_turn, bool heartbeat) {
  if (!note_if_paused(job, last_turn)) return RunStop::kTakenOver;
  if (cancelled(job, heartbeat)) return RunStop::kCancelled;
  if (stopping()) return RunStop::kShutdown;
  return std::nullopt;
}

bool BatchJobs::ended_before_start(Job& job) {
  const JobStatus& s = job.status;
  if (cancelled(job, true)) {
    // A job taken over from a silent owner may be cancelled with the owner's rows stored.
    finish(job, JobState::kCancelled,
           s.done == 0 ? "cancelled before it started"
                       : "cancelled after " + std::to_string(s.done) + " of " +
                             std::to_string(s.total) + " recipes");
    return true;
  }
  if (stopping()) {
    if (helped_ && helped_->hand_over(s.id)) {
      spdlog::info(
          "batch job {}: this replica stops before the job started; handed to the "
          "replicas that help it",
          s.id);
      return true;
    }
    finish(job, JobState::kFailed,
           "the service shut down before the job started; POST the job again");
    return true;
  }
  return false;
}

void BatchJobs::run(Job& job) {
  if (ended_before_start(job)) return;
  JobStatus& s = job.status;
  s.state = JobState::kRunning;
  if (!s.started_ms) s.started_ms = unix_ms_now();
  write_record(job);
  std::deque<StartedItem> window;
  std::vector<std::string> rows;
  // A job taken over from a silent owner carries on after the rows it had stored.
  std::size_t next = s.done;
  std::vector<std::size_t> cached;  // rows that were cache hits, not yet given their share
  std::size_t next_at_beat = next;
  auto last_flush = std::chrono::steady_clock::now();
  RunStop stop = RunStop::kAllDone;
  bool heartbeat = false;
  std::size_t row_bytes = 0;  // of this job's rows, against batch_jobs_bytes
  const std::size_t max_bytes = service_.config().batch_jobs_bytes;
  auto last_turn = std::chrono::steady_clock::now();
  while (s.done < s.total) {
    if (const std::optional<RunStop> before = stop_before_row(job, last_turn, heartbeat)) {
      stop = *before;
      break;
    }
    next = fill_window(job, next, window);
    const StartedItem& head = window.front();
    if (!head.pending.valid() ||
        head.pending.wait_for(std::chrono::milliseconds(100)) == std::future_status::ready) {
      const BatchResult result = head.get();
      window.pop_front();
      // A solve the shutdown refused is not the recipe's row: the job stops before it, and the
      // replica that takes it over (or a POST again) plans it.
      if (result.refused() && stopping()) {
        stop = RunStop::kShutdown;
        break;
      }
      row_bytes += keep_row(job, result, rows, cached);
      if (row_bytes > max_bytes) {
        stop = RunStop::kTooLarge;
        break;
      }
    }
    heartbeat = std::chrono::steady_clock::now() - last_flush >= kHeartbeat;
    if (heartbeat) {
      if (helped_ && !beat_helpers(job, cached, front_of(next, next_at_beat))) {
        stop = RunStop::kTakenOver;
        break;
      }
      flush(job, rows);
      last_flush = std::chrono::steady_clock::now();
    }
  }
  end_run(job, stop, rows, cached);
}

void BatchJobs::end_run(Job& job, RunStop stop, std::vector<std::string>& rows,
                        std::vector<std::size_t>& cached) {
  // The last row may have come in the very turn this replica resumed after a pause long enough
  // for another replica to take the job over: asked once more before the final writes (which
  // the job store makes only while the job's owner mark names this replica anyway).
  // A job handed over at a shutdown keeps its helpers on the items from its stored rows on.
  const std::size_t front = stop == RunStop::kShutdown ? job.status.done : job.status.total;
  if (stop != RunStop::kTakenOver && helped_ && !beat_helpers(job, cached, front, true)) {
    stop = RunStop::kTakenOver;
  }
  if (stop == RunStop::kTakenOver) return finish_run(job, stop);
  flush(job, rows);
  finish_run(job, stop);
}

std::size_t BatchJobs::keep_row(Job& job, const BatchResult& result, std::vector<std::string>& rows,
                                std::vector<std::size_t>& cached) {
  JobStatus& s = job.status;
  const api::PlanTableRow row = plan_row(job.rows[s.done], result, job.view);
  if (row.failed) ++s.failed;
  // A helped job's row is credited at the next heartbeat to the replica that solved its plan
  // first (a helper's solve may have been a cache hit here, or raced this replica's).
  if (helped_) {
    cached.push_back(s.done);
  } else {
    ++items_stored_;
  }
  rows.push_back(api::table_row_text(row));
  ++s.done;
  return rows.back().size();
}

bool BatchJobs::beat_helpers(Job& job, std::vector<std::size_t>& cached, std::size_t front,
                             bool last) {
  JobStatus& s = job.status;
  const auto owner = helped_->beat(s.id, front);
  // Another replica took the job over while this one was silent (paused, cut off): it runs it.
  if (owner && !owner->empty() && *owner != helped_->replica()) return false;
  if (owner && owner->empty() && !job.cancel) {
    // Redis answered without the help offer and without an owner mark: it was emptied (or the
    // keys expired) while the job ran. Offered again from where this replica is, so that the
    // other replicas help, and take the job over if this one stops.
    if (helped_->publish(s, job.rows, std::min(front, s.total))) {
      spdlog::info("batch job {}: offered to the other replicas again (Redis had lost the offer)",
                   s.id);
    }
  }
  const auto solvers = helped_->credit(s.id, cached);
  if (solvers || last) {
    // Without an answer at the job's end the rows are this replica's: its record must name a
    // solver for each (the helpers' note of them is then not counted either).
    for (std::size_t k = 0; k < cached.size(); ++k) {
      add_share(s, solvers ? (*solvers)[k].solver : helped_->replica());
      // Counted where it was noted: here now, or by the helper that noted it first (which may
      // be this replica's own, for a job it took over).
      if (!solvers || (*solvers)[k].noted_now) ++items_stored_;
    }
    cached.clear();
  }
  // The items the helpers solved ahead of the stored rows count in the progress too.
  if (const auto ahead = helped_->solved_from(s.id, s.done)) s.solved_ahead = *ahead;
  if (last) s.solved_ahead = 0;
  return true;
}

void BatchJobs::finish_run(Job& job, RunStop stop) {
  const JobStatus& s = job.status;
  if (stop == RunStop::kTakenOver) {
    spdlog::warn(
        "batch job {}: another replica took it over while this one was silent; it "
        "runs it on from its record in the shared job store",
        s.id);
    store_.drop_local(s.id);
    return;
  }
  const std::string progress =
      std::to_string(s.done) + " of " + std::to_string(s.total) + " recipes";
  // A graceful stop (a rolling deploy) leaves a helped job to the replicas that help it: one of
  // them takes it over at once from the rows stored so far, as it would from a silent owner.
  if (stop == RunStop::kShutdown && helped_ && helped_->hand_over(s.id)) {
    spdlog::info("batch job {}: this replica stops after {}; handed to the replicas that help it",
                 s.id, progress);
    return;
  }
  if (helped_) helped_->close(s.id, true);
  if (stop == RunStop::kCancelled) {
    return finish(job, JobState::kCancelled, "cancelled after " + progress);
  }
  if (stop == RunStop::kTooLarge) {
    return finish(job, JobState::kFailed,
                  too_large_text(service_.config().batch_jobs_bytes, s.done, s.total));
  }
  if (stop == RunStop::kShutdown) {
    return finish(job, JobState::kFailed,
                  "the service shut down after " + progress +
                      "; POST the job again (the finished plans are cached)");
  }
  // A DELETE accepted after the last row was stored, before the run read the flag again: the job
  // is done, and its record keeps the cancel it was asked.
  if (cancelled(job, true)) job.status.note = late_cancel_note(job.status.note);
  finish(job, JobState::kDone, "");
}

}  // namespace slosh::service
