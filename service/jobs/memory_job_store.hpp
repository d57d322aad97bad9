#pragma once
// The job store of one process (service/jobs/job_store.hpp): MemoryJobStore keeps jobs in memory,
// bounded by age and count.

#include <chrono>
#include <cstddef>
#include <functional>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "jobs/job_store.hpp"

namespace slosh::service {

/// Bounds of a MemoryJobStore.
struct MemoryJobStoreLimits {
  /// A job whose record was not written for this long is forgotten [s]. A job that runs rewrites
  /// its record at least every second (its heartbeat), so only finished (or abandoned) jobs age.
  /// Default 3600 s (config batch_job_ttl_s).
  double ttl_s{3600.0};
  /// Most jobs kept; beyond, the least recently written go first (finished jobs, as running ones
  /// are rewritten every second). Default 128.
  std::size_t max_jobs{128};
  /// Most bytes of records and rows kept; beyond, the least recently written jobs other than the
  /// one being written go first. Default 256 MiB (config batch_jobs_bytes).
  std::size_t max_bytes{std::size_t{256} << 20};
};

/// JobStore in memory, thread-safe. Writes never fail.
class MemoryJobStore final : public JobStore {
 public:
  using Clock = std::chrono::steady_clock;
  /// `now` is the clock (tests pass their own to age jobs without waiting).
  explicit MemoryJobStore(MemoryJobStoreLimits limits = {},
                          std::function<Clock::time_point()> now = Clock::now);

  bool put_record(const std::string& id, const std::string& record) override;
  [[nodiscard]] RecordLookup lookup_record(const std::string& id) override;
  bool put_rows(const std::string& id, std::size_t first,
                const std::vector<std::string>& rows) override;
  [[nodiscard]] std::optional<std::vector<std::string>> rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) override;
  bool request_cancel(const std::string& id) override;
  [[nodiscard]] bool cancel_requested(const std::string& id) override;
  bool remove(const std::string& id) override;

  [[nodiscard]] std::vector<std::string> ids() override;

  /// Jobs held now (after expiry).
  [[nodiscard]] std::size_t size();

 private:
  struct Entry {
    std::string record;
    std::vector<std::string> rows;
    bool cancel{false};
    std::size_t bytes{0};  // of the record and the rows
    Clock::time_point written;
    std::list<std::string>::iterator age;  // position in by_age_
  };
  // Drops expired entries, the oldest beyond max_jobs and, beyond max_bytes, the oldest other
  // than `keep` (the job being written); the lock is held.
  void expire(Clock::time_point now, const std::string* keep = nullptr);
  void erase(std::unordered_map<std::string, Entry>::iterator it);
  // The entry of `id` or nullptr (expired entries dropped first); the lock is held.
  Entry* find(const std::string& id);
  // Marks `entry` written now (moves it to the young end).
  void touch(Entry& entry, Clock::time_point now);

  MemoryJobStoreLimits limits_;
  std::function<Clock::time_point()> now_;
  std::mutex mutex_;
  std::unordered_map<std::string, Entry> entries_;
  std::list<std::string> by_age_;  // ids, least recently written first
  std::size_t bytes_{0};           // of every entry
};

}  // namespace slosh::service
