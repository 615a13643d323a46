#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + coverage) in build-fuzz/ and runs each for a
# bounded time. Exits non-zero when a fuzzer finds a crash; skips (exit 0) without clang.
#   FUZZ_SECONDS=60 ./scripts/fuzz.sh
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v clang >/dev/null 2>&1 || ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: clang not found, skipping (install clang and libclang-rt-dev to fuzz)"
  exit 0
fi

seconds=${FUZZ_SECONDS:-20}
build_dir=build-fuzz
jobs=${FUZZ_JOBS:-2}
instrument="-fsanitize=fuzzer-no-link,address -fno-omit-frame-pointer -g"

echo "fuzz: configuring ${build_dir}/"
CC=clang CXX=clang++ cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DVLPGROUND_BUILD_FUZZERS=ON -DVLPGROUND_BUILD_TESTS=ON -DVLPGROUND_BUILD_APPS=OFF \
  -DVLPGROUND_BUILD_BENCHMARKS=OFF "-DCMAKE_CXX_FLAGS=${instrument}" "-DCMAKE_C_FLAGS=${instrument}" \
  > "$build_dir.configure.log" 2>&1 || { cat "$build_dir.configure.log"; exit 1; }
echo "fuzz: building fuzz_decoder fuzz_pcap_reader"
cmake --build "$build_dir" -j "$jobs" --target fuzz_decoder fuzz_pcap_reader

status=0
for target in fuzz_decoder fuzz_pcap_reader; do
  corpus="$build_dir/corpus/$target"
  mkdir -p "$corpus" "$build_dir/crashes"
  # Seeds from the shared captures when present (never copied into the repository).
  for seed in ../shared/data/real/vlp16_one_packet.pcap ../shared/data/real/vlp16_one_position_packet.pcap; do
    [ -f "$seed" ] && cp -n "$seed" "$corpus/" || true
  done
  echo "fuzz: running $target for ${seconds}s"
  if ! "$build_dir/tests/fuzz/$target" "$corpus" -max_total_time="$seconds" -max_len=4096 \
      -artifact_prefix="$build_dir/crashes/$target-" -print_final_stats=1 2> "$build_dir/$target.log"; then
    echo "fuzz: $target FOUND A CRASH (see $build_dir/$target.log and $build_dir/crashes/)"
    tail -40 "$build_dir/$target.log"
    status=1
  else
    grep -E "stat::number_of_executed_units|Done" "$build_dir/$target.log" | tail -2 || true
  fi
done
rm -f /dev/shm/vlpground-fuzz-*.pcap
exit $status
