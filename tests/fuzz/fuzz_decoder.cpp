// libFuzzer: arbitrary bytes through the data-packet decoder and the position-packet parser.
// Inputs of the right sizes are the interesting ones; the fuzzer also pads/cuts to them.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/driver/position_packet.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vlpground;
  static PacketDecoder decoder;  // keeps timing / warning state across inputs, as in use
  static DecodedPacket out;
  const std::span<const std::uint8_t> bytes(data, size);
  decoder.decode(bytes, static_cast<std::int64_t>(size) * 1'000'000, out);

  // The same bytes placed into exact-size packets, so the deep paths are reached.
  std::array<std::uint8_t, kDataPacketBytes> packet{};
  std::copy_n(data, std::min(size, packet.size()), packet.begin());
  for (std::size_t b = 0; b < 12 && size < 600; ++b) {  // short inputs: keep the flags valid
    packet[b * 100] = 0xFF;
    packet[b * 100 + 1] = 0xEE;
  }
  decoder.decode(packet, 0, out);

  PositionPacket position;
  parse_position_packet(bytes, 0, position);
  std::array<std::uint8_t, kPositionPacketBytes> position_bytes{};
  std::copy_n(data, std::min(size, position_bytes.size()), position_bytes.begin());
  if (parse_position_packet(position_bytes, 0, position)) decoder.set_gps_time_reference(position);
  parse_gprmc(reinterpret_cast<const char*>(data), size);
  return 0;
}
