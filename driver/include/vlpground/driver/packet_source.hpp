// Where packets come from: a pcap/pcapng file or a live UDP socket, behind one interface.
// libpcap and Boost.Asio stay behind pimpl; this header has no third-party includes.
//
// Thread-safety: a PacketSource is used by one thread; request_stop() may be called from any.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace vlpground {

enum class PacketKind : std::uint8_t { data, position };
/// The port a packet arrived on, as a push source's caller states it.
using PacketPort = PacketKind;

/// Sender of a packet: a plain value (no allocation per packet) for routing by address.
struct SourceAddress {
  std::uint8_t version = 0;              // 4 or 6; 0 = unknown (e.g. pushed without one)
  std::array<std::uint8_t, 16> bytes{};  // IPv4 in bytes[0..3], network order
  std::uint16_t port = 0;                // sender's UDP port (0 = unknown)
  [[nodiscard]] bool operator==(const SourceAddress&) const = default;
  /// "192.168.1.201:2368", "[fe80::1]:2368", "unknown" (allocates; for logs).
  [[nodiscard]] std::string to_string() const;
};

/// A view of one UDP payload, valid until the next call to PacketSource::next().
struct PacketView {
  std::span<const std::uint8_t> bytes;
  PacketKind kind = PacketKind::data;
  SourceAddress source;                // sender (pcap, UDP; whatever push() was given)
  std::int64_t receive_ns = 0;         // capture timestamp (pcap) or kernel/host receive time (UDP)
  std::int64_t steady_receive_ns = 0;  // host steady clock at receipt (for latency)
  // Looped replay: added to the packet's own stamp (microseconds past the hour) by the
  // decoder, so that each pass of the file continues the previous one on the sensor's clock.
  std::int64_t stamp_offset_ns = 0;
};

enum class SourceStatus : std::uint8_t {
  packet,       // `out` holds a packet
  timeout,      // no packet within the wait (live only)
  end_of_file,  // replay finished
  stopped,      // request_stop() was called
};

struct SourceCounters {
  std::uint64_t records = 0;  // pcap records / datagrams seen
  std::uint64_t data_packets = 0;
  std::uint64_t position_packets = 0;
  std::uint64_t skipped_other = 0;  // not UDP to our ports, other traffic
  std::uint64_t skipped_wrong_size = 0;
  std::uint64_t skipped_fragment = 0;
  std::uint64_t skipped_address = 0;  // filtered by sensor address
  std::uint64_t truncated = 0;        // records cut short (snaplen, truncated file)
  std::uint64_t kernel_drops = 0;     // SO_RXQ_OVFL (live)
  std::uint64_t queue_full = 0;       // push source: packets refused because it was full
  std::uint64_t loop_wraps = 0;       // looped replay: times the file was joined to its start
  std::uint64_t skipped_loop = 0;     // looped replay: packets skipped at the start of a pass
                                      // so that the rotation continues (PcapSourceConfig::loop)
  [[nodiscard]] std::uint64_t skipped() const {
    return skipped_other + skipped_wrong_size + skipped_fragment + skipped_address + truncated +
           queue_full + skipped_loop;
  }
};

class PacketSource {
 public:
  virtual ~PacketSource() = default;
  /// Waits up to `timeout_ms` for the next data or position packet (0: do not wait;
  /// negative: wait without limit). Datagrams that are not ours are counted and skipped.
  /// Never allocates. A paced replay returns `timeout` while its next packet is not yet due
  /// (the packet is kept for the next call).
  virtual SourceStatus next(PacketView& out, int timeout_ms) = 0;
  /// Makes a blocked or future next() return `stopped`. Callable from any thread.
  virtual void request_stop() = 0;
  [[nodiscard]] virtual const SourceCounters& counters() const = 0;
  /// True for live sources (frames may be dropped under backpressure), false for replay.
  [[nodiscard]] virtual bool is_live() const = 0;
  /// Fraction of the input consumed, 0..1 (replay), or -1 when unknown (live).
  [[nodiscard]] virtual double progress() const { return -1.0; }
  /// One-line description for logs ("pcap foo.pcap", "udp 0.0.0.0:2368").
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// Replay of a pcap or pcapng file (link types: Ethernet with any VLAN/QinQ tags, Linux SLL
/// and SLL2, raw IPv4/IPv6, BSD loopback). A packet is a UDP datagram to `data_port` of 1206
/// bytes or to `position_port` of 512 bytes; anything else is counted in SourceCounters.
/// `receive_ns` is the record's capture stamp (ns since epoch, nanosecond precision kept).
struct PcapSourceConfig {
  std::string path;
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;
  std::string sensor_address;  // empty: any; else only packets from this IPv4/IPv6 address
  double rate = 0.0;           // 0 = as fast as possible; 1.0 = real time by capture stamps
  /// Replays the file again at its end, joined as if it were one continuous recording:
  /// each later pass starts at the data packet that continues the rotation where the
  /// previous pass ended (the packets before it are skipped and counted in
  /// SourceCounters::skipped_loop) and is shifted in time so that this packet comes one
  /// packet period after the previous pass's last one, on the capture stamps (receive_ns)
  /// and on the sensor's clock (PacketView::stamp_offset_ns). Frames then run across the
  /// seam as full rotations. A capture of less than a rotation plus two packets is not
  /// joined: its passes follow one another (receive_ns shifted by the capture's span plus
  /// its mean record spacing, at least 1 us). A pass without any packet ends the replay
  /// (no endless spinning). SourceCounters::loop_wraps counts the joins.
  bool loop = false;
  /// Throws std::invalid_argument (empty path, data_port 0, rate < 0, bad sensor_address).
  void validate() const;
};

/// Live reception. Each port gets its own socket with SO_TIMESTAMPNS (receive_ns = kernel
/// receive time, ns since epoch) and SO_RXQ_OVFL (SourceCounters::kernel_drops). With a
/// multicast group the sockets bind to the group address and join it on the interface of
/// `bind_address` (IPv4; IPv6 joins on the default interface).
struct UdpSourceConfig {
  std::string bind_address = "0.0.0.0";
  std::uint16_t data_port = 2368;
  std::uint16_t position_port = 8308;          // 0 = do not listen for position packets
  std::string multicast_group;                 // empty: none
  std::string sensor_address;                  // empty: any
  bool reuse_address = false;                  // SO_REUSEADDR + SO_REUSEPORT
  int receive_buffer_bytes = 4 * 1024 * 1024;  // SO_RCVBUFFORCE if permitted, else SO_RCVBUF
  /// Throws std::invalid_argument (unparsable or non-multicast addresses, data_port 0,
  /// equal ports, non-positive buffer).
  void validate() const;
};

/// Opens a capture. Throws vlpground::Error (a std::runtime_error; cannot_open_file,
/// unsupported_link_type) with a one-line reason when the file is
/// missing, unreadable, not a capture or of an unsupported link type;
/// std::invalid_argument when validate() fails.
std::unique_ptr<PacketSource> open_pcap_source(const PcapSourceConfig& config);

/// Binds the sockets. Throws vlpground::Error (port_in_use, permission_denied,
/// address_not_available, socket_error) when the port is in use ("port 2368 on
/// 0.0.0.0 is already in use"), the address is bad or not on this host, or validate() fails.
/// `granted_buffer_bytes` (optional) receives the kernel's actual receive buffer size (Linux
/// reports twice the request, capped at 2 x net.core.rmem_max without CAP_NET_ADMIN).
std::unique_ptr<PacketSource> open_udp_source(const UdpSourceConfig& config,
                                              int* granted_buffer_bytes = nullptr);

}  // namespace vlpground
