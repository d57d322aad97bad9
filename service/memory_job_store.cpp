#include "memory_job_store.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

namespace slosh::service {

MemoryJobStore::MemoryJobStore(MemoryJobStoreLimits limits, std::function<Clock::time_point()> now)
    : limits_(limits), now_(std::move(now)) {}

void MemoryJobStore::erase(std::unordered_map<std::string, Entry>::iterator it) {
  bytes_ -= it->second.bytes;
  by_age_.erase(it->second.age);
  entries_.erase(it);
}

void MemoryJobStore::expire(Clock::time_point now, const std::string* keep) {
  const auto ttl =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits_.ttl_s));
  while (!by_age_.empty()) {
    auto it = entries_.find(by_age_.front());
    const bool too_many = entries_.size() > std::max<std::size_t>(1, limits_.max_jobs);
    if (!too_many && now - it->second.written < ttl) break;
    erase(it);
  }
  // Over the byte budget (checked on writes, which name the job written): the least recently
  // written go first, never the job being written (the job manager bounds it: a job whose own
  // results pass the budget stops).
  if (keep == nullptr) return;
  for (auto age = by_age_.begin(); bytes_ > limits_.max_bytes && age != by_age_.end();) {
    const auto next = std::next(age);
    if (*age != *keep) erase(entries_.find(*age));
    age = next;
  }
}

MemoryJobStore::Entry* MemoryJobStore::find(const std::string& id) {
  expire(now_());
  auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

void MemoryJobStore::touch(Entry& entry, Clock::time_point now) {
  entry.written = now;
  by_age_.splice(by_age_.end(), by_age_, entry.age);
}

bool MemoryJobStore::put_record(const std::string& id, const std::string& record) {
  const std::lock_guard lock(mutex_);
  const Clock::time_point now = now_();
  auto [it, added] = entries_.try_emplace(id);
  if (added) it->second.age = by_age_.insert(by_age_.end(), id);
  bytes_ = bytes_ - it->second.record.size() + record.size();
  it->second.bytes = it->second.bytes - it->second.record.size() + record.size();
  it->second.record = record;
  touch(it->second, now);
  expire(now, &id);
  return true;
}

std::optional<std::string> MemoryJobStore::record(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const Entry* entry = find(id);
  if (entry == nullptr) return std::nullopt;
  return entry->record;
}

bool MemoryJobStore::put_rows(const std::string& id, std::size_t first,
                              const std::vector<std::string>& rows) {
  const std::lock_guard lock(mutex_);
  Entry* entry = find(id);
  if (entry == nullptr) return false;  // rows follow the record: an unknown job takes none
  if (first > entry->rows.size()) return false;  // a gap: rows are kept contiguous here
  const std::size_t end = first + rows.size();
  if (entry->rows.size() < end) entry->rows.resize(end);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::string& slot = entry->rows[first + i];
    entry->bytes = entry->bytes - slot.size() + rows[i].size();
    bytes_ = bytes_ - slot.size() + rows[i].size();
    slot = rows[i];
  }
  const Clock::time_point now = now_();
  touch(*entry, now);
  expire(now, &id);
  return true;
}

std::optional<std::vector<std::string>> MemoryJobStore::rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) {
  const std::lock_guard lock(mutex_);
  const Entry* entry = find(id);
  if (entry == nullptr) return std::nullopt;
  const std::size_t begin = std::min(offset, entry->rows.size());
  const std::size_t end = begin + std::min(count, entry->rows.size() - begin);
  return std::vector<std::string>(entry->rows.begin() + static_cast<std::ptrdiff_t>(begin),
                                  entry->rows.begin() + static_cast<std::ptrdiff_t>(end));
}

bool MemoryJobStore::request_cancel(const std::string& id) {
  const std::lock_guard lock(mutex_);
  Entry* entry = find(id);
  if (entry == nullptr) return false;
  entry->cancel = true;
  return true;
}

bool MemoryJobStore::cancel_requested(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const Entry* entry = find(id);
  return entry != nullptr && entry->cancel;
}

void MemoryJobStore::remove(const std::string& id) {
  const std::lock_guard lock(mutex_);
  auto it = entries_.find(id);
  if (it == entries_.end()) return;
  erase(it);
}

std::vector<std::string> MemoryJobStore::ids() {
  const std::lock_guard lock(mutex_);
  expire(now_());
  return {by_age_.begin(), by_age_.end()};
}

std::size_t MemoryJobStore::size() {
  const std::lock_guard lock(mutex_);
  expire(now_());
  return entries_.size();
}

// ---- TieredJobStore ---------------------------------------------------------------------------

namespace {
/// Jobs whose row counts are kept before those the local store dropped are forgotten.
constexpr std::size_t kMaxCountedJobs = 1024;
}  // namespace

bool TieredJobStore::put_record(const std::string& id, const std::string& record) {
  const bool local = local_.put_record(id, record);
  const bool shared = shared_.put_record(id, record);
  if (local && !shared) {
    const std::lock_guard lock(mutex_);
    unsynced_.insert(id);
  }
  return local || shared;
}

bool TieredJobStore::publish(const std::string& id) {
  const auto record = local_.record(id);
  if (!record) return true;  // dropped here: nothing to publish
  RowCounts& counts = counts_[id];
  const std::size_t from = std::min(counts.shared, counts.local);
  const auto rows = local_.rows(id, from, counts.local - from);
  if (!rows || rows->size() != counts.local - from) return true;  // the local copy is gone
  if (!shared_.put_rows(id, from, *rows)) return false;
  counts.shared = counts.local;
  if (local_.cancel_requested(id) && !shared_.request_cancel(id)) return false;
  return shared_.put_record(id, *record);
}

void TieredJobStore::resync() {
  const bool emptied = shared_.emptied_since_last_check();
  std::vector<std::string> ids;
  if (emptied) ids = local_.ids();
  const std::lock_guard lock(mutex_);
  if (emptied) {
    for (const std::string& id : ids) {
      counts_[id].shared = 0;  // the shared store holds none of its rows any more
      unsynced_.insert(id);
    }
  }
  for (auto it = unsynced_.begin(); it != unsynced_.end();) {
    it = publish(*it) ? unsynced_.erase(it) : std::next(it);
  }
}

std::optional<std::string> TieredJobStore::record(const std::string& id) {
  return lookup_record(id).text;
}

JobStore::RecordLookup TieredJobStore::lookup_record(const std::string& id) {
  if (auto r = local_.record(id)) return {std::move(r), true};
  return shared_.lookup_record(id);
}

bool TieredJobStore::put_rows(const std::string& id, std::size_t first,
                              const std::vector<std::string>& rows) {
  const std::lock_guard lock(mutex_);
  if (counts_.size() > kMaxCountedJobs) {
    // Forget the counts of jobs the local store has dropped (expired or removed).
    std::erase_if(counts_, [this](const auto& entry) { return !local_.record(entry.first); });
  }
  RowCounts& counts = counts_[id];
  const bool local = local_.put_rows(id, first, rows);
  if (local) counts.local = std::max(counts.local, first + rows.size());
  // The shared store gets what it missed (from the local copy) before these rows. A write that
  // timed out may have landed: sending it again rewrites the same indexes (no duplicate).
  const std::size_t from = std::min(counts.shared, first);
  std::vector<std::string> pending;
  if (local && from < first) {
    if (auto earlier = local_.rows(id, from, first - from)) pending = std::move(*earlier);
  }
  const bool complete = !local || pending.size() == first - from;
  pending.insert(pending.end(), rows.begin(), rows.end());
  if (complete && shared_.put_rows(id, local ? from : first, pending)) {
    counts.shared = std::max(counts.shared, (local ? from : first) + pending.size());
    return true;
  }
  if (local) unsynced_.insert(id);
  return local;
}

std::optional<std::vector<std::string>> TieredJobStore::rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) {
  if (auto r = local_.rows(id, offset, count)) return r;
  return shared_.rows(id, offset, count);
}

bool TieredJobStore::request_cancel(const std::string& id) {
  const bool local = local_.request_cancel(id);
  const bool shared = shared_.request_cancel(id);
  return local || shared;
}

bool TieredJobStore::cancel_requested(const std::string& id) {
  return local_.cancel_requested(id) || shared_.cancel_requested(id);
}

void TieredJobStore::remove(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    counts_.erase(id);
    unsynced_.erase(id);
  }
  local_.remove(id);
  shared_.remove(id);
}

}  // namespace slosh::service
