// vlpground::mcap::Writer against the MCAP spec, read back by an independent small reader.
#include <catch2/catch.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "allocation_counter.hpp"
#include "mini_reader.hpp"
#include "vlpground/mcap/writer.hpp"

namespace fs = std::filesystem;
using namespace vlpground::mcap;
using namespace vlpground::test::mcap;

namespace {

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("vlpground_mcap_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::vector<std::byte> payload(std::size_t n, int seed) {
  std::vector<std::byte> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = std::byte(static_cast<std::uint8_t>((i * 7 + static_cast<std::size_t>(seed)) % 251));
  return p;
}

std::span<const std::byte> text(std::string_view s) { return std::as_bytes(std::span(s.data(), s.size())); }

// Three channels on two schemas; `frames` frames of three messages each, one chunk per frame.
struct Written {
  std::string path;
  std::vector<Message> messages;  // as written
};

Written write_sample(const std::string& name, WriterConfig config, int frames, bool flush_per_frame = true) {
  Written w{temp_path(name), {}};
  Writer writer;
  writer.open(w.path, config);
  const auto s_points = writer.add_schema("foxglove.PointCloud", "protobuf", text("descriptor-set"));
  const auto s_status = writer.add_schema("vlpground.Status", "jsonschema", text(R"({"type":"object"})"));
  const std::uint16_t ch[3] = {writer.add_channel(s_points, "/points", "protobuf"),
                               writer.add_channel(s_points, "/ground", "protobuf", {{"k", "v"}}),
                               writer.add_channel(s_status, "/status", "json")};
  std::uint32_t seq[3] = {0, 0, 0};
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t t = std::uint64_t{1'700'000'000'000'000'000} +
                              static_cast<std::uint64_t>(f) * 100'000'000 + static_cast<std::uint64_t>(c);
      auto data = payload(200 + static_cast<std::size_t>(f * 13 + c * 50), f * 3 + c);
      writer.write(ch[c], t, t + 5, data);
      w.messages.push_back({ch[c], seq[c]++, t, t + 5, data});
    }
    if (flush_per_frame) writer.flush();
  }
  writer.close();
  return w;
}

std::map<std::uint8_t, int> count_opcodes(const std::vector<Record>& records) {
  std::map<std::uint8_t, int> counts;
  for (const Record& r : records) ++counts[r.opcode];
  return counts;
}

void require_same(const std::vector<Message>& got, const std::vector<Message>& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    CHECK(got[i].channel_id == want[i].channel_id);
    CHECK(got[i].sequence == want[i].sequence);
    CHECK(got[i].log_time == want[i].log_time);
    CHECK(got[i].publish_time == want[i].publish_time);
    CHECK(got[i].data == want[i].data);
  }
}

}  // namespace

TEST_CASE("mcap writer: file layout follows the spec", "[mcap]") {
  const Written w = write_sample("layout.mcap", {}, 5);
  const auto file = read_file(w.path);
  fs::remove(w.path);
  const std::span<const std::byte> magic(file.data(), 8);
  REQUIRE(std::vector<std::byte>(magic.begin(), magic.end()) ==
          std::vector<std::byte>(file.end() - 8, file.end()));
  CHECK(magic[0] == std::byte{0x89});
  CHECK(std::string(reinterpret_cast<const char*>(file.data()) + 1, 7) == "MCAP0\r\n");

  const auto records = split_records(std::span(file).subspan(8, file.size() - 16), 8);
  REQUIRE(records.size() > 3);
  // Every byte between the magics is a record: nothing cut, nothing left over.
  CHECK(records.back().offset + records.back().total_length() == file.size() - 8);

  // Order: Header, Schemas, Channels, (Chunk, MessageIndex x3) x5, DataEnd, summary, Footer.
  std::string order;
  for (const Record& r : records) order += static_cast<char>('A' + r.opcode);
  const std::string expected = std::string("B") + "DD" + "EEE" + [] {
    std::string s;
    for (int i = 0; i < 5; ++i) s += "GHHH";
    return s;
  }() + "P" + "DD" + "EEE" + "IIIII" + "L" + "OOOO" + "C";
  CHECK(order == expected);

  Fields header(records.front().body);
  CHECK(header.string().empty());  // profile
  CHECK(header.string() == "vlpground");

  Fields footer(records.back().body);
  const std::uint64_t summary_start = footer.u64();
  const std::uint64_t summary_offset_start = footer.u64();
  const std::uint32_t summary_crc = footer.u32();
  CHECK(footer.done());
  std::size_t first_summary = 0;
  while (records[first_summary].offset != summary_start) ++first_summary;
  const Record& data_end = records[first_summary - 1];
  REQUIRE(data_end.opcode == 0x0F);  // DataEnd right before the summary
  CHECK(Fields(data_end.body).u32() == crc32(std::span(file).first(data_end.offset)));
  CHECK(records[first_summary].opcode == 0x03);
  std::size_t first_offset = 0;
  while (records[first_offset].offset != summary_offset_start) ++first_offset;
  CHECK(records[first_offset].opcode == 0x0E);
  // CRC from the summary start through the footer's summary_offset_start field.
  const std::size_t crc_end = file.size() - 8 - 4;
  CHECK(summary_crc == crc32(std::span(file).subspan(summary_start, crc_end - summary_start)));
}

TEST_CASE("mcap writer: summary offsets, chunk and message indexes point at their records",
          "[mcap]") {
  const Written w = write_sample("index.mcap", {}, 4);
  const auto file = read_file(w.path);
  fs::remove(w.path);
  const auto records = split_records(std::span(file).subspan(8, file.size() - 16), 8);
  std::map<std::uint64_t, const Record*> at;
  for (const Record& r : records) at[r.offset] = &r;

  int groups = 0;
  for (const Record& r : records) {
    if (r.opcode != 0x0E) continue;
    ++groups;
    Fields f(r.body);
    const std::uint8_t op = f.u8();
    const std::uint64_t start = f.u64(), length = f.u64();
    // The group is a run of records of that opcode, exactly `length` bytes long.
    std::uint64_t pos = start;
    while (pos < start + length) {
      REQUIRE(at.count(pos) == 1);
      CHECK(at[pos]->opcode == op);
      pos += at[pos]->total_length();
    }
    CHECK(pos == start + length);
  }
  CHECK(groups == 4);

  int chunk_indexes = 0;
  for (const Record& r : records) {
    if (r.opcode != 0x08) continue;
    ++chunk_indexes;
    Fields f(r.body);
    const std::uint64_t start_time = f.u64(), end_time = f.u64();
    const std::uint64_t chunk_offset = f.u64(), chunk_length = f.u64();
    REQUIRE(at.count(chunk_offset) == 1);
    const Record& chunk = *at[chunk_offset];
    CHECK(chunk.opcode == 0x06);
    CHECK(chunk.total_length() == chunk_length);
    Fields c(chunk.body);
    CHECK(c.u64() == start_time);
    CHECK(c.u64() == end_time);
    const auto uncompressed = chunk_records(chunk.body);

    Fields offsets(f.bytes32());
    std::uint64_t index_bytes = 0;
    int channels = 0;
    while (!offsets.done()) {
      const std::uint16_t channel = offsets.u16();
      const std::uint64_t offset = offsets.u64();
      REQUIRE(at.count(offset) == 1);
      const Record& mi = *at[offset];
      CHECK(mi.opcode == 0x07);
      index_bytes += mi.total_length();
      ++channels;
      Fields m(mi.body);
      CHECK(m.u16() == channel);
      Fields entries(m.bytes32());
      while (!entries.done()) {
        const std::uint64_t log_time = entries.u64(), msg_offset = entries.u64();
        // The offset names a Message record of this channel at this time in the chunk.
        const auto msg = split_records(std::span(uncompressed).subspan(msg_offset));
        REQUIRE_FALSE(msg.empty());
        CHECK(msg.front().opcode == 0x05);
        Fields mf(msg.front().body);
        CHECK(mf.u16() == channel);
        mf.u32();
        CHECK(mf.u64() == log_time);
      }
    }
    CHECK(channels == 3);
    CHECK(f.u64() == index_bytes);  // message_index_length
    CHECK(f.string() == "zstd");
    CHECK(f.u64() == chunk.body.size() - (8 + 8 + 8 + 4 + 4 + 4 + 8));  // compressed_size
    CHECK(f.u64() == uncompressed.size());
  }
  CHECK(chunk_indexes == 4);

  for (const Record& r : records) {
    if (r.opcode != 0x0B) continue;
    Fields s(r.body);
    CHECK(s.u64() == 12);  // messages
    CHECK(s.u16() == 2);   // schemas
    CHECK(s.u32() == 3);   // channels
    CHECK(s.u32() == 0);
    CHECK(s.u32() == 0);
    CHECK(s.u32() == 4);  // chunks
    CHECK(s.u64() == w.messages.front().log_time);
    CHECK(s.u64() == w.messages.back().log_time);
    Fields counts(s.bytes32());
    for (std::uint16_t ch = 0; ch < 3; ++ch) {
      CHECK(counts.u16() == ch);
      CHECK(counts.u64() == 4);
    }
  }
}

TEST_CASE("mcap writer: messages round-trip with each compression", "[mcap]") {
  for (const Compression c : {Compression::zstd, Compression::lz4, Compression::none}) {
    DYNAMIC_SECTION(to_string(c)) {
      WriterConfig config;
      config.compression = c;
      const Written w = write_sample("roundtrip.mcap", config, 6);
      const auto file = read_file(w.path);
      fs::remove(w.path);
      int chunks = 0;
      require_same(stream_messages(file, &chunks), w.messages);
      CHECK(chunks == 6);
    }
  }
}

TEST_CASE("mcap writer: chunks close at their size bound without flush()", "[mcap]") {
  WriterConfig config;
  config.chunk_size_bytes = 2000;  // a few messages per chunk
  const Written w = write_sample("bounded.mcap", config, 20, /*flush_per_frame=*/false);
  const auto file = read_file(w.path);
  fs::remove(w.path);
  int chunks = 0;
  require_same(stream_messages(file, &chunks), w.messages);
  CHECK(chunks > 10);
  for (const Record& r : split_records(std::span(file).subspan(8), 8)) {
    if (r.opcode == 0x06) CHECK(chunk_records(r.body).size() < 2000 + 1000);
  }
}

TEST_CASE("mcap writer: a file cut at any byte reads up to its last complete chunk", "[mcap]") {
  const Written w = write_sample("cut.mcap", {}, 8);
  const auto file = read_file(w.path);
  fs::remove(w.path);
  // Where each chunk's records end (a cut at or after it keeps that chunk's frame).
  std::vector<std::uint64_t> chunk_ends;
  for (const Record& r : split_records(std::span(file).subspan(8), 8)) {
    if (r.opcode == 0x06) chunk_ends.push_back(r.offset + r.total_length());
  }
  REQUIRE(chunk_ends.size() == 8);
  for (std::size_t cut = 0; cut <= file.size(); ++cut) {
    const std::size_t complete = static_cast<std::size_t>(
        std::upper_bound(chunk_ends.begin(), chunk_ends.end(), cut) - chunk_ends.begin());
    int chunks = -1;
    const auto got = stream_messages(std::span(file).first(cut), &chunks);
    REQUIRE(chunks == static_cast<int>(complete));
    REQUIRE(got.size() == complete * 3);
  }
}

TEST_CASE("mcap writer: no allocation per message after warm-up", "[mcap]") {
  if (vlpground::test::allocation_count() < 0) {
    WARN("skipped: allocations are not counted under AddressSanitizer");
    return;
  }
  const std::string path = temp_path("alloc.mcap");
  Writer writer;
  writer.open(path, {});
  const auto schema = writer.add_schema("s", "jsonschema", text("{}"));
  const auto a = writer.add_channel(schema, "/a", "json");
  const auto b = writer.add_channel(schema, "/b", "json");
  const auto big = payload(300'000, 1);
  const auto small = payload(100, 2);
  std::uint64_t t = 1;
  auto frame = [&] {
    writer.write(a, t, t, big);
    writer.write(b, t, t, small);
    ++t;
    writer.flush();
  };
  for (int i = 0; i < 3; ++i) frame();  // warm-up
  const long before = vlpground::test::allocation_count();
  for (int i = 0; i < 200; ++i) frame();
  CHECK(vlpground::test::allocation_count() - before == 0);
  writer.close();
  fs::remove(path);
}

TEST_CASE("mcap writer: errors are clear", "[mcap]") {
  Writer writer;
  CHECK_THROWS_WITH(writer.open("/nonexistent-dir/x.mcap"),
                    Catch::Contains("/nonexistent-dir/x.mcap"));
  WriterConfig bad;
  bad.chunk_size_bytes = 0;
  CHECK_THROWS_AS(bad.validate(), std::invalid_argument);
  CHECK_THROWS_AS(writer.write(0, 0, 0, {}), std::logic_error);

  const std::string path = temp_path("errors.mcap");
  writer.open(path);
  CHECK_THROWS_AS(writer.add_channel(7, "/x", "json"), std::invalid_argument);
  CHECK_THROWS_AS(writer.write(3, 0, 0, {}), std::invalid_argument);
  writer.close();
  writer.close();  // idempotent
  CHECK_FALSE(writer.is_open());
  // An empty file (no message) is still valid: magic, header, data end, summary, footer.
  const auto file = read_file(path);
  fs::remove(path);
  const auto counts = count_opcodes(split_records(std::span(file).subspan(8, file.size() - 16), 8));
  CHECK(counts.at(0x01) == 1);
  CHECK(counts.at(0x0F) == 1);
  CHECK(counts.at(0x0B) == 1);
  CHECK(counts.at(0x02) == 1);
  CHECK(counts.count(0x06) == 0);

  CHECK(parse_compression("zstd") == Compression::zstd);
  CHECK(parse_compression("lz4") == Compression::lz4);
  CHECK(parse_compression("none") == Compression::none);
  CHECK_FALSE(parse_compression("gzip").has_value());
}

TEST_CASE("mcap writer: a write error is reported once, then the writer refuses", "[mcap]") {
  if (!fs::exists("/dev/full")) {
    WARN("skipped: no /dev/full");
    return;
  }
  Writer writer;
  CHECK_THROWS_WITH(writer.open("/dev/full"), Catch::Contains("No space left on device"));
  CHECK_THROWS_WITH(writer.add_schema("s", "jsonschema", text("{}")),
                    Catch::Contains("earlier write error"));
  CHECK_NOTHROW(writer.close());  // no summary after a torn record; nothing else to do
  CHECK_FALSE(writer.is_open());
}
