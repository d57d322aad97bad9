#!/usr/bin/env python3
"""The benchmark guard itself (bench/bench_check.py): a fake run over budget fails with the exact
message, one within budget passes, a benchmark without a budget (or a budget without a run) fails,
and --update writes budgets that the same run then passes. Fake Google Benchmark JSON files, the
real checker as a subprocess.

Usage: test_bench_check.py --checker bench/bench_check.py
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = None


def aggregate(name, cpu_time, unit, kind="median"):
    # The wall time is not in proportion to the CPU time (4 x for the benchmarks, 1 x for the
    # calibration loop, as on a machine where the benchmarks wait): a checker reading real_time
    # gets other quotients and fails these tests.
    real_time = cpu_time * (1.0 if name == "calibration" else 4.0)
    return {"name": f"{name}_{kind}", "run_name": name, "run_type": "aggregate",
            "aggregate_name": kind, "cpu_time": cpu_time, "real_time": real_time,
            "time_unit": unit, "iterations": 5}


def error_run(name, message):
    """A repetition of a benchmark that called SkipWithError: no aggregates follow it."""
    return {"name": name, "run_name": name, "run_type": "iteration", "repetitions": 5,
            "error_occurred": True, "error_message": message, "cpu_time": 0, "real_time": 0,
            "time_unit": "us", "iterations": 0}


class BenchCheck(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.result = os.path.join(self.dir.name, "result.json")
        self.budgets = os.path.join(self.dir.name, "budgets.tsv")

    def tearDown(self):
        self.dir.cleanup()

    def write_run(self, calibration_us, benchmarks):
        rows = [aggregate("calibration", calibration_us, "us"),
                aggregate("calibration", calibration_us * 9, "us", "mean")]
        for name, (value, unit) in benchmarks.items():
            rows.append(aggregate(name, value, unit))
            rows.append(aggregate(name, value * 100, unit, "stddev"))  # never read
        with open(self.result, "w", encoding="utf-8") as f:
            json.dump({"context": {}, "benchmarks": rows}, f)

    def write_budgets(self, text):
        with open(self.budgets, "w", encoding="utf-8") as f:
            f.write(text)

    def run_checker(self, *extra):
        return subprocess.run([sys.executable, CHECKER, self.result, self.budgets, *extra],
                              capture_output=True, text=True, check=False)

    def test_over_three_times_the_budget_fails_naming_it(self):
        # calibration 2 ms; plan/notch 26 ms = 13 units against a budget of 4 (limit 12).
        self.write_run(2000, {"plan/notch": (26, "ms"), "serve/cached_full": (40, "us")})
        self.write_budgets("# comment\nplan/notch\t4\nserve/cached_full\t0.02\n")
        r = self.run_checker()
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertEqual(r.stderr.splitlines(), [
            "bench-check: plan/notch takes 13 calibration units, more than 3 x its budget of 4",
            "bench-check: when a change is meant to cost more, rewrite the budgets with "
            "`make bench-budgets` and commit bench/budgets.tsv"])
        self.assertIn("ok   serve/cached_full", r.stdout)

    def test_within_three_times_the_budget_passes(self):
        # 11.9 units against 4: slower than the budget, but not by 3 x.
        self.write_run(2000, {"plan/notch": (23.8, "ms"), "serve/cached_full": (40000, "ns")})
        self.write_budgets("plan/notch\t4\nserve/cached_full\t0.02\n")
        r = self.run_checker()
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(r.stdout.splitlines()[-1],
                         "bench-check: 2 benchmarks within 3 x their budgets")

    def test_the_calibration_scales_the_budget(self):
        # The same run on a machine twice as slow: every time doubles, the check still passes.
        self.write_budgets("plan/notch\t4\n")
        self.write_run(4000, {"plan/notch": (47.6, "ms")})
        self.assertEqual(self.run_checker().returncode, 0)
        self.write_run(2000, {"plan/notch": (47.6, "ms")})
        self.assertEqual(self.run_checker().returncode, 1)

    def test_a_benchmark_without_a_budget_fails(self):
        self.write_run(2000, {"plan/notch": (2, "ms"), "plan/new": (2, "ms")})
        self.write_budgets("plan/notch\t4\nplan/gone\t1\n")
        r = self.run_checker()
        self.assertEqual(r.returncode, 1)
        self.assertIn(f"bench-check: plan/new has no budget in {self.budgets}", r.stderr)
        self.assertIn("bench-check: plan/gone has a budget but was not measured", r.stderr)

    def test_update_writes_budgets_the_same_run_passes(self):
        self.write_run(2000, {"plan/notch": (26, "ms"), "response/linear": (30, "us")})
        self.write_budgets("plan/notch\t4\n")
        r = self.run_checker("--update")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.budgets, encoding="utf-8") as f:
            lines = [line for line in f.read().splitlines() if not line.startswith("#")]
        self.assertEqual(lines, ["plan/notch\t13", "response/linear\t0.015"])
        self.assertEqual(self.run_checker().returncode, 0)

    def test_a_benchmark_that_failed_says_its_error(self):
        self.write_run(2000, {"plan/notch": (2, "ms")})
        with open(self.result, encoding="utf-8") as f:
            run = json.load(f)
        run["benchmarks"] += [error_run("serve/cached_full", "the plan was not solved")] * 5
        with open(self.result, "w", encoding="utf-8") as f:
            json.dump(run, f)
        self.write_budgets("plan/notch\t4\nserve/cached_full\t0.02\n")
        r = self.run_checker()
        self.assertEqual(r.returncode, 1)
        self.assertIn("bench-check: serve/cached_full failed: the plan was not solved", r.stderr)
        self.assertNotIn("not measured", r.stderr)
        # Nor are budgets written from such a run.
        r = self.run_checker("--update")
        self.assertEqual(r.returncode, 1)
        self.assertIn("bench-check: serve/cached_full failed: the plan was not solved", r.stderr)
        with open(self.budgets, encoding="utf-8") as f:
            self.assertEqual(f.read(), "plan/notch\t4\nserve/cached_full\t0.02\n")

    def test_a_run_without_the_calibration_loop_is_refused(self):
        with open(self.result, "w", encoding="utf-8") as f:
            json.dump({"benchmarks": [aggregate("plan/notch", 2, "ms")]}, f)
        self.write_budgets("plan/notch\t4\n")
        r = self.run_checker()
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("has no median of the 'calibration' loop", r.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--checker", required=True)
    args, rest = parser.parse_known_args()
    CHECKER = os.path.abspath(args.checker)
    unittest.main(argv=[sys.argv[0], *rest])
