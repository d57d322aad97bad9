# shellcheck shell=bash
# Sourced by the load scripts (bench/load.sh, serve_load.sh, jobs.sh, redis_load.sh), after
# `set -euo pipefail`: the loopback helpers of scripts/lib/loopback.sh (a scratch directory and the
# processes started, all stopped and removed when the script exits) under the names these
# scripts use:
#   slosh_dir                        the scratch directory (lua scripts, logs, port files)
#   slosh_serve NAME BUILD ARGS...   starts `BUILD/slosh serve --host 127.0.0.1 --port 0 ARGS...`
#                                    (log in $slosh_dir/NAME.log), waits for its port file and sets
#                                    slosh_url=http://127.0.0.1:PORT; exits 1 with the server's log
#                                    when no port appears within 10 s or the server ends first
#   slosh_track PID                  another background process to stop at exit (redis-server)

# shellcheck source=../scripts/lib/loopback.sh
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/lib/loopback.sh"

# shellcheck disable=SC2034  # read by the sourcing script
slosh_dir=$lb_dir

slosh_track() { lb_track "$1"; }

slosh_serve() {
  local name=$1 build=$2
  shift 2
  lb_serve "$name" "$build/slosh" "$@"
  # shellcheck disable=SC2034  # read by the sourcing script
  slosh_url="http://127.0.0.1:$lb_port"
}
