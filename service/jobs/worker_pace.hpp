#pragma once
// The pace of a replica's two job workers (shared_job_worker.cpp runs the shared jobs' items,
// helper_worker.cpp helps with another replica's jobs): both poll the same streams, so they wait
// alike.

#include <chrono>

namespace slosh::service {

/// How long an idle worker waits before it looks for items again.
inline constexpr std::chrono::milliseconds kIdlePoll{100};
/// How long a busy worker waits for its oldest item before it looks at the others again.
inline constexpr std::chrono::milliseconds kItemWait{20};
/// How often a replica whose name another live replica uses says so in its log.
inline constexpr std::chrono::seconds kNameWarnEvery{60};

}  // namespace slosh::service
