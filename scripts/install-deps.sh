#!/usr/bin/env bash
# Installs the Debian packages slosh needs to build, test, benchmark and run, and the locked npm
# packages of the OPC UA gateway (opcua/package-lock.json, `npm ci`).
# Idempotent: installs only what is missing, runs `apt-get update` only when
# something is missing, works as root without sudo (and uses sudo otherwise);
# `npm ci` runs only when opcua/node_modules is missing or was installed from another lock file.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

packages=(
  build-essential cmake ninja-build pkg-config git # toolchain
  ccache                                           # compiler cache (rebuilds, second clones)
  libeigen3-dev                                    # dense linear algebra (core)
  libnlopt-cxx-dev                                 # NLopt optimisers (core/optimize)
  coinor-libipopt-dev                              # Ipopt interior point (core/optimize)
  nlohmann-json3-dev                               # JSON (api)
  libcpp-httplib-dev                               # HTTP server/client (service)
  zlib1g-dev                                       # gzip responses (service)
  libspdlog-dev                                    # structured logs (service)
  libsqlite3-dev                                   # persistent plan cache (service)
  libhiredis-dev                                   # Redis client: shared plan cache, job store (service)
  redis-server                                     # a real Redis for the replica tests (tests)
  libssl-dev                                       # SHA-256 of recipe keys (api)
  libcli11-dev                                     # command-line parsing (service)
  libcsv-dev                                       # CSV recipe/plan tables (service)
  libgtest-dev libgmock-dev                        # unit and integration tests
  libbenchmark-dev                                 # Google Benchmark targets
  clang-format                                     # formatting check
  clang libclang-rt-14-dev llvm                    # sanitizer build + fuzzers: libFuzzer, ASan/UBSan runtimes, llvm-symbolizer
  curl wrk jq                                      # loopback load script; JSON in the documented commands
  nginx-light                                      # reverse proxy of the replica tests (tests/support/proxy.hpp)
  yamllint                                         # lint of deploy/compose.yaml and deploy/k8s (tests/deploy)
  prometheus                                       # promtool check metrics (test Metrics.PromtoolAcceptsTheExposition)
  libjs-chart.js                                   # Chart.js 3.9 for the web page (embedded)
  chromium chromium-driver python3-selenium        # the web page's browser test
)

# Node.js >= 18 and npm for the OPC UA gateway (opcua/, node-opcua): Debian 12's nodejs (18) and
# npm, unless a node >= 18 with its npm is already installed (NodeSource's nodejs package bundles
# npm and conflicts with Debian's npm package, so asking apt for npm there would fail).
node_major=$(node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0)
if [ "$node_major" -lt 18 ] || ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi

# The gateway's packages exactly as locked. The stamp holds the SHA-256 of the lock they were
# installed from, so a changed lock (a pull) reinstalls them and an unchanged one costs nothing.
install_opcua_packages() {
  local lock="$root/opcua/package-lock.json" stamp="$root/opcua/node_modules/.slosh-lock.sha256" sum
  [ -f "$lock" ] || return 0
  sum=$(sha256sum "$lock" | cut -d' ' -f1)
  if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$sum" ]; then
    echo "install-deps: opcua/node_modules matches opcua/package-lock.json"
    return 0
  fi
  echo "install-deps: npm ci in opcua/ (OPC UA gateway packages)"
  (cd "$root/opcua" && npm ci --no-audit --no-fund --loglevel=error)
  echo "$sum" > "$stamp"
}

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  install_opcua_packages
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_opcua_packages
