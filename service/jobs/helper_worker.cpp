#include "jobs/helper_worker.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "jobs/batch_job_record.hpp"
#include "jobs/job_messages.hpp"
#include "jobs/worker_pace.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

namespace {

/// How often the helper looks at the helped jobs (and their owners' heartbeats).
constexpr std::chrono::milliseconds kLook{500};
/// The shortest adoption lock: two heartbeats of the runner (batch_job_runner.cpp), so that the
/// replica that won it has beaten before another may try.
constexpr std::chrono::milliseconds kAdoptLockFloor{1000};

}  // namespace

HelperWorker::HelperWorker(PlanService& service, std::shared_ptr<RedisClient> client,
                           std::string replica, std::chrono::milliseconds ttl,
                           std::chrono::milliseconds stale, JobStore& store,
                           std::function<bool(const std::string&)> adopt)
    : service_(service),
      client_(client),
      jobs_(std::move(client), std::move(replica), ttl),
      stale_(stale),
      store_(store),
      adopt_(std::move(adopt)),
      token_(new_job_id()),
      thread_([this] { run(); }) {}

HelperWorker::~HelperWorker() {
  stop();
  if (thread_.joinable()) thread_.join();
}

void HelperWorker::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
}

bool HelperWorker::stopping() const {
  const std::lock_guard lock(mutex_);
  return stopping_;
}

void HelperWorker::hold_name() {
  if (jobs_.hold_name(token_, stale_)) return;
  const auto now = std::chrono::steady_clock::now();
  if (warned_name_ == std::chrono::steady_clock::time_point{} ||
      now - warned_name_ > kNameWarnEvery) {
    warned_name_ = now;
    spdlog::warn("{}", duplicate_replica_id_text(jobs_.replica()));
  }
}

bool HelperWorker::silent_for_long(const std::string& id) {
  // Seen silent at two looks in a row: a stall of Redis ages every heartbeat at once (their
  // expiry runs on), and the first look after it may be answered before the owner's heartbeat
  // that waited through it; a live owner has beaten again by the next look.
  const auto now = std::chrono::steady_clock::now();
  // When Redis failed this replica's own commands a moment ago it stalled or was cut off for
  // every replica: the owner's client waits out its retry interval before it writes again (at
  // its next heartbeat), so its silence is only judged once that has passed.
  const auto settle = client_->options().retry_interval + 2 * kLook;
  if (now - client_->state().last_failure < settle) {
    silent_since_.erase(id);
    return false;
  }
  const auto [seen, first] = silent_since_.try_emplace(id, now);
  return !first && now - seen->second >= kLook;
}

std::vector<HelpedJobs::Helped> HelperWorker::look() {
  hold_name();
  std::vector<HelpedJobs::Helped> out;
  std::vector<HelpedJobs::Helped> listed = jobs_.jobs();
  for (auto it = silent_since_.begin(); it != silent_since_.end();) {
    const bool still = std::any_of(listed.begin(), listed.end(),
                                   [&](const HelpedJobs::Helped& j) { return j.id == it->first; });
    it = still ? std::next(it) : silent_since_.erase(it);
  }
  for (HelpedJobs::Helped& job : listed) {
    if (job.owner == jobs_.replica()) continue;  // runs here
    const JobStore::RecordLookup lookup = store_.lookup_record(job.id);
    const auto record = lookup.text ? api::parse_job_record(*lookup.text) : std::nullopt;
    if (record && api::is_final(record->state)) {
      jobs_.close(job.id);  // its owner stopped before it closed it
      continue;
    }
    // Half the stale time: adopted before any replica reads the job as failed.
    const auto beat = store_.heartbeat_age_ms(job.id);
    const bool silent = lookup.answered && record && (!beat || *beat > stale_.count() / 2);
    if (!silent) silent_since_.erase(job.id);
    if (!silent || !silent_for_long(job.id)) {
      out.push_back(std::move(job));
      continue;
    }
    // The lock only picks one taker among the helpers, whose heartbeat starts at once: a taker
    // that dies right after must be adopted after half the stale time like any silent owner,
    // before the job reads as failed, not after a lock of the whole stale time.
    const auto lock = std::max(stale_ / 2, kAdoptLockFloor);
    if (jobs_.adopt(job.id, lock, stale_)) {
      spdlog::warn("batch job {}: its replica {} stopped answering; this replica runs it on",
                   job.id, job.owner);
      if (adopt_ && adopt_(job.id)) continue;
      jobs_.give_back(job.id);
      spdlog::warn(
          "batch job {}: this replica could not run it on (it is stopping, or the shared store "
          "did not give the job's table); handed to the replicas that help it",
          job.id);
    }
    out.push_back(std::move(job));
  }
  return out;
}

void HelperWorker::fill(const std::vector<HelpedJobs::Helped>& jobs) {
  const std::size_t workers = std::max<std::size_t>(1, service_.workers());
  const double budget = service_.engine().config().solve_budget_s;
  for (const HelpedJobs::Helped& job : jobs) {
    if (flight_.size() >= workers) return;
    if (met_.count(job.id) != 0) continue;
    for (SharedItem& item : jobs_.take(job.id, workers - flight_.size())) {
      if (item.index < job.front) {
        met_.insert(job.id);  // the owner has started this one, and every one before it
        break;
      }
      if (item.recipe.error) continue;  // its row is its reading error: nothing to solve
      try {
        flight_.push_back(
            {job.id, item.index,
             service_.start_batch_item(api::batch_item_of(item.recipe.request, budget),
                                       TaskPriority::kBackground)});
      } catch (const api::ApiError&) {
        // Refused (the queue is full): the owner solves it.
      }
    }
  }
}

bool HelperWorker::finish_ready() {
  bool any = false;
  for (auto it = flight_.begin(); it != flight_.end();) {
    const auto& pending = it->started.pending;
    if (pending.valid() && pending.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++it;
      continue;
    }
    const BatchResult result = it->started.get();
    // Counted only when credited with the item (the first replica to solve it), as the job's
    // shares count it: a plan the owner or another helper finished first is not this one's.
    if (!result.error && jobs_.note_helped(it->job, it->index)) ++solved_;
    any = true;
    it = flight_.erase(it);
  }
  return any;
}

void HelperWorker::run() {
  std::vector<HelpedJobs::Helped> jobs;
  auto last_look = std::chrono::steady_clock::now() - kLook;
  while (!stopping()) {
    if (std::chrono::steady_clock::now() - last_look >= kLook) {
      jobs = look();
      last_look = std::chrono::steady_clock::now();
      std::set<std::string> live;
      for (const auto& j : jobs) live.insert(j.id);
      for (auto it = met_.begin(); it != met_.end();) {
        it = live.count(*it) != 0 ? std::next(it) : met_.erase(it);
      }
    }
    fill(jobs);
    if (finish_ready()) continue;
    if (!flight_.empty()) {
      (void)flight_.front().started.pending.wait_for(kItemWait);
      continue;
    }
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, kIdlePoll, [this] { return stopping_; });
  }
}

}  // namespace slosh::service
