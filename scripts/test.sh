#!/usr/bin/env bash
# README command 2: install what is missing, build, run the whole test suite with ctest.
#   ./scripts/test.sh              Release build in build/ (tests + benchmarks compiled)
#   ./scripts/test.sh --sanitize   ASan+UBSan build of the tests in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
cmake_args=(-DVLPGROUND_BUILD_TESTS=ON -DVLPGROUND_BUILD_APPS=ON -DVLPGROUND_BUILD_BENCHMARKS=ON)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  cmake_args=(-DVLPGROUND_BUILD_TESTS=ON -DVLPGROUND_BUILD_APPS=ON -DVLPGROUND_SANITIZE=ON
              -DCMAKE_BUILD_TYPE=RelWithDebInfo)
fi

./scripts/setup.sh
# ccache (installed by setup.sh) makes rebuilds of unchanged files free, also across clones.
if command -v ccache > /dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$PWD"
fi
jobs=$(nproc 2>/dev/null || echo 2)
echo "test: configuring ${build_dir}/"
cmake -S . -B "$build_dir" "${cmake_args[@]}" > "$build_dir.configure.log" 2>&1 ||
  { cat "$build_dir.configure.log"; exit 1; }
echo "test: building with ${jobs} jobs"
cmake --build "$build_dir" -j "$jobs"
echo "test: running ctest"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" --timeout 600
