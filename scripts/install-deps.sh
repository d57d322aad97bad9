#!/usr/bin/env bash
# Installs the Debian packages slosh needs to build, test, benchmark and run.
# Idempotent: installs only what is missing, runs `apt-get update` only when
# something is missing, works as root without sudo (and uses sudo otherwise).
set -euo pipefail

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
  clang libclang-rt-14-dev llvm                    # fuzzers: libFuzzer, ASan/UBSan runtimes, llvm-symbolizer
  curl wrk jq                                      # loopback load script; JSON in the documented commands
  nginx-light                                      # reverse proxy of the replica tests (tests/support/proxy.hpp)
  yamllint                                         # lint of deploy/compose.yaml and deploy/k8s (tests/deploy)
  prometheus                                       # promtool check metrics (test Metrics.PromtoolAcceptsTheExposition)
  libjs-chart.js                                   # Chart.js 3.9 for the web page (embedded)
  chromium chromium-driver python3-selenium        # the web page's browser test
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
