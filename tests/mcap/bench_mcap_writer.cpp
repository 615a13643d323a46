// Google Benchmark: Writer::write + flush of one lidar-frame-sized chunk (a point cloud of
// 28 800 points x 32 bytes with sensor-like structure, plus two small messages) per iteration,
// for each compression. Reports bytes/s of uncompressed message data and the compression ratio.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "vlpground/mcap/writer.hpp"

namespace {

using namespace vlpground::mcap;

// A point cloud with the regularity of a real scan (smooth ranges, repeated rings/labels).
std::vector<std::byte> point_cloud(std::size_t points) {
  std::vector<std::byte> bytes(points * 32);
  for (std::size_t i = 0; i < points; ++i) {
    const float az = static_cast<float>(i / 16) * 0.0035f;
    const float r = 8.0f + 3.0f * std::sin(az * 5.0f) + static_cast<float>(i % 16) * 0.4f;
    const float xyz[4] = {r * std::cos(az), r * std::sin(az), -1.5f + static_cast<float>(i % 16) * 0.1f,
                          static_cast<float>((i * 13) % 100)};
    std::memcpy(&bytes[i * 32], xyz, sizeof xyz);
    const std::uint32_t ring_label[2] = {static_cast<std::uint32_t>(i % 16), i % 16 < 6 ? 1u : 2u};
    std::memcpy(&bytes[i * 32 + 16], ring_label, sizeof ring_label);
  }
  return bytes;
}

void write_frames(benchmark::State& state, Compression compression) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("vlpground_bench_" + std::string(to_string(compression)) + ".mcap"))
          .string();
  WriterConfig config;
  config.compression = compression;
  Writer writer;
  writer.open(path, config);
  const std::byte schema[] = {std::byte{'{'}, std::byte{'}'}};
  const auto s = writer.add_schema("bench", "jsonschema", schema);
  const auto points = writer.add_channel(s, "/points", "json");
  const auto small = writer.add_channel(s, "/small", "json");
  const auto cloud = point_cloud(28'800);
  const std::vector<std::byte> tiny(400, std::byte{7});
  std::uint64_t t = 1;
  for (auto _ : state) {
    writer.write(points, t, t, cloud);
    writer.write(small, t, t, tiny);
    writer.write(small, t, t, tiny);
    writer.flush();
    ++t;
  }
  const WriterStats stats = writer.stats();
  state.SetBytesProcessed(static_cast<std::int64_t>(stats.uncompressed_bytes));
  state.counters["ratio"] = static_cast<double>(stats.uncompressed_bytes) /
                            static_cast<double>(std::max<std::uint64_t>(stats.file_bytes, 1));
  writer.close();
  std::filesystem::remove(path);
}

BENCHMARK_CAPTURE(write_frames, zstd, Compression::zstd)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(write_frames, lz4, Compression::lz4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(write_frames, none, Compression::none)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
