#include "frontends/foxglove_frontend.hpp"

#include <charconv>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <stdexcept>

#if VLPGROUND_HAVE_VIZ
#include "vlpground/viz/channels.hpp"
#include "vlpground/viz/foxglove_server.hpp"
#endif

namespace vlpground::cli {

std::pair<std::string, std::uint16_t> parse_listen_address(const std::string& text) {
  std::string address = kDefaultFoxgloveAddress;
  std::string port = text;
  if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    address = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (address.size() >= 2 && address.front() == '[' && address.back() == ']') {
      address = address.substr(1, address.size() - 2);  // [IPv6]
    }
  }
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc() || end != port.data() + port.size() || value > 65535) {
    throw std::invalid_argument("expects [ADDR:]PORT with PORT 0..65535, got '" + text + "'");
  }
  if (address.empty()) throw std::invalid_argument("empty address in '" + text + "'");
  return {address, static_cast<std::uint16_t>(value)};
}

void add_foxglove_options(CLI::App& cmd, FoxgloveOptions& o) {
  cmd.add_option("--foxglove", o.listen,
                 "serve the frames live to Foxglove (WebSocket, ws://ADDR:PORT) and a "
                 "bird's-eye web page (http://ADDR:PORT/); ADDR defaults to 127.0.0.1, "
                 "Foxglove's usual port is 8765, 0 picks a free one (docs/foxglove.md)")
      ->type_name("[ADDR:]PORT")
      ->check([](const std::string& text) {
        try {
          parse_listen_address(text);
          return std::string();
        } catch (const std::invalid_argument& e) {
          return std::string(e.what());
        }
      })
      ->group("Outputs");
}

#if VLPGROUND_HAVE_VIZ
namespace {

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Encodes only the channels someone subscribed to, and hands them to the server thread;
// never blocks the detection thread on a client. `first_channel`: where this sensor's
// channels start on the (possibly shared) server.
class FoxgloveSink : public FrameSink {
 public:
  FoxgloveSink(viz::FrameEncoder encoder, std::shared_ptr<viz::FoxgloveServer> server,
               std::size_t first_channel)
      : encoder_(std::move(encoder)), server_(std::move(server)), first_(first_channel) {
    publish_ = [this](std::size_t channel, std::int64_t t, std::span<const std::byte> bytes) {
      server_->publish(first_ + channel, t, bytes);
    };
  }

  void write(const LabelledFrame& f) override {
    const viz::ChannelMask wanted = mine() & ~(viz::ChannelMask{1} << viz::kStatusChannel);
    if (wanted != 0) encoder_.encode(f, publish_, wanted);
  }
  void on_stats(const PipelineStats& stats) override {
    if ((mine() >> viz::kStatusChannel & 1u) != 0) encoder_.encode_status(stats, now_ns(), publish_);
  }
  void on_position(const PositionPacket& p) override { encoder_.note_position(p); }
  // The last frames of a run reach every reading client before the server closes (at most
  // a second: a client that stopped reading keeps its queue).
  void finish() override { server_->flush(std::chrono::seconds(1)); }

 private:
  [[nodiscard]] viz::ChannelMask mine() const {
    return (server_->subscribed() >> first_) & viz::kAllChannels;
  }
  viz::FrameEncoder encoder_;
  std::shared_ptr<viz::FoxgloveServer> server_;
  std::size_t first_;
  viz::MessageSink publish_;
};

// One server per --foxglove address in the process, shared by the sensors' sinks.
std::shared_ptr<viz::FoxgloveServer> server_for(const std::string& listen,
                                                std::vector<viz::ChannelSpec> channels,
                                                std::size_t& first_channel) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<viz::FoxgloveServer>> servers;
  const std::lock_guard lock(mutex);
  if (auto server = servers[listen].lock()) {
    first_channel = server->add_channels(std::move(channels));
    return server;
  }
  const auto [address, port] = parse_listen_address(listen);
  viz::ServerConfig config;
  config.address = address;
  config.port = port;
  auto server = std::make_shared<viz::FoxgloveServer>(std::move(config), std::move(channels));
  servers[listen] = server;
  first_channel = 0;
  const std::string host = address.find(':') != std::string::npos ? "[" + address + "]" : address;
  std::fprintf(stderr,
               "vlpground: Foxglove live view on ws://%s:%u (Foxglove: Open connection), "
               "web page http://%s:%u/\n",
               host.c_str(), server->port(), host.c_str(), server->port());
  return server;
}

}  // namespace

std::unique_ptr<FrameSink> make_foxglove_sink(const FoxgloveOptions& o,
                                              const PipelineConfig& config) {
  if (o.listen.empty()) return nullptr;
  viz::FrameEncoderConfig encoder_config;
  encoder_config.extrinsics = config.detector.extrinsics;
  if (!o.sensor.empty()) encoder_config.topic_prefix += "/" + o.sensor;
  viz::FrameEncoder encoder(std::move(encoder_config));
  std::size_t first = 0;
  auto server = server_for(o.listen, encoder.channels(), first);
  return std::make_unique<FoxgloveSink>(std::move(encoder), std::move(server), first);
}

#else

std::unique_ptr<FrameSink> make_foxglove_sink(const FoxgloveOptions& o,
                                              const PipelineConfig& /*config*/) {
  if (o.listen.empty()) return nullptr;
  throw std::runtime_error(
      "this vlpground was built without vlpground::viz (libprotobuf, protoc, nlohmann-json, "
      "Boost.Beast), which serves the live view");
}

#endif

}  // namespace vlpground::cli
