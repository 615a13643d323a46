// Foxglove WebSocket protocol v1 messages (JSON text and binary frames), server side.
// Reference: the protocol spec of foxglove/ws-protocol (docs/spec.md there).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vlpground/viz/channels.hpp"

namespace vlpground::viz::detail {

inline constexpr std::string_view kSubprotocols[] = {"foxglove.websocket.v1", "foxglove.sdk.v1"};

/// The first subprotocol of the client's Sec-WebSocket-Protocol list that we speak, or "".
std::string choose_subprotocol(std::string_view requested);

std::string server_info_json(const std::string& name, const std::string& session_id);
/// Advertises `channels` with ids first_id, first_id + 1, ...
std::string advertise_json(const std::vector<ChannelSpec>& channels, std::size_t first_id = 0);
enum class StatusLevel : int { info = 0, warning = 1, error = 2 };
std::string status_json(StatusLevel level, const std::string& message);

/// Binary "message data" frame header: opcode 0x01, subscription id (u32 LE), log time (u64 LE).
inline constexpr std::size_t kDataHeaderBytes = 13;
std::array<std::uint8_t, kDataHeaderBytes> data_header(std::uint32_t subscription_id,
                                                       std::int64_t log_time_ns);

struct Subscribe {
  std::vector<std::pair<std::uint32_t, std::uint64_t>> subscriptions;  // (id, channel id)
};
struct Unsubscribe {
  std::vector<std::uint32_t> subscription_ids;
};
struct Unsupported {
  std::string op;  // a well-formed request for something this server does not offer
};
struct Garbage {
  std::string reason;  // not JSON, not an object with "op", or a malformed known op
};
using ClientRequest = std::variant<Subscribe, Unsubscribe, Unsupported, Garbage>;

/// Parses one text message of a client. Never throws.
ClientRequest parse_client_text(std::string_view text);

}  // namespace vlpground::viz::detail
