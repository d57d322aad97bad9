#!/usr/bin/env bash
# Batch job throughput on loopback: one `slosh serve` with N workers, a job of R
# distinct recipes (POST /v1/batches) polled until done: recipes/s uncached (every recipe a
# solve), then the same table again (every recipe a cache hit), then the interactive latency of
# a POST /v1/plans (a new recipe: a solve) while a job runs.
# Usage: bench/jobs.sh [build-dir] [recipes] [workers] [strategy]. Figures go to the README.
set -euo pipefail
build=${1:-build}
recipes=${2:-1000}
workers=${3:-2}
strategy=${4:-multi_notch}
command -v python3 >/dev/null || { echo "jobs.sh: needs python3"; exit 1; }
# shellcheck source=bench/serve_common.sh
source "$(dirname "$0")/serve_common.sh"
slosh_serve server "$build" --cache "" --workers "$workers"
url=$slosh_url
python3 - "$url" "$recipes" "$strategy" <<'PY'
import json, sys, time, urllib.request
url, n, strategy = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def recipe(i, base=1.0):
    return {"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water",
                       "stroke_mm": 800, "motion_time_s": base + 1e-4 * i}, "strategy": strategy}
def call(method, path, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req) as r:
        return json.loads(r.read())
def run(label, table):
    t0 = time.monotonic()
    job = call("POST", "/v1/batches", {"requests": table})
    while True:
        rec = call("GET", "/v1/batches/" + job["id"] + "?limit=1")
        if rec["state"] not in ("queued", "running"):
            break
        time.sleep(0.05)
    dt = time.monotonic() - t0
    print(f"== {label}: {n} recipes ({strategy}) in {dt:.2f} s = {n / dt:.0f} recipes/s "
          f"(state {rec['state']}, {rec['progress']['failed']} failed)")
table = [recipe(i) for i in range(n)]
run("uncached job", table)
run("cached job (same table)", table)
# Interactive plans while a job of new recipes runs.
job = call("POST", "/v1/batches", {"requests": [recipe(i, 2.0) for i in range(n)]})
time.sleep(0.5)
lat = []
for k in range(10):
    t0 = time.monotonic()
    call("POST", "/v1/plans", recipe(k, 3.0))
    lat.append((time.monotonic() - t0) * 1e3)
    time.sleep(0.1)
alone = []
call("DELETE", "/v1/batches/" + job["id"])
time.sleep(1.0)
for k in range(10):
    t0 = time.monotonic()
    call("POST", "/v1/plans", recipe(k, 4.0))
    alone.append((time.monotonic() - t0) * 1e3)
lat.sort(); alone.sort()
print(f"== interactive POST /v1/plans (a solve) during a job: median {lat[5]:.1f} ms, "
      f"max {lat[-1]:.1f} ms; with no job: median {alone[5]:.1f} ms, max {alone[-1]:.1f} ms")
PY
