#include "calibration/calibration_store.hpp"

#include <stdexcept>

#include <sqlite3.h>

#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"

namespace slosh::service {

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

bool CalibrationStore::put(const std::string& name, const nlohmann::json& calibration) {
  const std::lock_guard lock(mutex_);
  SqliteStatement st =
      db_.prepare("INSERT OR REPLACE INTO calibrations (name, body) VALUES (?, ?)");
  if (!st) return false;
  const std::string body = api::dump_json(calibration);
  st.bind_text(1, name);
  st.bind_text(2, body);
  return st.step() == SQLITE_DONE;
}

std::optional<nlohmann::json> CalibrationStore::get(const std::string& name) const {
  const std::lock_guard lock(mutex_);
  SqliteStatement st = db_.prepare("SELECT body FROM calibrations WHERE name = ?");
  if (!st) return std::nullopt;
  st.bind_text(1, name);
  if (st.step() != SQLITE_ROW) return std::nullopt;
  if (st.column_is_null(0)) return nlohmann::json(nullptr);
  return nlohmann::json::parse(st.column(0), nullptr, false);
}

nlohmann::json resolve_model_name(nlohmann::json body, const CalibrationStore& store) {
  if (!body.is_object() || !body.contains("options") || !body["options"].is_object()) return body;
  nlohmann::json& options = body["options"];
  if (!options.contains("model") || !options["model"].is_string()) return body;
  const std::string name = options["model"].get<std::string>();
  api::validate_calibration_name(name, "options.model");
  const std::optional<nlohmann::json> stored = store.get(name);
  if (!stored || !stored->contains("model")) {
    throw api::ApiError(api::ErrorCode::kNotFound, "options.model",
                        "options.model = \"" + name +
                            "\": no stored calibration of that name (POST /v1/calibrations "
                            "with \"name\" stores one)");
  }
  options["model"] = (*stored)["model"];
  return body;
}

}  // namespace slosh::service
