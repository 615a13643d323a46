// FrameEncoder: every channel decodes with its own schema alone, carries what the frame
// holds (points and labels in CSV order, the planes, the range image, the status), and
// encoding allocates nothing once warm.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "allocation_counter.hpp"
#include "labelled_frames.hpp"
#include "schema_decoder.hpp"
#include "vlpground/viz/channels.hpp"

using namespace vlpground;
using namespace vlpground::test;
using viz::FrameEncoder;

namespace {

struct Message {
  std::int64_t log_time_ns = 0;
  std::string bytes;
  [[nodiscard]] std::span<const std::byte> span() const {
    return std::as_bytes(std::span{bytes.data(), bytes.size()});
  }
};

std::map<std::size_t, Message> encode_all(FrameEncoder& encoder, const LabelledFrame& f) {
  std::map<std::size_t, Message> out;
  encoder.encode(f, [&](std::size_t channel, std::int64_t t, std::span<const std::byte> b) {
    out[channel] = {t, std::string(reinterpret_cast<const char*>(b.data()), b.size())};
  });
  return out;
}

std::uint8_t label_at(const GroundResult& g, int layer, int ring, int col) {
  return g.label[layer][static_cast<std::size_t>(ring) * static_cast<std::size_t>(g.stride) +
                        static_cast<std::size_t>(col)];
}

}  // namespace

TEST_CASE("the channels are the four of docs/foxglove.md, each with a usable schema") {
  FrameEncoder encoder;
  const auto& ch = encoder.channels();
  REQUIRE(ch.size() == viz::kChannelCount);
  CHECK(ch[viz::kPointsChannel].topic == "/vlpground/points");
  CHECK(ch[viz::kPointsChannel].schema_name == "foxglove.PointCloud");
  CHECK(ch[viz::kGroundChannel].topic == "/vlpground/ground");
  CHECK(ch[viz::kGroundChannel].schema_name == "foxglove.SceneUpdate");
  CHECK(ch[viz::kRangeImageChannel].topic == "/vlpground/range_image");
  CHECK(ch[viz::kRangeImageChannel].schema_name == "foxglove.RawImage");
  CHECK(ch[viz::kStatusChannel].topic == "/vlpground/status");
  CHECK(ch[viz::kStatusChannel].message_encoding == "json");
  CHECK(nlohmann::json::parse(ch[viz::kStatusChannel].schema)["type"] == "object");
  for (std::size_t i = 0; i < viz::kStatusChannel; ++i) {
    CHECK(ch[i].message_encoding == "protobuf");
    CHECK(ch[i].schema_encoding == "protobuf");
    CHECK_NOTHROW(SchemaDecoder(ch[i]));
  }
}

TEST_CASE("bad encoder configuration is refused with the field's name") {
  viz::FrameEncoderConfig c;
  c.topic_prefix = "vlpground";
  CHECK_THROWS_WITH(FrameEncoder(c), Catch::Contains("topic_prefix"));
  c = {};
  c.frame_id.clear();
  CHECK_THROWS_WITH(FrameEncoder(c), Catch::Contains("frame_id"));
}

TEST_CASE("points: every valid return with its label, in CSV order, placed by the extrinsics") {
  const auto frames = labelled_frames("urban_demo.pcap");
  REQUIRE(frames.size() >= 3);
  viz::FrameEncoderConfig config;
  config.extrinsics = {0.5, 0.0, 1.8, 0.0, 0.0, 90.0};
  FrameEncoder encoder(config);
  SchemaDecoder decoder(encoder.channels()[viz::kPointsChannel]);
  const LabelledFrame& lf = *frames[1];
  const auto messages = encode_all(encoder, lf);
  const auto cloud = decoder.decode(messages.at(viz::kPointsChannel).span());
  CHECK(messages.at(viz::kPointsChannel).log_time_ns == lf.frame.meta.first_time_ns);

  CHECK(text(*cloud, "frame_id") == "vehicle");
  const auto& pose = sub(*cloud, "pose");
  CHECK(real(sub(pose, "position"), "z") == Approx(1.8));
  CHECK(real(sub(pose, "orientation"), "z") == Approx(std::sqrt(0.5)));  // 90 deg yaw
  CHECK(real(sub(pose, "orientation"), "w") == Approx(std::sqrt(0.5)));
  REQUIRE(u32(*cloud, "point_stride") == 16);
  std::vector<std::string> names;
  for (int i = 0; i < count(*cloud, "fields"); ++i) names.push_back(text(at(*cloud, "fields", i), "name"));
  CHECK(names == std::vector<std::string>{"x", "y", "z", "intensity", "ring", "label", "return"});

  const std::string data = text(*cloud, "data");
  const Frame& f = lf.frame;
  std::size_t n = 0, ground = 0;
  for (int col = 0; col < f.columns(); ++col) {
    for (int laser = 0; laser < kLasers; ++laser) {
      const int ring = static_cast<int>(std::find(f.laser_of_ring, f.laser_of_ring + kLasers, laser) -
                                        f.laser_of_ring);
      const std::size_t cell = f.index(ring, col);
      if (f.layer[0].valid[cell] == 0) continue;
      REQUIRE((n + 1) * 16 <= data.size());
      float xyz[3];
      std::memcpy(xyz, data.data() + n * 16, sizeof xyz);
      const auto* b = reinterpret_cast<const std::uint8_t*>(data.data() + n * 16 + 12);
      REQUIRE(xyz[0] == f.layer[0].x_m[cell]);
      REQUIRE(xyz[2] == f.layer[0].z_m[cell]);
      REQUIRE(b[0] == f.layer[0].intensity[cell]);
      REQUIRE(b[1] == ring);
      REQUIRE(b[2] == label_at(lf.ground, 0, ring, col));
      REQUIRE(b[3] == 0);
      ground += b[2] == 1 ? 1u : 0u;
      ++n;
    }
  }
  CHECK(data.size() == n * 16);
  CHECK(ground == lf.ground.ground_returns);
  CHECK(ground > n / 4);
}

TEST_CASE("points of a dual-return frame carry both returns, tagged") {
  const auto frames = labelled_frames("slope_dual.pcap");
  REQUIRE_FALSE(frames.empty());
  FrameEncoder encoder;
  SchemaDecoder decoder(encoder.channels()[viz::kPointsChannel]);
  const auto cloud = decoder.decode(encode_all(encoder, *frames[0]).at(0).span());
  const std::string data = text(*cloud, "data");
  std::size_t per_layer[2] = {};
  for (std::size_t i = 0; i < data.size() / 16; ++i) ++per_layer[static_cast<std::uint8_t>(data[i * 16 + 15])];
  const auto valid = [&](int l) {
    return static_cast<std::size_t>(std::count(frames[0]->frame.layer[l].valid.begin(),
                                               frames[0]->frame.layer[l].valid.end(), 1));
  };
  CHECK(per_layer[0] == valid(0));
  CHECK(per_layer[1] == valid(1));
  CHECK(per_layer[1] > 0);
}

TEST_CASE("ground: each segment's plane patch over its cell, outlines, and the frame number") {
  const auto frames = labelled_frames("urban_demo.pcap");
  FrameEncoder encoder;
  SchemaDecoder decoder(encoder.channels()[viz::kGroundChannel]);
  const LabelledFrame& lf = *frames[1];
  const auto update = decoder.decode(encode_all(encoder, lf).at(viz::kGroundChannel).span());
  REQUIRE(count(*update, "entities") == 1);
  const auto& entity = at(*update, "entities", 0);
  CHECK(text(entity, "id") == "ground");
  REQUIRE(count(entity, "triangles") == 4);
  REQUIRE(count(entity, "lines") == 4);
  std::map<std::string, std::string> meta;
  for (int i = 0; i < count(entity, "metadata"); ++i)
    meta[text(at(entity, "metadata", i), "key")] = text(at(entity, "metadata", i), "value");
  CHECK(meta["frame"] == std::to_string(lf.frame.meta.sequence));
  CHECK(meta["delivered"] == "1");
  CHECK(meta["detect_ms"] == "1.500");
  CHECK(meta["ground_returns"] == std::to_string(lf.ground.ground_returns));
  int green = 0;
  for (int s = 0; s < 4; ++s) {
    const GroundSegment& g = lf.ground.segments[static_cast<std::size_t>(s)];
    const auto& patch = at(entity, "triangles", s);
    REQUIRE(count(patch, "points") == 4);
    CHECK(count(patch, "indices") == 6);
    for (int i = 0; i < 4; ++i) {
      const auto& p = at(patch, "points", i);
      const double x = real(p, "x"), y = real(p, "y"), z = real(p, "z");
      CHECK((x == Approx(g.x_min_m) || x == Approx(g.x_max_m)));
      CHECK((y == Approx(g.y_min_m) || y == Approx(g.y_max_m)));
      CHECK(g.plane.nx * x + g.plane.ny * y + g.plane.nz * z + g.plane.d == Approx(0).margin(1e-4));
    }
    const auto& colour = sub(patch, "color");
    if (g.has_ground) {
      ++green;
      CHECK(real(colour, "g") > real(colour, "r"));
      CHECK(real(colour, "a") > 0);
    }
    const auto& outline = at(entity, "lines", s);
    CHECK(outline.GetReflection()->GetEnumValue(outline, field(outline, "type")) == 1);  // loop
  }
  CHECK(green >= 2);
}

TEST_CASE("range image: 16 x N rgb8, top row the highest ring, ground green, obstacles red") {
  const auto frames = labelled_frames("urban_demo.pcap");
  FrameEncoder encoder;
  SchemaDecoder decoder(encoder.channels()[viz::kRangeImageChannel]);
  const LabelledFrame& lf = *frames[1];
  const auto image = decoder.decode(encode_all(encoder, lf).at(viz::kRangeImageChannel).span());
  const auto width = static_cast<std::size_t>(lf.frame.columns());
  CHECK(u32(*image, "width") == width);
  CHECK(u32(*image, "height") == 16);
  CHECK(text(*image, "encoding") == "rgb8");
  CHECK(u32(*image, "step") == width * 3);
  const std::string data = text(*image, "data");
  REQUIRE(data.size() == width * 3 * 16);
  int checked = 0;
  for (int row = 0; row < 16; ++row) {
    const int ring = 15 - row;
    for (std::size_t col = 0; col < width; col += 7) {
      const auto* px = reinterpret_cast<const std::uint8_t*>(data.data() + (static_cast<std::size_t>(row) * width + col) * 3);
      if (lf.frame.layer[0].valid[lf.frame.index(ring, static_cast<int>(col))] == 0) {
        CHECK((px[0] | px[1] | px[2]) == 0);
        continue;
      }
      const auto label = label_at(lf.ground, 0, ring, static_cast<int>(col));
      if (label == 1) CHECK(px[1] > px[0]);
      if (label == 2) CHECK(px[0] > px[1]);
      ++checked;
    }
  }
  CHECK(checked > 100);
}

TEST_CASE("status: counters, the frame rate between calls, and the GPS state") {
  FrameEncoder encoder;
  PipelineStats s;
  s.frames_delivered = 10;
  s.elapsed_s = 1.0;
  s.detect.p50_ms = 4.0;
  std::string last;
  const viz::MessageSink keep = [&](std::size_t channel, std::int64_t t, std::span<const std::byte> b) {
    CHECK(channel == viz::kStatusChannel);
    CHECK(t == 123);
    last.assign(reinterpret_cast<const char*>(b.data()), b.size());
  };
  encoder.encode_status(s, 123, keep);
  auto j = nlohmann::json::parse(last);
  CHECK(j["frames"]["delivered"] == 10);
  CHECK(j["frame_rate_hz"].get<double>() == Approx(10.0));  // the first: since the start
  CHECK(j["gps"]["pps"] == "absent");
  s.frames_delivered = 20;
  s.elapsed_s = 3.0;
  PositionPacket p;
  p.pps = PpsStatus::locked;
  p.gprmc.parsed = p.gprmc.valid = true;
  p.gprmc.latitude_deg = 37.5;
  encoder.note_position(p);
  encoder.encode_status(s, 123, keep);
  j = nlohmann::json::parse(last);
  CHECK(j["frame_rate_hz"].get<double>() == Approx(5.0));  // 10 frames in 2 s
  CHECK(j["detect"]["p50_ms"] == 4.0);
  CHECK(j["gps"]["pps"] == "locked");
  CHECK(j["gps"]["gprmc"] == "valid");
  CHECK(j["gps"]["latitude_deg"] == 37.5);
}

TEST_CASE("encoding allocates nothing once warm") {
  if (allocation_count() < 0) {
    WARN("skipped: allocations are not counted under AddressSanitizer");
    return;
  }
  const auto frames = labelled_frames("urban_demo.pcap");
  FrameEncoder encoder;
  std::size_t bytes = 0;
  const viz::MessageSink sink = [&bytes](std::size_t, std::int64_t, std::span<const std::byte> b) {
    bytes += b.size();
  };
  for (const auto& f : frames) encoder.encode(*f, sink);  // warm-up: the largest frame
  const long before = allocation_count();
  for (int pass = 0; pass < 3; ++pass)
    for (const auto& f : frames) encoder.encode(*f, sink);
  CHECK(allocation_count() - before == 0);
  CHECK(bytes > 0);
}
