#pragma once
// Where batch jobs (POST /v1/batches, SPEC §13) keep their state, so that any replica can answer
// for a job: a memory store in one process, a Redis store shared by the replicas.
//
// The store holds opaque text: the job's record (its state as the job manager renders it, JSON)
// and its result rows in item order (one per recipe, in the job's row format). The job manager
// owns the meaning; a store only keeps, bounds and expires them.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace slosh::service {

class JobStore {
 public:
  virtual ~JobStore() = default;

  /// Writes the record of job `id`, replacing the previous one (a new job's first write creates
  /// it). False when the store could not be written (the caller keeps its own copy).
  virtual bool put_record(const std::string& id, const std::string& record) = 0;
  /// The record of job `id`; nullopt when the store does not know it or cannot be read.
  [[nodiscard]] virtual std::optional<std::string> record(const std::string& id) = 0;

  /// Appends result rows of job `id` after the ones already stored (rows arrive in item order).
  /// False when the store could not be written.
  virtual bool append_rows(const std::string& id, const std::vector<std::string>& rows) = 0;
  /// Rows [offset, offset + count) of job `id` (fewer at the end); nullopt when the store does
  /// not know the job or cannot be read.
  [[nodiscard]] virtual std::optional<std::vector<std::string>> rows(const std::string& id,
                                                                     std::size_t offset,
                                                                     std::size_t count) = 0;

  /// Asks the replica that runs job `id` to cancel it (it polls cancel_requested()). False when
  /// the store could not be written.
  virtual bool request_cancel(const std::string& id) = 0;
  [[nodiscard]] virtual bool cancel_requested(const std::string& id) = 0;

  /// Forgets job `id` (its record, rows and cancel flag).
  virtual void remove(const std::string& id) = 0;

  /// False while the store, or the shared level of a tiered one, cannot be asked (Redis down):
  /// a job it does not answer for may then run on another replica. Default true.
  [[nodiscard]] virtual bool reachable() const { return true; }
};

}  // namespace slosh::service
