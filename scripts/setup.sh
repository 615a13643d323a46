#!/usr/bin/env bash
# Installs the Debian packages vlpground needs, and only those that are missing.
# Does nothing (and says so) when everything is already present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libboost-dev libeigen3-dev libpcap-dev libspdlog-dev libfmt-dev
  catch2 libbenchmark-dev libyaml-cpp-dev nlohmann-json3-dev libstb-dev
  libcli11-dev ccache
  # Round 2 front-ends: ROS 2 over DDS, Foxglove/MCAP, Python.
  cyclonedds-dev cyclonedds-tools
  libprotobuf-dev protobuf-compiler libwebsocketpp-dev libboost-system-dev libzstd-dev liblz4-dev zlib1g-dev
  pybind11-dev python3-dev python3-numpy python3-distributed python3-pytest python3-matplotlib
  python3-pip python3-setuptools python3-wheel
  chromium
)
# Optional extras: clang + its runtime for the fuzz targets (skipped quietly if unavailable).
optional=(clang libclang-rt-14-dev)

is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

missing=()
for p in "${packages[@]}"; do is_installed "$p" || missing+=("$p"); done
missing_optional=()
for p in "${optional[@]}"; do is_installed "$p" || missing_optional+=("$p"); done

# node (>= 18) runs the protocol tests of the Foxglove server and the MCAP writer; Debian's
# nodejs/npm are installed only when no node is on the PATH.
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  for p in nodejs npm; do is_installed "$p" || missing+=("$p"); done
fi

if [ ${#missing[@]} -eq 0 ] && [ ${#missing_optional[@]} -eq 0 ]; then
  echo "setup: all Debian packages are installed."
else
  if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  echo "setup: installing missing packages: ${missing[*]} ${missing_optional[*]}"
  "${sudo[@]}" apt-get update -qq
  if [ ${#missing[@]} -gt 0 ]; then
    "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  if [ ${#missing_optional[@]} -gt 0 ]; then
    "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing_optional[@]}" ||
      echo "setup: optional packages (${missing_optional[*]}) unavailable; fuzz targets will be skipped."
  fi
fi

# The node test clients (@foxglove/ws-protocol, @mcap/core, ...), pinned by the lock file
# in tests/node/; installed again only when the lock file changed.
here=$(cd "$(dirname "$0")/.." && pwd)
node_dir="$here/tests/node"
if [ -f "$node_dir/package-lock.json" ]; then
  stamp="$node_dir/node_modules/.installed-lock"
  if ! cmp -s "$node_dir/package-lock.json" "$stamp"; then
    echo "setup: installing the node test clients (npm ci in tests/node)"
    (cd "$node_dir" && npm ci --no-audit --no-fund --loglevel=error)
    cp "$node_dir/package-lock.json" "$stamp"
  fi
fi
echo "setup: done."
