#!/usr/bin/env bash
# Scores deploy/slosh.service (alone, and with the line-network drop-in) with
# `systemd-analyze security --offline=yes` (systemd >= 252; no running systemd needed) in a
# scratch root, and fails when the exposure is above the threshold (default 2.0; the unit before
# hardening scored 8.3 EXPOSED). Usage: scripts/check-unit-security.sh [slosh-binary] [threshold]
# Exit 77 (skipped, for ctest) when systemd-analyze is not installed.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
binary="${1:-$here/build/slosh}"
threshold="${2:-2.0}"
command -v systemd-analyze >/dev/null || { echo "systemd-analyze not installed: skipped"; exit 77; }
root="$(mktemp -d)"
trap 'rm -rf "$root"' EXIT
units="$root/etc/systemd/system"
mkdir -p "$units" "$root/usr/local/bin"
cp "$here/deploy/slosh.service" "$units/"
cp "$binary" "$root/usr/local/bin/slosh"
# systemd-analyze's threshold is in tenths (exposure 2.0 = 20).
tenths="$(awk -v t="$threshold" 'BEGIN { printf "%d", t * 10 + 0.5 }')"
status=0
score() {  # prints the overall line; remembers a failure
  local out rc=0
  out="$(systemd-analyze security --offline=yes --root="$root" --threshold="$tenths" \
           slosh.service 2>&1)" || rc=$?
  echo "$1: $(tail -n 1 <<<"$out")"
  if [ "$rc" -ne 0 ]; then
    echo "$1: exposure above $threshold (exit $rc)"
    status=1
  fi
}
score "slosh.service"
mkdir -p "$units/slosh.service.d"
cp "$here/deploy/slosh.service.d/line-network.conf" "$units/slosh.service.d/"
score "slosh.service + line-network.conf"
exit "$status"
