#pragma once
// The background worker of a replica that helps the batch jobs other replicas run
// (batch_job_spread = "helpers"; HelpedJobs): it takes their items from the table's end, solves
// their plans on the solve pool at background priority (at most `workers` in flight, so
// interactive plans and the replica's own jobs still go first) into the shared plan cache, and
// notes which it solved. It stores no row: the job's owner does, finding the plans cached. Every
// heartbeat it looks whether a helped job's owner has gone silent (its heartbeat older than half
// of batch_job_stale_s) and, if so, hands the job to `adopt` to run it here from where it is.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "http/plan_service.hpp"
#include "jobs/helped_jobs.hpp"
#include "jobs/job_store.hpp"

namespace slosh::service {

class HelperWorker {
 public:
  /// `adopt(id)` runs job `id` here (its owner went silent); whether it did. `stale`: the
  /// replicas' batch_job_stale_s.
  HelperWorker(PlanService& service, std::shared_ptr<RedisClient> client, std::string replica,
               std::chrono::milliseconds ttl, std::chrono::milliseconds stale, JobStore& store,
               std::function<bool(const std::string&)> adopt);
  ~HelperWorker();
  HelperWorker(const HelperWorker&) = delete;
  HelperWorker& operator=(const HelperWorker&) = delete;

  void stop();
  /// Plans this replica solved first for jobs other replicas run (credited to it in their
  /// shares).
  [[nodiscard]] std::uint64_t items_solved() const { return solved_.load(); }

 private:
  struct InFlight {
    std::string job;
    std::size_t index{0};
    StartedItem started;
  };
  void run();
  // Adopts the jobs whose owner went silent; returns the jobs to help, oldest first.
  std::vector<HelpedJobs::Helped> look();
  // Holds this replica's name in Redis; warns (once a minute) while another process holds it.
  void hold_name();
  // Whether job `id`, silent at this look, was already silent at a look a while before.
  bool silent_for_long(const std::string& id);
  void fill(const std::vector<HelpedJobs::Helped>& jobs);
  bool finish_ready();
  [[nodiscard]] bool stopping() const;

  PlanService& service_;
  std::shared_ptr<RedisClient> client_;  // this replica's, shared with jobs_
  HelpedJobs jobs_;
  std::chrono::milliseconds stale_;
  JobStore& store_;
  std::function<bool(const std::string&)> adopt_;
  std::vector<InFlight> flight_;
  // Jobs whose owner has started every item left in their stream: not read again.
  std::set<std::string> met_;
  // When each helped job was first seen with its owner silent (since then at every look).
  std::map<std::string, std::chrono::steady_clock::time_point> silent_since_;
  std::atomic<std::uint64_t> solved_{0};
  // This process's token for its replica name in Redis (HelpedJobs::hold_name), and when it last
  // warned that another live replica uses the same name.
  std::string token_;
  std::chrono::steady_clock::time_point warned_name_{};
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_{false};
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace slosh::service
