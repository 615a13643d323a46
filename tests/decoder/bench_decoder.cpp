// Google Benchmark: PacketDecoder::decode alone on a rotating stream of encoded packets.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <vector>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/sim/packet_encoder.hpp"

namespace {

using namespace vlpground;

// One rotation at 600 rpm of packets with varied ranges (deterministic pattern).
std::vector<std::array<std::uint8_t, kDataPacketBytes>> make_packets(std::uint8_t mode) {
  std::vector<std::array<std::uint8_t, kDataPacketBytes>> packets(76);
  const bool dual = mode == kModeDual;
  double azimuth = 0.0;
  std::uint32_t stamp = 0;
  for (auto& bytes : packets) {
    sim::DataPacketFields f;
    f.return_mode = mode;
    f.stamp_us_past_hour = stamp;
    stamp += dual ? 664 : 1327;
    for (std::size_t b = 0; b < 12; ++b) {
      f.azimuth_centideg[b] = static_cast<std::uint16_t>(static_cast<int>(azimuth) % 36000);
      if (!dual || b % 2 == 1) azimuth += 39.81;
      for (std::size_t ch = 0; ch < 32; ++ch) {
        f.distance_2mm[b][ch] = static_cast<std::uint16_t>((b * 977 + ch * 131 + stamp) % 60000);
        f.reflectivity[b][ch] = static_cast<std::uint8_t>(ch * 7);
      }
    }
    sim::encode_data_packet(f, bytes);
  }
  return packets;
}

void decode_stream(benchmark::State& state, std::uint8_t mode) {
  const auto packets = make_packets(mode);
  PacketDecoder decoder;
  DecodedPacket out;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(decoder.decode(packets[i], 0, out));
    benchmark::ClobberMemory();
    i = i + 1 == packets.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["packets_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_DecodeSingle(benchmark::State& state) { decode_stream(state, kModeStrongest); }
void BM_DecodeDual(benchmark::State& state) { decode_stream(state, kModeDual); }

}  // namespace

BENCHMARK(BM_DecodeSingle);
BENCHMARK(BM_DecodeDual);
BENCHMARK_MAIN();
