# shellcheck shell=bash
# Sourced by the loopback measurement scripts (scripts/jobs-shared.sh, jobs-replicas.sh,
# load-replicas.sh), after `set -euo pipefail`: a scratch directory and the processes they start,
# all stopped and removed when the script exits, however it exits.
#   lb_dir                          the scratch directory (logs, port files, configs)
#   lb_track PID                    another background process to stop at exit
#   lb_free_port                    prints a free loopback TCP port
#   lb_redis                        starts redis-server (no persistence) on a free port, waits for
#                                   it and sets lb_redis_url=redis://127.0.0.1:PORT/0
#   lb_serve NAME BINARY ARGS...    starts `BINARY serve --host 127.0.0.1 --port 0 ARGS...` (log in
#                                   $lb_dir/NAME.log), waits for its port file and sets lb_port
#                                   and lb_pid; exits 1 with its log when no port appears in 10 s

lb_dir=$(mktemp -d)
lb_pids=()
lb_cleanup() {
  local p
  for p in "${lb_pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$lb_dir"
}
trap lb_cleanup EXIT

lb_track() { lb_pids+=("$1"); }

lb_free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'
}

lb_redis() {
  local port
  port=$(lb_free_port)
  redis-server --port "$port" --bind 127.0.0.1 --save "" --appendonly no --dir "$lb_dir" \
    >"$lb_dir/redis.log" 2>&1 &
  lb_track "$!"
  local _
  for _ in $(seq 100); do redis-cli -p "$port" ping >/dev/null 2>&1 && break; sleep 0.1; done
  # shellcheck disable=SC2034  # read by the sourcing script
  lb_redis_url="redis://127.0.0.1:$port/0"
}

lb_serve() {
  local name=$1 binary=$2
  shift 2
  local port_file="$lb_dir/$name.port" log="$lb_dir/$name.log"
  "$binary" serve --host 127.0.0.1 --port 0 --port-file "$port_file" "$@" >"$log" 2>&1 &
  lb_pid=$!
  lb_track "$lb_pid"
  local _
  for _ in $(seq 200); do
    [ -s "$port_file" ] && break
    kill -0 "$lb_pid" 2>/dev/null || break
    sleep 0.05
  done
  if [ ! -s "$port_file" ]; then
    echo "$(basename "$0"): slosh serve ($name) wrote no port file within 10 s; its log:" >&2
    cat "$log" >&2
    exit 1
  fi
  # shellcheck disable=SC2034  # read by the sourcing script
  lb_port=$(cat "$port_file")
}
