#include "jobs/tiered_job_store.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <utility>

namespace slosh::service {

namespace {
/// Jobs whose row counts are kept before those the local store dropped are forgotten.
constexpr std::size_t kMaxCountedJobs = 1024;
}  // namespace

bool TieredJobStore::put_record(const std::string& id, const std::string& record) {
  {
    const std::lock_guard lock(mutex_);
    if (disowned_locked(id)) return false;
  }
  const bool local = local_.put_record(id, record);
  {
    // The shared store is behind on this job: the record goes with its rows at the next resync
    // (written now, it would announce rows the shared store does not hold yet).
    const std::lock_guard lock(mutex_);
    if (local && unsynced_.count(id) != 0) return true;
  }
  const bool shared = shared_.put_record(id, record);
  if (!shared && lost_to_another(id)) return false;
  if (local && !shared) {
    const std::lock_guard lock(mutex_);
    fell_behind(id);
  }
  return local || shared;
}

bool TieredJobStore::lost_to_another(const std::string& id) {
  const auto other = shared_.taken_over_by(id);
  if (!other) return false;
  local_.remove(id);
  {
    const std::lock_guard lock(mutex_);
    counts_.erase(id);
    unsynced_.erase(id);
    refused_.erase(id);
    if (disowned_.size() >= kRemembered) disowned_.clear();
    if (!disowned_.insert(id).second) return true;
  }
  spdlog::warn(
      "batch job {}: replica {} took it over while this replica could not write to the shared "
      "job store; this replica's copy is dropped and the job is served as replica {} runs it",
      id, *other, *other);
  return true;
}

void TieredJobStore::fell_behind(const std::string& id) {
  unsynced_.insert(id);
  std::string why = shared_.last_write_failure();
  if (why.empty()) why = "the shared job store did not take the write";
  auto [it, added] = refused_.try_emplace(id, why);
  if (!added) {
    it->second = std::move(why);
    return;
  }
  // Once per job falling behind: its rows stay here and are sent again at every heartbeat.
  spdlog::warn(
      "batch job {}: {}; its rows and record are kept on this replica and sent again at every "
      "heartbeat",
      id, it->second);
}

std::optional<JobStore::Unshared> TieredJobStore::unshared(const std::string& id) {
  const std::lock_guard lock(mutex_);
  if (unsynced_.count(id) == 0) return std::nullopt;
  const auto counts = counts_.find(id);
  Unshared out;
  if (counts != counts_.end() && counts->second.local > counts->second.shared) {
    out.rows = counts->second.local - counts->second.shared;
  }
  const auto why = refused_.find(id);
  out.reason = why != refused_.end()
                   ? why->second
                   : "the shared job store lost the job (emptied or evicted); it is being "
                     "published there again";
  return out;
}

std::string TieredJobStore::sharing_problem() {
  std::size_t jobs = 0;
  {
    const std::lock_guard lock(mutex_);
    jobs = refused_.size();
  }
  if (jobs == 0) return {};
  return shared_.last_write_failure() + "; " + std::to_string(jobs) +
         (jobs == 1 ? " batch job's" : " batch jobs'") +
         " rows or records are kept on this replica only and sent again at every heartbeat "
         "(other replicas cannot serve them until then)";
}

std::optional<std::string> TieredJobStore::create(const std::string& id,
                                                  const std::string& record) {
  if (auto refused = shared_.create(id, record)) {
    // Nobody learns the id of a refused job, but a write that timed out may land once Redis
    // runs again: its record would then sit there as a queued job that never runs.
    const std::lock_guard lock(mutex_);
    remember(id, true, false);
    return refused;
  }
  (void)local_.put_record(id, record);  // a memory store: never fails
  return std::nullopt;
}

bool TieredJobStore::put_rows(const std::string& id, std::size_t first,
                              const std::vector<std::string>& rows) {
  {
    const std::lock_guard lock(mutex_);
    if (disowned_locked(id)) return false;
  }
  const bool local = local_.put_rows(id, first, rows);
  {
    const std::lock_guard lock(mutex_);
    if (counts_.size() > kMaxCountedJobs) {
      // Forget the counts of jobs the local store has dropped (expired or removed).
      std::erase_if(counts_, [this](const auto& entry) { return !local_.record(entry.first); });
    }
    RowCounts& counts = counts_[id];
    if (local) counts.local = std::max(counts.local, first + rows.size());
    // In step with the shared store: these rows follow the ones it holds. Else they wait for
    // resync(), which sends every row it misses once, in order.
    if (local && (unsynced_.count(id) != 0 || counts.shared != first)) {
      unsynced_.insert(id);
      return true;
    }
  }
  const bool shared = shared_.put_rows(id, first, rows);
  if (!shared && lost_to_another(id)) return false;
  const std::lock_guard lock(mutex_);
  if (shared) {
    RowCounts& counts = counts_[id];
    counts.shared = std::max(counts.shared, first + rows.size());
  } else if (local) {
    fell_behind(id);
  }
  return local || shared;
}

bool TieredJobStore::keep_copy(const std::string& id, const std::string& record,
                               const std::vector<std::string>& rows) {
  {
    // Read from the shared store until the copy is whole: the local store takes the record
    // before the rows, and a reader meanwhile would find the final record without its rows.
    const std::lock_guard lock(mutex_);
    copying_.insert(id);
  }
  const bool kept = copy_here(id, record, rows);
  const std::lock_guard lock(mutex_);
  copying_.erase(id);
  if (kept) {
    counts_[id] = RowCounts{rows.size(), rows.size()};
    disowned_.erase(id);  // taken (back) over by this replica
  }
  return kept;
}

bool TieredJobStore::copy_here(const std::string& id, const std::string& record,
                               const std::vector<std::string>& rows) {
  if (!local_.put_record(id, record)) return false;
  for (std::size_t first = 0; first < rows.size(); first += kPublishChunk) {
    const std::vector<std::string> chunk(
        rows.begin() + static_cast<std::ptrdiff_t>(first),
        rows.begin() + static_cast<std::ptrdiff_t>(std::min(rows.size(), first + kPublishChunk)));
    if (!local_.put_rows(id, first, chunk)) {
      local_.remove(id);  // never a copy that lacks rows: it would be published as the job
      return false;
    }
  }
  return true;
}

bool TieredJobStore::copying(const std::string& id) {
  const std::lock_guard lock(mutex_);
  return copying_.count(id) != 0;
}

TieredJobStore::Published TieredJobStore::publish(const std::string& id) {
  // The record first: it counts no more rows than the local store held when it was written
  // (rows are stored before their record), so the rows sent below cover it.
  const auto record = local_.record(id);
  if (!record) {  // dropped here (expired, removed): nothing to publish
    const std::lock_guard lock(mutex_);
    counts_.erase(id);
    return Published::kDone;
  }
  // Every write below lands only while the job's owner mark allows it: one that another replica
  // took over meanwhile is dropped here.
  const auto failed = [&] { return lost_to_another(id) ? Published::kLost : Published::kFailed; };
  std::size_t from = 0;
  std::size_t to = 0;
  {
    const std::lock_guard lock(mutex_);
    const RowCounts& counts = counts_[id];
    from = std::min(counts.shared, counts.local);
    to = counts.local;
  }
  for (std::size_t at = from; at < to; at += kPublishChunk) {
    const std::size_t n = std::min(kPublishChunk, to - at);
    const auto rows = local_.rows(id, at, n);
    if (!rows || rows->size() != n) {
      // The local copy lost rows it had taken (it cannot, short of a bug): publish the record
      // anyway, so that readers refuse the table naming the missing rows instead of reading an
      // older state.
      spdlog::error(
          "batch job {}: the local job store holds {} of rows {} to {}; publishing its "
          "record without them",
          id, rows ? rows->size() : 0, at + 1, at + n);
      break;
    }
    if (!shared_.put_rows(id, at, *rows)) return failed();
    const std::lock_guard lock(mutex_);
    RowCounts& counts = counts_[id];
    counts.shared = std::max(counts.shared, at + n);
  }
  if (local_.cancel_requested(id) && !shared_.request_cancel(id)) return Published::kFailed;
  return shared_.put_record(id, *record) ? Published::kDone : failed();
}

void TieredJobStore::remember(const std::string& id, bool removed, bool told) {
  auto [it, added] = remembered_.try_emplace(id, removed);
  if (added) {
    remembered_order_.push_back(id);
  } else {
    it->second = it->second || removed;
  }
  if (told) {
    untold_.erase(id);
  } else {
    untold_.insert(id);
  }
  while (remembered_order_.size() > kRemembered) {
    remembered_.erase(remembered_order_.front());
    untold_.erase(remembered_order_.front());
    remembered_order_.pop_front();
  }
}

void TieredJobStore::tell_shared() {
  std::vector<std::pair<std::string, bool>> pending;
  {
    const std::lock_guard lock(mutex_);
    for (const std::string& id : untold_) pending.emplace_back(id, remembered_.at(id));
  }
  for (const auto& [id, removed] : pending) {
    if (!(removed ? shared_.remove(id) : shared_.request_cancel(id))) return;  // down: later
    const std::lock_guard lock(mutex_);
    untold_.erase(id);
  }
}

void TieredJobStore::resync() {
  const bool emptied = shared_.emptied_since_last_check();
  if (emptied) {
    const std::vector<std::string> ids = local_.ids();
    const std::lock_guard lock(mutex_);
    for (const std::string& id : ids) {
      counts_[id].shared = 0;  // the shared store holds none of its rows any more
      unsynced_.insert(id);
    }
    for (const auto& [id, removed] : remembered_) untold_.insert(id);
  }
  // Cancels and removals first: a job removed is not published again below.
  tell_shared();
  // Jobs whose record the shared store lost on its own (evicted under maxmemory, or deleted):
  // published again in full, as after an emptying. Jobs already waiting for resync are skipped.
  {
    std::vector<std::string> synced;
    for (const std::string& id : local_.ids()) {
      const std::lock_guard lock(mutex_);
      if (unsynced_.count(id) == 0) synced.push_back(id);
    }
    for (const std::string& id : shared_.records_missing_among(synced)) {
      spdlog::warn(
          "batch job {}: its record is missing from the shared job store; publishing it "
          "again",
          id);
      const std::lock_guard lock(mutex_);
      counts_[id].shared = 0;
      unsynced_.insert(id);
    }
  }
  // Jobs removed through another replica: this replica forgets its own copy (it would else
  // answer for the job and publish it again after an emptying).
  for (const std::string& id : shared_.removed_among(local_.ids())) {
    local_.remove(id);
    const std::lock_guard lock(mutex_);
    counts_.erase(id);
    unsynced_.erase(id);
    refused_.erase(id);
  }
  publish_unsynced();
}

void TieredJobStore::publish_unsynced() {
  std::vector<std::string> pending;
  {
    const std::lock_guard lock(mutex_);
    pending.assign(unsynced_.begin(), unsynced_.end());
  }
  for (const std::string& id : pending) {
    const Published published = publish(id);
    if (published == Published::kLost) continue;
    if (published == Published::kFailed) {
      // Still refused: the reason may have changed, and other replicas must keep reading the job
      // as alive (a full Redis takes the heartbeat's PEXPIRE though it refuses the record).
      (void)shared_.touch(id);
      const std::lock_guard lock(mutex_);
      fell_behind(id);
      continue;
    }
    const std::lock_guard lock(mutex_);
    unsynced_.erase(id);
    if (refused_.erase(id) != 0) {
      spdlog::info("batch job {}: the shared job store took its rows and record again", id);
    }
  }
}

JobStore::RecordLookup TieredJobStore::lookup_record(const std::string& id) {
  if (!copying(id)) {
    if (auto r = local_.record(id)) return {std::move(r), true};
  }
  return shared_.lookup_record(id);
}

std::optional<std::vector<std::string>> TieredJobStore::rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) {
  if (!copying(id)) {
    if (auto r = local_.rows(id, offset, count)) return r;
  }
  return shared_.rows(id, offset, count);
}

JobStore::SlotsRead TieredJobStore::read_slots(const std::string& id, std::size_t offset,
                                               std::size_t count) {
  if (!copying(id)) {
    if (auto r = local_.row_slots(id, offset, count)) return {std::move(r), {}};
  }
  return shared_.read_slots(id, offset, count);
}

std::optional<std::vector<std::optional<std::string>>> TieredJobStore::row_slots(
    const std::string& id, std::size_t offset, std::size_t count) {
  if (!copying(id)) {
    if (auto r = local_.row_slots(id, offset, count)) return r;
  }
  return shared_.row_slots(id, offset, count);
}

bool TieredJobStore::request_cancel(const std::string& id) {
  const bool local = local_.request_cancel(id);
  const bool shared = shared_.request_cancel(id);
  // A cancel only the local copy took is told to the shared store at the next resync, whatever
  // becomes of that copy: another replica may have taken the job over meanwhile, and this copy is
  // then dropped at its first refused write while the cancel was answered as accepted.
  if (local || shared) {
    const std::lock_guard lock(mutex_);
    remember(id, false, shared);
  }
  return local || shared;
}

bool TieredJobStore::cancel_requested(const std::string& id) {
  return local_.cancel_requested(id) || shared_.cancel_requested(id);
}

void TieredJobStore::drop_local(const std::string& id) {
  local_.remove(id);
  const std::lock_guard lock(mutex_);
  counts_.erase(id);
  unsynced_.erase(id);
  refused_.erase(id);
}

bool TieredJobStore::remove(const std::string& id) {
  const bool local = local_.remove(id);
  const bool shared = shared_.remove(id);
  const std::lock_guard lock(mutex_);
  counts_.erase(id);
  unsynced_.erase(id);
  refused_.erase(id);
  remember(id, true, shared);
  return local || shared;
}

}  // namespace slosh::service
