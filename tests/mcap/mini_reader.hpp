// A small MCAP reader for the writer's tests: splits a file into records, decompresses
// chunks (zstd, lz4 frame) and decodes the fields the tests check. Independent of the writer's
// code on purpose (only the spec in common); the reference reader runs in the node tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace vlpground::test::mcap {

struct Record {
  std::uint8_t opcode = 0;
  std::uint64_t offset = 0;  // of the opcode in the file (or in the chunk's records)
  std::span<const std::byte> body;
  [[nodiscard]] std::uint64_t total_length() const { return 9 + body.size(); }
};

/// Reads fields of a record body in order; throws std::runtime_error on overrun.
class Fields {
 public:
  explicit Fields(std::span<const std::byte> body) : body_(body) {}
  std::uint8_t u8();
  std::uint16_t u16();
  std::uint32_t u32();
  std::uint64_t u64();
  std::string string();
  std::span<const std::byte> bytes32();
  std::span<const std::byte> bytes64();
  std::span<const std::byte> rest();
  [[nodiscard]] bool done() const { return pos_ == body_.size(); }

 private:
  std::span<const std::byte> take(std::size_t n);
  std::span<const std::byte> body_;
  std::size_t pos_ = 0;
};

/// Records from `offset` until the data ends or a record is cut short (not returned).
std::vector<Record> split_records(std::span<const std::byte> data, std::uint64_t offset = 0);

std::vector<std::byte> read_file(const std::string& path);

/// Chunk body -> uncompressed records; throws on CRC mismatch or unknown compression.
std::vector<std::byte> chunk_records(std::span<const std::byte> chunk_body);

std::uint32_t crc32(std::span<const std::byte> bytes);

struct Message {
  std::uint16_t channel_id;
  std::uint32_t sequence;
  std::uint64_t log_time, publish_time;
  std::vector<std::byte> data;
};

/// Streams the file from the start like a sequential reader: every message of every complete
/// chunk (stops at the first incomplete record). `chunks` counts complete chunks.
std::vector<Message> stream_messages(std::span<const std::byte> file, int* chunks = nullptr);

}  // namespace vlpground::test::mcap
