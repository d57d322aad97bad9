#!/usr/bin/env bash
# Loopback load test of the shared Redis cache level: two `slosh serve` replicas sharing one
# redis-server (started here, no persistence). Recipes are solved through replica A, then wrk
# asks replica B for them: (1) one recipe, answered from B's memory; (2) eight recipes in turn
# with a memory LRU of 1 entry (config cache_entries 1), so nearly every request is answered from
# Redis. /metrics of B tells how many came from each level.
# Usage: bench/redis_load.sh [build-dir] [seconds] [connections]. Figures go to the README.
set -euo pipefail
build=${1:-build}
seconds=${2:-10}
connections=${3:-16}
command -v wrk >/dev/null || { echo "redis_load.sh: wrk is not installed (scripts/install-deps.sh)"; exit 1; }
command -v redis-server >/dev/null || { echo "redis_load.sh: redis-server is not installed (scripts/install-deps.sh)"; exit 1; }
# shellcheck source=bench/serve_common.sh
source "$(dirname "$0")/serve_common.sh"
dir=$slosh_dir
redis_port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
redis-server --port "$redis_port" --bind 127.0.0.1 --save "" --appendonly no --dir "$dir" \
  --logfile "$dir/redis.log" &
slosh_track $!
for _ in $(seq 100); do redis-cli -p "$redis_port" ping >/dev/null 2>&1 && break; sleep 0.05; done
echo '{"cache_entries": 1}' > "$dir/config.json"
slosh_serve a "$build" --config "$dir/config.json" --cache "redis://127.0.0.1:$redis_port/0"
a=$slosh_url
slosh_serve b "$build" --config "$dir/config.json" --cache "redis://127.0.0.1:$redis_port/0"
b=$slosh_url
body() { echo "{\"format\": {\"container\": {\"radius_mm\": 48.5}, \"fill_height_mm\": 82, \"fluid\": \"water\", \"stroke_mm\": $1, \"motion_time_s\": 1.0}, \"strategy\": \"multi_notch\"}"; }
strokes="800 790 780 770 760 750 740 730"
for stroke in $strokes; do
  curl -s -o /dev/null -X POST -H 'Content-Type: application/json' -d "$(body $stroke)" "$a/v1/plans"
done
cat > "$dir/memory.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
wrk.body = '$(body 800)'
LUA
cat > "$dir/redis.lua" <<LUA
local bodies = {$(for s in $strokes; do printf "'%s', " "$(body "$s")"; done)}
local n = 0
request = function()
  n = n + 1
  return wrk.format("POST", "/v1/plans", {["Content-Type"] = "application/json"}, bodies[n % #bodies + 1])
end
LUA
hits() { curl -s "$b/metrics" | grep -E '^slosh_cache_(hits|misses)_total' | tr '\n' ' '; echo; }
echo "== replica B, one cached recipe (memory level; $connections connections, ${seconds}s, 2 wrk threads)"
wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$dir/memory.lua" "$b/v1/plans" |
  grep -E 'Requests/sec|Latency|50%|90%|99%|Non-2xx'
hits
echo "== replica B, eight recipes in turn over a 1-entry memory LRU (mostly the redis level)"
wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$dir/redis.lua" "$b/v1/plans" |
  grep -E 'Requests/sec|Latency|50%|90%|99%|Non-2xx'
hits
