// Ros2Publisher against an in-process subscriber written with the generated types only.
#include <pthread.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "../outputs/labelled_frame.hpp"
#include "allocation_counter.hpp"
#include "cloud_reader.hpp"
#include "dds_loopback.hpp"
#include "vlpground/outputs/pointcloud2.hpp"
#include "vlpground/ros2/publisher.hpp"

using namespace vlpground;
using test::CloudReader;
using test::ReaderQos;
using test::ReceivedCloud;

namespace {

constexpr int kTimeoutMs = 10000;

ros2::Ros2Config config_for(const std::string& topic) {
  ros2::Ros2Config c;
  c.domain_id = test::confine_dds_to_loopback();
  c.topic = topic;
  c.capacity_columns = 64;
  return c;
}

}  // namespace

TEST_CASE("ROS 2 names and config checks") {
  CHECK(ros2::dds_topic_name("/vlpground/points") == "rt/vlpground/points");
  CHECK(ros2::parse_qos_profile("reliable") == ros2::QosProfile::reliable);
  CHECK(ros2::parse_qos_profile("sensor-data") == ros2::QosProfile::sensor_data);
  CHECK_THROWS_WITH(ros2::parse_qos_profile("best"), Catch::Contains("reliable or sensor-data"));
  ros2::Ros2Config c;
  CHECK_NOTHROW(c.validate());
  CHECK(c.topic == "/vlpground/points");
  CHECK(c.frame_id == "velodyne");
  CHECK(c.domain_id == 0);
  CHECK(c.qos == ros2::QosProfile::reliable);
  for (const char* bad : {"points", "/a//b", "/a/", "/1a", "/a b", "/"}) {
    c.topic = bad;
    CHECK_THROWS_WITH(c.validate(), Catch::Contains("absolute ROS 2 name"));
  }
  c = {};
  c.ground_topic = c.topic;
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("differ"));
  c = {};
  c.domain_id = 233;
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("0..232"));
  c = {};
  c.frame_id.clear();
  CHECK_THROWS_WITH(c.validate(), Catch::Contains("frame_id"));
}

TEST_CASE("A reliable subscriber receives the organized cloud with stamp, frame id and layout") {
  auto config = config_for("/vlpground/points");
  config.frame_id = "lidar_top";
  ros2::Ros2Publisher publisher(config);
  CloudReader reader(config.domain_id, "rt/vlpground/points", ReaderQos::reliable);
  REQUIRE(publisher.wait_for_subscribers(1, kTimeoutMs));

  const std::int64_t t0 = 1'700'000'000'123'456'789;
  test::LabelledTestFrame in(12, ReturnMode::dual, t0);
  publisher.publish(in.frame, in.ground);
  REQUIRE(publisher.finish(kTimeoutMs));

  ReceivedCloud cloud;
  REQUIRE(reader.take(cloud, kTimeoutMs));
  CHECK(cloud.sec == 1'700'000'000);
  CHECK(cloud.nanosec == 123'456'789u);
  CHECK(cloud.frame_id == "lidar_top");
  CHECK(cloud.height == 32);
  CHECK(cloud.width == 12);
  CHECK(cloud.point_step == 24);
  CHECK(cloud.row_step == 12 * 24);
  CHECK_FALSE(cloud.is_dense);
  CHECK_FALSE(cloud.is_bigendian);
  REQUIRE(cloud.fields.size() == outputs::kPointFields.size());
  for (std::size_t i = 0; i < cloud.fields.size(); ++i) {
    CHECK(cloud.fields[i].name == outputs::kPointFields[i].name);
    CHECK(cloud.fields[i].offset == outputs::kPointFields[i].offset);
    CHECK(cloud.fields[i].datatype == static_cast<std::uint8_t>(outputs::kPointFields[i].datatype));
    CHECK(cloud.fields[i].count == 1);
  }
  std::vector<std::uint8_t> expected(outputs::max_cloud_bytes(in.frame));
  const auto shape =
      outputs::encode_pointcloud2(in.frame, in.ground, outputs::CloudKind::organized, expected);
  expected.resize(shape.bytes());
  CHECK(cloud.data == expected);  // NaN cells compare equal bytewise
  const auto stats = publisher.stats();
  CHECK(stats.frames_offered == 1);
  CHECK(stats.frames_published == 1);
  CHECK(stats.write_errors == 0);
}

TEST_CASE("A best-effort subscriber also receives from the reliable publisher") {
  auto config = config_for("/vlpground/best_effort_points");
  ros2::Ros2Publisher publisher(config);
  CloudReader reader(config.domain_id, "rt/vlpground/best_effort_points", ReaderQos::best_effort);
  REQUIRE(publisher.wait_for_subscribers(1, kTimeoutMs));
  test::LabelledTestFrame in(8, ReturnMode::strongest, 0);
  publisher.publish(in.frame, in.ground);
  REQUIRE(publisher.finish(kTimeoutMs));
  ReceivedCloud cloud;
  REQUIRE(reader.take(cloud, kTimeoutMs));
  CHECK(cloud.height == 16);
  CHECK(cloud.width == 8);
}

TEST_CASE("sensor-data (best effort) does not match a reliable subscriber, as in ROS 2") {
  auto config = config_for("/vlpground/sensor_points");
  config.qos = ros2::QosProfile::sensor_data;
  ros2::Ros2Publisher publisher(config);
  CloudReader reliable(config.domain_id, "rt/vlpground/sensor_points", ReaderQos::reliable);
  CHECK(reliable.wait_incompatible_qos(kTimeoutMs));
  CHECK(publisher.stats().matched_subscribers == 0);
  CloudReader best_effort(config.domain_id, "rt/vlpground/sensor_points", ReaderQos::best_effort);
  CHECK(publisher.wait_for_subscribers(1, kTimeoutMs));
}

TEST_CASE("Ground-only and obstacle-only topics carry dense clouds") {
  auto config = config_for("/vlpground/all");
  config.ground_topic = "/vlpground/ground";
  config.obstacle_topic = "/vlpground/obstacles";
  ros2::Ros2Publisher publisher(config);
  CloudReader ground(config.domain_id, "rt/vlpground/ground", ReaderQos::reliable);
  CloudReader obstacles(config.domain_id, "rt/vlpground/obstacles", ReaderQos::reliable);
  REQUIRE(ground.wait_matched(kTimeoutMs));
  REQUIRE(obstacles.wait_matched(kTimeoutMs));
  test::LabelledTestFrame in(10, ReturnMode::strongest, 0);
  publisher.publish(in.frame, in.ground);
  REQUIRE(publisher.finish(kTimeoutMs));
  std::uint32_t counts[3] = {0, 0, 0};
  for (int r = 0; r < kLasers; ++r)
    for (int c = 0; c < 10; ++c) ++counts[in.label(0, r, c)];
  for (auto& [reader, label] : {std::pair{&ground, 1}, std::pair{&obstacles, 2}}) {
    ReceivedCloud cloud;
    REQUIRE(reader->take(cloud, kTimeoutMs));
    CHECK(cloud.height == 1);
    CHECK(cloud.width == counts[label]);
    CHECK(cloud.is_dense);
    REQUIRE(cloud.data.size() == cloud.width * 24u);
    for (std::size_t i = 0; i < cloud.width; ++i) CHECK(cloud.data[i * 24 + 18] == label);
  }
}

TEST_CASE("publish() allocates nothing after warm-up and never waits for a subscriber") {
  auto config = config_for("/vlpground/nobody_listens");
  ros2::Ros2Publisher publisher(config);  // no subscriber at all
  test::LabelledTestFrame in(64, ReturnMode::dual, 0);
  publisher.publish(in.frame, in.ground);  // warm-up
  const long before = test::allocation_count();
  constexpr int kFrames = 200;
  for (int k = 0; k < kFrames; ++k) publisher.publish(in.frame, in.ground);
  const long after = test::allocation_count();
  if (before >= 0) CHECK(after == before);  // counts every thread, the publisher's included
  REQUIRE(publisher.finish(kTimeoutMs));
  const auto stats = publisher.stats();
  CHECK(stats.frames_offered == kFrames + 1);
  // Every frame was either written or replaced by a newer one while the thread was busy.
  CHECK(stats.frames_published + stats.frames_skipped == kFrames + 1);
  CHECK(stats.write_errors == 0);
  CHECK_THROWS_AS(publisher.publish(in.frame, in.ground), std::logic_error);
}

TEST_CASE("The publisher's threads (DDS's included) leave SIGINT and SIGTERM to the application") {
  auto config = config_for("/vlpground/signals");
  const auto tid_of = [](const std::filesystem::path& task) { return task.filename().string(); };
  std::set<std::string> before;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    before.insert(tid_of(task.path()));
  }
  // The creating thread leaves both signals unblocked (threads would inherit that)...
  sigset_t wanted;
  sigemptyset(&wanted);
  sigaddset(&wanted, SIGINT);
  sigaddset(&wanted, SIGTERM);
  sigset_t old;
  REQUIRE(pthread_sigmask(SIG_UNBLOCK, &wanted, &old) == 0);
  ros2::Ros2Publisher publisher(config);
  // ... and still does afterwards.
  sigset_t now;
  REQUIRE(pthread_sigmask(SIG_SETMASK, &old, &now) == 0);
  CHECK(sigismember(&now, SIGINT) == 0);
  CHECK(sigismember(&now, SIGTERM) == 0);
  int new_threads = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    if (before.count(tid_of(task.path())) != 0) continue;
    std::ifstream status(task.path() / "status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("SigBlk:", 0) != 0) continue;
      const unsigned long long blocked = std::stoull(line.substr(7), nullptr, 16);
      INFO("thread " << tid_of(task.path()) << " " << line);
      CHECK(((blocked >> (SIGINT - 1)) & 1ULL) == 1ULL);
      CHECK(((blocked >> (SIGTERM - 1)) & 1ULL) == 1ULL);
      ++new_threads;
    }
  }
  CHECK(new_threads >= 2);  // the publisher thread and Cyclone's own
}

TEST_CASE("WhenBusy::wait loses no frame to a reliable subscriber") {
  auto config = config_for("/vlpground/every_frame");
  config.when_busy = ros2::WhenBusy::wait;
  ros2::Ros2Publisher publisher(config);
  CloudReader reader(config.domain_id, "rt/vlpground/every_frame", ReaderQos::reliable);
  REQUIRE(publisher.wait_for_subscribers(1, kTimeoutMs));
  constexpr int kFrames = 30;
  for (int k = 0; k < kFrames; ++k) {
    test::LabelledTestFrame in(40 + k, ReturnMode::strongest, k * 100'000'000LL);
    publisher.publish(in.frame, in.ground);
  }
  REQUIRE(publisher.finish(kTimeoutMs));
  CHECK(publisher.stats().frames_skipped == 0);
  CHECK(publisher.stats().frames_published == kFrames);
  for (int k = 0; k < kFrames; ++k) {
    ReceivedCloud cloud;
    REQUIRE(reader.take(cloud, kTimeoutMs));
    CHECK(cloud.width == static_cast<std::uint32_t>(40 + k));  // in order, none missing
  }
}
