// Drives a RotationAssembler and records what it emits, column by column.
#pragma once

#include <cstdint>
#include <vector>

#include "synthetic_stream.hpp"
#include "vlpground/driver/rotation_assembler.hpp"

namespace vlpground::test {

struct ColumnRecord {
  std::int64_t time_ns = 0;
  std::uint64_t packet_index = 0;
  int in_packet = 0;
  bool valid = false;
  double azimuth_deg = 0.0;
  friend bool operator==(const ColumnRecord&, const ColumnRecord&) = default;
};

class AssemblerHarness {
 public:
  explicit AssemblerHarness(const AssemblerConfig& config = {})
      : assembler(config), out(config.capacity_columns) {}

  /// Pushes a packet, recording its real columns as sent unless `expect_skip`.
  void push(const DecodedPacket& p, std::int64_t steady_ns = -1, bool expect_skip = false) {
    if (!expect_skip) {
      for (int c = 0; c < p.column_count; ++c) {
        sent.push_back({p.column_time_ns[static_cast<std::size_t>(c)], p.packet_index, c, true,
                        p.azimuth(c, 0)});
      }
    }
    if (assembler.push(p, out, steady_ns)) take();
    while (assembler.pop(out)) take();
  }
  void flush() {
    while (assembler.flush(out)) take();
  }
  void expire(std::int64_t steady_now_ns) {
    while (assembler.expire(steady_now_ns, out)) take();
  }

  /// The real (valid) columns of all emitted frames, in order.
  [[nodiscard]] std::vector<ColumnRecord> emitted_valid() const {
    std::vector<ColumnRecord> all;
    for (const auto& f : frames) {
      for (const auto& c : f) {
        if (c.valid) all.push_back(c);
      }
    }
    return all;
  }

  RotationAssembler assembler;
  Frame out;
  std::vector<FrameMeta> metas;
  std::vector<std::vector<ColumnRecord>> frames;
  std::vector<ColumnRecord> sent;

 private:
  void take() {
    metas.push_back(out.meta);
    auto& cols = frames.emplace_back();
    for (int c = 0; c < out.columns(); ++c) {
      const auto i = static_cast<std::size_t>(c);
      cols.push_back({out.column_time_ns[i], out.column_packet_index[i], out.column_in_packet[i],
                      out.column_valid[i] != 0, out.column_azimuth_deg[i]});
    }
  }
};

}  // namespace vlpground::test
