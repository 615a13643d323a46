// Live UDP reception from one sensor (or any sender): a data socket and an optional position
// socket (udp_socket.hpp), waited for together with the stop signal.
#include <array>
#include <stdexcept>
#include <string>

#include "packet_filter.hpp"
#include "udp_socket.hpp"
#include "vlpground/driver/packet_source.hpp"

namespace vlpground {

namespace {

driver_detail::UdpSocketOptions socket_options(const UdpSourceConfig& config) {
  return {config.bind_address, config.multicast_group, config.reuse_address,
          config.receive_buffer_bytes};
}

}  // namespace

void UdpSourceConfig::validate() const {
  driver_detail::validate_socket_options(socket_options(*this), "udp source");
  if (data_port == 0) throw std::invalid_argument("udp source: data_port must not be 0");
  if (position_port == data_port) {
    throw std::invalid_argument("udp source: data_port and position_port must differ");
  }
  (void)driver_detail::parse_sensor_address(sensor_address);
}

namespace {

using driver_detail::ReadResult;
using driver_detail::UdpSocket;

/// Thread-safety: one thread calls next(); request_stop() from any thread.
class UdpSource final : public PacketSource {
 public:
  UdpSource(const UdpSourceConfig& config, int* granted_buffer_bytes) : config_(config) {
    filter_.data_port = config.data_port;
    filter_.position_port = config.position_port;
    filter_.sensor = driver_detail::parse_sensor_address(config.sensor_address);
    const auto options = socket_options(config);
    sockets_[socket_count_++] = std::make_unique<UdpSocket>(options, config.data_port);
    if (config.position_port != 0) {
      sockets_[socket_count_++] = std::make_unique<UdpSocket>(options, config.position_port);
    }
    if (granted_buffer_bytes != nullptr) {
      *granted_buffer_bytes = sockets_[0]->granted_buffer_bytes();
    }
    for (std::size_t i = 0; i < socket_count_; ++i) waiter_.add(sockets_[i]->native_handle());
  }

  SourceStatus next(PacketView& out, int timeout_ms) override {
    return waiter_.next(timeout_ms, [&] { return receive_any(out); });
  }

  void request_stop() override { waiter_.request_stop(); }

  [[nodiscard]] const SourceCounters& counters() const override { return counters_; }
  [[nodiscard]] bool is_live() const override { return true; }

  [[nodiscard]] std::string describe() const override {
    std::string text = "udp " + config_.bind_address + ":" + std::to_string(config_.data_port);
    if (config_.position_port != 0)
      text += " (position " + std::to_string(config_.position_port) + ")";
    if (!config_.multicast_group.empty()) text += " group " + config_.multicast_group;
    return text;
  }

 private:
  enum class Receive : std::uint8_t { packet, skipped, empty };

  // Round-robin over the sockets so a busy data port cannot starve the position port.
  // Drains datagrams that are not ours without waiting.
  bool receive_any(PacketView& out) {
    for (std::size_t tried = 0; tried < socket_count_; ++tried) {
      const std::size_t index = (next_socket_ + tried) % socket_count_;
      Receive result;
      while ((result = receive_one(*sockets_[index], out)) == Receive::skipped) {
        if (waiter_.stop_requested()) return false;
      }
      if (result == Receive::packet) {
        next_socket_ = (index + 1) % socket_count_;
        return true;
      }
    }
    return false;
  }

  Receive receive_one(UdpSocket& socket, PacketView& out) {
    driver_detail::ReceivedDatagram received;
    const ReadResult result = socket.read(received);
    if (result == ReadResult::interrupted) return Receive::skipped;
    if (result == ReadResult::empty) return Receive::empty;
    ++counters_.records;
    counters_.kernel_drops += received.new_kernel_drops;
    if (received.oversize) {
      ++counters_.skipped_wrong_size;
      return Receive::skipped;
    }
    driver_detail::UdpDatagram datagram;
    datagram.source = received.source;
    datagram.source_port = received.source_port;
    datagram.destination_port = socket.port();
    datagram.payload = received.payload;
    const auto kind = filter_.accept(datagram, counters_);
    if (!kind) return Receive::skipped;
    out.bytes = datagram.payload;
    out.kind = *kind;
    out.source = driver_detail::to_source_address(datagram);
    out.receive_ns = received.receive_ns;
    out.steady_receive_ns = received.steady_receive_ns;
    return Receive::packet;
  }

  UdpSourceConfig config_;
  driver_detail::PacketFilter filter_;
  SourceCounters counters_;
  std::array<std::unique_ptr<UdpSocket>, 2> sockets_;
  std::size_t socket_count_ = 0;
  std::size_t next_socket_ = 0;
  driver_detail::SocketWaiter waiter_;  // after the sockets: destroyed first
};

}  // namespace

std::unique_ptr<PacketSource> open_udp_source(const UdpSourceConfig& config,
                                              int* granted_buffer_bytes) {
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());  // the documented contract: bad address = runtime_error
  }
  return std::make_unique<UdpSource>(config, granted_buffer_bytes);
}

}  // namespace vlpground
