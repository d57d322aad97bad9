#pragma once
// What a test must know of the sanitizer build (make test-asan), where the product runs under
// AddressSanitizer and UBSan several times slower than in the release build. The test drivers
// are the same objects in both builds (tests/CMakeLists.txt), so it is asked at run time.

// Defined by AddressSanitizer's runtime, which only the sanitizer build links.
extern "C" __attribute__((weak)) void __asan_init();

namespace slosh::test {

/// Whether the product under test runs under AddressSanitizer.
inline bool product_sanitized() {
  return __asan_init != nullptr;
}

/// The solve budget [s] of a test that checks what a plan reaches, not how fast: `release_s` in
/// the release build, 20 times it under the sanitizers, where a budget met with room to spare in
/// release runs out on the instrumentation alone.
inline double solve_budget(double release_s) {
  return product_sanitized() ? 20.0 * release_s : release_s;
}

}  // namespace slosh::test

/// Skips the calling test under the sanitizers, saying `why`: a test whose check would test the
/// sanitizer there (an address-space limit), or one of the few that spend minutes there (50 times
/// their release time) planning time_domain along paths and tanks, code that faster tests of the
/// same suites run under the sanitizers too; the release run checks what these check
/// (docs/testing.md lists them).
#define SLOSH_SKIP_WHEN_SANITIZED(why) \
  if (::slosh::test::product_sanitized()) GTEST_SKIP() << "under the sanitizers: " << (why)
