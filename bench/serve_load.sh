#!/usr/bin/env bash
# Loopback load test of the cached serve path of `slosh serve` (SPEC §8): one cached recipe asked
# again and again with POST /v1/plans, as the full plan and as the compact view, each without and
# with `Accept-Encoding: gzip`. wrk runs on the same machine as the server (2 threads, 32
# connections by default), so the figures are a floor of what the service does on its own.
# "Every client served": wrk reports no socket error (connect, read, write, timeout) and no
# non-2xx answer; the script fails otherwise.
# Usage: bench/serve_load.sh [build-dir] [seconds] [connections].
set -euo pipefail
build=${1:-build}
seconds=${2:-10}
connections=${3:-32}
command -v wrk >/dev/null || { echo "serve_load.sh: wrk is not installed (scripts/install-deps.sh)"; exit 1; }
# shellcheck source=bench/serve_common.sh
source "$(dirname "$0")/serve_common.sh"
dir=$slosh_dir
slosh_serve server "$build" --cache "$dir/plans.sqlite"
url=$slosh_url
body='{"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "multi_notch"}'
curl -s -o /dev/null -X POST -H 'Content-Type: application/json' -d "$body" "$url/v1/plans"

status=0
run() {
  local name=$1 path=$2 encoding=$3
  cat > "$dir/cached.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
$( [ -n "$encoding" ] && echo "wrk.headers[\"Accept-Encoding\"] = \"$encoding\"" )
wrk.body = '$body'
LUA
  local out
  out=$(wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$dir/cached.lua" "$url$path")
  local rps p50 p99 max errors non2xx
  rps=$(awk '/Requests\/sec/ {print $2}' <<<"$out")
  p50=$(awk '$1 == "50%" {print $2}' <<<"$out")
  p99=$(awk '$1 == "99%" {print $2}' <<<"$out")
  max=$(awk '$1 == "Latency" {print $4}' <<<"$out")
  errors=$(awk '/Socket errors/ {print $0}' <<<"$out")
  non2xx=$(awk '/Non-2xx/ {print $NF}' <<<"$out")
  printf '%-28s %10s req/s  p50 %-8s p99 %-8s max %-8s %s%s\n' "$name" "$rps" "$p50" "$p99" "$max" \
    "${errors:-no socket errors}" "${non2xx:+, non-2xx $non2xx}"
  if [ -n "$errors" ] || [ -n "$non2xx" ]; then status=1; fi
}
echo "== cached POST /v1/plans, ${connections} connections, ${seconds} s each, 2 wrk threads (load $(cut -d' ' -f1-3 /proc/loadavg))"
run "full" "/v1/plans" ""
run "full, gzip" "/v1/plans" "gzip"
run "compact" "/v1/plans?view=compact" ""
run "compact, gzip" "/v1/plans?view=compact" "gzip"
exit $status
