// Live UDP emitter (Boost.Asio, kept out of the public header).
#include "vlpground/sim/udp_emitter.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "random.hpp"

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

constexpr std::size_t kJunkSizes = 2200;  // junk sizes cycle through 0..2199 bytes

// Sends packets with the configured faults injected; counts what it sent.
class FaultySender {
 public:
  FaultySender(boost::asio::ip::udp::socket& socket, const UdpStreamConfig& config)
      : socket_(socket), faults_(config.faults), rng_(config.faults.seed), junk_(kJunkSizes) {
    for (auto& b : junk_) b = static_cast<std::uint8_t>(rng_.next());
  }

  void send(const Outgoing& o, const boost::asio::ip::udp::endpoint& to,
            const boost::asio::ip::udp::endpoint& data_to) {
    send_junk(data_to);
    if (faults_.loss > 0 && rng_.chance(faults_.loss)) {
      ++stats_.lost;
      return;
    }
    if (!o.position && faults_.truncate > 0 && rng_.chance(faults_.truncate)) {
      const auto length = static_cast<std::size_t>(rng_.integer(1, 1205));
      if (transmit(boost::asio::buffer(o.bytes.data(), length), to)) ++stats_.truncated;
      return;
    }
    if (held_ == nullptr && faults_.reorder > 0 && rng_.chance(faults_.reorder)) {
      held_ = &o;
      held_to_ = to;
      return;
    }
    send_whole(o, to);
    flush();
  }

  /// Sends a held-back packet (at the end of a pass).
  void flush() {
    if (held_ == nullptr) return;
    const Outgoing* held = held_;
    held_ = nullptr;
    if (send_whole(*held, held_to_)) ++stats_.reordered;
  }

  UdpStreamStats stats_;

 private:
  bool transmit(const boost::asio::const_buffer& bytes, const boost::asio::ip::udp::endpoint& to) {
    boost::system::error_code ec;
    socket_.send_to(bytes, to, 0, ec);
    if (ec) ++stats_.send_errors;
    return !ec;
  }

  bool send_whole(const Outgoing& o, const boost::asio::ip::udp::endpoint& to) {
    if (!transmit(boost::asio::buffer(o.bytes), to)) return false;
    ++(o.position ? stats_.position_packets : stats_.data_packets);
    return true;
  }

  void send_junk(const boost::asio::ip::udp::endpoint& to) {
    if (faults_.junk <= 0) return;
    const double whole = std::floor(faults_.junk);
    const int count = static_cast<int>(whole) + (rng_.chance(faults_.junk - whole) ? 1 : 0);
    for (int i = 0; i < count; ++i) {
      const std::size_t size = junk_size_;
      junk_size_ = (junk_size_ + 1) % kJunkSizes;
      junk_[rng_.next() % kJunkSizes] ^= static_cast<std::uint8_t>(rng_.next() | 1);
      if (transmit(boost::asio::buffer(junk_.data(), size), to)) ++stats_.junk;
    }
  }

  boost::asio::ip::udp::socket& socket_;
  UdpFaults faults_;
  detail::Rng rng_;
  std::vector<std::uint8_t> junk_;
  std::size_t junk_size_ = 0;
  const Outgoing* held_ = nullptr;
  boost::asio::ip::udp::endpoint held_to_;
};

}  // namespace

UdpStreamStats& UdpStreamStats::operator+=(const UdpStreamStats& o) {
  data_packets += o.data_packets;
  position_packets += o.position_packets;
  send_errors += o.send_errors;
  lost += o.lost;
  reordered += o.reordered;
  truncated += o.truncated;
  junk += o.junk;
  return *this;
}

void UdpStreamConfig::validate() const {
  if (host.empty()) throw std::invalid_argument("udp: empty host");
  if (data_port == 0 || position_port == 0) throw std::invalid_argument("udp: port 0");
  if (!(rate > 0.0 && rate <= 1000.0))
    throw std::invalid_argument("udp: rate must be in (0, 1000]");
  for (const double fraction : {faults.loss, faults.reorder, faults.truncate}) {
    if (!(fraction >= 0.0 && fraction <= 1.0)) {
      throw std::invalid_argument("udp: fault fractions must be in [0, 1]");
    }
  }
  if (!(faults.junk >= 0.0 && faults.junk <= 100.0)) {
    throw std::invalid_argument("udp: junk must be in [0, 100] datagrams per packet");
  }
}

struct PreparedStream::Impl {
  std::vector<Outgoing> all;
  std::int64_t packet_period_ns = 0;
  std::int64_t applied_shift_ns = 0;  // stamps in `all` are shifted by this
};

PreparedStream::PreparedStream(const Simulator& sim) : impl_(std::make_unique<Impl>()) {
  impl_->all = prepare(sim);
  impl_->packet_period_ns = sim.packet_period_ns();
}

PreparedStream::~PreparedStream() = default;
PreparedStream::PreparedStream(PreparedStream&&) noexcept = default;
PreparedStream& PreparedStream::operator=(PreparedStream&&) noexcept = default;

UdpStreamStats PreparedStream::play(const UdpStreamConfig& config,
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
  if (!config.source_address.empty()) {
    const auto from = ip::make_address(config.source_address, ec);
    if (!ec) socket.bind(ip::udp::endpoint(from, 0), ec);
    if (ec) {
      throw std::invalid_argument("udp: cannot send from '" + config.source_address +
                                  "': " + ec.message());
    }
  }

  std::vector<Outgoing>& all = impl_->all;
  FaultySender sender(socket, config);
  if (all.empty()) return sender.stats_;
  const std::int64_t first_ns = all.front().capture_ns;
  // One cycle lasts the span plus one packet period, so a loop continues the clock.
  const std::int64_t cycle_ns = all.back().capture_ns - first_ns + impl_->packet_period_ns;
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t cycle = 0;; ++cycle) {
    const std::int64_t shift = cycle * cycle_ns;
    if (shift != impl_->applied_shift_ns) {
      for (Outgoing& o : all) restamp(o, shift);
      impl_->applied_shift_ns = shift;
    }
    for (const Outgoing& o : all) {
      if (should_stop && should_stop()) {
        sender.flush();
        return sender.stats_;
      }
      const auto due =
          start + std::chrono::nanoseconds(static_cast<std::int64_t>(
                      static_cast<double>(o.capture_ns + shift - first_ns) / config.rate));
      std::this_thread::sleep_until(due);
      sender.send(o, o.position ? position_to : data_to, data_to);
    }
    sender.flush();
    if (!config.loop) return sender.stats_;
  }
}

UdpStreamStats stream_udp(const Simulator& sim, const UdpStreamConfig& config,
                          const std::function<bool()>& should_stop) {
  config.validate();
  return PreparedStream(sim).play(config, should_stop);
}

}  // namespace vlpground::sim
