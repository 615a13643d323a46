// `vlpground replay --ros2` received by an independent subscriber process (ros2_listener):
// layout, point count, and every point and label equal to `--csv` of the same capture.
#include <signal.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <set>
#include <string>

#include "child_process.hpp"
#include "cli_helpers.hpp"
#include "dds_loopback.hpp"
#include "test_data.hpp"
#include "udp_sender.hpp"

using vlpground::test::ChildProcess;
using vlpground::test::run_cli;

namespace {

constexpr int kTimeoutMs = 60'000;

// Distinct frame numbers in a CSV written by --csv.
std::size_t csv_frames(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::set<std::string> frames;
  while (std::getline(in, line)) frames.insert(line.substr(0, line.find(',')));
  return frames.size();
}

struct Run {
  std::string csv;
  std::size_t frames;
};

// The reference: --csv of the capture, without ROS 2.
Run reference_csv(const std::string& capture, const std::string& tag) {
  const auto dir = vlpground::test::temp_dir(tag);
  const std::string csv = (dir / "returns.csv").string();
  const auto r = run_cli({VLPGROUND_CLI, "replay", capture, "--csv", csv});
  REQUIRE(r.code == 0);
  const std::size_t frames = csv_frames(csv);
  REQUIRE(frames > 0);
  return {csv, frames};
}

// `rate`: "0" as fast as possible (a replay publishes every frame, waiting for DDS), "1"
// real time (a frame every 100 ms, as from the sensor).
void replay_to_listener(const std::string& capture, const char* listener_qos,
                        std::size_t want_frames, const Run& ref, const char* rate) {
  const std::string domain = std::to_string(vlpground::test::confine_dds_to_loopback());
  ChildProcess listener({VLPGROUND_ROS2_LISTENER, "--domain", domain, "--topic",
                         "rt/vlpground/points", "--qos", listener_qos, "--frames",
                         std::to_string(want_frames), "--csv", ref.csv, "--timeout-ms",
                         std::to_string(kTimeoutMs)});
  REQUIRE(listener.wait_for_stderr("listening", kTimeoutMs));
  const auto r = run_cli({VLPGROUND_CLI, "replay", capture, "--rate", rate, "--ros2",
                          "--ros2-domain", domain, "--ros2-wait-subscribers", "1",
                          "--ros2-wait-timeout", "30"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string all = std::to_string(ref.frames);
  CHECK_THAT(r.err, Catch::Contains("ros2: " + all + " of " + all + " frames published on "
                                    "/vlpground/points (0 skipped"));
  const int code = listener.wait_exit(kTimeoutMs);
  INFO(listener.out << listener.err);
  CHECK(code == 0);
  CHECK_THAT(listener.out,
             Catch::Contains("received " + std::to_string(want_frames) + " clouds, 0 failed"));
}

}  // namespace

TEST_CASE("replay --ros2: a reliable subscriber process receives every frame, labels = CSV") {
  const std::string capture = vlpground::test::project_pcap("urban_demo.pcap").string();
  const Run ref = reference_csv(capture, "ros2_cli_reliable");
  replay_to_listener(capture, "reliable", ref.frames, ref, "0");
}

TEST_CASE("replay --ros2 --rate 1: a reliable subscriber receives every frame in real time") {
  const std::string capture = vlpground::test::project_pcap("urban_demo.pcap").string();
  const Run ref = reference_csv(capture, "ros2_cli_realtime");
  replay_to_listener(capture, "reliable", ref.frames, ref, "1");
}

TEST_CASE("replay --ros2 of a dual-return capture: 32 rows, labels = CSV") {
  const std::string capture = vlpground::test::project_pcap("slope_dual.pcap").string();
  const Run ref = reference_csv(capture, "ros2_cli_dual");
  replay_to_listener(capture, "reliable", ref.frames, ref, "0");
}

TEST_CASE("replay --ros2: a best-effort subscriber process also receives") {
  const std::string capture = vlpground::test::project_pcap("urban_demo.pcap").string();
  const Run ref = reference_csv(capture, "ros2_cli_best_effort");
  replay_to_listener(capture, "best-effort", 1, ref, "1");
}

TEST_CASE("replay --ros2-wait-subscribers: no subscriber ends the run with the reason") {
  const std::string domain = std::to_string(vlpground::test::confine_dds_to_loopback());
  const auto r = run_cli({VLPGROUND_CLI, "replay",
                          vlpground::test::project_pcap("urban_demo.pcap").string(), "--ros2",
                          "--ros2-domain", domain, "--ros2-topic", "/nobody/listens",
                          "--ros2-wait-subscribers", "1", "--ros2-wait-timeout", "0.3"});
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Catch::Contains("no subscriber matched /nobody/listens"));
}

TEST_CASE("replay --ros2 with bad options fails with a one-line reason") {
  const std::string capture = vlpground::test::project_pcap("urban_demo.pcap").string();
  auto r = run_cli({VLPGROUND_CLI, "replay", capture, "--ros2", "--ros2-topic", "points"});
  CHECK(r.code != 0);
  CHECK_THAT(r.err, Catch::Contains("absolute ROS 2 name"));
  r = run_cli({VLPGROUND_CLI, "replay", capture, "--ros2", "--ros2-qos", "fast"});
  CHECK(r.code != 0);
  CHECK_THAT(r.err, Catch::Contains("--ros2-qos"));
}

TEST_CASE("live --ros2: UDP frames reach a subscriber with the labels of the same run's CSV, "
          "and Ctrl-C ends cleanly") {
  const std::string domain = std::to_string(vlpground::test::confine_dds_to_loopback());
  const auto dir = vlpground::test::temp_dir("ros2_cli_live");
  const std::string csv = (dir / "live.csv").string();
  constexpr int kFrames = 3;  // urban_demo holds 3 complete rotations between partial ones
  ChildProcess listener({VLPGROUND_ROS2_LISTENER, "--domain", domain, "--topic",
                         "rt/vlpground/points", "--qos", "reliable", "--frames",
                         std::to_string(kFrames), "--csv", csv, "--timeout-ms",
                         std::to_string(kTimeoutMs)});
  REQUIRE(listener.wait_for_stderr("listening", kTimeoutMs));
  const std::uint16_t port = vlpground::test::free_port();
  // --csv before --ros2: each frame's CSV rows are flushed before it is published.
  ChildProcess live({VLPGROUND_CLI, "live", "--bind", "127.0.0.1", "--port", std::to_string(port),
                     "--position-port", "0", "--csv", csv, "--ros2", "--ros2-domain", domain,
                     "--ros2-wait-subscribers", "1", "--ros2-wait-timeout", "30"});
  REQUIRE(live.wait_for_stderr("listening on", kTimeoutMs));  // after the subscriber matched
  vlpground::test::send_capture(vlpground::test::project_pcap("urban_demo.pcap").string(), port,
                                0);
  const int code = listener.wait_exit(kTimeoutMs);
  INFO(listener.out << listener.err);
  CHECK(code == 0);
  CHECK_THAT(listener.out,
             Catch::Contains("received " + std::to_string(kFrames) + " clouds, 0 failed"));
  live.signal(SIGINT);
  INFO(live.err);
  CHECK(live.wait_exit(kTimeoutMs) == 0);
  CHECK_THAT(live.err, Catch::Contains("frames published on /vlpground/points"));
}
