#include "jobs/memory_job_store.hpp"

#include <spdlog/spdlog.h>

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

JobStore::RecordLookup MemoryJobStore::lookup_record(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const Entry* entry = find(id);
  if (entry == nullptr) return {std::nullopt, true};
  return {entry->record, true};
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

bool MemoryJobStore::remove(const std::string& id) {
  const std::lock_guard lock(mutex_);
  auto it = entries_.find(id);
  if (it != entries_.end()) erase(it);
  return true;
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

}  // namespace slosh::service
