#pragma once
// Stored calibrations: name -> the JSON text of POST /v1/calibrations' response, in a
// table `calibrations` of its own SQLite database (the plan cache's file is not touched). A plan,
// simulate or min-time request names one with options.model = "<name>".

#include <mutex>
#include <optional>
#include <string>

#include "storage/sqlite_db.hpp"

namespace slosh::service {

class CalibrationStore {
 public:
  /// Opens (creating) the database at `path`; ":memory:" keeps it in memory. Throws
  /// std::runtime_error when it cannot be opened.
  explicit CalibrationStore(const std::string& path);
  CalibrationStore(const CalibrationStore&) = delete;
  CalibrationStore& operator=(const CalibrationStore&) = delete;

  /// Stores (replacing) the calibration `name`; false when the write failed.
  bool put(const std::string& name, const std::string& calibration);
  /// The JSON text stored under `name`, or nullopt.
  [[nodiscard]] std::optional<std::string> get(const std::string& name) const;

 private:
  mutable std::mutex mutex_;
  SqliteDb db_;
};

/// The calibrations database next to the plan cache: "<cache_path>.calibrations", or ":memory:"
/// when the cache is in memory (empty or ":memory:").
[[nodiscard]] std::string calibration_store_path(const std::string& cache_path);

}  // namespace slosh::service
