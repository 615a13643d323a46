// viz::McapRecorder: the Foxglove channels of a capture's labelled frames in an MCAP file
// (read back by the small reader; @mcap/core reads the CLI's files in the node tests).
#include <catch2/catch.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "allocation_counter.hpp"
#include "labelled_frames.hpp"
#include "mini_reader.hpp"
#include "vlpground/viz/mcap_recorder.hpp"

namespace fs = std::filesystem;
using namespace vlpground;
using namespace vlpground::test::mcap;

namespace {
std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() /
          ("vlpground_recorder_" + std::to_string(::getpid()) + "_" + name))
      .string();
}
}  // namespace

TEST_CASE("mcap recorder: one message per frame on each frame channel, schemas in the file",
          "[mcap]") {
  const auto frames = test::labelled_frames("urban_demo.pcap");
  REQUIRE(frames.size() >= 3);
  const std::string path = temp_path("urban.mcap");
  viz::FrameEncoder reference;  // the channels the recorder must declare
  {
    viz::McapRecorder recorder(path);
    for (const auto& f : frames) recorder.record(*f);
    recorder.record_status(PipelineStats{});
    recorder.close();
    CHECK(recorder.frames_recorded() == frames.size());
  }
  const auto file = read_file(path);
  fs::remove(path);

  std::map<std::uint16_t, std::string> topic_of;
  int schemas = 0;
  for (const Record& r : split_records(std::span(file).subspan(8), 8)) {
    if (r.opcode == 0x0F) break;  // DataEnd: the summary repeats schemas and channels
    if (r.opcode == 0x03) {
      Fields s(r.body);
      const std::uint16_t id = s.u16();
      const std::string name = s.string(), encoding = s.string();
      const auto data = s.bytes32();
      const auto& spec = reference.channels().at(static_cast<std::size_t>(id - 1));
      CHECK(name == spec.schema_name);
      CHECK(encoding == spec.schema_encoding);
      CHECK(std::string(reinterpret_cast<const char*>(data.data()), data.size()) == spec.schema);
      ++schemas;
    }
    if (r.opcode == 0x04) {
      Fields c(r.body);
      const std::uint16_t id = c.u16();
      c.u16();
      topic_of[id] = c.string();
      CHECK(c.string() == reference.channels().at(id).message_encoding);
    }
  }
  CHECK(schemas == static_cast<int>(reference.channels().size()));

  int chunks = 0;
  const auto messages = stream_messages(file, &chunks);
  CHECK(chunks == static_cast<int>(frames.size()) + 1);  // one per frame, one for the status
  std::map<std::string, std::size_t> count;
  for (const Message& m : messages) ++count[topic_of.at(m.channel_id)];
  CHECK(count["/vlpground/points"] == frames.size());
  CHECK(count["/vlpground/ground"] == frames.size());
  CHECK(count["/vlpground/range_image"] == frames.size());
  CHECK(count["/vlpground/status"] == 1);
  // Frame messages are stamped with their frame's first firing; the status with the last frame.
  const auto first = static_cast<std::uint64_t>(frames.front()->frame.meta.first_time_ns);
  const auto last = static_cast<std::uint64_t>(frames.back()->frame.meta.first_time_ns);
  CHECK(messages.front().log_time == first);
  CHECK(messages.back().log_time == last);
}

TEST_CASE("mcap recorder: a status before the first frame is not recorded", "[mcap]") {
  const std::string path = temp_path("status.mcap");
  {
    viz::McapRecorder recorder(path);
    recorder.record_status(PipelineStats{});
  }
  const auto file = read_file(path);
  fs::remove(path);
  CHECK(stream_messages(file).empty());
}

TEST_CASE("mcap recorder: no allocation per frame once warm", "[mcap]") {
  if (test::allocation_count() < 0) {
    WARN("skipped: allocations are not counted under AddressSanitizer");
    return;
  }
  const auto frames = test::labelled_frames("urban_demo.pcap");
  const std::string path = temp_path("alloc.mcap");
  viz::McapRecorder recorder(path);
  for (int pass = 0; pass < 2; ++pass) {
    for (const auto& f : frames) recorder.record(*f);  // warm-up
  }
  const long before = test::allocation_count();
  for (int pass = 0; pass < 3; ++pass) {
    for (const auto& f : frames) recorder.record(*f);
  }
  CHECK(test::allocation_count() - before == 0);
  recorder.close();
  fs::remove(path);
}

TEST_CASE("mcap recorder: a file that cannot be created is a clear error", "[mcap]") {
  CHECK_THROWS_WITH(viz::McapRecorder("/nonexistent-dir/x.mcap"),
                    Catch::Contains("/nonexistent-dir/x.mcap"));
}
