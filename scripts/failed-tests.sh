#!/usr/bin/env bash
# Repeats what the failed tests of the last scripts/run-tests.sh in BUILD_DIR printed (at most
# MAX_LINES lines each) and the list ctest closed with; prints nothing when none failed.
#   scripts/failed-tests.sh BUILD_DIR [MAX_LINES]
set -uo pipefail
log="${1:?build dir}/Testing/run-tests.log"
max_lines=${2:-120}
[ -f "$log" ] || exit 0
grep -q 'The following tests FAILED' "$log" || exit 0
echo "failed-tests: the output of each failed test in $1"
awk -v max="$max_lines" '
  /^ *Start +[0-9]+:/ || /^[0-9]+\/[0-9]+ Test +#[0-9]+:/ {
    if (/Test +#[0-9]+:/ && !/ Passed / && !/Not Run|Skipped/) { printing = 1; n = 0; print; next }
    printing = 0
  }
  /^[0-9]+% tests passed/ { printing = 0 }
  printing && n < max { print; n++ }
' "$log"
sed -n '/The following tests FAILED/,$p' "$log"
