#!/usr/bin/env bash
# Installs the Debian packages the project builds with, and only those that are missing.
# Quick and silent about installing when everything is already there.
set -euo pipefail

packages=(
  build-essential cmake make pkg-config
  libeigen3-dev        # core: SE(3) helpers, Umeyama
  nlohmann-json3-dev   # dsg/io: JSON and Spark-DSG JSON
  libcli11-dev         # apps: command line
  libceres-dev libsuitesparse-dev  # optim: pose-graph optimization, sparse Cholesky
  libopenblas0-serial  # optim: CHOLMOD's dense kernels (Debian's default BLAS is slower)
  libjemalloc-dev      # every executable's malloc (the maps' and graphs' small blocks)
  libnanoflann-dev     # core: KD-tree nearest neighbours
  libgtest-dev libgmock-dev  # tests
  libzmq3-dev cppzmq-dev     # net: robots and station over ZeroMQ
  libsqlite3-dev             # store: the station's journal
  libzstd-dev                # net: update payloads compressed on the wire
  iproute2 iptables          # tests: robots' links with faults, in network namespaces
  libcpp-httplib-dev         # web: the viewer's HTTP server
  chromium                   # tests: the viewer page in a real browser (headless)
  clang libclang-rt-dev      # make fuzz: libFuzzer targets under ASan and UBSan
)
# The viewer page is built with npm (web/package-lock.json): Node.js 20.19 or newer, as vite
# needs; Debian's own nodejs only when the machine has none.
if ! command -v node > /dev/null 2>&1; then packages+=(nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

check_node() {
  local version
  version=$(node -p 'process.versions.node' 2> /dev/null || echo 0)
  if ! node -e 'const [a, b] = process.versions.node.split(".").map(Number); process.exit(a > 20 || (a === 20 && b >= 19) ? 0 : 1)' 2> /dev/null; then
    echo "deps: Node.js $version is too old for the viewer page's build (vite needs 20.19 or newer);" \
      "install a newer Node.js, or configure with -DHYDRA_MULTI_VIEWER_PAGE=OFF" >&2
    exit 1
  fi
}

if [ ${#missing[@]} -eq 0 ]; then
  check_node
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: installed ${#missing[@]} package(s)"
check_node
