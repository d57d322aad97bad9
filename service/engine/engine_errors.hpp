#pragma once
// The refusals the engine and its handlers share, worded once.

#include <string>

#include "slosh/api/error.hpp"

namespace slosh::service {

/// Seconds a client is told to wait after a 503 (the Retry-After header, and the overloaded
/// message's "retry after").
inline constexpr int kRetryAfterSeconds = 1;

/// Nobody waits for the solve any more (its answer is for a connection that is gone).
[[nodiscard]] inline api::ApiError cancelled_error() {
  return api::ApiError(api::ErrorCode::kCancelled, "",
                       "not solved: every client waiting for it closed the connection");
}

/// No cached plan of `key` (field "key"; the key is cut to 64 characters).
[[nodiscard]] inline api::ApiError plan_not_found(const std::string& key) {
  return api::ApiError(
      api::ErrorCode::kNotFound, "key",
      "no plan with key '" + key.substr(0, 64) + "': POST the recipe to /v1/plans first");
}

}  // namespace slosh::service
