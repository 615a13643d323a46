// Writes a simulated capture: STEM.pcap (classic pcap, Ethernet/IPv4/UDP 2368 -> 2368 and
// position packets 8308 -> 8308, checksums right), STEM.labels (384 bytes per data packet),
// STEM.heights (each slot's height above the terrain, int16 little-endian cm, same order) and
// STEM.json (how it was made).
//
// Thread-safety: free functions; PcapWriter is single-threaded.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include "vlpground/sim/simulator.hpp"

namespace vlpground::sim {

inline constexpr std::uint16_t kDataPort = 2368;
inline constexpr std::uint16_t kPositionPort = 8308;
inline constexpr std::size_t kUdpFrameOverhead = 42;  // Ethernet 14 + IPv4 20 + UDP 8

/// Wraps `payload` in Ethernet + IPv4 (192.168.1.201 -> 255.255.255.255) + UDP headers with
/// correct IP and UDP checksums. `out` must hold payload.size() + 42 bytes; returns the length.
std::size_t build_udp_frame(std::span<const std::uint8_t> payload, std::uint16_t src_port,
                            std::uint16_t dst_port, std::uint16_t ip_id,
                            std::span<std::uint8_t> out);

/// Classic little-endian pcap, microsecond resolution, LINKTYPE_ETHERNET.
class PcapWriter {
 public:
  /// Throws std::runtime_error when the file cannot be created.
  explicit PcapWriter(const std::filesystem::path& path);
  void write(std::int64_t capture_ns, std::span<const std::uint8_t> frame);
  /// Flushes; throws std::runtime_error on a write error.
  void close();

 private:
  std::ofstream out_;
  std::filesystem::path path_;
};

struct CaptureSummary {
  std::uint64_t data_packets = 0;
  std::uint64_t position_packets = 0;
  std::uint64_t returns = 0;  // slots with a distance
  std::uint64_t ground_returns = 0;
  double duration_s = 0.0;  // capture time span
};

/// The STEM.json content: scene, seed, frames, rpm, mode, model, sensor_height_m, speed_mps,
/// mount_roll_pitch_deg, packets, objects (+ start time, noise, dropout, range).
std::string describe_json(const Simulator& sim, std::uint64_t packets);

/// Writes STEM.pcap, STEM.labels, STEM.heights and STEM.json. Throws std::runtime_error on I/O
/// errors.
CaptureSummary write_capture(const Simulator& sim, const std::filesystem::path& stem);

}  // namespace vlpground::sim
