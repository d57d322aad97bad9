# shellcheck shell=bash
# Sourced by the load scripts (bench/load.sh, serve_load.sh, jobs.sh, redis_load.sh), after
# `set -euo pipefail`: a scratch directory and the servers they start, all removed or stopped
# when the script exits, however it exits.
#   slosh_dir                        the scratch directory (lua scripts, logs, port files)
#   slosh_serve NAME BUILD ARGS...   starts `BUILD/slosh serve --port 0 ARGS...` (log in
#                                    $slosh_dir/NAME.log), waits for its port file and sets
#                                    slosh_url=http://127.0.0.1:PORT; exits 1 with the server's log
#                                    when no port appears within 10 s or the server ends first
#   slosh_track PID                  another background process to stop at exit (redis-server)

slosh_dir=$(mktemp -d)
slosh_pids=()
slosh_cleanup() {
  local p
  for p in "${slosh_pids[@]}"; do
    kill "$p" 2>/dev/null || true
    wait "$p" 2>/dev/null || true
  done
  rm -rf "$slosh_dir"
}
trap slosh_cleanup EXIT

slosh_track() { slosh_pids+=("$1"); }

slosh_serve() {
  local name=$1 build=$2
  shift 2
  local port_file="$slosh_dir/$name.port" log="$slosh_dir/$name.log"
  "$build/slosh" serve --port 0 --port-file "$port_file" "$@" > "$log" 2>&1 &
  local pid=$!
  slosh_track "$pid"
  local _
  for _ in $(seq 200); do
    [ -s "$port_file" ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  if [ ! -s "$port_file" ]; then
    echo "$(basename "$0"): slosh serve ($name) wrote no port file within 10 s; its log:" >&2
    cat "$log" >&2
    exit 1
  fi
  # shellcheck disable=SC2034  # read by the sourcing script
  slosh_url="http://127.0.0.1:$(cat "$port_file")"
}
