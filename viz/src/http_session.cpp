#include "http_session.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <optional>

#include "ws_session.hpp"

namespace vlpground::viz::detail {

extern const std::string_view kWebPage;  // viz/web/index.html, embedded at build time

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;

constexpr auto kRequestTimeout = std::chrono::seconds(10);
constexpr std::size_t kMaxHeaderBytes = 8 * 1024;
constexpr std::size_t kMaxBodyBytes = 1024;

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(net::ip::tcp::socket socket, ServerCore& core) : stream_(std::move(socket)), core_(core) {
    beast::error_code ec;
    const auto peer = stream_.socket().remote_endpoint(ec);
    remote_ = ec ? "?" : peer.address().to_string() + ":" + std::to_string(peer.port());
  }

  void run() {
    parser_.emplace();
    parser_->header_limit(kMaxHeaderBytes);
    parser_->body_limit(kMaxBodyBytes);
    stream_.expires_after(kRequestTimeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) {
                       self->on_request(ec);
                     });
  }

 private:
  void on_request(beast::error_code ec) {
    if (ec) {
      // Silence or a bare disconnect is not worth a line; a malformed request is.
      if (ec != http::error::end_of_stream && ec != beast::error::timeout &&
          ec != net::error::connection_reset && ec != net::error::eof) {
        core_.log("connection from " + remote_ + " dropped: bad HTTP request (" + ec.message() + ")");
      }
      return;
    }
    auto& request = parser_->get();
    if (websocket::is_upgrade(request)) {
      upgrade();
      return;
    }
    ++core_.http_requests;
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      respond(http::status::method_not_allowed, "text/plain", "only GET\n");
    } else if (request.target() == "/" || request.target() == "/index.html") {
      respond(http::status::ok, "text/html; charset=utf-8", std::string(kWebPage));
    } else {
      respond(http::status::not_found, "text/plain", "not found; the live view is at /\n");
    }
  }

  void upgrade() {
    auto& request = parser_->get();
    const auto offered = request[http::field::sec_websocket_protocol];
    const std::string protocol = choose_subprotocol({offered.data(), offered.size()});
    if (protocol.empty()) {
      core_.log("client " + remote_ + " refused: no supported WebSocket subprotocol offered");
      respond(http::status::bad_request, "text/plain",
              "offer subprotocol foxglove.websocket.v1 or foxglove.sdk.v1\n");
      return;
    }
    if (core_.session_count() >= core_.config.max_clients) {
      core_.log("client " + remote_ + " refused: " + std::to_string(core_.config.max_clients) +
                " clients already connected");
      respond(http::status::service_unavailable, "text/plain", "too many clients\n");
      return;
    }
    auto session = std::make_shared<WsSession>(std::move(stream_), core_, remote_, protocol);
    session->start(parser_->release());
  }

  void respond(http::status status, const char* type, std::string body) {
    const bool head = parser_->get().method() == http::verb::head;
    response_.emplace(status, parser_->get().version());
    response_->set(http::field::server, "vlpground");
    response_->set(http::field::content_type, type);
    response_->set(http::field::cache_control, "no-store");
    response_->keep_alive(false);
    const std::size_t length = body.size();
    response_->body() = head ? std::string() : std::move(body);
    response_->prepare_payload();
    if (head) response_->content_length(length);
    http::async_write(stream_, *response_, [self = shared_from_this()](beast::error_code, std::size_t) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
    });
  }

  beast::tcp_stream stream_;
  ServerCore& core_;
  std::string remote_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::optional<http::response<http::string_body>> response_;
};

}  // namespace

void serve_connection(net::ip::tcp::socket socket, ServerCore& core) {
  std::make_shared<HttpSession>(std::move(socket), core)->run();
}

}  // namespace vlpground::viz::detail
