// What the library reports, as codes of one std::error_category ("vlpground"): thrown with
// vlpground::Error (a std::runtime_error, message unchanged) when a source cannot be
// opened, and carried by diagnostics (vlpground::Diagnostic::code) with their message.
//
// Configuration mistakes stay std::invalid_argument (programming errors, found by
// validate() before anything runs).
//
// Thread-safety: the category is a stateless singleton; everything here is immutable.
#pragma once

#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>

namespace vlpground {

enum class ErrorCode : int {
  // Opening a source (thrown as vlpground::Error).
  cannot_open_file = 1,     // missing, unreadable or not a pcap/pcapng capture
  unsupported_link_type,    // a capture of a link type the reader does not parse
  port_in_use,              // the UDP port is taken (and reuse was not asked for)
  permission_denied,        // e.g. a port below 1024 without privileges
  address_not_available,    // the bind address is not on this host
  socket_error,             // any other socket, multicast or eventfd failure
  // Input (diagnostic warnings; the packets are counted and skipped).
  malformed_packet,         // wrong size, bad block flag, bad azimuth, unknown mode
  wrong_sensor,             // packet timing of another sensor family (e.g. HDL-32E)
  product_mismatch,         // product byte unknown or contradicting the packet timing
  not_vlp16_timing,         // data packets closer together than a VLP-16's period
  // Drops (diagnostics; counted in the stats).
  frame_dropped,            // a pending frame dropped to make room (live backpressure)
  queue_full,               // a push source refused packets: its queue was full
  kernel_drops,             // the socket's receive buffer overflowed (SO_RXQ_OVFL)
  // The program and the run.
  callback_exception,       // a frame / telemetry callback threw; the pipeline goes on
  source_failed,            // the reader failed mid-stream; the input ends
};

/// The "vlpground" category: message() describes each ErrorCode.
const std::error_category& error_category() noexcept;

inline std::error_code make_error_code(ErrorCode e) noexcept {
  return {static_cast<int>(e), error_category()};
}

/// A failure with a code; what() is the full one-line message.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(make_error_code(code)) {}
  [[nodiscard]] const std::error_code& code() const noexcept { return code_; }

 private:
  std::error_code code_;
};

}  // namespace vlpground

template <>
struct std::is_error_code_enum<vlpground::ErrorCode> : std::true_type {};
