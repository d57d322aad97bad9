#pragma once
// How the server keeps glibc's heap small under many connection threads and large bodies.

namespace slosh::service {

/// At most 4 malloc arenas (glibc's default is 8 per core, and up to 256 connection threads each
/// grabbing one fragments the heap), and freed memory kept until trim_freed_memory (not trimmed
/// at each free, under the arena's lock). Call once at start-up, before threads are started.
void limit_malloc_arenas();

/// Gives freed memory back to the system: a large batch response or series leaves glibc's arenas
/// holding hundreds of MB otherwise. Cheap enough to call every few seconds.
void trim_freed_memory();

}  // namespace slosh::service
