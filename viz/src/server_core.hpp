// State of a FoxgloveServer shared by its sessions. Everything here is used on the server
// thread, except what is atomic or guarded by `mutex` (read by stats() and subscribed()).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "vlpground/viz/foxglove_server.hpp"

namespace vlpground::viz::detail {

inline constexpr std::size_t kMaxChannels = 32;  // ChannelMask bits

class WsSession;

struct ServerCore {
  ServerConfig config;
  std::vector<ChannelSpec> channels;  // grown on the server thread only
  std::atomic<std::size_t> channel_count{0};  // channels.size(), for the other threads
  std::string server_info;  // serverInfo JSON
  std::string advertise;    // advertise JSON of every channel

  std::array<std::atomic<int>, kMaxChannels> subscribers{};  // per channel
  std::atomic<std::uint64_t> next_client_id{1};
  std::atomic<std::uint64_t> clients_accepted{0}, clients_closed{0}, clients_dropped{0},
      http_requests{0}, messages_published{0}, publish_dropped{0};

  mutable std::mutex mutex;  // guards `sessions`
  std::map<std::uint64_t, std::shared_ptr<WsSession>> sessions;

  void log(const std::string& line) const;
  [[nodiscard]] std::size_t session_count() const;
};

}  // namespace vlpground::viz::detail
