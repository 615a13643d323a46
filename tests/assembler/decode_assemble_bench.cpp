// Decode + assemble throughput from packets held in memory (no I/O). Goal: >= 754,000
// single-return packets/s on one core (the sensor sends ~754/s, so 1000x real time).
#include <benchmark/benchmark.h>

#include "encoded_stream.hpp"
#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/rotation_assembler.hpp"

using namespace vlpground;

namespace {

void decode_assemble(benchmark::State& state, ReturnMode mode) {
  const int count = 20000;
  const auto packets = test::encode_stream(count, 600, mode);
  const std::int64_t period =
      mode == ReturnMode::dual ? kDualPacketPeriodNs : kSinglePacketPeriodNs;
  const std::int64_t hour_ns = 1'699'999'200'000'000'000;
  PacketDecoder decoder;
  RotationAssembler assembler;
  DecodedPacket decoded;
  Frame out;
  std::int64_t frames = 0, processed = 0;
  std::int64_t lap = 0;
  for (auto _ : state) {
    for (int i = 0; i < count; ++i) {
      // Replays continue in time so the assembler sees one long stream.
      const std::int64_t receive = hour_ns + 1'000'000'000 + (lap * count + i) * period;
      if (decoder.decode(packets[static_cast<std::size_t>(i)], receive, decoded) ==
          DecodeStatus::ok) {
        decoded.time_ns += lap * count * period;
        for (int c = 0; c < decoded.column_count; ++c) {
          decoded.column_time_ns[static_cast<std::size_t>(c)] += lap * count * period;
        }
        if (assembler.push(decoded, out)) ++frames;
        while (assembler.pop(out)) ++frames;
      }
    }
    processed += count;
    ++lap;
    benchmark::DoNotOptimize(out.columns());
  }
  state.SetItemsProcessed(processed);
  state.counters["packets_per_s"] =
      benchmark::Counter(static_cast<double>(processed), benchmark::Counter::kIsRate);
  state.counters["frames"] = static_cast<double>(frames);
}

void BM_DecodeAssembleSingle(benchmark::State& state) {
  decode_assemble(state, ReturnMode::strongest);
}
void BM_DecodeAssembleDual(benchmark::State& state) { decode_assemble(state, ReturnMode::dual); }

}  // namespace

BENCHMARK(BM_DecodeAssembleSingle)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeAssembleDual)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
