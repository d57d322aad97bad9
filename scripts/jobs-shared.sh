#!/usr/bin/env bash
# Throughput of one batch job shared out to 1, 2 and 3 `slosh serve` replicas through Redis
# (batch_job_spread as given, by default the default "helpers"; one solve worker each), all started
# here on loopback: for each
# replica count, one job of N distinct recipes (time_domain, or the strategy given; the motion
# time differs, and each run uses other recipes, so nothing is cached) is POSTed to the first
# replica and polled until done (every run spans the same motion times, 0.9 s + 0.8 ms steps,
# shifted by 10 µs per run: a time_domain recipe near 0.93 s costs three times one near 1 s, so
# runs over different time ranges would not compare); prints recipes/s, each replica's share and the machine's load
# average (the figures mean little when other processes take the cores). Then, with 3 replicas, the first replica (which
# accepted the job) is killed (-9) at 30 %: prints the time from the kill to the job's end, the
# rows stored and whether each row is there once, against the time the remaining 70 % would take
# at the 2-replica rate (the excess is the take-over time, batch_job_stale_s, plus start-up).
# Usage: scripts/jobs-shared.sh [slosh-binary] [recipes] [stale-s] [strategy] [spread]
# Use a strategy whose recipes cost real solve time (time_domain, ~13 ms each on a quiet core):
# with notch (~1 ms) the Redis round trips per item dominate and the figures measure overhead.
# Needs: redis-server, redis-cli, python3. Stops everything it started (scripts/lib/loopback.sh).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
slosh="${1:-$here/build/slosh}"
n="${2:-600}"
stale="${3:-5}"
strategy="${4:-time_domain}"
spread="${5:-helpers}"
# shellcheck source=scripts/lib/loopback.sh
. "$here/scripts/lib/loopback.sh"
lb_redis
# start_replicas RUN COUNT: starts COUNT replicas named run-RUN-i; their ports in ports[], pids in
# run_pids[].
start_replicas() {
  ports=()
  run_pids=()
  for i in $(seq "$2"); do
    SLOSH_BATCH_JOB_SPREAD="$spread" SLOSH_BATCH_JOB_STALE_S="$stale" \
      lb_serve "slosh-$1-$i" "$slosh" --workers 1 --cache "$lb_redis_url" --replica-id "run$1-$i"
    run_pids+=("$lb_pid")
    ports+=("$lb_port")
  done
}

stop_replicas() {
  for pid in "${run_pids[@]}"; do kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; done
}

# run_job RUN KILL_AT PORTS...: posts N recipes (offset by RUN) to the first port and polls through
# the last one; KILL_AT (a fraction, 0 = none) kills the first replica (pid in $victim) then.
run_job() {
  python3 - "$n" "$1" "$2" "${victim:-0}" "$strategy" "${@:3}" <<'PY'
import json, os, signal, sys, time, urllib.request
n, run, kill_at, victim, strategy, ports = int(sys.argv[1]), int(sys.argv[2]), \
    float(sys.argv[3]), int(sys.argv[4]), sys.argv[5], sys.argv[6:]
def call(port, path, data=None):
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}",
                                 data=None if data is None else json.dumps(data).encode(),
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=30) as r:
        return r.read()
body = {"requests": [{"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
         "fluid": "water", "stroke_mm": 800,
         "motion_time_s": 0.9 + 0.0008 * i + 0.00001 * run}, "strategy": strategy} for i in range(n)]}
start = time.monotonic()
job = json.loads(call(ports[0], "/v1/batches", body))["id"]
killed = None
while True:
    rec = json.loads(call(ports[-1], f"/v1/batches/{job}?limit=1"))
    done = rec["progress"]["done"]
    # solved (helped jobs) counts the items the helpers solved ahead of the stored rows
    solved = rec["progress"].get("solved", done)
    if killed is None and kill_at > 0 and solved >= kill_at * n:
        os.kill(victim, signal.SIGKILL)
        killed = (time.monotonic(), solved)
    if rec["state"] not in ("queued", "running"):
        break
    time.sleep(0.05)
wall = time.monotonic() - start
csv = call(ports[-1], f"/v1/batches/{job}/results.csv").decode().splitlines()[1:]
rows = sorted(int(line.split(",")[0]) for line in csv)
once = rows == list(range(1, n + 1))
print(f"{len(ports)} replica(s): {rec['state']}, {done} recipes in {wall:.2f} s = "
      f"{done / wall:.1f} recipes/s; shares {rec.get('shares')}; every row once: {once}")
if killed:
    after = time.monotonic() - killed[0]
    print(f"  killed the accepting replica at {killed[1]} recipes solved; the job ended {after:.2f} s later")
PY
}

run=1
for count in 1 2 3; do
  start_replicas "$run" "$count"
  if [ "$count" = 1 ]; then
    # A first job on a fresh process and Redis runs slower (page faults, allocator, connections):
    # one job of other recipes first, not counted.
    run_job 99 0 "${ports[@]}" >/dev/null
  fi
  echo "== $count replica(s), 1 worker each, $n $strategy recipes (load $(cut -d' ' -f1-3 /proc/loadavg))"
  run_job "$run" 0 "${ports[@]}"
  stop_replicas
  run=$((run + 1))
done
start_replicas "$run" 3
victim="${run_pids[0]}"
echo "== 3 replicas, the accepting one killed (-9) at 30 %, batch_job_stale_s = $stale (load $(cut -d' ' -f1-3 /proc/loadavg))"
run_job "$run" 0.3 "${ports[@]}"
stop_replicas
