#include "jobs/shared_job_worker.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <set>
#include <utility>

#include "jobs/job_messages.hpp"
#include "jobs/plan_table.hpp"
#include "jobs/worker_pace.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/job_record.hpp"
#include "slosh/api/plan_table_row.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/service_bodies.hpp"

namespace slosh::service {

namespace {

/// How often the worker rewrites the shared jobs' records and renews its items (the heartbeat).
constexpr std::chrono::milliseconds kHeartbeat{500};

}  // namespace

struct SharedJobWorker::InFlight {
  std::string job;
  SharedItem item;
  StartedItem started;
  // The solved row (and whether it is an error row) once its solve has finished: kept while Redis
  // refuses or fails its write, and sent again each heartbeat. Meanwhile this replica renews its
  // hold of the item, so a refused write is not a take another replica must make again.
  std::optional<std::string> text;
  bool failed{false};
  std::chrono::steady_clock::time_point retry_at{};
};

SharedJobWorker::SharedJobWorker(PlanService& service, std::shared_ptr<RedisClient> client,
                                 SharedQueueOptions options,
                                 std::function<void(const std::string&)> finished)
    : service_(service),
      queue_(std::move(client), std::move(options)),
      finished_(std::move(finished)),
      token_(new_job_id()),
      thread_([this] { run(); }) {}

SharedJobWorker::~SharedJobWorker() {
  stop();
  if (thread_.joinable()) thread_.join();
}

void SharedJobWorker::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
}

bool SharedJobWorker::stopping() const {
  const std::lock_guard lock(mutex_);
  return stopping_;
}

std::size_t SharedJobWorker::owned() const {
  const std::lock_guard lock(mutex_);
  return owned_.size();
}

std::optional<std::string> SharedJobWorker::publish(const JobStatus& status,
                                                    std::vector<RecipeRow> recipes) {
  if (auto refused = queue_.publish(status, recipes)) return refused;
  {
    const std::lock_guard lock(mutex_);
    owned_[status.id] = Owned{status, std::move(recipes), "", false};
  }
  wake_.notify_all();
  return std::nullopt;
}

std::vector<std::string> SharedJobWorker::heartbeat(std::vector<InFlight>& flight) {
  if (!queue_.hold_name(token_)) {
    const auto now = std::chrono::steady_clock::now();
    if (warned_name_ == std::chrono::steady_clock::time_point{} ||
        now - warned_name_ > kNameWarnEvery) {
      warned_name_ = now;
      spdlog::warn("{}", duplicate_replica_id_text(queue_.options().replica));
    }
  }
  std::vector<std::string> jobs = queue_.jobs();
  std::set<std::string> beaten;
  std::vector<std::string> running;
  std::set<std::string> over;
  for (const std::string& id : jobs) {
    beaten.insert(id);
    const SharedJobQueue::Fate fate = queue_.beat(id);
    if (fate == SharedJobQueue::Fate::kFinished || fate == SharedJobQueue::Fate::kGone) {
      over.insert(id);
    } else {
      running.push_back(id);
    }
  }
  beat_owned(beaten, over, running);
  // The items of a job that is over are not stored (their solves finish on the pool anyway).
  flight.erase(std::remove_if(flight.begin(), flight.end(),
                              [&](const InFlight& f) { return over.count(f.job) != 0; }),
               flight.end());
  std::map<std::string, std::vector<std::string>> held;
  for (const InFlight& f : flight) held[f.job].push_back(f.item.entry);
  for (const auto& [id, entries] : held) queue_.keep(id, entries);
  return running;
}

void SharedJobWorker::beat_owned(const std::set<std::string>& beaten,
                                 const std::set<std::string>& over,
                                 std::vector<std::string>& running) {
  std::vector<std::pair<std::string, Owned>> owned;
  {
    const std::lock_guard lock(mutex_);
    owned.assign(owned_.begin(), owned_.end());
  }
  for (auto& [id, job] : owned) {
    if (job.cancel && queue_.request_cancel(id)) {
      const std::lock_guard lock(mutex_);
      if (auto it = owned_.find(id); it != owned_.end()) it->second.cancel = false;
    }
    SharedJobQueue::Fate fate = SharedJobQueue::Fate::kRunning;
    if (beaten.count(id) == 0 || over.count(id) != 0) fate = queue_.beat(id);
    if (fate == SharedJobQueue::Fate::kGone) {
      // Redis lost the job (restarted empty, flushed): this replica still has its table, so it
      // runs again from its first row (the plans are in the replicas' local caches).
      spdlog::warn("batch job {}: the shared job store lost it; publishing it again", id);
      if (!queue_.publish(job.status, job.recipes)) running.push_back(id);
      continue;
    }
    if (fate == SharedJobQueue::Fate::kFinished) {
      if (finished_) finished_(id);
      const std::lock_guard lock(mutex_);
      owned_.erase(id);
      continue;
    }
    const std::lock_guard lock(mutex_);
    if (fate != SharedJobQueue::Fate::kRunning) continue;
    if (auto live = queue_.live_record(id)) {
      if (auto it = owned_.find(id); it != owned_.end()) it->second.last_record = std::move(*live);
    }
  }
}

std::optional<std::string> SharedJobWorker::owned_record(const std::string& id) const {
  const std::lock_guard lock(mutex_);
  const auto it = owned_.find(id);
  if (it == owned_.end()) return std::nullopt;
  if (!it->second.last_record.empty()) return it->second.last_record;
  return api::job_record_text(it->second.status, unix_ms_now());
}

void SharedJobWorker::note_view(const std::string& id, std::string record) {
  const std::lock_guard lock(mutex_);
  if (auto it = owned_.find(id); it != owned_.end()) it->second.last_record = std::move(record);
}

bool SharedJobWorker::owns(const std::string& id) const {
  const std::lock_guard lock(mutex_);
  return owned_.count(id) != 0;
}

bool SharedJobWorker::cancel_later(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    const auto it = owned_.find(id);
    if (it == owned_.end()) return false;
    it->second.cancel = true;
  }
  wake_.notify_all();
  return true;
}

bool SharedJobWorker::fill(const std::vector<std::string>& jobs, std::vector<InFlight>& flight) {
  const std::size_t workers = std::max<std::size_t>(1, service_.workers());
  const double budget = service_.engine().config().solve_budget_s;
  bool took = false;
  for (const std::string& id : jobs) {
    if (flight.size() >= workers) break;
    std::set<std::string> held;
    for (const InFlight& f : flight) {
      if (f.job == id) held.insert(f.item.entry);
    }
    for (SharedItem& item : queue_.take(id, workers - flight.size(), held)) {
      took = true;
      InFlight f{id, std::move(item), {}, std::nullopt, false, {}};
      const std::size_t max_takes = queue_.options().max_takes;
      if (f.item.recipe.error) {  // an unreadable row: its error is its result
        f.started.result.error = *f.item.recipe.error;
      } else if (f.item.takes > max_takes) {
        // Its earlier takers all stopped before storing it: it may be what stops them.
        spdlog::warn("batch job {}: row {} was taken {} times and never stored; recorded failed",
                     id, f.item.index + 1, f.item.takes - 1);
        f.started.result.error =
            api::ApiError(api::ErrorCode::kInternal, "", dead_item_text(f.item.takes, max_takes));
      } else {
        try {
          f.started = service_.start_batch_item(api::batch_item_of(f.item.recipe.request, budget),
                                                TaskPriority::kBackground);
        } catch (const api::ApiError& e) {
          f.started.result.error = e;
        }
      }
      flight.push_back(std::move(f));
    }
  }
  return took;
}

bool SharedJobWorker::store_ready(std::vector<InFlight>& flight, bool& complete) {
  bool any = false;
  const auto now = std::chrono::steady_clock::now();
  for (auto it = flight.begin(); it != flight.end();) {
    if (!it->text) {
      const StartedItem& s = it->started;
      const bool ready = !s.pending.valid() ||
                         s.pending.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
      if (!ready) {
        ++it;
        continue;
      }
      const BatchResult result = s.get();
      // The shutdown refused this solve (it was still queued, or taken as the replica stopped):
      // not the recipe's row. Left unstored, the item stays pending in the job's stream for
      // another replica to take.
      if (result.refused() && stopping()) {
        it = flight.erase(it);
        continue;
      }
      std::optional<api::PlanView> view;
      if (it->item.view) view = api::parse_plan_view(*it->item.view);
      const api::PlanTableRow row = plan_row(it->item.recipe, result, view);
      it->text = api::table_row_text(row);
      it->failed = row.failed;
    } else if (now < it->retry_at) {
      ++it;
      continue;
    }
    const auto result = queue_.store(it->job, it->item, *it->text, it->failed);
    if (result.stored == SharedJobQueue::Stored::kFailed) {
      if (it->retry_at == std::chrono::steady_clock::time_point{}) {
        spdlog::warn(
            "batch job {}: row {} was not stored (Redis refused or did not answer); this "
            "replica keeps it and stores it once Redis takes it",
            it->job, it->item.index + 1);
      }
      it->retry_at = now + kHeartbeat;
      ++it;
      continue;
    }
    if (result.stored == SharedJobQueue::Stored::kNew) ++stored_;
    // Stored the last row, or found the job closed (cancelled, past its bytes): its final
    // record at once.
    if (result.done >= it->item.total || result.stored == SharedJobQueue::Stored::kClosed) {
      complete = true;
    }
    any = true;
    it = flight.erase(it);
  }
  return any;
}

void SharedJobWorker::run() {
  std::vector<InFlight> flight;
  std::vector<std::string> jobs;
  auto last_beat = std::chrono::steady_clock::now() - kHeartbeat;
  bool complete = false;  // a job's last row was stored here: its final record at once
  while (!stopping()) {
    if (complete || std::chrono::steady_clock::now() - last_beat >= kHeartbeat) {
      jobs = heartbeat(flight);
      last_beat = std::chrono::steady_clock::now();
    } else if (flight.empty()) {
      jobs = queue_.jobs();  // idle: a new job's items are taken within kIdlePoll
    }
    const bool took = fill(jobs, flight);
    complete = false;
    if (store_ready(flight, complete)) continue;  // room again: the next items at once
    if (!flight.empty()) {
      const auto solving = std::find_if(flight.begin(), flight.end(), [](const InFlight& f) {
        return !f.text && f.started.pending.valid();
      });
      if (solving != flight.end()) {
        (void)solving->started.pending.wait_for(kItemWait);
      } else {  // every row solved, waiting for Redis to take it
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, kItemWait, [this] { return stopping_; });
      }
      continue;
    }
    if (took) continue;
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, kIdlePoll, [this] { return stopping_; });
  }
}

}  // namespace slosh::service
