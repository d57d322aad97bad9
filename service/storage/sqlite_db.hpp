#pragma once
// The one wrapper over SQLite's C API that every SQLite file of the service goes through (the plan
// store and the calibrations): a connection that closes itself, prepared statements that finalize
// themselves, and failures reported as SQLite's own message, so that no caller frees a handle by
// hand on each error path.

#include <cstdint>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace slosh::service {

/// A prepared statement; finalized when destroyed. Empty (false) when preparing it failed.
class SqliteStatement {
 public:
  SqliteStatement() = default;
  ~SqliteStatement();
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement& operator=(SqliteStatement&& other) noexcept;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  explicit operator bool() const { return stmt_ != nullptr; }

  /// Binds `text` to the 1-based parameter `index`. With copy = false the caller keeps `text`
  /// alive until the statement is stepped and reset. Returns SQLite's result code (SQLITE_TOOBIG
  /// for text over INT_MAX bytes).
  int bind_text(int index, std::string_view text, bool copy = true);
  int bind_int64(int index, std::int64_t value);
  /// One step: SQLITE_ROW, SQLITE_DONE or an error code.
  int step();
  /// The bytes of column `index` of the current row (empty for NULL); valid until the next step.
  [[nodiscard]] std::string_view column(int index) const;
  [[nodiscard]] bool column_is_null(int index) const;
  /// Ready for the next use: reset and bindings cleared.
  void reset();

 private:
  friend class SqliteDb;
  explicit SqliteStatement(sqlite3_stmt* stmt) : stmt_(stmt) {}
  sqlite3_stmt* stmt_{nullptr};
};

/// A connection; closed when destroyed (statements still alive keep it until they are finalized).
class SqliteDb {
 public:
  SqliteDb() = default;
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  /// Opens `path` with SQLite's open `flags`; on failure the connection stays closed and `error`
  /// holds SQLite's reason.
  bool open(const std::string& path, int flags, std::string& error);
  void close();
  explicit operator bool() const { return db_ != nullptr; }

  /// SQLite's message for the last failure ("out of memory" when there is no connection).
  [[nodiscard]] std::string message() const;
  void busy_timeout(int milliseconds) const;
  [[nodiscard]] bool read_only() const;
  /// Prepares `sql`; persistent for statements kept for the connection's life. Empty on failure
  /// (message() says why).
  [[nodiscard]] SqliteStatement prepare(std::string_view sql, bool persistent = false) const;
  /// Runs `sql` (one or more statements without results); sets `error` on failure.
  void execute(std::string_view sql, std::string& error) const;
  /// Runs `sql` and returns the first column of its first row ("" when there is none); sets
  /// `error` on failure.
  std::string query_text(std::string_view sql, std::string& error) const;

 private:
  sqlite3* db_{nullptr};
};

}  // namespace slosh::service
