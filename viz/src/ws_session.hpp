// One WebSocket client of the Foxglove server: its subscriptions, its bounded queue of
// pending messages (oldest data dropped first when full) and its read loop. Lives on the
// server thread only; counters are atomic for stats().
#pragma once

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "server_core.hpp"
#include "ws_protocol.hpp"

namespace vlpground::viz::detail {

using Payload = std::vector<std::byte>;

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(boost::beast::tcp_stream stream, ServerCore& core, std::string remote,
            std::string subprotocol);

  /// Completes the WebSocket handshake for `request`, then sends serverInfo + advertise.
  void start(boost::beast::http::request<boost::beast::http::string_body> request);
  /// Queues `payload` for every subscription of this client to `channel`.
  void send_data(std::size_t channel, std::int64_t log_time_ns,
                 const std::shared_ptr<const Payload>& payload);
  /// Ends the session (idempotent); `dropped`: ended by us for a protocol error.
  void close(const std::string& reason, bool dropped);
  /// Queues a JSON text message (protocol replies, advertise of new channels).
  void send_text(std::string text);

  [[nodiscard]] ClientStats stats() const;

 private:
  struct Pending {
    std::array<std::uint8_t, kDataHeaderBytes> header{};
    std::shared_ptr<const Payload> payload;  // data message when set
    std::string text;                        // else a JSON text message
    std::size_t bytes = 0;
  };

  void read_next();
  void on_text(std::string_view text);
  void subscribe(const Subscribe& request);
  void unsubscribe(const Unsubscribe& request);
  void enqueue_data(Pending message);
  bool make_room(std::size_t bytes);
  void write_next();

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  ServerCore& core_;
  const std::uint64_t id_;
  const std::string remote_;
  const std::string subprotocol_;
  boost::beast::flat_buffer read_buffer_;
  std::deque<Pending> queue_;
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
  std::size_t pending_texts_ = 0;
  std::map<std::uint32_t, std::size_t> subscriptions_;  // subscription id -> channel

  std::atomic<std::uint64_t> sent_{0}, dropped_{0}, bytes_sent_{0};
  std::atomic<std::size_t> queued_bytes_{0}, peak_queued_bytes_{0}, subscription_count_{0};
};

}  // namespace vlpground::viz::detail
