// pcap + labels + heights + json output of the simulator.
#include "vlpground/sim/capture_writer.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

namespace vlpground::sim {
namespace {

constexpr std::array<std::uint8_t, 6> kDstMac = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
constexpr std::array<std::uint8_t, 6> kSrcMac = {0x60, 0x76, 0x88, 0x00, 0x00, 0x01};
constexpr std::array<std::uint8_t, 4> kSrcIp = {192, 168, 1, 201};
constexpr std::array<std::uint8_t, 4> kDstIp = {255, 255, 255, 255};

void put16be(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  p[1] = static_cast<std::uint8_t>(v & 0xFF);
}

void put16le(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v & 0xFF);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}

void put32le(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF);
}

// One packet's heights as the .heights file holds them: int16 little-endian per slot.
std::array<std::uint8_t, 2 * kSlotsPerPacket> heights_le(
    const std::array<std::int16_t, kSlotsPerPacket>& heights_cm) {
  std::array<std::uint8_t, 2 * kSlotsPerPacket> out{};
  for (std::size_t i = 0; i < heights_cm.size(); ++i) {
    put16le(out.data() + 2 * i, static_cast<std::uint16_t>(heights_cm[i]));
  }
  return out;
}

// One's-complement sum of 16-bit big-endian words (RFC 1071), not yet folded.
std::uint32_t ones_sum(const std::uint8_t* p, std::size_t n, std::uint32_t sum = 0) {
  for (std::size_t i = 0; i + 1 < n; i += 2) sum += (std::uint32_t{p[i]} << 8) | p[i + 1];
  if (n % 2 != 0) sum += std::uint32_t{p[n - 1]} << 8;
  return sum;
}

std::uint16_t fold(std::uint32_t sum) {
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum & 0xFFFF);
}

}  // namespace

std::size_t build_udp_frame(std::span<const std::uint8_t> payload, std::uint16_t src_port,
                            std::uint16_t dst_port, std::uint16_t ip_id,
                            std::span<std::uint8_t> out) {
  const std::size_t total = payload.size() + kUdpFrameOverhead;
  if (out.size() < total || payload.size() > 1472) {
    throw std::invalid_argument("build_udp_frame: payload too large or buffer too small");
  }
  std::uint8_t* eth = out.data();
  std::memcpy(eth, kDstMac.data(), 6);
  std::memcpy(eth + 6, kSrcMac.data(), 6);
  put16be(eth + 12, 0x0800);
  std::uint8_t* ip = eth + 14;
  ip[0] = 0x45;
  ip[1] = 0;
  put16be(ip + 2, static_cast<std::uint32_t>(20 + 8 + payload.size()));
  put16be(ip + 4, ip_id);
  put16be(ip + 6, 0x4000);  // don't fragment
  ip[8] = 64;
  ip[9] = 17;
  put16be(ip + 10, 0);
  std::memcpy(ip + 12, kSrcIp.data(), 4);
  std::memcpy(ip + 16, kDstIp.data(), 4);
  put16be(ip + 10, fold(ones_sum(ip, 20)));
  std::uint8_t* udp = ip + 20;
  const auto udp_len = static_cast<std::uint32_t>(8 + payload.size());
  put16be(udp, src_port);
  put16be(udp + 2, dst_port);
  put16be(udp + 4, udp_len);
  put16be(udp + 6, 0);
  std::memcpy(udp + 8, payload.data(), payload.size());
  // Pseudo-header: source, destination, protocol, UDP length.
  std::uint32_t sum = ones_sum(ip + 12, 8);
  sum += 17 + udp_len;
  std::uint16_t check = fold(ones_sum(udp, udp_len, sum));
  if (check == 0) check = 0xFFFF;  // 0 means "no checksum" in UDP over IPv4
  put16be(udp + 6, check);
  return total;
}

PcapWriter::PcapWriter(const std::filesystem::path& path)
    : out_(path, std::ios::binary | std::ios::trunc), path_(path) {
  if (!out_) throw std::runtime_error("cannot create " + path.string());
  std::array<std::uint8_t, 24> header{};
  put32le(header.data(), 0xA1B2C3D4u);
  header[4] = 2;  // version 2.4
  header[6] = 4;
  put32le(header.data() + 16, 65535);  // snaplen
  put32le(header.data() + 20, 1);      // LINKTYPE_ETHERNET
  out_.write(reinterpret_cast<const char*>(header.data()), header.size());
}

void PcapWriter::write(std::int64_t capture_ns, std::span<const std::uint8_t> frame) {
  std::array<std::uint8_t, 16> record{};
  put32le(record.data(), static_cast<std::uint32_t>(capture_ns / 1'000'000'000));
  put32le(record.data() + 4, static_cast<std::uint32_t>((capture_ns % 1'000'000'000) / 1000));
  put32le(record.data() + 8, static_cast<std::uint32_t>(frame.size()));
  put32le(record.data() + 12, static_cast<std::uint32_t>(frame.size()));
  out_.write(reinterpret_cast<const char*>(record.data()), record.size());
  out_.write(reinterpret_cast<const char*>(frame.data()),
             static_cast<std::streamsize>(frame.size()));
}

void PcapWriter::close() {
  out_.flush();
  if (!out_) throw std::runtime_error("write error on " + path_.string());
  out_.close();
}

std::string describe_json(const Simulator& sim, std::uint64_t packets) {
  const SimConfig& c = sim.config();
  nlohmann::ordered_json j;
  j["scene"] = std::string(to_string(c.scene));
  j["seed"] = c.seed;
  j["frames"] = c.frames;
  if (c.rpm == std::floor(c.rpm)) {
    j["rpm"] = static_cast<int>(c.rpm);  // as the shared captures write it
  } else {
    j["rpm"] = c.rpm;
  }
  j["mode"] = std::string(to_string(c.mode));
  j["model"] = std::string(to_string(c.model));
  j["sensor_height_m"] = sim.sensor_height_m();
  j["speed_mps"] = sim.speed_mps();
  j["mount_roll_pitch_deg"] = {c.mount_roll_deg, c.mount_pitch_deg};
  j["packets"] = packets;
  j["objects"] = sim.scene().obstacles().size();
  j["start_utc_ns"] = c.start_utc_ns;
  j["start_azimuth_deg"] = sim.start_azimuth_deg();
  j["range_noise_m"] = c.range_noise_m;
  j["dropout_probability"] = c.dropout_probability;
  j["max_range_m"] = c.max_range_m;
  j["generator"] = "vlpground sim";
  return j.dump(1) + "\n";
}

CaptureSummary write_capture(const Simulator& sim, const std::filesystem::path& stem) {
  const auto with_ext = [&](const char* ext) {
    std::filesystem::path p = stem;
    p += ext;
    return p;
  };
  PcapWriter pcap(with_ext(".pcap"));
  std::ofstream labels(with_ext(".labels"), std::ios::binary | std::ios::trunc);
  if (!labels) throw std::runtime_error("cannot create " + with_ext(".labels").string());
  std::ofstream heights(with_ext(".heights"), std::ios::binary | std::ios::trunc);
  if (!heights) throw std::runtime_error("cannot create " + with_ext(".heights").string());

  CaptureSummary summary;
  auto packet = std::make_unique<SimulatedPacket>();
  SimulatedPositionPacket position;
  std::vector<std::uint8_t> frame(1206 + kUdpFrameOverhead);
  std::uint16_t ip_id = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  for (std::uint64_t i = 0; i < sim.packet_count(); ++i) {
    sim.simulate_packet(i, *packet);
    if (i == 0) first_ns = packet->capture_ns;
    last_ns = packet->capture_ns;
    const auto n = build_udp_frame(packet->bytes, kDataPort, kDataPort, ip_id++, frame);
    pcap.write(packet->capture_ns, std::span(frame.data(), n));
    labels.write(reinterpret_cast<const char*>(packet->labels.data()), kSlotsPerPacket);
    const auto heights_bytes = heights_le(packet->heights_cm);
    heights.write(reinterpret_cast<const char*>(heights_bytes.data()),
                  static_cast<std::streamsize>(heights_bytes.size()));
    for (const std::uint8_t l : packet->labels) {
      summary.returns += l != 0 ? 1u : 0u;
      summary.ground_returns += l == 1 ? 1u : 0u;
    }
    ++summary.data_packets;
    if (sim.position_after(i, position)) {
      const auto m = build_udp_frame(position.bytes, kPositionPort, kPositionPort, ip_id++, frame);
      pcap.write(position.capture_ns, std::span(frame.data(), m));
      ++summary.position_packets;
    }
  }
  pcap.close();
  labels.flush();
  if (!labels) throw std::runtime_error("write error on " + with_ext(".labels").string());
  heights.flush();
  if (!heights) throw std::runtime_error("write error on " + with_ext(".heights").string());
  std::ofstream json(with_ext(".json"), std::ios::trunc);
  json << describe_json(sim, summary.data_packets);
  if (!json) throw std::runtime_error("write error on " + with_ext(".json").string());
  summary.duration_s = static_cast<double>(last_ns - first_ns) * 1e-9;
  return summary;
}

}  // namespace vlpground::sim
