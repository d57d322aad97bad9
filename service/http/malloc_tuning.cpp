#include "http/malloc_tuning.hpp"

#include <malloc.h>

namespace slosh::service {

void limit_malloc_arenas() {
  mallopt(M_ARENA_MAX, 4);
}

void trim_freed_memory() {
  malloc_trim(0);
}

}  // namespace slosh::service
