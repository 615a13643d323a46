// Which UDP datagrams are Velodyne packets for us: selection by destination port, sensor
// address and size, shared by the pcap and UDP sources (private to the driver).
// Thread-safety: const methods only; the counters passed in belong to the caller.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "frame_parser.hpp"
#include "vlpground/driver/packet_source.hpp"

namespace vlpground::driver_detail {

inline constexpr std::size_t kDataPacketBytes = 1206;
inline constexpr std::size_t kPositionPacketBytes = 512;

/// Parses a sensor-address setting; empty means "any". Throws std::invalid_argument.
inline std::optional<IpAddress> parse_sensor_address(const std::string& text) {
  if (text.empty()) return std::nullopt;
  auto address = parse_ip_address(text);
  if (!address) {
    throw std::invalid_argument("sensor_address '" + text + "' is not an IPv4 or IPv6 address");
  }
  return address;
}

/// True when `from` matches `wanted`, also when an IPv4 sender is seen as IPv4-mapped IPv6.
inline bool same_address(const IpAddress& wanted, const IpAddress& from) {
  if (wanted == from) return true;
  if (wanted.version != 4 || from.version != 6) return false;
  static constexpr std::uint8_t kMappedPrefix[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF};
  for (std::size_t i = 0; i < 12; ++i) {
    if (from.bytes[i] != kMappedPrefix[i]) return false;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    if (from.bytes[12 + i] != wanted.bytes[i]) return false;
  }
  return true;
}

/// The public, plain form of a datagram's sender.
inline SourceAddress to_source_address(const UdpDatagram& datagram) {
  SourceAddress address;
  address.version = datagram.source.version;
  address.bytes = datagram.source.bytes;
  address.port = datagram.source_port;
  return address;
}

struct PacketFilter {
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;  // 0 = none
  std::optional<IpAddress> sensor;

  /// The packet kind when `datagram` is one of ours; otherwise counts why not and returns
  /// nullopt. When data and position share one port, the size decides.
  std::optional<PacketKind> accept(const UdpDatagram& datagram, SourceCounters& counters) const {
    const std::uint16_t port = datagram.destination_port;
    const bool on_data = port == data_port;
    const bool on_position = position_port != 0 && port == position_port;
    if (!on_data && !on_position) {
      ++counters.skipped_other;
      return std::nullopt;
    }
    if (sensor && !same_address(*sensor, datagram.source)) {
      ++counters.skipped_address;
      return std::nullopt;
    }
    const std::size_t size = datagram.payload.size();
    if (on_data && size == kDataPacketBytes) {
      ++counters.data_packets;
      return PacketKind::data;
    }
    if (on_position && size == kPositionPacketBytes) {
      ++counters.position_packets;
      return PacketKind::position;
    }
    ++counters.skipped_wrong_size;
    return std::nullopt;
  }
};

}  // namespace vlpground::driver_detail
