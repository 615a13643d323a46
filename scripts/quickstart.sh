#!/usr/bin/env bash
# README command 1: install what is missing, build, and replay a capture from pcaps/ through
# the driver and the ground detector, printing a line per frame and a summary, and writing
# a picture of every labelled frame into out/.
set -euo pipefail
cd "$(dirname "$0")/.."

capture=${1:-pcaps/urban_demo.pcap}
./scripts/setup.sh
if command -v ccache > /dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$PWD"
fi
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DVLPGROUND_BUILD_APPS=ON > build.configure.log 2>&1 ||
  { cat build.configure.log; exit 1; }
cmake --build build -j "$jobs" --target vlpground_cli
mkdir -p out
./build/apps/vlpground replay "$capture" --png out/ --csv out/returns.csv
echo "quickstart: pictures of the labelled frames are in out/ (e.g. out/$(ls out | grep -m1 png))"
