#!/usr/bin/env bash
# Loopback load test of `slosh serve` with wrk: cached POST /v1/plans (the same recipe, answered
# from the cache) and uncached ones (a new recipe per request, each a real solve).
# Usage: bench/load.sh [build-dir] [seconds] [connections]. Figures go to the README.
set -euo pipefail
build=${1:-build}
seconds=${2:-10}
connections=${3:-32}
command -v wrk >/dev/null || { echo "load.sh: wrk is not installed (scripts/install-deps.sh)"; exit 1; }
# shellcheck source=bench/serve_common.sh
source "$(dirname "$0")/serve_common.sh"
dir=$slosh_dir
slosh_serve server "$build" --cache "$dir/plans.sqlite"
url=$slosh_url
body='{"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "multi_notch"}'
curl -s -o /dev/null -X POST -H 'Content-Type: application/json' -d "$body" "$url/v1/plans"

cat > "$dir/cached.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
wrk.body = '$body'
LUA
# A distinct stroke per request: every one is a cache miss and a multi_notch solve.
cat > "$dir/uncached.lua" <<'LUA'
local n = 0
request = function()
  n = n + 1
  local stroke = 400 + (n % 100000) * 0.001 + math.random() * 1e-6
  local body = string.format('{"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water", "stroke_mm": %.9f, "motion_time_s": 1.0}, "strategy": "multi_notch"}', stroke)
  return wrk.format("POST", "/v1/plans", {["Content-Type"] = "application/json"}, body)
end
LUA
echo "== cached POST /v1/plans ($connections connections, ${seconds}s, 2 wrk threads)"
wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$dir/cached.lua" "$url/v1/plans" |
  grep -E 'Requests/sec|Latency|50%|90%|99%|Non-2xx'
echo "== uncached POST /v1/plans (multi_notch solves)"
wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$dir/uncached.lua" "$url/v1/plans" |
  grep -E 'Requests/sec|Latency|50%|90%|99%|Non-2xx'
