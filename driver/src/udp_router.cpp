// Routing by source address: a table of (port, address) -> sensor, searched linearly (a car
// has at most a handful of sensors, so this beats any hashing).
#include "vlpground/driver/udp_router.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "packet_filter.hpp"
#include "udp_socket.hpp"

namespace vlpground {

namespace {

driver_detail::UdpSocketOptions socket_options(const UdpRouterConfig& config) {
  return {config.bind_address, config.multicast_group, config.reuse_address,
          config.receive_buffer_bytes};
}

std::string sensor_text(std::size_t index) { return "udp router: sensor " + std::to_string(index); }

}  // namespace

void UdpRouterConfig::validate() const {
  driver_detail::validate_socket_options(socket_options(*this), "udp router");
  if (sensors.empty()) throw std::invalid_argument("udp router: no sensor configured");
  std::vector<std::optional<driver_detail::IpAddress>> addresses;
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    const RoutedSensor& s = sensors[i];
    if (s.data_port == 0) throw std::invalid_argument(sensor_text(i) + ": data_port is 0");
    if (s.position_port == s.data_port) {
      throw std::invalid_argument(sensor_text(i) + ": data_port and position_port must differ");
    }
    addresses.push_back(driver_detail::parse_sensor_address(s.address));
    if (!addresses.back() && sensors.size() > 1) {
      throw std::invalid_argument(sensor_text(i) +
                                  " has no address; with several sensors each needs one");
    }
  }
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const RoutedSensor& a = sensors[i];
      const RoutedSensor& b = sensors[j];
      if (a.data_port == b.data_port && addresses[i] == addresses[j]) {
        throw std::invalid_argument("udp router: sensors " + std::to_string(j) + " and " +
                                    std::to_string(i) + " both listen for " + a.address +
                                    " on port " + std::to_string(a.data_port));
      }
      const bool crossed = a.data_port == b.position_port || a.position_port == b.data_port;
      if (crossed) {
        throw std::invalid_argument("udp router: sensors " + std::to_string(j) + " and " +
                                    std::to_string(i) +
                                    " use one port for data and for position packets");
      }
    }
  }
}

namespace {

using driver_detail::ReadResult;
using driver_detail::UdpSocket;

struct Route {
  std::uint16_t port = 0;
  std::optional<driver_detail::IpAddress> address;  // nullopt: any (a single sensor)
  std::size_t sensor = 0;
  PacketKind kind = PacketKind::data;
};

class Router final : public UdpRouter {
 public:
  explicit Router(const UdpRouterConfig& config) : config_(config) {
    counters_.sensors.resize(config.sensors.size());
    for (std::size_t i = 0; i < config.sensors.size(); ++i) {
      const RoutedSensor& s = config.sensors[i];
      const auto address = driver_detail::parse_sensor_address(s.address);
      routes_.push_back({s.data_port, address, i, PacketKind::data});
      if (s.position_port != 0) routes_.push_back({s.position_port, address, i, PacketKind::position});
    }
    const auto options = socket_options(config);
    for (const Route& route : routes_) {
      const bool open = std::any_of(sockets_.begin(), sockets_.end(),
                                    [&](const auto& s) { return s->port() == route.port; });
      if (!open) sockets_.push_back(std::make_unique<UdpSocket>(options, route.port));
    }
    for (const auto& socket : sockets_) waiter_.add(socket->native_handle());
  }

  SourceStatus next(RoutedPacket& out, int timeout_ms) override {
    return waiter_.next(timeout_ms, [&] { return receive_any(out); });
  }

  void request_stop() override { waiter_.request_stop(); }

  [[nodiscard]] const UdpRouterCounters& counters() const override { return counters_; }

  [[nodiscard]] std::string describe() const override {
    std::string text = "udp " + config_.bind_address + " port";
    if (sockets_.size() > 1) text += "s";
    for (std::size_t i = 0; i < sockets_.size(); ++i) {
      text += (i == 0 ? " " : ", ") + std::to_string(sockets_[i]->port());
    }
    if (!config_.multicast_group.empty()) text += " group " + config_.multicast_group;
    return text + ": " + std::to_string(config_.sensors.size()) + " sensor" +
           (config_.sensors.size() == 1 ? "" : "s");
  }

 private:
  // Round-robin over the sockets so no port starves another; drains datagrams that are not
  // ours without waiting.
  bool receive_any(RoutedPacket& out) {
    for (std::size_t tried = 0; tried < sockets_.size(); ++tried) {
      const std::size_t index = (next_socket_ + tried) % sockets_.size();
      for (;;) {
        if (waiter_.stop_requested()) return false;
        driver_detail::ReceivedDatagram received;
        const ReadResult result = sockets_[index]->read(received);
        if (result == ReadResult::interrupted) continue;
        if (result == ReadResult::empty) break;
        if (route(*sockets_[index], received, out)) {
          next_socket_ = (index + 1) % sockets_.size();
          return true;
        }
      }
    }
    return false;
  }

  const Route* find_route(std::uint16_t port, const driver_detail::IpAddress& from) const {
    for (const Route& r : routes_) {
      if (r.port == port && (!r.address || driver_detail::same_address(*r.address, from))) {
        return &r;
      }
    }
    return nullptr;
  }

  bool route(const UdpSocket& socket, const driver_detail::ReceivedDatagram& received,
             RoutedPacket& out) {
    ++counters_.records;
    counters_.kernel_drops += received.new_kernel_drops;
    const Route* r = find_route(socket.port(), received.source);
    if (r == nullptr) {
      ++counters_.unknown_source;
      return false;
    }
    SourceCounters& sensor = counters_.sensors[r->sensor];
    ++sensor.records;
    const std::size_t size = received.payload.size();
    const std::size_t wanted = r->kind == PacketKind::data ? driver_detail::kDataPacketBytes
                                                           : driver_detail::kPositionPacketBytes;
    if (received.oversize || size != wanted) {
      ++sensor.skipped_wrong_size;
      return false;
    }
    ++(r->kind == PacketKind::data ? sensor.data_packets : sensor.position_packets);
    out.sensor = r->sensor;
    out.packet.bytes = received.payload;
    out.packet.kind = r->kind;
    out.packet.source = {received.source.version, received.source.bytes, received.source_port};
    out.packet.receive_ns = received.receive_ns;
    out.packet.steady_receive_ns = received.steady_receive_ns;
    return true;
  }

  UdpRouterConfig config_;
  std::vector<Route> routes_;
  UdpRouterCounters counters_;
  std::vector<std::unique_ptr<UdpSocket>> sockets_;
  std::size_t next_socket_ = 0;
  driver_detail::SocketWaiter waiter_;
};

}  // namespace

std::unique_ptr<UdpRouter> open_udp_router(const UdpRouterConfig& config) {
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  return std::make_unique<Router>(config);
}

}  // namespace vlpground
