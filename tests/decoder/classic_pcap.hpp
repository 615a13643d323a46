// A tiny test-local reader of classic little-endian pcap files with Ethernet + IPv4 + UDP
// frames (42-byte headers), enough for the shared captures. Data (1206-byte) and position
// (512-byte) payloads are returned; other or truncated records are skipped.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

namespace vlpground::test {

struct PcapPayload {
  std::int64_t receive_ns = 0;
  std::vector<std::uint8_t> bytes;
};

struct PcapPayloads {
  std::vector<PcapPayload> data;      // 1206-byte payloads, in file order
  std::vector<PcapPayload> position;  // 512-byte payloads
};

inline std::uint32_t pcap_u32(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

inline PcapPayloads read_classic_pcap(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)),
                                       std::istreambuf_iterator<char>());
  if (file.size() < 24) throw std::runtime_error("not a pcap: " + path.string());
  const bool nanos = pcap_u32(file, 0) == 0xA1B23C4D;
  PcapPayloads out;
  for (std::size_t at = 24; at + 16 <= file.size();) {
    const std::int64_t sec = pcap_u32(file, at);
    const std::int64_t frac = pcap_u32(file, at + 4);
    const std::size_t captured = pcap_u32(file, at + 8);
    const std::size_t start = at + 16;
    at = start + captured;
    if (at > file.size() || captured < 42) continue;
    const std::size_t payload = captured - 42;
    if (payload != 1206 && payload != 512) continue;
    PcapPayload p;
    p.receive_ns = sec * 1'000'000'000 + frac * (nanos ? 1 : 1000);
    p.bytes.assign(file.begin() + static_cast<std::ptrdiff_t>(start + 42),
                   file.begin() + static_cast<std::ptrdiff_t>(at));
    (payload == 1206 ? out.data : out.position).push_back(std::move(p));
  }
  return out;
}

}  // namespace vlpground::test
