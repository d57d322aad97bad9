#!/usr/bin/env bash
# Loopback load through the proxy: two `slosh serve` replicas (memory cache, 1 solve worker each)
# behind nginx run from deploy/nginx.conf (upstream, listen line and paths rewritten as
# tests/support/proxy.hpp does; the per-client limit_req/limit_conn dropped, since wrk is one
# client), a plan solved once on each replica, then wrk POSTs that cached plan through the proxy,
# and for comparison straight to one replica. Prints wrk's figures.
# Usage: scripts/load-replicas.sh [slosh-binary] [seconds] [connections] [cache]
#   cache: "" (default) = each replica's own memory cache; "redis" = a redis-server started here
#   on a free loopback port (no persistence) that both replicas share (--cache redis://...).
# Needs: nginx (nginx-light), wrk, curl (and redis-server for "redis"). Runs only on loopback;
# stops everything it started (scripts/lib/loopback.sh).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
slosh="${1:-$here/build/slosh}"
seconds="${2:-10}"
connections="${3:-32}"
cache_mode="${4:-}"
# shellcheck source=scripts/lib/loopback.sh
. "$here/scripts/lib/loopback.sh"
dir="$lb_dir"
cache=""
if [ "$cache_mode" = redis ]; then
  lb_redis
  cache="$lb_redis_url"
fi

ports=()
for i in 1 2; do
  lb_serve "slosh$i" "$slosh" --cache "$cache" --workers 1 --replica-id "load-$i"
  ports+=("$lb_port")
done

proxy_port="$(lb_free_port)"
servers="server 127.0.0.1:${ports[0]} max_fails=1 fail_timeout=5s; server 127.0.0.1:${ports[1]} max_fails=1 fail_timeout=5s;"
sed -e '/^\s*server slosh-[0-9]*:[0-9]*/d' \
    -e "s|keepalive 32;|$servers keepalive 32;|" \
    -e "s|listen 8080;|listen 127.0.0.1:$proxy_port;|" \
    -e "s|/tmp/nginx|$dir/nginx|g" \
    -e 's|worker_processes auto;|worker_processes 1;|' \
    -e '/^\s*limit_req zone/d' -e '/^\s*limit_conn slosh_conn/d' \
    -e "s|access_log /dev/stdout slosh;|access_log $dir/access.log slosh;|" \
    "$here/deploy/nginx.conf" >"$dir/nginx.conf"
user=""
[ "$(id -u)" -eq 0 ] && user="user root;"
nginx -p "$dir/" -e "$dir/error.log" -c "$dir/nginx.conf" -g "daemon off; $user" \
  >"$dir/nginx.out" 2>&1 &
lb_track "$!"
for _ in $(seq 100); do curl -s -o /dev/null "http://127.0.0.1:$proxy_port/healthz" && break; sleep 0.1; done

body='{"format": {"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
"fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "notch"}'
for port in "${ports[@]}"; do  # solved once on each replica: every later request is a hit
  curl -sf -o /dev/null -H 'Content-Type: application/json' -d "$body" "http://127.0.0.1:$port/v1/plans"
done
bytes="$(curl -sf -H 'Content-Type: application/json' -d "$body" "http://127.0.0.1:$proxy_port/v1/plans" | wc -c)"
cat >"$dir/post.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
wrk.body = [[$body]]
LUA

echo "== cached plan (notch, $bytes-byte answer), $connections connections, ${seconds}s, nproc $(nproc), cache ${cache:-memory}"
echo "-- through nginx to 2 replicas (127.0.0.1:$proxy_port -> ${ports[*]})"
wrk -t2 -c"$connections" -d"${seconds}s" -s "$dir/post.lua" "http://127.0.0.1:$proxy_port/v1/plans"
echo "-- straight to one replica (127.0.0.1:${ports[0]})"
wrk -t2 -c"$connections" -d"${seconds}s" -s "$dir/post.lua" "http://127.0.0.1:${ports[0]}/v1/plans"
echo "-- answers per replica through the proxy (access log upstream=)"
grep -o 'upstream=[0-9.:]*' "$dir/access.log" | sort | uniq -c
