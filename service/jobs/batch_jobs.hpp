#pragma once
// Batch jobs as resources (SPEC §13): POST /v1/batches starts a job of up to
// batch_job_max recipes and answers 202 at once; GET /v1/batches/{id} reports its progress and,
// once it is finished, its results (paged JSON rows); GET .../results.csv and .../results.jsonl
// download them in the `slosh batch` formats; DELETE cancels (or forgets a finished job).
//
// A job runs on the solve pool at background priority (WorkerPool: interactive plans first) with
// at most `workers` of its items queued or running at a time, so an interactive plan never waits
// behind a job's thousands of items. With batch_job_spread = "replicas" and a Redis cache, a job's
// items are shared out to every replica instead (SharedJobWorker, SharedJobQueue). Its record and
// rows live in the JobStore (memory, or Redis shared by the replicas), so any replica answers GET
// for it; a DELETE on any replica sets the store's cancel flag, which the owner polls. The owner
// rewrites the record at least every second; a queued or running record not rewritten for
// batch_job_stale_s reads as failed (its replica stopped). On shutdown (SIGTERM) the running and
// queued jobs end as failed, with a message.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "http/plan_service.hpp"
#include "jobs/batch_job_record.hpp"
#include "jobs/helped_jobs.hpp"
#include "jobs/helper_worker.hpp"
#include "jobs/job_store.hpp"
#include "jobs/recipe_table.hpp"
#include "jobs/shared_job_worker.hpp"

namespace slosh::service {

/// The query of GET /v1/batches/{id}: every value of offset and limit as received.
struct JobPageQuery {
  std::vector<std::string> offset;
  std::vector<std::string> limit;
};

/// Most rows one GET /v1/batches/{id} page holds (query limit).
constexpr std::size_t kJobPageMax = 1000;
/// Rows of a page when no limit is given.
constexpr std::size_t kJobPageDefault = 100;

class BatchJobs {
 public:
  /// Jobs run on `service`'s pool and keep their state in `store`; both outlive this object.
  BatchJobs(PlanService& service, JobStore& store);
  /// shutdown(), then joins the runner.
  ~BatchJobs();
  BatchJobs(const BatchJobs&) = delete;
  BatchJobs& operator=(const BatchJobs&) = delete;

  /// POST /v1/batches: 202 with the record and Location: /v1/batches/{id}; 422 for a bad body
  /// or more than batch_job_max recipes; 503 when batch_jobs_max jobs are queued or running here,
  /// and 503 (unavailable, naming the store and why) when the job's first record cannot be
  /// written where every replica reads it (a shared Redis store down): nothing of it is kept.
  Reply post(const std::string& body);
  /// GET /v1/batches/{id}: the record, with "results" (a page of rows) once it is finished.
  Reply get(const std::string& id, const JobPageQuery& query);
  /// GET /v1/batches/{id}/results.csv or .jsonl: every row of a finished job, 409 before it has
  /// finished, and 409 for a cancelled or failed job that lacks rows unless `partial` (the values
  /// of ?partial=) is "1" or "true": then its done rows. Headers X-Slosh-Partial (true when rows
  /// are missing), X-Slosh-Rows, X-Slosh-Rows-Total and X-Slosh-Job-State say which. 503 when
  /// the rows are not all in the shared store (naming why) or it does not answer in time.
  Reply results(const std::string& id, TableFormat format,
                const std::vector<std::string>& partial = {});
  /// DELETE /v1/batches/{id}: a queued or running job is asked to cancel (202 with its record,
  /// again on every DELETE until it has stopped); a finished one is forgotten (200 with its last
  /// record; then 404).
  Reply cancel(const std::string& id);

  /// Puts the stored calibration in for every recipe whose options.model names one (as POST
  /// /v1/plans does): `resolve` maps a plan request's text to the text with the model put in, and
  /// throws api::ApiError for a bad or unknown name (that recipe's row is then its error). Set
  /// before the first post(); without it a named model is left to the plan's own validation.
  void resolve_models_with(std::function<std::string(const std::string&)> resolve) {
    resolve_models_ = std::move(resolve);
  }

  /// Refuses new jobs and ends the queued and running ones as failed; returns at once (the
  /// runner finishes writing their records).
  void shutdown();

  /// Jobs queued or running on this replica (with batch_job_spread = "replicas": the jobs posted
  /// here that have not finished).
  [[nodiscard]] std::size_t active() const;
  /// Job items (rows) this replica solved and stored, of its own jobs and of shared ones; a row
  /// of a shared job is counted by the one replica that stored it first, a row of a helped job
  /// by the one credited with it in the job's shares (the first to solve its plan).
  [[nodiscard]] std::uint64_t items_stored() const {
    return items_stored_.load() + (shared_ ? shared_->items_stored() : 0) +
           (helper_ ? helper_->items_solved() : 0);
  }

  /// For /readyz: why some jobs' rows or records are held on this replica only (the shared
  /// store refuses or fails their writes, naming it and its reason); empty when none are.
  [[nodiscard]] std::string store_warning() { return store_.sharing_problem(); }

 private:
  struct Job;
  // post() of a job shared out to the replicas: published in Redis, not run here.
  Reply post_shared(Job& job);
  // Keeps a local copy (record and rows) of shared job `id` posted here, which has finished,
  // when its done rows are the table's first (every job done), so that this replica publishes it
  // again if Redis loses it, as it does for a job it ran alone.
  void keep_finished_shared(const std::string& id);
  // Runs job `id` here from where its silent owner left it (batch_job_spread = "helpers"): its
  // table from the helpers' stream, its record and first `done` rows from the shared store.
  // Whether it was taken.
  bool adopt(const std::string& id);
  // The first `done` rows of job `id` as the shared store holds them.
  struct DoneRows {
    std::vector<std::string> rows;  // the rows before the first lost one
    std::vector<std::size_t> lost;  // 1-based numbers of the rows it answered without
    bool answered{true};            // false: the store did not answer (nothing is known)
  };
  DoneRows read_done_rows(const std::string& id, std::size_t done);
  // Ends job `id`, taken over from its silent owner, as failed: the shared store lost parts of
  // it. Keeps the rows before the first lost one.
  void fail_lost_job(Job& job, std::size_t recipes_lost, const DoneRows& done);
  // The owner's heartbeat to the helpers and the shares of the rows stored and not credited yet
  // (`cached`: their indexes; kept while Redis does not answer, unless `last`: the job's end);
  // false when another replica owns the job now (it took the job over while this one was
  // silent). Offers the job again when Redis lost its offer (emptied).
  bool beat_helpers(Job& job, std::vector<std::size_t>& cached, std::size_t front,
                    bool last = false);
  // Adds the row of the job's next item (`result`) to `rows` and counts it (a helped job's row:
  // noted in `cached`, credited at the next heartbeat); returns its length.
  std::size_t keep_row(Job& job, const BatchResult& result, std::vector<std::string>& rows,
                       std::vector<std::size_t>& cached);
  void run_jobs();
  void run(Job& job);
  // Starts items until `workers` of the job's solves are in flight; returns the next item.
  std::size_t fill_window(Job& job, std::size_t next, std::deque<StartedItem>& window);
  // Stores the buffered rows and the record (the heartbeat), also of the queued jobs.
  void flush(Job& job, std::vector<std::string>& rows);
  // Notes in the job's record and the log that this process did not run since `last_turn` when
  // that gap is long (paused, starved); sets `last_turn` to now.
  // Returns false when, after a pause, the job's owner mark names another replica (it took the
  // job over): then nothing is written and the job is dropped here.
  bool note_if_paused(Job& job, std::chrono::steady_clock::time_point& last_turn);
  // Why a run stopped: all rows done, cancelled, its rows passed batch_jobs_bytes, shutdown.
  enum class RunStop { kAllDone, kCancelled, kTooLarge, kShutdown, kTakenOver };
  // Ends a job cancelled or caught by shutdown before its run started; false when it may run.
  bool ended_before_start(Job& job);
  // Why a run stops before its next row (taken over, cancelled, shutdown), if it does.
  std::optional<RunStop> stop_before_row(Job& job, std::chrono::steady_clock::time_point& last_turn,
                                         bool heartbeat);
  // The last writes of a run that stopped as `stop` (its rows not yet flushed, the cache hits not
  // yet credited), then finish_run().
  void end_run(Job& job, RunStop stop, std::vector<std::string>& rows,
               std::vector<std::size_t>& cached);
  // Ends a run that stopped as `stop` with its state and message.
  void finish_run(Job& job, RunStop stop);
  // Ends `job` in `state` with `message`: its rows and final record stored.
  void finish(Job& job, JobState state, const std::string& message);
  // The job's record as stored (JSON text), and its write.
  static std::string record_text(Job& job);
  bool write_record(Job& job);
  // 503 (overloaded) when stopping or batch_jobs_max jobs are queued or running here.
  void check_capacity() const;
  void check_capacity_locked() const;  // mutex_ held
  // Marks a stale queued or running record failed, unless the job runs on this replica or its
  // owner's heartbeat in the shared store says it is alive (then "unshared" says the record
  // there is behind).
  // A record silent past batch_job_stale_s reads as failed only once this replica has seen it so
  // for silence_confirmation(); until then it reads as it is, with a note saying so.
  void judge_liveness(JobRecord& record, const std::string& id) const;
  static std::chrono::milliseconds silence_confirmation(double stale_s);
  // How long this replica has seen job `id`'s record, written at `updated_unix_ms`, silent.
  std::chrono::milliseconds silence_seen_for(const std::string& id,
                                             std::int64_t updated_unix_ms) const;
  void forget_silence(const std::string& id) const;
  // The record of job `id` (load_record()); while the store cannot be asked, a shared job
  // posted here answers with this replica's last view of it, marked unshared.
  [[nodiscard]] JobRecord load(const std::string& id) const;
  // Whether the job is to be cancelled (`ask_store`: also polls the store's flag).
  [[nodiscard]] bool cancelled(Job& job, bool ask_store);
  [[nodiscard]] bool stopping() const;

  PlanService& service_;
  JobStore& store_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Job>> queue_;                        // waiting to run, in order
  std::unordered_map<std::string, std::shared_ptr<Job>> active_;  // queued or running here
  bool stopping_{false};
  // Other replicas' jobs seen silent past batch_job_stale_s: the record's write time and when this
  // replica first saw it so.
  struct Silence {
    std::int64_t updated_unix_ms;
    std::chrono::steady_clock::time_point first;
  };
  mutable std::unordered_map<std::string, Silence> silences_;
  std::function<std::string(const std::string&)> resolve_models_;
  std::atomic<std::uint64_t> items_stored_{0};  // rows of the jobs run here
  // The worker of the jobs shared out through Redis (batch_job_spread = "replicas"), else null.
  std::unique_ptr<SharedJobWorker> shared_;
  // With batch_job_spread = "helpers": this replica's jobs offered to the others, and its help
  // with theirs; else null.
  std::unique_ptr<HelpedJobs> helped_;
  std::unique_ptr<HelperWorker> helper_;
  std::thread runner_;  // last: started once the members above exist
};

}  // namespace slosh::service
