#include "ws_session.hpp"

#include <algorithm>
#include <chrono>

namespace vlpground::viz::detail {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;

namespace {

constexpr std::size_t kWriteFrameBytes = 64 * 1024;

// Errors that only mean the peer went away; everything else is a protocol error.
bool is_disconnect(const beast::error_code& ec) {
  return ec == net::error::eof || ec == net::error::connection_reset ||
         ec == net::error::broken_pipe || ec == net::error::connection_aborted ||
         ec == beast::error::timeout ||
         ec == websocket::error::closed;
}

}  // namespace

WsSession::WsSession(beast::tcp_stream stream, ServerCore& core, std::string remote,
                     std::string subprotocol)
    : ws_(std::move(stream)),
      core_(core),
      id_(core.next_client_id++),
      remote_(std::move(remote)),
      subprotocol_(std::move(subprotocol)) {}

void WsSession::start(http::request<http::string_body> request) {
  beast::get_lowest_layer(ws_).expires_never();
  auto timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
  timeouts.handshake_timeout = std::chrono::seconds(5);  // opening and closing handshakes
  timeouts.idle_timeout = std::chrono::seconds(30);      // pinged, then dropped when silent
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  ws_.set_option(websocket::stream_base::decorator([protocol = subprotocol_](
                                                       websocket::response_type& response) {
    response.set(http::field::sec_websocket_protocol, protocol);
    response.set(http::field::server, "vlpground");
  }));
  ws_.read_message_max(core_.config.client_message_max_bytes);
  ws_.write_buffer_bytes(kWriteFrameBytes);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) {
      self->core_.log("client " + self->remote_ + ": WebSocket handshake failed: " + ec.message());
      return;
    }
    self->open_ = true;
    ++self->core_.clients_accepted;
    {
      std::lock_guard lock(self->core_.mutex);
      self->core_.sessions[self->id_] = self;
    }
    self->core_.log("client " + std::to_string(self->id_) + " (" + self->remote_ +
                    ") connected, " + self->subprotocol_);
    self->send_text(self->core_.server_info);
    self->send_text(self->core_.advertise);
    self->read_next();
  });
}

void WsSession::read_next() {
  ws_.async_read(read_buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (self->closed_) return;
    if (ec) {
      if (is_disconnect(ec)) {
        self->close(ec == websocket::error::closed ? "closed the connection"
                                                  : "disconnected (" + ec.message() + ")",
                    false);
      } else {
        self->close("protocol error: " + ec.message(), true);
      }
      return;
    }
    if (!self->ws_.got_text()) {
      self->close("sent a binary message (client publishing is not offered)", true);
      return;
    }
    const auto data = self->read_buffer_.cdata();
    self->on_text({static_cast<const char*>(data.data()), data.size()});
    self->read_buffer_.consume(self->read_buffer_.size());
    if (!self->closed_) self->read_next();
  });
}

void WsSession::on_text(std::string_view text) {
  const ClientRequest request = parse_client_text(text);
  if (const auto* s = std::get_if<Subscribe>(&request)) {
    subscribe(*s);
  } else if (const auto* u = std::get_if<Unsubscribe>(&request)) {
    unsubscribe(*u);
  } else if (const auto* op = std::get_if<Unsupported>(&request)) {
    send_text(status_json(StatusLevel::error, "operation '" + op->op + "' is not supported"));
  } else {
    close("sent garbage: " + std::get<Garbage>(request).reason, true);
  }
}

void WsSession::subscribe(const Subscribe& request) {
  for (const auto& [id, channel] : request.subscriptions) {
    if (channel >= core_.channels.size()) {
      send_text(status_json(StatusLevel::warning, "unknown channel " + std::to_string(channel)));
    } else if (subscriptions_.count(id) != 0) {
      send_text(status_json(StatusLevel::error,
                            "subscription id " + std::to_string(id) + " is already in use"));
    } else {
      subscriptions_[id] = channel;
      ++core_.subscribers[channel];
    }
  }
  subscription_count_ = subscriptions_.size();
}

void WsSession::unsubscribe(const Unsubscribe& request) {
  for (const std::uint32_t id : request.subscription_ids) {
    const auto it = subscriptions_.find(id);
    if (it == subscriptions_.end()) {
      send_text(status_json(StatusLevel::warning, "no subscription " + std::to_string(id)));
      continue;
    }
    --core_.subscribers[it->second];
    subscriptions_.erase(it);
  }
  subscription_count_ = subscriptions_.size();
}

void WsSession::send_data(std::size_t channel, std::int64_t log_time_ns,
                          const std::shared_ptr<const Payload>& payload) {
  if (!open_ || closed_) return;
  for (const auto& [id, ch] : subscriptions_) {
    if (ch != channel) continue;
    Pending m;
    m.header = data_header(id, log_time_ns);
    m.payload = payload;
    m.bytes = kDataHeaderBytes + payload->size();
    enqueue_data(std::move(m));
  }
}

void WsSession::send_text(std::string text) {
  if (closed_) return;
  if (pending_texts_ >= core_.config.client_unread_replies_max) {
    close("does not read its replies", true);
    return;
  }
  ++pending_texts_;
  Pending m;
  m.bytes = text.size();
  m.text = std::move(text);
  queued_bytes_ += m.bytes;
  queue_.push_back(std::move(m));
  if (!writing_) write_next();
}

// Drops the oldest data messages not being written until `bytes` more fit; false when they
// cannot (the message alone is larger than the queue).
bool WsSession::make_room(std::size_t bytes) {
  const auto fits = [&] {
    return queue_.size() < core_.config.client_queue_messages &&
           queued_bytes_ + bytes <= core_.config.client_queue_bytes;
  };
  auto it = queue_.begin() + (writing_ ? 1 : 0);
  while (!fits()) {
    it = std::find_if(it, queue_.end(), [](const Pending& p) { return p.payload != nullptr; });
    if (it == queue_.end()) return false;
    queued_bytes_ -= it->bytes;
    it = queue_.erase(it);
    ++dropped_;
  }
  return true;
}

void WsSession::enqueue_data(Pending message) {
  if (!make_room(message.bytes)) {
    ++dropped_;
    return;
  }
  queued_bytes_ += message.bytes;
  peak_queued_bytes_ = std::max(peak_queued_bytes_.load(), queued_bytes_.load());
  queue_.push_back(std::move(message));
  if (!writing_) write_next();
}

void WsSession::write_next() {
  if (closed_ || queue_.empty()) {
    writing_ = false;
    return;
  }
  writing_ = true;
  const Pending& m = queue_.front();
  auto on_written = [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (self->closed_) return;
    if (ec) {
      self->close(is_disconnect(ec) ? "disconnected (" + ec.message() + ")"
                                    : "write failed: " + ec.message(),
                  !is_disconnect(ec));
      return;
    }
    const Pending& done = self->queue_.front();
    ++self->sent_;
    self->bytes_sent_ += done.bytes;
    self->queued_bytes_ -= done.bytes;
    if (done.payload == nullptr) --self->pending_texts_;
    self->queue_.pop_front();
    self->write_next();
  };
  if (m.payload != nullptr) {
    ws_.binary(true);
    const std::array<net::const_buffer, 2> buffers{
        net::buffer(m.header), net::buffer(m.payload->data(), m.payload->size())};
    ws_.async_write(buffers, std::move(on_written));
  } else {
    ws_.text(true);
    ws_.async_write(net::buffer(m.text), std::move(on_written));
  }
}

void WsSession::close(const std::string& reason, bool dropped) {
  if (closed_) return;
  closed_ = true;
  const auto keep_alive = shared_from_this();  // the registry may hold the last reference
  for (const auto& [id, channel] : subscriptions_) --core_.subscribers[channel];
  subscriptions_.clear();
  subscription_count_ = 0;
  if (open_) {
    {
      // Leaving the registry and counting the close are one step to stats(), which reads
      // both under the same lock: a client closed is never still listed.
      std::lock_guard lock(core_.mutex);
      core_.sessions.erase(id_);
      ++core_.clients_closed;
      if (dropped) ++core_.clients_dropped;
    }
    core_.log("client " + std::to_string(id_) + " (" + remote_ + ") " +
              (dropped ? "dropped: " : "left: ") + reason + "; sent " + std::to_string(sent_) +
              " messages, dropped " + std::to_string(dropped_) + " for being slow, peak queue " +
              std::to_string(peak_queued_bytes_) + " bytes");
  }
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(net::ip::tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).socket().close(ignored);
}

ClientStats WsSession::stats() const {
  ClientStats s;
  s.id = id_;
  s.remote = remote_;
  s.subprotocol = subprotocol_;
  s.messages_sent = sent_;
  s.messages_dropped = dropped_;
  s.bytes_sent = bytes_sent_;
  s.queued_bytes = queued_bytes_;
  s.peak_queued_bytes = peak_queued_bytes_;
  s.subscriptions = subscription_count_;
  return s;
}

}  // namespace vlpground::viz::detail
