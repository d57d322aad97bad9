#pragma once
// Waiting for a solve on behalf of an HTTP client that may hang up: the one loop the plan,
// min-time and calibration endpoints share.

#include <algorithm>
#include <chrono>
#include <functional>
#include <future>

namespace slosh::service {

/// How often a request waiting for its solve checks whether its client is still there.
inline constexpr auto kClientPoll = std::chrono::milliseconds(100);

/// How a wait_for_client ended.
enum class WaitEnd {
  kReady,    ///< the future is ready
  kGone,     ///< `abandoned` said the client has gone (the future is not ready)
  kTimeout,  ///< `until` passed first
};

/// Waits for `future` (a std::future or std::shared_future) until `until`, asking `abandoned`
/// (optional: none = a client that never hangs up) every kClientPoll whether the client went away.
template <typename Future>
WaitEnd wait_for_client(const Future& future, std::chrono::steady_clock::time_point until,
                        const std::function<bool()>& abandoned) {
  for (;;) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= until) {
      return future.wait_for(std::chrono::seconds(0)) == std::future_status::ready
                 ? WaitEnd::kReady
                 : WaitEnd::kTimeout;
    }
    const auto slice = abandoned
                           ? std::min<std::chrono::steady_clock::duration>(kClientPoll, until - now)
                           : until - now;
    if (future.wait_for(slice) == std::future_status::ready) return WaitEnd::kReady;
    if (abandoned && abandoned()) return WaitEnd::kGone;
  }
}

/// The time point `seconds` from now.
inline std::chrono::steady_clock::time_point after(double seconds) {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
             std::chrono::duration<double>(seconds));
}

}  // namespace slosh::service
