#!/usr/bin/env python3
"""The benchmark guard of `make bench-check`: compares a bench_check run with the committed budgets.

Each benchmark's median CPU time is divided by the median CPU time of the run's own `calibration`
loop (a fixed floating-point workload): a "calibration unit" is the same amount of work on a fast
or a slow, an idle or a shared machine, so the quotients stay put where raw times would not. A
benchmark fails when its quotient is more than FACTOR (3) times its budget in the budget file.

  bench_check.py RESULT.json BUDGETS.tsv            check (exit 1 on a regression)
  bench_check.py RESULT.json BUDGETS.tsv --update   rewrite BUDGETS.tsv from RESULT.json

RESULT.json: Google Benchmark's JSON output with repetitions (the `median` aggregates are used).
BUDGETS.tsv: `name<TAB>budget` lines (calibration units), `#` comments.
"""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys

FACTOR = 3.0
CALIBRATION = "calibration"
UNIT_SECONDS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def medians(result_path):
    """Median CPU time [s] of each benchmark of a Google Benchmark JSON file, and the error of each
    benchmark that called SkipWithError (such a benchmark has error runs and no median)."""
    with open(result_path, encoding="utf-8") as f:
        result = json.load(f)
    out = {}
    errors = {}
    for b in result.get("benchmarks", []):
        if b.get("error_occurred"):
            errors.setdefault(b["run_name"], b.get("error_message", ""))
            continue
        if b.get("run_type") != "aggregate" or b.get("aggregate_name") != "median":
            continue
        out[b["run_name"]] = b["cpu_time"] * UNIT_SECONDS[b.get("time_unit", "ns")]
    # A benchmark that failed in one repetition is not measured, whatever the others gave.
    return {name: t for name, t in out.items() if name not in errors}, errors


def units(result_path):
    """Each benchmark's median in calibration units (the calibration loop itself excluded), the
    calibration median [s], and the errors of the benchmarks that failed."""
    m, errors = medians(result_path)
    if CALIBRATION not in m or m[CALIBRATION] <= 0:
        raise SystemExit(f"bench-check: {result_path} has no median of the '{CALIBRATION}' loop")
    measured = {name: t / m[CALIBRATION] for name, t in m.items() if name != CALIBRATION}
    return measured, m[CALIBRATION], errors


def read_budgets(path):
    budgets = {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            fields = line.split("\t")
            if len(fields) != 2:
                raise SystemExit(f"bench-check: {path}:{number}: expected 'name<TAB>budget'")
            budgets[fields[0]] = float(fields[1])
    return budgets


def check(result_path, budgets_path, factor):
    measured, _, errors = units(result_path)
    budgets = read_budgets(budgets_path)
    failures = [f"bench-check: {name} failed: {errors[name]}" for name in sorted(errors)]
    for name in sorted(budgets):
        if name not in measured and name not in errors:
            failures.append(f"bench-check: {name} has a budget but was not measured")
    for name in sorted(measured):
        value = measured[name]
        budget = budgets.get(name)
        if budget is None:
            failures.append(f"bench-check: {name} has no budget in {budgets_path}")
            continue
        status = "FAIL" if value > factor * budget else "ok"
        print(f"{status:4} {name:28} {value:12.4g} units  budget {budget:10.4g}  "
              f"({value / budget:5.2f} x)")
        if status == "FAIL":
            failures.append(
                f"bench-check: {name} takes {value:.4g} calibration units, more than {factor:g} x "
                f"its budget of {budget:.4g}")
    if failures:
        for line in failures:
            print(line, file=sys.stderr)
        print("bench-check: when a change is meant to cost more, rewrite the budgets with "
              "`make bench-budgets` and commit bench/budgets.tsv", file=sys.stderr)
        return 1
    print(f"bench-check: {len(measured)} benchmarks within {factor:g} x their budgets")
    return 0


def update(result_path, budgets_path):
    measured, calibration, errors = units(result_path)
    if errors:
        # Budgets without the failed benchmarks would pass a run where they fail again.
        for name in sorted(errors):
            print(f"bench-check: {name} failed: {errors[name]}", file=sys.stderr)
        print(f"bench-check: {budgets_path} left as it was", file=sys.stderr)
        return 1
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=False).stdout.strip() or "unknown"
    except OSError:
        commit = "unknown"
    try:
        load = " ".join(open("/proc/loadavg", encoding="utf-8").read().split()[:3])
    except OSError:
        load = "unknown"
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        "# Budgets of `make bench-check`, in calibration units: a benchmark's median CPU time",
        "# divided by the median CPU time of the calibration loop of the same run (bench_check.cpp).",
        f"# The check fails when a benchmark takes more than {FACTOR:g} x its budget.",
        f"# Set from one run (`make bench-budgets`) at commit {commit} on {platform.node()}, {stamp},",
        f"# load average {load}, {os.cpu_count()} cores; calibration loop {calibration * 1e6:.0f} us.",
        "# Rewrite them the same way when a change is meant to cost more (or after one that made",
        "# things faster, so that the guard holds the gain), and commit this file.",
    ]
    for name in sorted(measured):
        lines.append(f"{name}\t{measured[name]:.6g}")
    with open(budgets_path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    print(f"bench-check: wrote {len(measured)} budgets to {budgets_path}")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("result")
    parser.add_argument("budgets")
    parser.add_argument("--update", action="store_true")
    parser.add_argument("--factor", type=float, default=FACTOR)
    args = parser.parse_args()
    if args.update:
        return update(args.result, args.budgets)
    return check(args.result, args.budgets, args.factor)


if __name__ == "__main__":
    sys.exit(main())
