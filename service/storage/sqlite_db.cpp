#include "storage/sqlite_db.hpp"

#include <climits>
#include <utility>

#include <sqlite3.h>

namespace slosh::service {

SqliteStatement::~SqliteStatement() {
  sqlite3_finalize(stmt_);
}

SqliteStatement::SqliteStatement(SqliteStatement&& other) noexcept
    : stmt_(std::exchange(other.stmt_, nullptr)) {}

SqliteStatement& SqliteStatement::operator=(SqliteStatement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    stmt_ = std::exchange(other.stmt_, nullptr);
  }
  return *this;
}

int SqliteStatement::bind_text(int index, std::string_view text, bool copy) {
  if (text.size() > static_cast<std::size_t>(INT_MAX)) return SQLITE_TOOBIG;
  return sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()),
                           copy ? SQLITE_TRANSIENT : SQLITE_STATIC);
}

int SqliteStatement::bind_int64(int index, std::int64_t value) {
  return sqlite3_bind_int64(stmt_, index, value);
}

int SqliteStatement::step() {
  return sqlite3_step(stmt_);
}

std::string_view SqliteStatement::column(int index) const {
  const auto* bytes = static_cast<const char*>(sqlite3_column_blob(stmt_, index));
  if (bytes == nullptr) return {};
  return {bytes, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, index))};
}

bool SqliteStatement::column_is_null(int index) const {
  return sqlite3_column_type(stmt_, index) == SQLITE_NULL;
}

void SqliteStatement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

SqliteDb::~SqliteDb() {
  close();
}

bool SqliteDb::open(const std::string& path, int flags, std::string& error) {
  close();
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) == SQLITE_OK) return true;
  error = message();
  close();  // a handle whose open failed still holds memory
  return false;
}

void SqliteDb::close() {
  sqlite3_close_v2(db_);
  db_ = nullptr;
}

std::string SqliteDb::message() const {
  return db_ == nullptr ? std::string("out of memory") : std::string(sqlite3_errmsg(db_));
}

void SqliteDb::busy_timeout(int milliseconds) const {
  sqlite3_busy_timeout(db_, milliseconds);
}

bool SqliteDb::read_only() const {
  return sqlite3_db_readonly(db_, "main") == 1;
}

SqliteStatement SqliteDb::prepare(std::string_view sql, bool persistent) const {
  sqlite3_stmt* stmt = nullptr;
  if (sql.size() > static_cast<std::size_t>(INT_MAX) ||
      sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()),
                         persistent ? SQLITE_PREPARE_PERSISTENT : 0, &stmt, nullptr) != SQLITE_OK) {
    sqlite3_finalize(stmt);
    return SqliteStatement();
  }
  return SqliteStatement(stmt);
}

void SqliteDb::execute(std::string_view sql, std::string& error) const {
  char* text = nullptr;
  if (sqlite3_exec(db_, std::string(sql).c_str(), nullptr, nullptr, &text) != SQLITE_OK) {
    error = text == nullptr ? message() : std::string(text);
  }
  sqlite3_free(text);
}

std::string SqliteDb::query_text(std::string_view sql, std::string& error) const {
  SqliteStatement statement = prepare(sql);
  std::string result;
  if (!statement) {
    error = message();
    return result;
  }
  int rc = statement.step();
  while (rc == SQLITE_ROW) {
    if (result.empty() && !statement.column_is_null(0)) result = statement.column(0);
    rc = statement.step();
  }
  if (rc != SQLITE_DONE) error = message();
  return result;
}

}  // namespace slosh::service
