// `vlpground sim SCENE ...`: writes a labelled synthetic capture, or streams it over UDP.
#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <string_view>

#include "commands/commands.hpp"
#include "vlpground/sim/capture_writer.hpp"
#include "vlpground/sim/simulator.hpp"
#include "vlpground/sim/udp_emitter.hpp"

namespace vlpground::cli {
namespace {

constexpr const char* kUsage =
    "usage: vlpground sim SCENE [options]\n"
    "  SCENE                 flat | urban | slope | hills | jam | fences | embankment |\n"
    "                        bank | bowl | crest | garage\n"
    "  --seed S              scene and noise seed (default 1)\n"
    "  --frames N            complete rotations to simulate (default 10)\n"
    "  --rpm R               motor speed, 300..1200 (default 600)\n"
    "  --mode M              strongest | last | dual (default strongest)\n"
    "  --model M             vlp16 | hires (default vlp16)\n"
    "  --out STEM            write STEM.pcap, STEM.labels, STEM.json (default: SCENE)\n"
    "  --height-m H          sensor height above the terrain (default: drawn from the seed)\n"
    "  --speed-mps V         forward speed (default: drawn from the seed)\n"
    "  --roll-deg D          mounting roll, left side up (default 0)\n"
    "  --pitch-deg D         mounting pitch, nose up (default 0)\n"
    "  --udp HOST:PORT       stream live to HOST:PORT (port default 2368) instead of writing\n"
    "  --position-port P     position packets port with --udp (default 8308)\n"
    "  --rate X              playback speed with --udp (default 1.0 = real time)\n"
    "  --loop                with --udp: repeat until interrupted\n";

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int /*sig*/) { g_stop = true; }

struct UsageError {
  std::string message;
};

template <typename T>
T parse_number(std::string_view option, std::string_view text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size()) {
    throw UsageError{"invalid value '" + std::string(text) + "' for " + std::string(option)};
  }
  return value;
}

ReturnMode parse_mode(std::string_view s) {
  if (s == "strongest") return ReturnMode::strongest;
  if (s == "last") return ReturnMode::last;
  if (s == "dual") return ReturnMode::dual;
  throw UsageError{"unknown --mode '" + std::string(s) + "' (strongest|last|dual)"};
}

Model parse_model(std::string_view s) {
  if (s == "vlp16") return Model::vlp16;
  if (s == "hires") return Model::hires;
  throw UsageError{"unknown --model '" + std::string(s) + "' (vlp16|hires)"};
}

struct Options {
  sim::SimConfig sim;
  std::string out;
  std::optional<sim::UdpStreamConfig> udp;
  std::optional<std::uint16_t> position_port;
  std::optional<double> rate;
  bool loop = false;
  bool help = false;
};

void parse_udp(std::string_view text, sim::UdpStreamConfig& udp) {
  const auto colon = text.rfind(':');
  udp.host = std::string(text.substr(0, colon));
  if (colon != std::string_view::npos) {
    udp.data_port = parse_number<std::uint16_t>("--udp port", text.substr(colon + 1));
  }
  if (udp.host.empty()) throw UsageError{"--udp needs HOST[:PORT]"};
}

Options parse(int argc, char** argv) {
  Options o;
  std::optional<std::string> scene;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    auto value = [&]() -> std::string_view {
      if (i + 1 >= argc) throw UsageError{"missing value for " + std::string(arg)};
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      o.help = true;
    } else if (arg == "--seed") {
      o.sim.seed = parse_number<std::uint64_t>(arg, value());
    } else if (arg == "--frames") {
      o.sim.frames = parse_number<int>(arg, value());
    } else if (arg == "--rpm") {
      o.sim.rpm = parse_number<double>(arg, value());
    } else if (arg == "--mode") {
      o.sim.mode = parse_mode(value());
    } else if (arg == "--model") {
      o.sim.model = parse_model(value());
    } else if (arg == "--out") {
      o.out = std::string(value());
    } else if (arg == "--height-m") {
      o.sim.sensor_height_m = parse_number<double>(arg, value());
    } else if (arg == "--speed-mps") {
      o.sim.speed_mps = parse_number<double>(arg, value());
    } else if (arg == "--roll-deg") {
      o.sim.mount_roll_deg = parse_number<double>(arg, value());
    } else if (arg == "--pitch-deg") {
      o.sim.mount_pitch_deg = parse_number<double>(arg, value());
    } else if (arg == "--udp") {
      o.udp.emplace();
      parse_udp(value(), *o.udp);
    } else if (arg == "--position-port") {
      o.position_port = parse_number<std::uint16_t>(arg, value());
    } else if (arg == "--rate") {
      o.rate = parse_number<double>(arg, value());
    } else if (arg == "--loop") {
      o.loop = true;
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError{"unknown option '" + std::string(arg) + "'"};
    } else if (!scene) {
      scene = std::string(arg);
    } else {
      throw UsageError{"unexpected argument '" + std::string(arg) + "'"};
    }
  }
  if (o.help) return o;
  if (!scene) throw UsageError{"missing SCENE (flat|urban|slope|hills|jam|fences|embankment|bank|bowl|crest|garage)"};
  const auto kind = sim::parse_scene_kind(*scene);
  if (!kind) {
    throw UsageError{"unknown scene '" + *scene + "' (" + std::string(sim::scene_kind_list()) +
                     ")"};
  }
  o.sim.scene = *kind;
  if (o.out.empty()) o.out = *scene;
  if (!o.udp && (o.position_port || o.rate || o.loop)) {
    throw UsageError{"--position-port, --rate and --loop need --udp"};
  }
  if (o.udp) {
    if (o.position_port) o.udp->position_port = *o.position_port;
    if (o.rate) o.udp->rate = *o.rate;
    o.udp->loop = o.loop;
  }
  return o;
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
  return stats.send_errors == 0 ? 0 : 1;
}

}  // namespace

int run_sim(int argc, char** argv) {
  Options options;
  try {
    options = parse(argc, argv);
    if (options.help) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    options.sim.validate();
    if (options.udp) options.udp->validate();
  } catch (const UsageError& e) {
    std::fprintf(stderr, "vlpground sim: %s (see --help)\n", e.message.c_str());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "vlpground sim: %s\n", e.what());
    return 2;
  }
  try {
    const auto started = std::chrono::steady_clock::now();
    const sim::Simulator simulator(options.sim);
    if (options.udp) return stream(simulator, *options.udp);
    const auto summary = sim::write_capture(simulator, options.out);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::printf(
        "wrote %s.pcap (%llu data + %llu position packets, %.3f s of capture), %s.labels "
        "(%llu returns, %.1f%% ground), %s.json in %.2f s\n",
        options.out.c_str(), static_cast<unsigned long long>(summary.data_packets),
        static_cast<unsigned long long>(summary.position_packets), summary.duration_s,
        options.out.c_str(), static_cast<unsigned long long>(summary.returns),
        summary.returns ? 100.0 * static_cast<double>(summary.ground_returns) /
                              static_cast<double>(summary.returns)
                        : 0.0,
        options.out.c_str(), seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vlpground sim: %s\n", e.what());
    return 1;
  }
}

}  // namespace vlpground::cli
