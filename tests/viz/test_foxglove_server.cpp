// FoxgloveServer: the protocol as a client sees it (serverInfo, advertise, subscribe, data
// frames), the web page over plain HTTP, and bad clients: no subprotocol, garbage, broken
// frames, one that never reads (its queue stays bounded, the others get everything), many
// coming and going.
#include <boost/beast/core/detail/base64.hpp>
#include <boost/beast/http.hpp>
#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <thread>

#include "vlpground/viz/channels.hpp"
#include "vlpground/viz/foxglove_server.hpp"
#include "ws_test_client.hpp"

using namespace vlpground;
using namespace vlpground::test;
using viz::FoxgloveServer;

namespace {

// Polls `condition` until it holds or `timeout` passes.
template <typename F>
bool wait_until(F condition, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

struct Logged {
  std::mutex mutex;
  std::vector<std::string> lines;
  bool contains(const std::string& needle) {
    std::lock_guard lock(mutex);
    for (const auto& l : lines)
      if (l.find(needle) != std::string::npos) return true;
    return false;
  }
};

viz::ServerConfig test_config(Logged& logged) {
  viz::ServerConfig c;
  c.port = 0;
  c.client_queue_bytes = std::size_t{1} << 20;
  c.client_queue_messages = 16;
  c.log = [&logged](std::string_view line) {
    std::lock_guard lock(logged.mutex);
    logged.lines.emplace_back(line);
  };
  return c;
}

std::span<const std::byte> bytes_of(const std::string& s) {
  return std::as_bytes(std::span{s.data(), s.size()});
}

// A connected client subscribed to channel 0 as subscription `id`, past the greeting.
std::unique_ptr<WsTestClient> subscribed_client(FoxgloveServer& server, std::uint32_t id) {
  auto c = std::make_unique<WsTestClient>(server.port());
  c->read_json();  // serverInfo
  c->read_json();  // advertise
  c->subscribe(id, 0);
  return c;
}

std::size_t subscriptions_total(const FoxgloveServer& server) {
  std::size_t n = 0;
  for (const auto& c : server.stats().clients) n += c.subscriptions;
  return n;
}

std::string http_get(std::uint16_t port, const std::string& target, std::string* content_type = nullptr) {
  namespace http = boost::beast::http;
  boost::asio::io_context ioc;
  boost::beast::tcp_stream stream(ioc);
  stream.connect(boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req(http::verb::get, target, 11);
  req.set(http::field::host, "127.0.0.1");
  http::write(stream, req);
  boost::beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  if (content_type != nullptr) *content_type = std::string(res[http::field::content_type]);
  return std::to_string(res.result_int()) + "\n" + res.body();
}

}  // namespace

TEST_CASE("serverInfo, advertise with the encoder's channels, subscribe, data frames") {
  Logged logged;
  viz::FrameEncoder encoder;
  FoxgloveServer server(test_config(logged), encoder.channels());
  REQUIRE(server.port() != 0);
  for (const char* protocol : {"foxglove.websocket.v1", "foxglove.sdk.v1"}) {
    WsTestClient client(server.port(), protocol);
    CHECK(client.accepted_subprotocol() == protocol);
    const auto info = client.read_json();
    CHECK(info["op"] == "serverInfo");
    CHECK(info["name"] == "vlpground");
    const auto ad = client.read_json();
    REQUIRE(ad["op"] == "advertise");
    REQUIRE(ad["channels"].size() == 4);
    for (std::size_t i = 0; i < 4; ++i) {
      const auto& ch = ad["channels"][i];
      const auto& spec = encoder.channels()[i];
      CHECK(ch["id"] == i);
      CHECK(ch["topic"] == spec.topic);
      CHECK(ch["encoding"] == spec.message_encoding);
      CHECK(ch["schemaName"] == spec.schema_name);
      CHECK(ch["schemaEncoding"] == spec.schema_encoding);
      if (spec.schema_encoding == "protobuf") {
        const std::string b64 = ch["schema"];
        std::string decoded(b64.size(), '\0');
        decoded.resize(boost::beast::detail::base64::decode(decoded.data(), b64.data(), b64.size()).first);
        CHECK(decoded == spec.schema);
      } else {
        CHECK(ch["schema"] == spec.schema);
      }
    }
  }

  WsTestClient client(server.port());
  client.read_json();
  client.read_json();
  CHECK(server.subscribed() == 0);
  server.publish(0, 1, bytes_of("nobody listens"));  // no subscriber: not even queued
  client.send_text(R"({"op":"subscribe","subscriptions":[{"id":7,"channelId":0},{"id":9,"channelId":3}]})");
  REQUIRE(wait_until([&] { return server.subscribed() == 0b1001u; }));
  for (int i = 0; i < 5; ++i) {
    server.publish(0, 1'700'000'000'000'000'000 + i, bytes_of("cloud " + std::to_string(i)));
  }
  server.publish(3, 42, bytes_of("{\"status\":1}"));
  for (int i = 0; i < 5; ++i) {
    const auto m = client.read_data();
    CHECK(m.subscription == 7);
    CHECK(m.log_time_ns == 1'700'000'000'000'000'000u + static_cast<unsigned>(i));
    CHECK(m.payload == "cloud " + std::to_string(i));
  }
  const auto status = client.read_data();
  CHECK(status.subscription == 9);
  CHECK(status.payload == "{\"status\":1}");

  SECTION("unsubscribe stops the channel; requests for unknown things get a status") {
    client.send_text(R"({"op":"unsubscribe","subscriptionIds":[7]})");
    REQUIRE(wait_until([&] { return server.subscribed() == 0b1000u; }));
    client.send_text(R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":99}]})");
    CHECK(client.read_json()["op"] == "status");
    client.send_text(R"({"op":"getParameters","parameterNames":[]})");
    const auto reply = client.read_json();
    CHECK(reply["level"] == 2);
    CHECK(reply["message"].get<std::string>().find("getParameters") != std::string::npos);
    CHECK(server.stats().clients_dropped == 0);
  }
}

TEST_CASE("plain HTTP GET returns the web page, other paths 404") {
  Logged logged;
  FoxgloveServer server(test_config(logged), viz::FrameEncoder().channels());
  std::string type;
  const std::string page = http_get(server.port(), "/", &type);
  CHECK(page.rfind("200\n", 0) == 0);
  CHECK(type.find("text/html") == 0);
  CHECK(page.find("<canvas") != std::string::npos);
  CHECK(page.find("foxglove.websocket.v1") != std::string::npos);
  CHECK(page.find("http://") == std::string::npos);  // nothing fetched from elsewhere
  CHECK(page.find("https://") == std::string::npos);
  CHECK(http_get(server.port(), "/nothing").rfind("404\n", 0) == 0);
  CHECK(server.stats().http_requests == 2);
}

TEST_CASE("clients without a Foxglove subprotocol are refused") {
  Logged logged;
  FoxgloveServer server(test_config(logged), viz::FrameEncoder().channels());
  CHECK_THROWS(WsTestClient(server.port(), ""));
  CHECK_THROWS(WsTestClient(server.port(), "chat"));
  CHECK(wait_until([&] { return logged.contains("no supported WebSocket subprotocol"); }));
  CHECK(server.stats().clients_accepted == 0);
}

TEST_CASE("garbage, binary frames and broken frames drop that client only, with a log line") {
  Logged logged;
  FoxgloveServer server(test_config(logged), viz::FrameEncoder().channels());
  auto good = subscribed_client(server, 1);
  REQUIRE(wait_until([&] { return server.subscribed() == 1u; }));

  {
    WsTestClient bad(server.port());
    bad.send_text("this is not JSON");
  }
  REQUIRE(wait_until([&] { return server.stats().clients_dropped == 1; }));
  CHECK(logged.contains("dropped: sent garbage: not JSON"));
  {
    WsTestClient bad(server.port());
    bad.send_text(R"({"op":"subscribe","subscriptions":"all"})");
  }
  REQUIRE(wait_until([&] { return server.stats().clients_dropped == 2; }));
  {
    WsTestClient bad(server.port());
    bad.read_json();
    bad.read_json();
    // Client frames must be masked: an unmasked one is a protocol error.
    const unsigned char frame[] = {0x82, 0x03, 'a', 'b', 'c'};
    boost::asio::write(bad.socket(), boost::asio::buffer(frame));
    CHECK_THROWS(bad.read_json());  // the server's close frame (1002, protocol error)
    REQUIRE(wait_until([&] { return server.stats().clients_dropped == 3; }));
  }
  CHECK(logged.contains("protocol error"));
  {
    // A frame announcing 1000 bytes, then the connection ends after 4 of them.
    WsTestClient bad(server.port());
    const unsigned char frame[] = {0x81, 0x80 | 126, 0x03, 0xE8, 1, 2, 3, 4, '{', '"', 'o', 'p'};
    boost::asio::write(bad.socket(), boost::asio::buffer(frame));
    bad.socket().close();
  }
  REQUIRE(wait_until([&] { return server.stats().clients_closed == 4; }));
  CHECK(logged.contains("disconnected"));

  server.publish(0, 5, bytes_of("still here"));
  CHECK(good->read_data().payload == "still here");
  CHECK(server.stats().clients.size() == 1);
}

TEST_CASE("a client that never reads: its queue stays bounded, the others get every message") {
  Logged logged;
  const auto config = test_config(logged);
  FoxgloveServer server(config, viz::FrameEncoder().channels());
  auto stuck = subscribed_client(server, 1);
  auto good = subscribed_client(server, 2);
  REQUIRE(wait_until([&] { return subscriptions_total(server) == 2; }));

  const std::string payload(256 * 1024, 'p');
  constexpr int kMessages = 150;  // 38 MB: far beyond the socket buffers and the queue
  for (int i = 0; i < kMessages; ++i) {
    server.publish(0, i, bytes_of(payload));
    const auto m = good->read_data();  // paced by the good client only
    REQUIRE(m.log_time_ns == static_cast<std::uint64_t>(i));
  }
  const auto stats = server.stats();
  REQUIRE(stats.clients.size() == 2);
  for (const auto& c : stats.clients) {
    INFO("client " << c.id << " sent " << c.messages_sent << " dropped " << c.messages_dropped);
    CHECK(c.peak_queued_bytes <= config.client_queue_bytes);
    if (c.subscriptions > 0 && c.messages_dropped > 0) {
      CHECK(c.messages_sent + c.messages_dropped + c.queued_bytes / (payload.size() + 13) >= kMessages);
    }
  }
  const auto& a = stats.clients[0];
  const auto& b = stats.clients[1];
  const auto& stuck_stats = a.messages_dropped > 0 ? a : b;
  const auto& good_stats = a.messages_dropped > 0 ? b : a;
  CHECK(stuck_stats.messages_dropped > kMessages / 2);
  CHECK(good_stats.messages_dropped == 0);
  CHECK(stats.publish_dropped == 0);
}

TEST_CASE("20 clients coming and going while another one receives everything") {
  Logged logged;
  FoxgloveServer server(test_config(logged), viz::FrameEncoder().channels());
  auto good = subscribed_client(server, 1);
  REQUIRE(wait_until([&] { return server.subscribed() == 1u; }));
  int published = 0;
  for (int i = 0; i < 20; ++i) {
    {
      auto passer = subscribed_client(server, 5);
      if (i % 2 == 0) passer->close();  // half say goodbye, half just vanish
    }
    server.publish(0, published++, bytes_of("m"));
    server.publish(0, published++, bytes_of("m"));
  }
  for (int i = 0; i < published; ++i) CHECK(good->read_data().log_time_ns == static_cast<std::uint64_t>(i));
  CHECK(wait_until([&] { return server.stats().clients_closed == 20; }));
  CHECK(server.stats().clients_dropped == 0);
  CHECK(server.stats().clients.size() == 1);
}

TEST_CASE("a client whose replies pile up is dropped while channels are added") {
  // A session whose unread replies reach the limit closes itself from inside the call that
  // queues one more; adding channels queues an advertisement to every session, so it must
  // not hold the registry's lock then (closing takes it: the call would never return).
  Logged logged;
  viz::ServerConfig config = test_config(logged);
  config.client_unread_replies_max = 12;
  FoxgloveServer server(config, viz::FrameEncoder().channels());
  auto stuck = subscribed_client(server, 1);
  REQUIRE(wait_until([&] { return subscriptions_total(server) == 1; }));
  const std::string payload(256 * 1024, 'p');
  // A data message queues its header and the payload. The data messages the server has handled for
  // the client: written (after the greeting's two texts), dropped for the slow client, or queued
  // behind the one being written; and those dropped before reaching it.
  const std::size_t data_message_bytes = kDataHeaderBytes + payload.size();
  const auto data_handled = [&] {
    const viz::ServerStats stats = server.stats();
    if (stats.clients.size() != 1 || stats.clients[0].messages_sent < 2) return std::uint64_t{0};
    const viz::ClientStats& c = stats.clients[0];
    return c.messages_sent - 2 + c.messages_dropped + c.queued_bytes / data_message_bytes +
           stats.publish_dropped;
  };
  // Published one at a time, each handled before the next, so that the socket takes all it
  // can: 150 messages (39 MB) are far past its buffers, and the client's queue ends full
  // behind a write that cannot finish. (Published at once, the server dropped most of them
  // in one go, and what it kept could still fit the buffers: 1 run in about 50 failed.)
  for (std::uint64_t i = 0; i < 150; ++i) {
    server.publish(0, static_cast<std::int64_t>(i), bytes_of(payload));
    REQUIRE(wait_until([&] { return data_handled() == i + 1; }));
  }
  // The replies' bytes in the client's queue: what it holds besides whole data messages.
  const auto reply_bytes = [&] {
    const auto clients = server.stats().clients;
    return clients.size() == 1 ? clients[0].queued_bytes % data_message_bytes : 0;
  };
  REQUIRE(server.stats().clients[0].queued_bytes >= data_message_bytes);
  const std::string request = R"({"op":"getParameters","parameterNames":[]})";
  stuck->send_text(request);
  REQUIRE(wait_until([&] { return reply_bytes() > 0; }));
  const std::size_t reply = reply_bytes();
  const std::size_t unread = config.client_unread_replies_max;
  for (std::size_t i = 1; i < unread; ++i) stuck->send_text(request);
  REQUIRE(wait_until([&] { return reply_bytes() == unread * reply; }));
  CHECK(server.stats().clients_dropped == 0);
  viz::FrameEncoderConfig rear;
  rear.topic_prefix = "/vlpground/rear";
  CHECK(server.add_channels(viz::FrameEncoder(rear).channels()) == 4);
  CHECK(server.stats().clients_dropped == 1);
  CHECK(logged.contains("does not read its replies"));
  CHECK(server.stats().clients.empty());
  WsTestClient late(server.port());  // and the server still serves
  CHECK(late.read_json()["op"] == "serverInfo");
}

TEST_CASE("bad server configuration is refused, and a busy port is a clear error") {
  viz::ServerConfig c;
  c.address = "localhost:80";
  CHECK_THROWS_WITH(FoxgloveServer(c, {}), Catch::Contains("not an IP address"));
  viz::ServerConfig no_replies;
  no_replies.client_unread_replies_max = 0;
  CHECK_THROWS_WITH(FoxgloveServer(no_replies, {}), Catch::Contains("client_unread_replies_max"));
  Logged logged;
  FoxgloveServer first(test_config(logged), {});
  viz::ServerConfig same;
  same.port = first.port();
  CHECK_THROWS_WITH(FoxgloveServer(same, {}), Catch::Contains("cannot listen on 127.0.0.1:"));
}

TEST_CASE("channels added later (another sensor) are advertised to connected and new clients") {
  Logged logged;
  viz::FrameEncoder front;
  FoxgloveServer server(test_config(logged), front.channels());
  WsTestClient early(server.port());
  early.read_json();
  CHECK(early.read_json()["channels"].size() == 4);
  viz::FrameEncoderConfig rear_config;
  rear_config.topic_prefix = "/vlpground/rear";
  const std::size_t first = server.add_channels(viz::FrameEncoder(rear_config).channels());
  CHECK(first == 4);
  const auto update = early.read_json();
  REQUIRE(update["op"] == "advertise");
  REQUIRE(update["channels"].size() == 4);
  CHECK(update["channels"][0]["id"] == 4);
  CHECK(update["channels"][0]["topic"] == "/vlpground/rear/points");
  early.subscribe(3, 4);
  REQUIRE(wait_until([&] { return server.subscribed() == 0b10000u; }));
  server.publish(4, 9, bytes_of("rear cloud"));
  const auto m = early.read_data();
  CHECK(m.subscription == 3);
  CHECK(m.payload == "rear cloud");

  WsTestClient late(server.port());
  late.read_json();
  CHECK(late.read_json()["channels"].size() == 8);
  std::vector<viz::ChannelSpec> too_many(25, front.channels()[0]);
  CHECK_THROWS_WITH(server.add_channels(too_many), Catch::Contains("at most 32"));
}
