#pragma once
// The levels of the plan cache a hit can come from (metrics label `level`).

#include <string_view>

namespace slosh::service {

enum class CacheLevel {
  kMemory,  ///< the in-memory LRU of this replica
  kLocal,   ///< the SQLite file of this replica (or machine)
  kShared,  ///< the Redis shared by the replicas
};

/// The metrics label of `level`: memory, sqlite or redis.
[[nodiscard]] constexpr std::string_view level_name(CacheLevel level) {
  return level == CacheLevel::kMemory ? "memory" : level == CacheLevel::kLocal ? "sqlite" : "redis";
}

}  // namespace slosh::service
