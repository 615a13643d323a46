// Simulator speed: one data packet (384 rays) per scene, and the rays per second it implies.
// Goal: a 10-frame 600 rpm capture (~800 packets) in a few seconds on one core.
#include <benchmark/benchmark.h>

#include <memory>

#include "vlpground/sim/simulator.hpp"

using namespace vlpground::sim;

static void BM_SimulatePacket(benchmark::State& state) {
  SimConfig config;
  config.scene = static_cast<SceneKind>(state.range(0));
  config.frames = 1;
  const Simulator sim(config);
  auto packet = std::make_unique<SimulatedPacket>();
  std::uint64_t index = 0;
  for (auto _ : state) {
    sim.simulate_packet(index, *packet);
    index = (index + 1) % sim.packet_count();
    benchmark::DoNotOptimize(packet->bytes.data());
  }
  state.SetLabel(std::string(to_string(config.scene)));
  state.SetItemsProcessed(state.iterations() * 384);  // rays
}
BENCHMARK(BM_SimulatePacket)->DenseRange(0, 5);

BENCHMARK_MAIN();
