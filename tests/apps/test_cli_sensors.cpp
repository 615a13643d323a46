// `vlpground live --sensor ...`: two simulated sensors (`vlpground sim --udp --from`) on one
// port, routed by source address, outputs per sensor. Loopback only, bounded waits.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "child_process.hpp"
#include "loopback.hpp"
#include "test_data.hpp"

using namespace vlpground;

namespace {

const std::string kVlpground = VLPGROUND_CLI;

std::size_t line_count(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  for (std::string l; std::getline(in, l);) ++n;
  return n;
}

}  // namespace

TEST_CASE("live --sensor: two sensors on one port, frames and outputs per sensor") {
  const auto dir = test::temp_dir("cli_sensors");
  const auto [port, position_port] = test::free_port_pair();
  const std::string data = std::to_string(port), position = std::to_string(position_port);
  // --frames 3 per sensor: the run ends once both sensors delivered three full rotations
  // (the partial first frame is output but not counted, as with one sensor).
  test::ChildProcess live({kVlpground, "live", "--bind", "127.0.0.1", "--port", data,
                           "--position-port", position, "--sensor", "front=127.0.0.2",
                           "--sensor", "rear=127.0.0.3@-1.0,0,0.2,0,0,180", "--frames", "3",
                           "--queue", "16", "--json", "--csv", (dir / "returns.csv").string(),
                           "--png", (dir / "png").string()});
  REQUIRE(live.wait_for_stderr("for rear", 20'000));
  for (const char* from : {"127.0.0.2", "127.0.0.3"}) {
    const auto sent = test::run_cli({kVlpground, "sim", "flat", "--frames", "4", "--udp",
                                     "127.0.0.1:" + data, "--position-port", position, "--rate",
                                     "4", "--from", from});
    INFO(sent.err);
    REQUIRE(sent.code == 0);
  }
  const int code = live.wait_exit(30'000);
  INFO(live.err);
  REQUIRE(code == 0);
  const std::string& json = live.out;
  CHECK(json.find("\"name\":\"front\"") != std::string::npos);
  CHECK(json.find("\"name\":\"rear\"") != std::string::npos);
  CHECK(json.find("\"unknown_source\":0") != std::string::npos);
  const auto parsed = nlohmann::json::parse(json);
  REQUIRE(parsed["sensors"].size() == 2);
  for (const auto& sensor : parsed["sensors"]) {
    INFO(sensor["name"]);
    const auto& frames = sensor["frames"];
    CHECK(frames["complete"] == 3);
    CHECK(frames["delivered"].get<int>() - frames["incomplete"].get<int>() == 3);
    CHECK(frames["incomplete"].get<int>() <= 1);  // at most the partial first rotation
    CHECK(sensor["model"] == "vlp16");  // the fields info --json shares, per sensor
    CHECK(sensor["gps"].is_object());
  }
  for (const char* name : {"front", "rear"}) {
    INFO(name);
    CHECK(line_count(dir / ("returns." + std::string(name) + ".csv")) > 1000);
    CHECK(std::filesystem::exists(dir / "png" / name / "frame_000001.png"));
    CHECK(std::filesystem::exists(dir / "png" / name / "overview.png"));
  }
  CHECK_FALSE(std::filesystem::exists(dir / "returns.csv"));
}

TEST_CASE("live --sensor: bad specs and conflicting options are one-line usage errors") {
  const std::string port = std::to_string(test::free_port());
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--sensor", "front"},
        std::vector<std::string>{"--sensor", "front=1.2.3.4@1,2"},
        std::vector<std::string>{"--sensor", "a=127.0.0.2", "--sensor", "a=127.0.0.3"},
        std::vector<std::string>{"--sensor", "a=127.0.0.2", "--sensor-ip", "127.0.0.2"}}) {
    std::vector<std::string> all = {kVlpground, "live", "--bind", "127.0.0.1", "--port", port};
    all.insert(all.end(), args.begin(), args.end());
    const auto r = test::run_cli(all);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find("--sensor") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

TEST_CASE("live --config sensors.yaml: the sensor list from a file") {
  const auto dir = test::temp_dir("cli_sensors_yaml");
  const auto [port, other_port] = test::free_port_pair();
  const auto yaml = dir / "sensors.yaml";
  std::ofstream(yaml) << "bind: 127.0.0.1\nposition-port: 0\nport: " << port
                      << "\nsensor:\n  - front=127.0.0.2@1.2,0,1.9,0,0,0\n"
                      << "  - rear=127.0.0.3:" << other_port << "@-1.0,0,1.9,0,0,180\n";
  const auto r = test::run_cli({kVlpground, "live", "--config", yaml.string(), "--duration",
                                "0.3", "--json"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("\"input\":\"front = 127.0.0.2:" + std::to_string(port) + "\"") !=
        std::string::npos);
  CHECK(r.out.find("\"input\":\"rear = 127.0.0.3:" + std::to_string(other_port) + "\"") !=
        std::string::npos);
}
