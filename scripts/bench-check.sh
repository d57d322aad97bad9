#!/usr/bin/env bash
# The benchmark guard (SPEC §8): runs bench_check (one plan of each strategy without its own
# robustness report, the report, one response of each model, the cached serve path, and the
# calibration loop), then bench/bench_check.py compares each median, in calibration units, with
# bench/budgets.tsv and fails on more than 3 x a budget.
# Usage: scripts/bench-check.sh [build-dir] [--update]
#   --update   rewrite bench/budgets.tsv from this run (commit it) instead of checking.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
mode=check
for arg in "$@"; do
  case $arg in
    --update) mode=update ;;
    *) build=$arg ;;
  esac
done
binary="$build/bench/bench_check"
[ -x "$binary" ] || { echo "bench-check: $binary is missing (cmake --build $build --target bench_check)" >&2; exit 2; }
result=$(mktemp --suffix=.json)
trap 'rm -f "$result"' EXIT
# 5 repetitions of at least 50 ms each (one iteration for the slowest plans): medians of 5, about
# 7 s on 2 cores. The calibration loop is measured among them, in the same process, and the
# repetitions of all benchmarks run in a random interleaved order, so a change of the machine's
# load during the run reaches the calibration's median as it reaches the plans'.
"$binary" --benchmark_repetitions=5 --benchmark_min_time=0.05 \
  --benchmark_enable_random_interleaving=true \
  --benchmark_report_aggregates_only=true --benchmark_out="$result" \
  --benchmark_out_format=json > /dev/null
if [ "$mode" = update ]; then
  python3 bench/bench_check.py "$result" bench/budgets.tsv --update
else
  python3 bench/bench_check.py "$result" bench/budgets.tsv
fi
