#!/usr/bin/env bash
# Soak and fault test: two simulated sensors streamed over loopback at 10x real time into a
# MultiPipeline with faults injected (junk datagrams of every size, truncated packets, loss,
# reordering, strongest <-> dual switches, sensor restarts, a stranger's datagrams) for
# MINUTES (default 1). Fails on a crash, a leak (RSS growth), a lost counter or a frame cut
# wrong; prints frames, drops and latency per sensor. CI runs 60 s of it (ctest soak_60s).
#   ./scripts/soak.sh          one minute
#   ./scripts/soak.sh 60       one hour
# Uses build/ (configured and built here when needed); loopback only, free ports.
set -euo pipefail
cd "$(dirname "$0")/.."

minutes=${1:-1}
if ! [[ "$minutes" =~ ^[0-9]+([.][0-9]+)?$ ]]; then
  echo "usage: scripts/soak.sh [MINUTES]" >&2
  exit 2
fi
if command -v ccache > /dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$PWD"
fi
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DVLPGROUND_BUILD_TESTS=ON -DVLPGROUND_BUILD_APPS=ON > build.configure.log 2>&1 ||
    { cat build.configure.log; exit 1; }
fi
cmake --build build -j "$(nproc 2>/dev/null || echo 2)" --target vlpground_soak
seconds=$(awk "BEGIN { print $minutes * 60 }")
exec build/tests/soak/vlpground_soak --seconds "$seconds"
