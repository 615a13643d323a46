#!/usr/bin/env bash
# Installs the Debian packages vlpground needs, and only those that are missing.
# Does nothing (and says so) when everything is already present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libboost-dev libeigen3-dev libpcap-dev libspdlog-dev libfmt-dev
  catch2 libbenchmark-dev libyaml-cpp-dev nlohmann-json3-dev libstb-dev
)
# Optional extras: clang + its runtime for the fuzz targets (skipped quietly if unavailable).
optional=(clang libclang-rt-14-dev)

is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

missing=()
for p in "${packages[@]}"; do is_installed "$p" || missing+=("$p"); done
missing_optional=()
for p in "${optional[@]}"; do is_installed "$p" || missing_optional+=("$p"); done

if [ ${#missing[@]} -eq 0 ] && [ ${#missing_optional[@]} -eq 0 ]; then
  echo "setup: all dependencies are installed; nothing to do."
  exit 0
fi

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
echo "setup: done."
