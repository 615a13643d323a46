#include "vlpground/viz/foxglove_server.hpp"

#include <utility>  // first: Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <chrono>
#include <cstdio>
#include <deque>
#include <future>
#include <stdexcept>
#include <thread>

#include "http_session.hpp"
#include "server_core.hpp"
#include "ws_protocol.hpp"
#include "ws_session.hpp"

namespace vlpground::viz {

namespace net = boost::asio;
using net::ip::tcp;

void ServerConfig::validate() const {
  boost::system::error_code ec;
  net::ip::make_address(address, ec);
  if (ec) throw std::invalid_argument("foxglove address '" + address + "' is not an IP address");
  if (client_queue_bytes < 1024) throw std::invalid_argument("foxglove client_queue_bytes must be >= 1024");
  if (client_queue_messages < 2) throw std::invalid_argument("foxglove client_queue_messages must be >= 2");
  if (max_clients < 1) throw std::invalid_argument("foxglove max_clients must be >= 1");
  if (publish_queue_messages < 1) throw std::invalid_argument("foxglove publish_queue_messages must be >= 1");
  if (client_unread_replies_max < 1) {
    throw std::invalid_argument("foxglove client_unread_replies_max must be >= 1");
  }
  if (client_message_max_bytes < 1024) {
    throw std::invalid_argument("foxglove client_message_max_bytes must be >= 1024");
  }
}

namespace detail {

void ServerCore::log(const std::string& line) const {
  if (config.log) {
    config.log(line);
  } else {
    std::fprintf(stderr, "vlpground foxglove: %s\n", line.c_str());
  }
}

std::size_t ServerCore::session_count() const {
  std::lock_guard lock(mutex);
  return sessions.size();
}

}  // namespace detail

namespace {

struct Outgoing {
  std::size_t channel = 0;
  std::int64_t log_time_ns = 0;
  std::shared_ptr<const detail::Payload> payload;
};

std::string session_id() {
  return std::to_string(std::chrono::system_clock::now().time_since_epoch().count());
}

}  // namespace

struct FoxgloveServer::Impl {
  Impl(ServerConfig config, std::vector<ChannelSpec> channels) : acceptor(ioc) {
    config.validate();
    if (channels.size() > detail::kMaxChannels) {
      throw std::invalid_argument("foxglove server: at most 32 channels");
    }
    core.config = std::move(config);
    core.channels.reserve(detail::kMaxChannels);
    core.channels = std::move(channels);
    core.channel_count = core.channels.size();
    core.server_info = detail::server_info_json(core.config.name, session_id());
    core.advertise = detail::advertise_json(core.channels);
    listen();
    port = acceptor.local_endpoint().port();
    accept();
    thread = std::thread([this] { ioc.run(); });
  }

  ~Impl() {
    // Close the listener and every session on the server thread, then stop it.
    std::promise<void> closed;
    net::post(ioc, [this, &closed] {
      boost::system::error_code ignored;
      acceptor.close(ignored);
      for (auto& s : sessions_now()) s->close("server stopping", false);
      closed.set_value();
    });
    closed.get_future().wait_for(std::chrono::seconds(2));
    ioc.stop();
    thread.join();
    std::lock_guard lock(core.mutex);
    core.sessions.clear();
  }

  void listen() {
    const tcp::endpoint endpoint(net::ip::make_address(core.config.address), core.config.port);
    boost::system::error_code ec;
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) acceptor.bind(endpoint, ec);
    if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec) {
      throw std::runtime_error("foxglove server: cannot listen on " + core.config.address + ":" +
                               std::to_string(core.config.port) + ": " + ec.message());
    }
  }

  void accept() {
    acceptor.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
      if (ec == net::error::operation_aborted) return;
      if (!ec) detail::serve_connection(std::move(socket), core);
      accept();
    });
  }

  void publish(std::size_t channel, std::int64_t log_time_ns, std::span<const std::byte> bytes) {
    if (channel >= core.channel_count || core.subscribers[channel] <= 0) return;
    auto payload = std::make_shared<const detail::Payload>(bytes.begin(), bytes.end());
    ++core.messages_published;
    std::lock_guard lock(handoff_mutex);
    if (handoff.size() >= core.config.publish_queue_messages) {
      handoff.pop_front();
      ++core.publish_dropped;
    }
    handoff.push_back({channel, log_time_ns, std::move(payload)});
    if (!drain_posted) {
      drain_posted = true;
      net::post(ioc, [this] { drain(); });
    }
  }

  // Appends channels on the server thread and advertises them to the connected clients.
  std::size_t add_channels(std::vector<ChannelSpec> more) {
    std::promise<std::size_t> done;
    net::post(ioc, [&] {
      if (core.channels.size() + more.size() > detail::kMaxChannels) {
        done.set_exception(std::make_exception_ptr(
            std::invalid_argument("foxglove server: at most 32 channels")));
        return;
      }
      const std::size_t first = core.channels.size();
      core.channels.insert(core.channels.end(), more.begin(), more.end());
      core.advertise = detail::advertise_json(core.channels);
      core.channel_count = core.channels.size();
      const std::string update = detail::advertise_json(more, first);
      // Outside the lock: a session whose queue overflows closes, and leaving the registry
      // takes the lock.
      for (auto& s : sessions_now()) s->send_text(update);
      done.set_value(first);
    });
    return done.get_future().get();
  }

  // The sessions registered now, held so that each may close (and leave the registry)
  // while the caller goes through them.
  [[nodiscard]] std::vector<std::shared_ptr<detail::WsSession>> sessions_now() const {
    std::vector<std::shared_ptr<detail::WsSession>> sessions;
    std::lock_guard lock(core.mutex);
    for (const auto& [id, s] : core.sessions) sessions.push_back(s);
    return sessions;
  }

  // Server thread: hands the published messages to the sessions.
  void drain() {
    std::deque<Outgoing> batch;
    {
      std::lock_guard lock(handoff_mutex);
      batch.swap(handoff);
      drain_posted = false;
    }
    const auto sessions = sessions_now();
    for (const Outgoing& m : batch) {
      for (auto& s : sessions) s->send_data(m.channel, m.log_time_ns, m.payload);
    }
  }

  net::io_context ioc{1};  // first: outlives everything that uses it
  detail::ServerCore core;
  tcp::acceptor acceptor;
  std::mutex handoff_mutex;
  std::deque<Outgoing> handoff;
  bool drain_posted = false;
  std::uint16_t port = 0;
  std::thread thread;
};

FoxgloveServer::FoxgloveServer(ServerConfig config, std::vector<ChannelSpec> channels)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(channels))) {}
FoxgloveServer::~FoxgloveServer() = default;

std::uint16_t FoxgloveServer::port() const { return impl_->port; }

ChannelMask FoxgloveServer::subscribed() const {
  ChannelMask mask = 0;
  for (std::size_t i = 0; i < impl_->core.channel_count; ++i) {
    if (impl_->core.subscribers[i] > 0) mask |= ChannelMask{1} << i;
  }
  return mask;
}

void FoxgloveServer::publish(std::size_t channel, std::int64_t log_time_ns,
                             std::span<const std::byte> payload) {
  impl_->publish(channel, log_time_ns, payload);
}

std::size_t FoxgloveServer::add_channels(std::vector<ChannelSpec> channels) {
  return impl_->add_channels(std::move(channels));
}

bool FoxgloveServer::flush(std::chrono::milliseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  // Messages still in the hand-off queue go to the sessions first, on the server thread.
  std::promise<void> drained;
  net::post(impl_->ioc, [this, &drained] {
    impl_->drain();
    drained.set_value();
  });
  if (drained.get_future().wait_until(deadline) != std::future_status::ready) return false;
  // Then the sessions write their queues; poll their counters until empty or the deadline.
  while (true) {
    bool empty = true;
    for (const ClientStats& c : stats().clients) empty = empty && c.queued_bytes == 0;
    if (empty) return true;
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

ServerStats FoxgloveServer::stats() const {
  const auto& c = impl_->core;
  ServerStats s;
  std::lock_guard lock(c.mutex);  // the counters and the clients listed as one snapshot
  s.clients_accepted = c.clients_accepted;
  s.clients_closed = c.clients_closed;
  s.clients_dropped = c.clients_dropped;
  s.http_requests = c.http_requests;
  s.messages_published = c.messages_published;
  s.publish_dropped = c.publish_dropped;
  for (const auto& [id, session] : c.sessions) s.clients.push_back(session->stats());
  return s;
}

}  // namespace vlpground::viz
