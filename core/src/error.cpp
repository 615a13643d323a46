#include "vlpground/error.hpp"

namespace vlpground {
namespace {

class Category final : public std::error_category {
 public:
  [[nodiscard]] const char* name() const noexcept override { return "vlpground"; }

  [[nodiscard]] std::string message(int value) const override {
    switch (static_cast<ErrorCode>(value)) {
      case ErrorCode::cannot_open_file:
        return "cannot open the capture file";
      case ErrorCode::unsupported_link_type:
        return "unsupported capture link type";
      case ErrorCode::port_in_use:
        return "UDP port already in use";
      case ErrorCode::permission_denied:
        return "permission denied";
      case ErrorCode::address_not_available:
        return "address not available on this host";
      case ErrorCode::socket_error:
        return "socket error";
      case ErrorCode::malformed_packet:
        return "malformed packet";
      case ErrorCode::wrong_sensor:
        return "not a VLP-16 family sensor";
      case ErrorCode::product_mismatch:
        return "product byte mismatch";
      case ErrorCode::not_vlp16_timing:
        return "packet spacing unlike a VLP-16";
      case ErrorCode::frame_dropped:
        return "frame dropped";
      case ErrorCode::queue_full:
        return "push queue full: packets refused";
      case ErrorCode::kernel_drops:
        return "socket receive buffer overflow: packets lost";
      case ErrorCode::callback_exception:
        return "callback threw an exception";
      case ErrorCode::source_failed:
        return "packet source failed";
    }
    return "unknown vlpground error";
  }
};

}  // namespace

const std::error_category& error_category() noexcept {
  static const Category category;
  return category;
}

}  // namespace vlpground
