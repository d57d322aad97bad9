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

# One target per core side by side (FUZZ_PARALLEL, default nproc): each target's time budget is
# wall-clock time of its own process, so running them together keeps every target's budget while
# the whole run takes ceil(targets / cores) budgets instead of one per target.
parallel=${FUZZ_PARALLEL:-$(nproc)}
for target in "${targets[@]}"; do
  if [ ! -x "$build_dir/fuzz/fuzz_$target" ]; then
    echo "fuzz: $build_dir/fuzz/fuzz_$target is missing (make fuzz builds it)" >&2
    exit 2
  fi
done

# Runs one target and leaves its one-line summary in $build_dir/fuzz-$target.summary and its exit
# status in $build_dir/fuzz-$target.rc.
run_target() {
  local target=$1
  local binary="$build_dir/fuzz/fuzz_$target"
  local work="$build_dir/fuzz-corpus/$target"
  local artifacts="fuzz-artifacts/$target"
  mkdir -p "$work" "$artifacts"
  local dict=fuzz/json.dict
  [ "$target" = recipe_csv ] && dict=fuzz/csv.dict
  local start
  start=$(date +%s)
  # shellcheck disable=SC2086
  "$binary" -max_total_time="$seconds" -timeout="$timeout_s" -rss_limit_mb="$rss_mb" \
    -max_len="$max_len" -dict="$dict" -artifact_prefix="$artifacts/" -print_final_stats=1 \
    $jobs_extra "$work" "fuzz/corpus/$target" >"$build_dir/fuzz-$target.log" 2>&1
  local rc=$?
  {
    grep -E '^stat::(number_of_executed_units|new_units_added|peak_rss_mb)' \
      "$build_dir/fuzz-$target.log" | tr '\n' ' '
    echo "($(($(date +%s) - start)) s, exit $rc)"
  } >"$build_dir/fuzz-$target.summary"
  echo "$rc" >"$build_dir/fuzz-$target.rc"
}

running=0
for target in "${targets[@]}"; do
  echo "fuzz: $target for ${seconds} s (timeout ${timeout_s} s/input, rss ${rss_mb} MB)"
  run_target "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait

failed=()
for target in "${targets[@]}"; do
  echo "fuzz: $target: $(cat "$build_dir/fuzz-$target.summary")"
  if [ "$(cat "$build_dir/fuzz-$target.rc")" -ne 0 ]; then
    failed+=("$target")
    echo "fuzz: $target FAILED; log: $build_dir/fuzz-$target.log; reproducer(s):" >&2
    ls -1 "fuzz-artifacts/$target" >&2
    grep -m1 -A40 -E '^==[0-9]+==ERROR|runtime error|^fuzz invariant|deadly signal|terminate called' \
      "$build_dir/fuzz-$target.log" >&2
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: ${#failed[@]} target(s) failed: ${failed[*]} (reproducers in fuzz-artifacts/)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} target(s) ran ${seconds} s each without a finding"
