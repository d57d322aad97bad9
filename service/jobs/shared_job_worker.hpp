#pragma once
// The background worker of a replica that solves shared batch jobs' items (batch_job_spread =
// "replicas", SPEC §13): it takes items from the jobs' Redis streams (SharedJobQueue), solves them
// on the solve pool at background priority with at most `workers` of them in flight (so
// interactive plans still overtake them), stores each row once and acknowledges its item. Every
// heartbeat it rewrites the record of every shared job (so a job stays alive while any replica
// works on it), renews its hold of the items it is solving, and gives its own jobs (those posted
// here) to Redis again when Redis lost them (restarted without persistence).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "http/plan_service.hpp"
#include "jobs/shared_job_queue.hpp"

namespace slosh::service {

class SharedJobWorker {
 public:
  /// Works on `service`'s pool (which outlives it) with the queue's Redis client. `finished` is
  /// called (on the worker's thread) with the id of each job posted here once its final record
  /// is in Redis, before the job stops counting as posted here: the replica keeps a copy of it.
  SharedJobWorker(PlanService& service, std::shared_ptr<RedisClient> client,
                  SharedQueueOptions options,
                  std::function<void(const std::string&)> finished = {});
  /// stop(), then joins the thread.
  ~SharedJobWorker();
  SharedJobWorker(const SharedJobWorker&) = delete;
  SharedJobWorker& operator=(const SharedJobWorker&) = delete;

  /// Publishes a job posted here (SharedJobQueue::publish) and keeps its table until it has
  /// finished, to publish it again if Redis loses it. nullopt once published; else why not.
  [[nodiscard]] std::optional<std::string> publish(const JobStatus& status,
                                                   std::vector<RecipeRow> recipes);
  /// Stops taking items; the items in flight are left to be taken over by other replicas.
  void stop();
  /// Rows this replica stored first (counted once across the replicas).
  [[nodiscard]] std::uint64_t items_stored() const { return stored_.load(); }
  /// SharedJobQueue::live_record.
  [[nodiscard]] std::optional<std::string> live_record(const std::string& id) {
    return queue_.live_record(id);
  }
  /// Jobs posted here that have not finished.
  [[nodiscard]] std::size_t owned() const;
  /// The record of job `id` as this replica last read it from Redis (its progress over all
  /// replicas at the last heartbeat) when the job was posted here and has not finished; nullopt
  /// otherwise. Answers for it while Redis cannot be asked.
  [[nodiscard]] std::optional<std::string> owned_record(const std::string& id) const;
  /// Keeps `record` (text) as this replica's latest view of job `id` when it was posted here.
  void note_view(const std::string& id, std::string record);
  /// Whether job `id` was posted here and has not finished.
  [[nodiscard]] bool owns(const std::string& id) const;
  /// Asks to cancel job `id` posted here: its cancel flag is set in Redis at the next heartbeat
  /// that Redis answers. Whether the job was posted here and has not finished.
  bool cancel_later(const std::string& id);

 private:
  struct InFlight;
  void run();
  // Beats every shared job and the owned ones (publishing again those Redis lost); drops the
  // items in flight of jobs that are over; returns the jobs with items left, oldest first.
  std::vector<std::string> heartbeat(std::vector<InFlight>& flight);
  // Takes items of `jobs` (oldest job first) until `workers` are in flight; whether it took any.
  bool fill(const std::vector<std::string>& jobs, std::vector<InFlight>& flight);
  // Stores the rows of the finished items; whether any finished. Sets `complete` when a job has
  // all its rows stored.
  bool store_ready(std::vector<InFlight>& flight, bool& complete);
  [[nodiscard]] bool stopping() const;

  PlanService& service_;
  SharedJobQueue queue_;
  std::function<void(const std::string&)> finished_;
  // This process's token for its replica name in Redis (SharedJobQueue::hold_name), and when it
  // last warned that another live replica uses the same name.
  std::string token_;
  std::chrono::steady_clock::time_point warned_name_{};
  std::atomic<std::uint64_t> stored_{0};
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_{false};
  struct Owned {
    JobStatus status;
    std::vector<RecipeRow> recipes;
    std::string last_record;  // as last read from Redis ("" before the first read)
    bool cancel{false};       // a DELETE here that Redis has not taken yet
  };
  // Beats the jobs posted here (publishing again those Redis lost, sending their cancels);
  // `beaten`/`over`: the shared jobs already beaten and those over. Adds the running ones.
  void beat_owned(const std::set<std::string>& beaten, const std::set<std::string>& over,
                  std::vector<std::string>& running);
  std::map<std::string, Owned> owned_;  // jobs posted here, until they have finished
  std::thread thread_;                  // last: started once the members above exist
};

}  // namespace slosh::service
