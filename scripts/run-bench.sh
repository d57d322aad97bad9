#!/usr/bin/env bash
# Runs the Google Benchmark targets (single-threaded figures for the README).
set -euo pipefail
build_dir=${1:-build}
for b in "$build_dir"/bench/bench_*; do
  [ -x "$b" ] || continue
  echo "== $(basename "$b")"
  "$b" --benchmark_min_time=0.2 --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    "${@:2}"
done
