#!/usr/bin/env bash
# Runs every test through ctest and closes with one summary line "N passed, N failed".
#   scripts/run-tests.sh [BUILD_DIR] [CTEST_ARGS...]   (e.g. -E REGEX leaves tests out)
# ctest's whole output is also kept in BUILD_DIR/Testing/run-tests.log, so that .ci/run can repeat
# the failed tests' output at the end of a long run, where a truncated log still shows it.
set -uo pipefail
build_dir=${1:-build}
shift || true
mkdir -p "$build_dir/Testing"
log="$build_dir/Testing/run-tests.log"
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" --timeout 600 "$@" 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
summary=$(grep -E '[0-9]+% tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -1)
if [ -z "$summary" ]; then
  echo "run-tests: ctest printed no summary" >&2
  exit 1
fi
total=$(sed -E 's/.*out of ([0-9]+).*/\1/' <<<"$summary")
failed=$(sed -E 's/.* ([0-9]+) tests failed.*/\1/' <<<"$summary")
echo "$((total - failed)) passed, ${failed} failed"
if [ "$total" -eq 0 ]; then
  echo "run-tests: no test ran" >&2
  exit 1
fi
exit "$rc"
