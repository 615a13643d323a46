// `vlpground sim SCENE ...`: writes a labelled synthetic capture, or streams it over UDP.
#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "cli/options.hpp"
#include "commands/commands.hpp"
#include "vlpground/sim/capture_writer.hpp"
#include "vlpground/sim/simulator.hpp"
#include "vlpground/sim/udp_emitter.hpp"
#include "writers/output_path.hpp"

namespace vlpground::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int /*sig*/) { g_stop = true; }

void parse_udp(const std::string& text, sim::UdpStreamConfig& udp) {
  const auto colon = text.rfind(':');
  udp.host = text.substr(0, colon);
  if (colon != std::string::npos) {
    const std::string port = text.substr(colon + 1);
    int value = 0;
    const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (ec != std::errc{} || end != port.data() + port.size() || value < 1 || value > 65535) {
      throw CLI::ValidationError("--udp", "port must be 1..65535, got '" + port + "'");
    }
    udp.data_port = static_cast<std::uint16_t>(value);
  }
  if (udp.host.empty()) throw CLI::ValidationError("--udp", "needs HOST[:PORT]");
}

int stream(const sim::Simulator& simulator, const sim::UdpStreamConfig& udp) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::fprintf(stderr, "vlpground sim: streaming %llu data packets to %s:%u (position %u)%s\n",
               static_cast<unsigned long long>(simulator.packet_count()), udp.host.c_str(),
               unsigned{udp.data_port}, unsigned{udp.position_port}, udp.loop ? ", looping" : "");
  const auto stats = sim::stream_udp(simulator, udp, [] { return g_stop.load(); });
  std::printf("sent %llu data + %llu position packets, %llu send errors\n",
              static_cast<unsigned long long>(stats.data_packets),
              static_cast<unsigned long long>(stats.position_packets),
              static_cast<unsigned long long>(stats.send_errors));
  return stats.send_errors == 0 ? kExitOk : kExitFailure;
}

// "sim config: sensor_height_m must be ..." -> "--height-m must be ...".
std::string in_option_names(std::string message) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"sim config: frames", "--frames"},
      {"sim config: rpm", "--rpm"},
      {"sim config: sensor_height_m", "--height-m"},
      {"sim config: speed_mps", "--speed-mps"},
      {"sim config: mount roll/pitch", "--roll-deg and --pitch-deg"},
  };
  for (const auto& [field, option] : kNames) {
    if (message.rfind(field, 0) == 0) return option + message.substr(std::strlen(field));
  }
  return message;
}

class SimCommand : public Command {
 public:
  explicit SimCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(
        "sim",
        "write a labelled synthetic capture (STEM.pcap, STEM.labels, STEM.heights, STEM.json), "
        "or stream it over UDP");
    sim::SimConfig& c = options_;
    cmd->add_option_function<std::string>(
           "scene",
           [this](const std::string& name) {
             scene_name_ = name;
             options_.scene = *sim::parse_scene_kind(name);
           },
           "the scene: " + std::string(sim::scene_kind_list()))
        ->check(CLI::Validator(
            [](std::string& name) {
              return sim::parse_scene_kind(name) ? std::string()
                                                 : "unknown scene '" + name + "' (" +
                                                       std::string(sim::scene_kind_list()) + ")";
            },
            "SCENE"))
        ->type_name("SCENE")
        ->required();
    cmd->add_option("--seed", c.seed, "scene and noise seed");
    cmd->add_option("--frames", c.frames, "complete rotations to simulate")
        ->check(CLI::Range(1, 10000));
    cmd->add_option("--rpm", c.rpm, "motor speed")->check(CLI::Range(300.0, 1200.0));
    add_choice_option<ReturnMode>(*cmd, "--mode", c.mode,
                                  {{"strongest", ReturnMode::strongest},
                                   {"last", ReturnMode::last},
                                   {"dual", ReturnMode::dual}},
                                  "return mode");
    add_choice_option<Model>(*cmd, "--model", c.model,
                             {{"vlp16", Model::vlp16}, {"hires", Model::hires}}, "sensor model");
    cmd->add_option("--out", out_,
                    "write STEM.pcap, STEM.labels, STEM.heights, STEM.json (an existing directory: "
                    "DIR/SCENE.*)")
        ->type_name("STEM")
        ->default_str("SCENE");
    cmd->add_option_function<double>(
           "--height-m", [&c](double v) { c.sensor_height_m = v; },
           "sensor height above the terrain (m)")
        ->default_str("drawn from the seed");
    cmd->add_option_function<double>(
           "--speed-mps", [&c](double v) { c.speed_mps = v; }, "forward speed (m/s)")
        ->default_str("drawn from the seed");
    cmd->add_option("--roll-deg", c.mount_roll_deg,
                    "mounting roll, right-handed about x (forward): > 0 = left side up (deg)");
    cmd->add_option("--pitch-deg", c.mount_pitch_deg,
                    "mounting pitch, right-handed about y (left): > 0 = nose down (deg); "
                    "STEM.json and eval use the same convention as --extrinsics");
    CLI::Option* udp = cmd->add_option_function<std::string>(
                              "--udp",
                              [this](const std::string& v) {
                                udp_.emplace();
                                parse_udp(v, *udp_);
                              },
                              "stream live to HOST:PORT (port default 2368) instead of writing")
                           ->type_name("HOST[:PORT]");
    const sim::UdpStreamConfig stream_defaults;
    cmd->add_option("--position-port", position_port_, "position packets port with --udp")
        ->default_val(stream_defaults.position_port)
        ->check(CLI::Range(1, 65535))
        ->needs(udp);
    cmd->add_option("--rate", rate_, "playback speed with --udp (1 = real time)")
        ->default_val(stream_defaults.rate)
        ->check(CLI::Range(0.001, 1000.0))
        ->needs(udp);
    cmd->add_flag("--loop", loop_, "with --udp: repeat until interrupted")->needs(udp);
    cmd->add_option("--from", from_,
                    "with --udp: send from this local address (127.0.0.2, 127.0.0.3, ... play "
                    "several sensors on one machine)")
        ->type_name("ADDR")
        ->needs(udp);
  }

  int run() override {
    if (out_.empty()) out_ = scene_name_;
    // One rule for output paths: an existing directory gets DIR/SCENE.*, missing parent
    // directories are created.
    if (std::filesystem::is_directory(out_))
      out_ = (std::filesystem::path(out_) / scene_name_).string();
    if (udp_) {
      udp_->position_port = position_port_;
      udp_->rate = rate_;
      udp_->loop = loop_;
      udp_->source_address = from_;
    }
    try {
      options_.validate();
      if (udp_) udp_->validate();
    } catch (const std::invalid_argument& e) {
      throw UsageError(in_option_names(e.what()));
    }
    const auto started = std::chrono::steady_clock::now();
    const sim::Simulator simulator(options_);
    if (udp_) return stream(simulator, *udp_);
    create_parent_directories(out_);
    const auto summary = sim::write_capture(simulator, out_);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::printf(
        "wrote %s.pcap (%llu data + %llu position packets, %.3f s of capture), %s.labels "
        "(%llu returns, %.1f%% ground), %s.heights, %s.json in %.2f s\n",
        out_.c_str(), static_cast<unsigned long long>(summary.data_packets),
        static_cast<unsigned long long>(summary.position_packets), summary.duration_s, out_.c_str(),
        static_cast<unsigned long long>(summary.returns),
        summary.returns ? 100.0 * static_cast<double>(summary.ground_returns) /
                              static_cast<double>(summary.returns)
                        : 0.0,
        out_.c_str(), out_.c_str(), seconds);
    return kExitOk;
  }

 private:
  sim::SimConfig options_;
  std::string scene_name_, out_;
  std::optional<sim::UdpStreamConfig> udp_;
  std::uint16_t position_port_ = 0;
  double rate_ = 0;
  bool loop_ = false;
  std::string from_;
};

}  // namespace

std::unique_ptr<Command> add_sim_command(CLI::App& app) {
  return std::make_unique<SimCommand>(app);
}

}  // namespace vlpground::cli
