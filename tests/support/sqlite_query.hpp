#pragma once
// Reads and writes a SQLite file through a connection of the test's own, beside the code under
// test: the store tests check what is on disk, not what the cache says, and damage it there.

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>

namespace slosh::test {

/// The first column of the first row of `sql` on the SQLite file `path`: "" for NULL, "<error>"
/// when the file cannot be opened or the statement yields no row.
inline std::string query(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  std::string result = "<error>";
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK &&
        sqlite3_step(stmt) == SQLITE_ROW) {
      const auto* text = sqlite3_column_text(stmt, 0);
      result = text == nullptr ? "" : reinterpret_cast<const char*>(text);
    }
    sqlite3_finalize(stmt);
  }
  sqlite3_close(db);
  return result;
}

/// Runs `sql` (statements without results) on the SQLite file `path` through a write connection
/// of the test's own; fails the test when it cannot.
inline void execute(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
  const std::string error = message == nullptr ? "" : message;
  sqlite3_free(message);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << error;
}

}  // namespace slosh::test
