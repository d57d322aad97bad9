#!/usr/bin/env bash
# Batch job throughput of two `slosh serve` replicas sharing a redis-server (cache and job store),
# all started here on loopback: one job of N distinct recipes (notch, the motion time differs, so
# nothing is cached) POSTed to each replica at once (POST /v1/batches), both polled until done;
# prints each job's rate and the total recipes/s (2 N / the wall time until both finished).
# Usage: scripts/jobs-replicas.sh [slosh-binary] [recipes-per-job] [workers-per-replica] [strategy]
# Needs: redis-server, redis-cli, python3. Stops everything it started (scripts/lib/loopback.sh).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
slosh="${1:-$here/build/slosh}"
n="${2:-500}"
workers="${3:-1}"
strategy="${4:-notch}"
# shellcheck source=scripts/lib/loopback.sh
. "$here/scripts/lib/loopback.sh"
lb_redis
ports=()
for i in 1 2; do
  lb_serve "slosh$i" "$slosh" --workers "$workers" --cache "$lb_redis_url" --replica-id "jobs-$i"
  ports+=("$lb_port")
done

python3 - "$n" "$strategy" "${ports[@]}" <<'PY'
import json, sys, time, urllib.request
n, strategy, ports = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
def body(first):
    return {"requests": [{"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
             "fluid": "water", "stroke_mm": 800, "motion_time_s": 0.9 + 0.0001 * (first + i)},
             "strategy": strategy} for i in range(n)]}
def call(port, path, data=None):
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}",
                                 data=None if data is None else json.dumps(data).encode(),
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req) as r:
        return json.load(r)
start = time.monotonic()
ids = [call(p, "/v1/batches", body(k * n))["id"] for k, p in enumerate(ports)]
ended = {}
while len(ended) < len(ids):
    for p, i in zip(ports, ids):
        if i in ended:
            continue
        other = ports[1 - ports.index(p)]  # read through the other replica (the shared store)
        rec = call(other, f"/v1/batches/{i}?limit=1")
        if rec["state"] not in ("queued", "running"):
            ended[i] = (time.monotonic() - start, rec)
    time.sleep(0.05)
for i, (t, rec) in ended.items():
    print(f"job {i}: {rec['state']}, {rec['progress']['done']} recipes "
          f"({rec['progress']['failed']} failed) in {t:.2f} s = {rec['progress']['done'] / t:.1f}/s")
wall = max(t for t, _ in ended.values())
total = sum(rec["progress"]["done"] for _, rec in ended.values())
print(f"== 2 replicas sharing Redis, {strategy}, {total} recipes in {wall:.2f} s: "
      f"{total / wall:.1f} recipes/s total")
PY
