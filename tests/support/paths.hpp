#pragma once
// Where the tests find the built binary and the source tree. Every test file sees these through
// a forced include (tests/CMakeLists.txt), and only tests/support/paths.cpp is compiled with the
// absolute paths: the other test files compile to the same bytes in every checkout, so a second
// clone's test build is answered by ccache.

namespace slosh::test {
/// The `slosh` binary under test (absolute path).
const char* binary_path();
/// The repository root (absolute path).
const char* source_dir();
}  // namespace slosh::test

#define SLOSH_BINARY (::slosh::test::binary_path())
#define SLOSH_SOURCE_DIR (::slosh::test::source_dir())
