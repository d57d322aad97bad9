#include "calibration_store.hpp"

#include <stdexcept>

#include <sqlite3.h>

#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"

namespace slosh::service {

namespace {

struct Statement {
  sqlite3_stmt* s{nullptr};
  Statement(sqlite3* db, const char* sql) {
    if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) s = nullptr;
  }
  ~Statement() { sqlite3_finalize(s); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
};

}  // namespace

std::string calibration_store_path(const std::string& cache_path) {
  if (cache_path.empty() || cache_path == ":memory:") return ":memory:";
  return cache_path + ".calibrations";
}

CalibrationStore::CalibrationStore(const std::string& path) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string why = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw std::runtime_error("cannot open the calibration store '" + path + "': " + why);
  }
  sqlite3_busy_timeout(db_, 5000);
  char* error = nullptr;
  if (sqlite3_exec(db_,
                   "CREATE TABLE IF NOT EXISTS calibrations (name TEXT PRIMARY KEY, body TEXT NOT "
                   "NULL, created TEXT NOT NULL DEFAULT CURRENT_TIMESTAMP)",
                   nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string why = error != nullptr ? error : "unknown error";
    sqlite3_free(error);
    sqlite3_close(db_);
    throw std::runtime_error("cannot create the calibrations table in '" + path + "': " + why);
  }
}

CalibrationStore::~CalibrationStore() {
  sqlite3_close(db_);
}

bool CalibrationStore::put(const std::string& name, const nlohmann::json& calibration) {
  const std::lock_guard lock(mutex_);
  Statement st(db_, "INSERT OR REPLACE INTO calibrations (name, body) VALUES (?, ?)");
  if (st.s == nullptr) return false;
  const std::string body = api::dump_json(calibration);
  sqlite3_bind_text(st.s, 1, name.c_str(), static_cast<int>(name.size()), SQLITE_TRANSIENT);
  sqlite3_bind_text(st.s, 2, body.c_str(), static_cast<int>(body.size()), SQLITE_TRANSIENT);
  return sqlite3_step(st.s) == SQLITE_DONE;
}

std::optional<nlohmann::json> CalibrationStore::get(const std::string& name) const {
  const std::lock_guard lock(mutex_);
  Statement st(db_, "SELECT body FROM calibrations WHERE name = ?");
  if (st.s == nullptr) return std::nullopt;
  sqlite3_bind_text(st.s, 1, name.c_str(), static_cast<int>(name.size()), SQLITE_TRANSIENT);
  if (sqlite3_step(st.s) != SQLITE_ROW) return std::nullopt;
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(st.s, 0));
  return nlohmann::json::parse(text != nullptr ? text : "null", nullptr, false);
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
