// Two (or more) VLP-16s in one process: both send to port 2368 and are told apart by their
// source address. Every frame names its sensor and is labelled with that sensor's pose.
//
//   two_sensors front=192.168.1.201@1.2,0,1.9,0,0,0 rear=192.168.1.202@-1.0,0,1.9,0,0,180 [SECONDS]
//
// Try it without sensors: `vlpground sim` streams simulated ones (see the README).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include "vlpground/multi_pipeline.hpp"

int main(int argc, char** argv) {
  vlpground::MultiPipelineConfig config;
  double seconds = 10;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg.find('=') != std::string::npos) {
        config.sensors.push_back(vlpground::parse_sensor_spec(arg));
      } else {
        seconds = std::stod(arg);
      }
    }
    if (config.sensors.empty()) throw std::invalid_argument("give at least one NAME=IP");
    vlpground::MultiPipeline sensors(config);  // validates: names, addresses, ports
    // Frames of different sensors arrive on different threads, possibly at the same time.
    sensors.on_frame([](const vlpground::LabelledFrame& f) {
      const std::uint64_t labelled = f.ground.ground_returns + f.ground.obstacle_returns;
      std::printf("%-8s frame %6llu: %4d columns, %5.1f%% ground, detect %.2f ms\n",
                  f.sensor_name.c_str(), static_cast<unsigned long long>(f.frame.meta.sequence),
                  f.frame.columns(),
                  labelled == 0 ? 0.0 : 100.0 * static_cast<double>(f.ground.ground_returns) /
                                            static_cast<double>(labelled),
                  f.timings.detect_ms);
    });
    sensors.on_diagnostics([&](std::size_t sensor, const vlpground::Diagnostic& d) {
      if (d.kind == vlpground::DiagnosticKind::warning) {
        std::fprintf(stderr, "%s: %s\n", sensors.sensor_config(sensor).name.c_str(),
                     d.message.c_str());
      }
    });
    sensors.start();  // throws std::runtime_error when a port cannot be bound
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    sensors.stop();
    sensors.wait();

    const vlpground::MultiPipelineStats stats = sensors.stats();
    for (const vlpground::SensorStats& s : stats.sensors) {
      std::printf("%-8s %llu frames, %llu dropped, latency p99 %.2f ms\n", s.name.c_str(),
                  static_cast<unsigned long long>(s.pipeline.frames_delivered),
                  static_cast<unsigned long long>(s.pipeline.frames_dropped),
                  s.pipeline.latency.p99_ms);
    }
    std::printf("datagrams from unknown addresses: %llu\n",
                static_cast<unsigned long long>(stats.router.unknown_source));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "two_sensors: %s\n", e.what());
    return 1;
  }
}
