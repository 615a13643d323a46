// A Foxglove WebSocket server (protocol "foxglove.websocket.v1", also offered as
// "foxglove.sdk.v1") for the channels of a FrameEncoder, plus a zero-install web page:
// a plain HTTP GET on the same port returns one self-contained page that connects back and
// draws the live bird's-eye view.
//
// The server runs its own thread. publish() copies the message into a bounded hand-off
// queue and returns at once: a slow or stuck client never slows the caller. Each client has
// a bounded queue of pending messages; when it is full the oldest pending data messages are
// dropped (counted per client). A client that sends garbage (not JSON, not a protocol
// message, binary frames) or breaks off mid-message is dropped with a log line; the others
// go on.
//
// Thread-safety: every member may be called from any thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vlpground/viz/channels.hpp"

namespace vlpground::viz {

struct ServerConfig {
  std::string address = "127.0.0.1";  // another address (e.g. 0.0.0.0) must be asked for
  std::uint16_t port = 8765;          // 0 = any free port; port() tells which
  std::string name = "vlpground";     // serverInfo name
  std::size_t client_queue_bytes = std::size_t{16} << 20;  // pending bytes per client
  std::size_t client_queue_messages = 256;                 // pending messages per client
  std::size_t max_clients = 32;                            // more are refused (HTTP 503)
  std::size_t publish_queue_messages = 64;                 // hand-off to the server thread
  std::size_t client_message_max_bytes = std::size_t{64} << 10;  // larger requests: dropped
  // Replies (status, advertisements, parameters) a client may leave unread: one more and
  // it is stuck, and dropped.
  std::size_t client_unread_replies_max = 64;
  // Where log lines go (connects, drops, errors); default: stderr. Called on the server thread.
  std::function<void(std::string_view)> log;

  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

struct ClientStats {
  std::uint64_t id = 0;
  std::string remote;  // "address:port"
  std::string subprotocol;
  std::uint64_t messages_sent = 0;
  std::uint64_t messages_dropped = 0;  // data messages dropped because the client was slow
  std::uint64_t bytes_sent = 0;
  std::size_t queued_bytes = 0;       // now
  std::size_t peak_queued_bytes = 0;  // the most ever pending
  std::size_t subscriptions = 0;
};

struct ServerStats {
  std::uint64_t clients_accepted = 0;  // WebSocket sessions opened
  std::uint64_t clients_closed = 0;    // ... and ended, for whatever reason
  std::uint64_t clients_dropped = 0;   // ... ended by the server for a protocol error
  std::uint64_t http_requests = 0;     // plain HTTP requests answered
  std::uint64_t messages_published = 0;
  std::uint64_t publish_dropped = 0;  // hand-off queue full (the server thread fell behind)
  std::vector<ClientStats> clients;   // connected now
};

class FoxgloveServer {
 public:
  /// Validates `config`, binds (std::runtime_error with the reason when it cannot) and starts
  /// the server thread. Channel i of `channels` is advertised with id i.
  FoxgloveServer(ServerConfig config, std::vector<ChannelSpec> channels);
  /// Closes every connection and joins the server thread.
  ~FoxgloveServer();
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  /// Adds channels (e.g. another sensor's) and advertises them to the connected clients;
  /// returns the id of the first one. At most 32 channels in all (std::invalid_argument).
  std::size_t add_channels(std::vector<ChannelSpec> channels);
  /// The bound port (useful with port 0).
  [[nodiscard]] std::uint16_t port() const;
  /// Channels with at least one subscriber (bit i = channel i): encode only those.
  [[nodiscard]] ChannelMask subscribed() const;
  /// Sends one message of `channel` to its subscribers; copies `payload` and returns at once.
  void publish(std::size_t channel, std::int64_t log_time_ns, std::span<const std::byte> payload);
  [[nodiscard]] ServerStats stats() const;
  /// Hands every published message to the clients and waits until their queues are empty
  /// or `timeout` passed (a client that does not read keeps its queue); true when all were
  /// sent. Call it before destroying the server so that the last frames of a run arrive.
  bool flush(std::chrono::milliseconds timeout);


 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::viz
