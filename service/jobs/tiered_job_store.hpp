#pragma once
// TieredJobStore: a local store in front of a shared one (Redis), so a replica keeps its own jobs
// while the shared store is down and reads other replicas' jobs from it.

#include <cstddef>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "jobs/job_store.hpp"

namespace slosh::service {

/// A local store in front of a shared one. Writes go to both; reads ask the local store first,
/// then the shared one. A job is created (create()) only once the shared store took its first
/// record; later writes succeed when the local store took them. A job whose write to the
/// shared store failed is "unsynced": its later records and rows go to the local store only, and
/// resync() sends the shared store what it misses (the rows in chunks, then the latest record),
/// so the shared copy never has a gap and nothing is sent twice. A job whose write the shared
/// store refused because another replica took it over (taken_over_by()) is dropped here, logged,
/// and never written here again: this replica then serves the new owner's state, not its own.
class TieredJobStore final : public JobStore {
 public:
  /// Both stores outlive this one.
  TieredJobStore(JobStore& local, JobStore& shared) : local_(local), shared_(shared) {}

  bool put_record(const std::string& id, const std::string& record) override;
  /// The shared store first: a job it did not take is refused (its reason returned) and kept
  /// nowhere, so that another replica never answers 404 for a job this one accepted. The write
  /// may have landed although it failed (a timeout): the job is removed from the shared store
  /// once it answers again (as remove() of a job the shared store did not take).
  [[nodiscard]] std::optional<std::string> create(const std::string& id,
                                                  const std::string& record) override;
  [[nodiscard]] RecordLookup lookup_record(const std::string& id) override;
  bool put_rows(const std::string& id, std::size_t first,
                const std::vector<std::string>& rows) override;
  [[nodiscard]] std::optional<std::vector<std::string>> rows(const std::string& id,
                                                             std::size_t offset,
                                                             std::size_t count) override;
  /// The local store's slots when it knows the job, else the shared store's.
  [[nodiscard]] std::optional<std::vector<std::optional<std::string>>> row_slots(
      const std::string& id, std::size_t offset, std::size_t count) override;
  /// As row_slots(), with the shared store's reason when it did not answer.
  [[nodiscard]] SlotsRead read_slots(const std::string& id, std::size_t offset,
                                     std::size_t count) override;
  [[nodiscard]] std::optional<std::int64_t> heartbeat_age_ms(const std::string& id) override {
    return shared_.heartbeat_age_ms(id);
  }
  [[nodiscard]] std::string last_write_failure() override { return shared_.last_write_failure(); }
  /// A job the shared store is behind on: its rows held here only and why (the shared store's
  /// refusal or failure, or its emptying).
  [[nodiscard]] std::optional<Unshared> unshared(const std::string& id) override;
  [[nodiscard]] std::string sharing_problem() override;
  [[nodiscard]] JobTraces traces(const std::string& id) override { return shared_.traces(id); }
  void drop_local(const std::string& id) override;
  /// Also remembered (the last kRemembered) and sent again after the shared store was emptied,
  /// so that a cancel this replica accepted reaches the owner that republishes the job.
  bool request_cancel(const std::string& id) override;
  [[nodiscard]] bool cancel_requested(const std::string& id) override;
  /// Removed here and in the shared store; remembered as request_cancel(), and sent again until
  /// the shared store took it: a DELETE accepted is never undone by the owner's republishing.
  bool remove(const std::string& id) override;
  [[nodiscard]] bool reachable() const override { return shared_.reachable(); }
  [[nodiscard]] bool recently_emptied() override { return shared_.recently_emptied(); }
  /// Written to the local store only; counted as held by the shared store too, so that only an
  /// emptying (or a lost record) sends it there again. Until the copy is whole, the job is read
  /// from the shared store (never the copy's record without its rows).
  bool keep_copy(const std::string& id, const std::string& record,
                 const std::vector<std::string>& rows) override;
  /// Also renews the heartbeat (touch()) of every job the shared store is still behind on, so
  /// that another replica reads it as alive although its record there is old.
  void resync() override;

  /// Rows sent to the shared store in one write when a job is published again.
  static constexpr std::size_t kPublishChunk = 500;
  /// Cancels and removals remembered for sending again after an emptying.
  static constexpr std::size_t kRemembered = 1024;

 private:
  // Writes the rows the shared store misses of job `id` (in chunks), its cancel flag and its
  // local record; kFailed when the shared store failed (tried again at the next resync), kLost
  // when another replica took the job over (lost_to_another()). The lock is not held: other
  // writes and reads go on meanwhile.
  enum class Published { kDone, kFailed, kLost };
  Published publish(const std::string& id);
  // keep_copy() without its bookkeeping: the record, then the rows; removed again on failure.
  bool copy_here(const std::string& id, const std::string& record,
                 const std::vector<std::string>& rows);
  // Whether keep_copy() of job `id` is under way (reads then go to the shared store).
  bool copying(const std::string& id);
  // Publishes every unsynced job; renews the heartbeat of those the shared store still refuses.
  void publish_unsynced();
  // After a failed write to the shared store: whether it refused it because another replica
  // took job `id` over; then the local copy is dropped, logged, and the job refused here from
  // now on. The lock is not held.
  bool lost_to_another(const std::string& id);
  // Whether job `id` was lost to another replica (lost_to_another()); the lock is held.
  [[nodiscard]] bool disowned_locked(const std::string& id) const {
    return disowned_.count(id) != 0;
  }
  // Sends the remembered cancels and removals the shared store has not taken.
  void tell_shared();
  // Remembers a cancel (`removed` false) or a removal of `id`; the lock is held.
  void remember(const std::string& id, bool removed, bool told);
  // Marks `id` unsynced after a failed write to the shared store, keeping the store's reason
  // (logged when the job was in step until now); the lock is held.
  void fell_behind(const std::string& id);

  JobStore& local_;
  JobStore& shared_;
  std::mutex mutex_;
  // Rows of each job written here: in total (the local store has them all) and in the shared one.
  struct RowCounts {
    std::size_t local{0};
    std::size_t shared{0};
  };
  std::unordered_map<std::string, RowCounts> counts_;
  std::unordered_set<std::string> unsynced_;  // jobs the shared store is behind on
  // Of the unsynced jobs, those whose write the shared store refused or failed: the reason.
  std::unordered_map<std::string, std::string> refused_;
  // Cancels (false) and removals (true) accepted here, oldest first, and those not yet taken by
  // the shared store.
  std::unordered_map<std::string, bool> remembered_;
  std::list<std::string> remembered_order_;
  std::unordered_set<std::string> untold_;
  // Jobs another replica took over (their writes here refused): at most kRemembered.
  std::unordered_set<std::string> disowned_;
  std::unordered_set<std::string> copying_;  // keep_copy() under way
};

}  // namespace slosh::service
