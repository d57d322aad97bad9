#include "http/malloc_tuning.hpp"

#include <malloc.h>

namespace slosh::service {

namespace {

/// Free memory an arena keeps at its top between two trims [bytes].
constexpr int kTrimThreshold = 64 << 20;

}  // namespace

void limit_malloc_arenas() {
  mallopt(M_ARENA_MAX, 4);
  // Freed memory goes back to the system in trim_freed_memory, every few seconds: without this,
  // a free that leaves more than 128 kB at an arena's top trims it at once (madvise or brk under
  // the arena's lock), every few dozen requests of a 40 kB plan, and the connection threads
  // sharing the arena wait for it.
  mallopt(M_TRIM_THRESHOLD, kTrimThreshold);
}

void trim_freed_memory() {
  malloc_trim(0);
}

}  // namespace slosh::service
