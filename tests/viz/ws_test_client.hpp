// A blocking Foxglove WebSocket client for the server tests (Boost.Beast), with a 10 s
// receive timeout so a missing message fails the test instead of hanging it.
#pragma once

#include <sys/socket.h>
#include <sys/time.h>

#include <utility>  // first: Boost 1.74's asio/awaitable.hpp uses std::exchange

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vlpground::test {

// The protocol's "message data" header, as a client reads it: opcode 0x01, subscription id
// (u32 LE), log time (u64 LE).
inline constexpr std::size_t kDataHeaderBytes = 13;

struct DataMessage {
  std::uint32_t subscription = 0;
  std::uint64_t log_time_ns = 0;
  std::string payload;
};

class WsTestClient {
 public:
  using tcp = boost::asio::ip::tcp;

  /// Connects and upgrades with `subprotocol` ("" offers none); throws on failure.
  explicit WsTestClient(std::uint16_t port, const std::string& subprotocol = "foxglove.websocket.v1")
      : ws_(ioc_) {
    ws_.next_layer().connect(tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port));
    timeval tv{10, 0};
    ::setsockopt(ws_.next_layer().native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ws_.set_option(boost::beast::websocket::stream_base::decorator(
        [subprotocol](boost::beast::websocket::request_type& r) {
          if (!subprotocol.empty()) r.set(boost::beast::http::field::sec_websocket_protocol, subprotocol);
        }));
    ws_.handshake(response_, "127.0.0.1", "/");
  }

  [[nodiscard]] std::string accepted_subprotocol() const {
    return std::string(response_[boost::beast::http::field::sec_websocket_protocol]);
  }

  nlohmann::json read_json() {
    const std::string text = read();
    if (!ws_.got_text()) throw std::runtime_error("expected a text message");
    return nlohmann::json::parse(text);
  }

  DataMessage read_data() {
    const std::string bytes = read();
    if (ws_.got_text()) throw std::runtime_error("expected binary, got " + bytes);
    if (bytes.size() < kDataHeaderBytes || bytes[0] != 1) {
      throw std::runtime_error("bad data header");
    }
    DataMessage m;
    std::memcpy(&m.subscription, bytes.data() + 1, 4);
    std::memcpy(&m.log_time_ns, bytes.data() + 5, 8);
    m.payload = bytes.substr(kDataHeaderBytes);
    return m;
  }

  void send_text(const std::string& text) {
    ws_.text(true);
    ws_.write(boost::asio::buffer(text));
  }
  void subscribe(std::uint32_t id, std::uint64_t channel) {
    send_text(nlohmann::json{{"op", "subscribe"},
                             {"subscriptions", {{{"id", id}, {"channelId", channel}}}}}
                  .dump());
  }
  /// The raw TCP socket below the WebSocket (to misbehave on purpose).
  tcp::socket& socket() { return ws_.next_layer(); }
  void close() { ws_.close(boost::beast::websocket::close_code::normal); }

 private:
  std::string read() {
    boost::beast::flat_buffer buffer;
    ws_.read(buffer);
    return boost::beast::buffers_to_string(buffer.data());
  }

  boost::asio::io_context ioc_;
  boost::beast::websocket::stream<tcp::socket> ws_;
  boost::beast::websocket::response_type response_;
};

}  // namespace vlpground::test
