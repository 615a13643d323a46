// A capture sent to 127.0.0.1 at its own pace, as a sensor would (live-mode tests; a free
// port comes from cli_helpers.hpp).
#pragma once

#include <cstdint>
#include <string>

namespace vlpground::test {

/// Sends the packets of `pcap` to 127.0.0.1: data packets to `data_port`, position packets
/// to `position_port` (0: not sent), paced by their capture stamps (`rate` 1 = real time).
void send_capture(const std::string& pcap, std::uint16_t data_port, std::uint16_t position_port,
                  double rate = 1.0);

}  // namespace vlpground::test
