// Several sensors in one process: the sensor spec parser, configuration errors, and two
// simulated sensors streamed from 127.0.0.2 and 127.0.0.3 to one port, each labelled with
// its own extrinsics and tagged with its name. Loopback only, bounded waits.
#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "loopback.hpp"
#include "vlpground/multi_pipeline.hpp"
#include "vlpground/sim/udp_emitter.hpp"

using namespace vlpground;

namespace {

std::string spec_error(std::string_view spec) {
  try {
    (void)parse_sensor_spec(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "parsed";
}

// Waits (bounded) until the router has read `datagrams` datagrams.
bool router_read(const MultiPipeline& multi, std::uint64_t datagrams) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto router = multi.stats().router;
    if (router.records + router.kernel_drops >= datagrams) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // polling a counter, bounded
  }
  return false;
}

}  // namespace

TEST_CASE("sensor spec: NAME=IP[:PORT][@x,y,z,roll,pitch,yaw]", "[multi]") {
  const SensorConfig plain = parse_sensor_spec("front=192.168.1.201");
  CHECK(plain.name == "front");
  CHECK(plain.address == "192.168.1.201");
  CHECK(plain.data_port == 2368);
  CHECK(plain.position_port == 8308);
  CHECK(plain.extrinsics.z_m == 0.0);

  const SensorConfig full = parse_sensor_spec("rear_left=10.0.0.7:2369@-1.5,0.8,1.9,0,2.5,180");
  CHECK(full.address == "10.0.0.7");
  CHECK(full.data_port == 2369);
  CHECK(full.extrinsics.x_m == -1.5);
  CHECK(full.extrinsics.y_m == 0.8);
  CHECK(full.extrinsics.z_m == 1.9);
  CHECK(full.extrinsics.pitch_deg == 2.5);
  CHECK(full.extrinsics.yaw_deg == 180.0);

  CHECK(parse_sensor_spec("v6=[fe80::1]:2370").address == "fe80::1");
  CHECK(parse_sensor_spec("v6=[fe80::1]:2370").data_port == 2370);
  CHECK(parse_sensor_spec("v6=fe80::1").address == "fe80::1");

  CHECK(spec_error("192.168.1.201").find("no '='") != std::string::npos);
  CHECK(spec_error("=1.2.3.4").find("the name must be") != std::string::npos);
  CHECK(spec_error("a b=1.2.3.4").find("the name must be") != std::string::npos);
  CHECK(spec_error("front=").find("no address") != std::string::npos);
  CHECK(spec_error("front=1.2.3.4:0").find("port '0'") != std::string::npos);
  CHECK(spec_error("front=1.2.3.4:http").find("port 'http'") != std::string::npos);
  CHECK(spec_error("front=1.2.3.4@1,2,3").find("exactly 6 numbers") != std::string::npos);
  CHECK(spec_error("front=1.2.3.4@1,2,3,4,5,6,7").find("exactly 6 numbers") != std::string::npos);
  CHECK(spec_error("front=1.2.3.4@1,2,x,4,5,6").find("'x' is not a number") != std::string::npos);
}

TEST_CASE("multi pipeline: configuration errors are clear", "[multi]") {
  MultiPipelineConfig config;
  auto message = [&] {
    try {
      config.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("valid");
  };
  CHECK(message() == "no sensor configured");
  config.sensors = {parse_sensor_spec("front=127.0.0.2"), parse_sensor_spec("rear=127.0.0.3")};
  CHECK(message() == "valid");
  config.sensors[1].name = "front";
  CHECK(message() == "two sensors are named 'front'");
  config.sensors[1].name = "rear";
  config.sensors[1].address = "127.0.0.2";
  CHECK(message().find("both listen for 127.0.0.2") != std::string::npos);
  config.sensors[1].address = "127.0.0.3";
  config.pipeline.detector.grid_bins = 0;
  CHECK(message().find("sensor 'front': ") == 0);
  CHECK_THROWS_AS(MultiPipeline(config), std::invalid_argument);
}

TEST_CASE("multi pipeline: two sensors on one port, routed, tagged, own extrinsics",
          "[multi][udp]") {
  sim::SimConfig sim_config;
  sim_config.scene = sim::SceneKind::flat;
  sim_config.frames = 3;
  sim_config.sensor_height_m = 1.8;
  sim_config.speed_mps = 0.0;
  const sim::Simulator front_sim(sim_config);
  sim_config.seed = 2;
  sim_config.mode = ReturnMode::dual;
  const sim::Simulator rear_sim(sim_config);

  const auto [data_port, position_port] = test::free_port_pair();
  MultiPipelineConfig config;
  config.bind_address = "127.0.0.1";
  config.sensors = {parse_sensor_spec("front=127.0.0.2:" + std::to_string(data_port)),
                    parse_sensor_spec("rear=127.0.0.3:" + std::to_string(data_port) +
                                      "@0,0,1.0,0,0,0")};
  for (auto& s : config.sensors) s.position_port = position_port;
  config.pipeline.detector.hypotheses = 60;
  config.pipeline.backpressure = Backpressure::block;  // keep every frame for the checks
  MultiPipeline multi(config);
  REQUIRE(multi.sensor_count() == 2);
  CHECK(multi.sensor_config(1).extrinsics.z_m == 1.0);

  struct Seen {
    std::string name;
    std::uint32_t index;
    ReturnMode mode;
    bool complete;
    float plane_d;
  };
  std::mutex mutex;
  std::vector<Seen> seen;
  multi.on_frame([&](const LabelledFrame& f) {
    const Seen s{f.sensor_name, f.sensor_index, f.frame.meta.mode, f.frame.meta.complete,
                 f.ground.segments[0].plane.d};
    std::lock_guard lock(mutex);
    seen.push_back(s);
  });
  multi.start();

  sim::UdpStreamConfig front;
  front.data_port = data_port;
  front.position_port = position_port;
  front.rate = 4.0;
  front.source_address = "127.0.0.2";
  sim::UdpStreamConfig rear = front;
  rear.source_address = "127.0.0.3";
  sim::UdpStreamStats sent_front, sent_rear;
  std::thread front_thread([&] { sent_front = sim::stream_udp(front_sim, front); });
  std::thread rear_thread([&] { sent_rear = sim::stream_udp(rear_sim, rear); });
  front_thread.join();
  rear_thread.join();
  test::Sender stranger("127.0.0.9");
  stranger.send(std::vector<std::uint8_t>(1206, 0), data_port);

  REQUIRE(router_read(multi, sent_front.datagrams() + sent_rear.datagrams() + 1));
  multi.stop();
  REQUIRE(multi.wait_for(10'000));

  const MultiPipelineStats stats = multi.stats();
  CHECK(stats.finished);
  CHECK(stats.router.unknown_source == 1);
  CHECK(stats.router.accounted() == stats.router.records);
  REQUIRE(stats.sensors.size() == 2);
  CHECK(stats.sensors[0].name == "front");
  CHECK(stats.router.sensors[0].data_packets == sent_front.data_packets);
  CHECK(stats.router.sensors[1].data_packets == sent_rear.data_packets);
  for (const SensorStats& s : stats.sensors) {
    CHECK(s.queue_full == 0);
    CHECK(s.pipeline.frames_dropped == 0);
  }
  CHECK(stats.sensors[0].pipeline.capture.source.data_packets == sent_front.data_packets);
  CHECK(stats.sensors[1].pipeline.capture.source.data_packets == sent_rear.data_packets);

  int complete[2] = {0, 0};
  float d[2] = {0, 0};
  for (const Seen& s : seen) {
    REQUIRE(s.index < 2);
    CHECK(s.name == (s.index == 0 ? "front" : "rear"));
    CHECK(s.mode == (s.index == 0 ? ReturnMode::strongest : ReturnMode::dual));
    if (s.complete) {
      ++complete[s.index];
      d[s.index] = s.plane_d;
    }
  }
  CHECK(complete[0] >= 3);
  CHECK(complete[1] >= 3);
  // The rear sensor sits 1 m higher in the vehicle: its ground plane (n.p + d = 0, in
  // vehicle coordinates) is 1 m higher than the front one's, both seeing ground 1.8 m down.
  CHECK(d[0] == Approx(1.8).margin(0.1));
  CHECK(d[1] == Approx(0.8).margin(0.1));
}

TEST_CASE("multi pipeline: pull each sensor's frames with sensor(i).next()", "[multi][udp]") {
  sim::SimConfig sim_config;
  sim_config.scene = sim::SceneKind::flat;
  sim_config.frames = 3;
  const sim::Simulator sim(sim_config);
  const auto [data_port, position_port] = test::free_port_pair();
  MultiPipelineConfig config;
  config.bind_address = "127.0.0.1";
  for (const char* spec : {"a=127.0.0.2", "b=127.0.0.3"}) {
    config.sensors.push_back(parse_sensor_spec(spec));
    config.sensors.back().data_port = data_port;
    config.sensors.back().position_port = position_port;
  }
  config.pipeline.detector.hypotheses = 60;
  MultiPipeline multi(config);  // no frame callback: pull mode
  multi.start();
  std::thread senders[2];
  for (int i = 0; i < 2; ++i) {
    senders[i] = std::thread([&, i] {
      sim::UdpStreamConfig c;
      c.data_port = data_port;
      c.position_port = position_port;
      c.rate = 4.0;
      c.source_address = i == 0 ? "127.0.0.2" : "127.0.0.3";
      (void)sim::stream_udp(sim, c);
    });
  }
  std::vector<FrameLease> held[2];
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while ((held[0].size() < 3 || held[1].size() < 3) && std::chrono::steady_clock::now() < deadline) {
    for (std::size_t s = 0; s < 2; ++s) {
      if (held[s].size() >= 3) continue;
      if (FrameLease f = multi.sensor(s).next(std::chrono::milliseconds(20))) {
        held[s].push_back(std::move(f));
      }
    }
  }
  for (auto& t : senders) t.join();
  for (std::size_t s = 0; s < 2; ++s) {
    REQUIRE(held[s].size() >= 3);
    for (const FrameLease& f : held[s]) {
      CHECK(f->sensor_index == s);
      CHECK(f->sensor_name == config.sensors[s].name);
    }
  }
  held[0].clear();
  held[1].clear();
  multi.stop();
  CHECK(multi.wait_for(10'000));
}

TEST_CASE("multi pipeline: a port in use fails start() with a clear error", "[multi][udp]") {
  const std::uint16_t port = test::free_port();
  MultiPipelineConfig config;
  config.bind_address = "127.0.0.1";
  config.sensors = {parse_sensor_spec("a=127.0.0.2:" + std::to_string(port))};
  config.sensors[0].position_port = 0;
  MultiPipeline first(config);
  first.start();
  MultiPipeline second(config);
  CHECK_THROWS_WITH(second.start(), Catch::Contains("is already in use"));
  CHECK(second.wait_for(0));  // never started: nothing to wait for
  first.stop();
  CHECK(first.wait_for(10'000));
}
