#include "calibration/calibration_store.hpp"

#include <stdexcept>

#include <spdlog/spdlog.h>
#include <sqlite3.h>

namespace slosh::service {

namespace {

/// The Redis key of calibration `name`.
std::string redis_key(const std::string& name) {
  return "slosh:calibrations:" + name;
}

}  // namespace

std::string calibration_store_path(const std::string& cache_path) {
  if (cache_path.empty() || cache_path == ":memory:") return ":memory:";
  return cache_path + ".calibrations";
}

CalibrationStore::CalibrationStore(const std::string& path) {
  std::string why;
  if (!db_.open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, why)) {
    throw std::runtime_error("cannot open the calibration store '" + path + "': " + why);
  }
  db_.busy_timeout(5000);
  db_.execute(
      "CREATE TABLE IF NOT EXISTS calibrations (name TEXT PRIMARY KEY, body TEXT NOT NULL, "
      "created TEXT NOT NULL DEFAULT CURRENT_TIMESTAMP)",
      why);
  if (!why.empty()) {
    throw std::runtime_error("cannot create the calibrations table in '" + path + "': " + why);
  }
}

bool CalibrationStore::put(const std::string& name, const std::string& calibration) {
  if (redis_) {
    const auto reply = redis_->command({"SET", redis_key(name), calibration});
    if (!reply || reply->is_error()) {
      spdlog::warn(
          "calibration '{}' was stored on this replica only: the shared Redis did not "
          "take it ({})",
          name, reply ? reply->text : redis_->state().error);
    }
  }
  return put_local(name, calibration);
}

std::optional<std::string> CalibrationStore::get(const std::string& name) const {
  if (redis_) {
    const auto reply = redis_->command({"GET", redis_key(name)});
    if (reply && reply->type == RedisReply::Type::kString) {
      if (get_local(name) != reply->text) put_local(name, reply->text);
      return reply->text;
    }
  }
  return get_local(name);
}

bool CalibrationStore::put_local(const std::string& name, const std::string& calibration) const {
  const std::lock_guard lock(mutex_);
  SqliteStatement st =
      db_.prepare("INSERT OR REPLACE INTO calibrations (name, body) VALUES (?, ?)");
  if (!st) return false;
  st.bind_text(1, name);
  st.bind_text(2, calibration);
  return st.step() == SQLITE_DONE;
}

std::optional<std::string> CalibrationStore::get_local(const std::string& name) const {
  const std::lock_guard lock(mutex_);
  SqliteStatement st = db_.prepare("SELECT body FROM calibrations WHERE name = ?");
  if (!st) return std::nullopt;
  st.bind_text(1, name);
  if (st.step() != SQLITE_ROW) return std::nullopt;
  if (st.column_is_null(0)) return std::string("null");
  return std::string(st.column(0));
}

}  // namespace slosh::service
