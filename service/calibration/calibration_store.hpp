#pragma once
// Stored calibrations: name -> the JSON text of POST /v1/calibrations' response, in a
// table `calibrations` of its own SQLite database (the plan cache's file is not touched). A plan,
// simulate or min-time request names one with options.model = "<name>". With a Redis cache the
// calibrations are shared through Redis too (key slosh:calibrations:<name>, no expiry), so that any
// replica plans with a calibration stored through another; the SQLite table keeps this replica's
// copy of each one it stored or read, answered while Redis is down.

#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "storage/redis_client.hpp"
#include "storage/sqlite_db.hpp"

namespace slosh::service {

class CalibrationStore {
 public:
  /// Opens (creating) the database at `path`; ":memory:" keeps it in memory. Throws
  /// std::runtime_error when it cannot be opened.
  explicit CalibrationStore(const std::string& path);
  CalibrationStore(const CalibrationStore&) = delete;
  CalibrationStore& operator=(const CalibrationStore&) = delete;

  /// Shares the calibrations through `redis` (the plan cache's client) from now on.
  void share_through(std::shared_ptr<RedisClient> redis) { redis_ = std::move(redis); }

  /// Stores (replacing) the calibration `name` here and, when shared, in Redis; false when the
  /// local write failed (a failed Redis write is logged: the other replicas then lack it).
  bool put(const std::string& name, const std::string& calibration);
  /// The JSON text stored under `name`: Redis's when shared and it answers (the latest, whichever
  /// replica stored it; kept here too), else this replica's copy; nullopt when neither has it.
  [[nodiscard]] std::optional<std::string> get(const std::string& name) const;

 private:
  [[nodiscard]] std::optional<std::string> get_local(const std::string& name) const;
  bool put_local(const std::string& name, const std::string& calibration) const;

  mutable std::mutex mutex_;
  SqliteDb db_;
  std::shared_ptr<RedisClient> redis_;
};

/// The calibrations database next to the plan cache: "<cache_path>.calibrations", or ":memory:"
/// when the cache is in memory (empty or ":memory:").
[[nodiscard]] std::string calibration_store_path(const std::string& cache_path);

}  // namespace slosh::service
