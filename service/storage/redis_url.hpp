#pragma once
// Redis URLs (redis://[:password@]host:port[/db]): the one parser and the one test of whether a
// setting names a Redis server or a SQLite file, for the cache, the job store and their checks.

#include <string>

namespace slosh::service {

/// The parts of redis://[:password@]host:port[/db].
struct RedisUrl {
  std::string host;
  int port{6379};
  int db{0};
  std::string password;  ///< empty = no AUTH
  /// The URL as it may be logged and shown: the password replaced by "***".
  [[nodiscard]] std::string display() const;
};

/// Whether `text` names a Redis server (starts with "redis://") rather than a SQLite file.
[[nodiscard]] bool is_redis_url(const std::string& text);

/// Parses redis://host:port/db (port 1 to 65535, db 0 to 15; ":port" and "/db" may be omitted:
/// 6379 and 0) and redis://:password@host:port/db. Throws std::invalid_argument with a sentence
/// naming the value and what is wrong, e.g. "redis://h:x/0 is not a Redis URL: the port 'x' is
/// not a number from 1 to 65535 (expected redis://host:port/db or
/// redis://:password@host:port/db)"; the password is never part of the message.
[[nodiscard]] RedisUrl parse_redis_url(const std::string& text);

}  // namespace slosh::service
