#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ for a bounded time each (make fuzz, make fuzz-smoke).
#   scripts/fuzz.sh BUILD_DIR SECONDS [TARGET...]      (default: every target)
# Each target starts from its seed corpus fuzz/corpus/<target> (read only) plus a working corpus
# in BUILD_DIR/fuzz-corpus/<target> (kept between runs, git-ignored). A crash, leak, UB report,
# timeout (FUZZ_TIMEOUT s per input) or out-of-memory (FUZZ_RSS_MB) stops that target, leaves the
# reproducer in fuzz-artifacts/<target>/ and makes the script exit 1 after the other targets ran.
# Replay a reproducer with: BUILD_DIR/fuzz/fuzz_<target> fuzz-artifacts/<target>/crash-...
set -uo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:?usage: scripts/fuzz.sh BUILD_DIR SECONDS [TARGET...]}
seconds=${2:?usage: scripts/fuzz.sh BUILD_DIR SECONDS [TARGET...]}
shift 2
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(plan_request simulate_request simulate_values batch_body recipe_csv recipe_jsonl)
fi
timeout_s=${FUZZ_TIMEOUT:-10}
rss_mb=${FUZZ_RSS_MB:-2048}
max_len=${FUZZ_MAX_LEN:-8192}
jobs_extra=${FUZZ_FLAGS:-}

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

failed=()
for target in "${targets[@]}"; do
  binary="$build_dir/fuzz/fuzz_$target"
  if [ ! -x "$binary" ]; then
    echo "fuzz: $binary is missing (make fuzz builds it)" >&2
    exit 2
  fi
  work="$build_dir/fuzz-corpus/$target"
  artifacts="fuzz-artifacts/$target"
  mkdir -p "$work" "$artifacts"
  dict=fuzz/json.dict
  [ "$target" = recipe_csv ] && dict=fuzz/csv.dict
  echo "fuzz: $target for ${seconds} s (timeout ${timeout_s} s/input, rss ${rss_mb} MB)"
  start=$(date +%s)
  # shellcheck disable=SC2086
  "$binary" -max_total_time="$seconds" -timeout="$timeout_s" -rss_limit_mb="$rss_mb" \
    -max_len="$max_len" -dict="$dict" -artifact_prefix="$artifacts/" -print_final_stats=1 \
    $jobs_extra "$work" "fuzz/corpus/$target" >"$build_dir/fuzz-$target.log" 2>&1
  rc=$?
  grep -E '^stat::(number_of_executed_units|new_units_added|peak_rss_mb)' \
    "$build_dir/fuzz-$target.log" | tr '\n' ' '
  echo "($(($(date +%s) - start)) s, exit $rc)"
  if [ $rc -ne 0 ]; then
    failed+=("$target")
    echo "fuzz: $target FAILED; log: $build_dir/fuzz-$target.log; reproducer(s):" >&2
    ls -1 "$artifacts" >&2
    grep -m1 -A40 -E '^==[0-9]+==ERROR|runtime error|^fuzz invariant|deadly signal|terminate called' \
      "$build_dir/fuzz-$target.log" >&2
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: ${#failed[@]} target(s) failed: ${failed[*]} (reproducers in fuzz-artifacts/)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} target(s) ran ${seconds} s each without a finding"
