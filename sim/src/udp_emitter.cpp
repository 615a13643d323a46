// Live UDP emitter (Boost.Asio, kept out of the public header).
#include "vlpground/sim/udp_emitter.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

namespace vlpground::sim {
namespace {

constexpr std::int64_t kHourNs = 3'600'000'000'000;

struct Outgoing {
  std::int64_t capture_ns = 0;
  std::int64_t stamp_time_ns = 0;  // UTC time encoded in the stamp
  std::size_t stamp_offset = 0;    // 1200 (data) or 198 (position)
  bool position = false;
  std::vector<std::uint8_t> bytes;
};

std::vector<Outgoing> prepare(const Simulator& sim) {
  std::vector<Outgoing> all;
  all.reserve(sim.packet_count() * 15 / 14 + 1);
  auto packet = std::make_unique<SimulatedPacket>();
  SimulatedPositionPacket position;
  for (std::uint64_t i = 0; i < sim.packet_count(); ++i) {
    sim.simulate_packet(i, *packet);
    all.push_back({packet->capture_ns,
                   packet->time_ns,
                   1200,
                   false,
                   {packet->bytes.begin(), packet->bytes.end()}});
    if (sim.position_after(i, position)) {
      all.push_back({position.capture_ns,
                     position.time_ns,
                     198,
                     true,
                     {position.bytes.begin(), position.bytes.end()}});
    }
  }
  return all;
}

void restamp(Outgoing& o, std::int64_t shift_ns) {
  const auto us = static_cast<std::uint32_t>(((o.stamp_time_ns + shift_ns) % kHourNs) / 1000);
  for (std::size_t i = 0; i < 4; ++i) {
    o.bytes[o.stamp_offset + i] = static_cast<std::uint8_t>((us >> (8 * i)) & 0xFF);
  }
}

}  // namespace

void UdpStreamConfig::validate() const {
  if (host.empty()) throw std::invalid_argument("udp: empty host");
  if (data_port == 0 || position_port == 0) throw std::invalid_argument("udp: port 0");
  if (!(rate > 0.0 && rate <= 1000.0))
    throw std::invalid_argument("udp: rate must be in (0, 1000]");
}

UdpStreamStats stream_udp(const Simulator& sim, const UdpStreamConfig& config,
                          const std::function<bool()>& should_stop) {
  config.validate();
  namespace ip = boost::asio::ip;
  boost::asio::io_context io;
  ip::udp::resolver resolver(io);
  boost::system::error_code ec;
  const auto results = resolver.resolve(ip::udp::v4(), config.host, "0", ec);
  if (ec || results.empty()) {
    throw std::runtime_error("udp: cannot resolve host '" + config.host + "'");
  }
  const ip::address address = results.begin()->endpoint().address();
  const ip::udp::endpoint data_to(address, config.data_port);
  const ip::udp::endpoint position_to(address, config.position_port);
  ip::udp::socket socket(io);
  socket.open(ip::udp::v4(), ec);
  if (ec) throw std::runtime_error("udp: cannot open socket: " + ec.message());
  if (address.to_v4() == ip::address_v4::broadcast()) {
    socket.set_option(boost::asio::socket_base::broadcast(true));
  }

  std::vector<Outgoing> all = prepare(sim);
  UdpStreamStats stats;
  if (all.empty()) return stats;
  const std::int64_t first_ns = all.front().capture_ns;
  // One cycle lasts the span plus one packet period, so a loop continues the clock.
  const std::int64_t cycle_ns = all.back().capture_ns - first_ns + sim.packet_period_ns();
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t cycle = 0;; ++cycle) {
    for (Outgoing& o : all) {
      if (should_stop && should_stop()) return stats;
      const std::int64_t shift = cycle * cycle_ns;
      if (cycle > 0) restamp(o, shift);
      const auto due =
          start + std::chrono::nanoseconds(static_cast<std::int64_t>(
                      static_cast<double>(o.capture_ns + shift - first_ns) / config.rate));
      std::this_thread::sleep_until(due);
      socket.send_to(boost::asio::buffer(o.bytes), o.position ? position_to : data_to, 0, ec);
      if (ec) {
        ++stats.send_errors;
      } else if (o.position) {
        ++stats.position_packets;
      } else {
        ++stats.data_packets;
      }
    }
    if (!config.loop) return stats;
  }
}

}  // namespace vlpground::sim
