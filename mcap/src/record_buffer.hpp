// Appends MCAP record fields (little-endian integers, length-prefixed strings, bytes, maps)
// to a byte vector. Growth is amortised; a cleared vector keeps its capacity, so steady-state
// appends do not allocate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

namespace vlpground::mcap::detail {

// MCAP opcodes (spec: "Records").
enum class Opcode : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  statistics = 0x0B,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

inline constexpr std::byte kMagic[8] = {std::byte{0x89}, std::byte{'M'}, std::byte{'C'},
                                        std::byte{'A'},  std::byte{'P'}, std::byte{'0'},
                                        std::byte{'\r'}, std::byte{'\n'}};
// opcode (1) + record length (8)
inline constexpr std::size_t kRecordPrefixBytes = 9;

class RecordBuffer {
 public:
  explicit RecordBuffer(std::vector<std::byte>& out) : out_(out) {}

  void u8(std::uint8_t v) { out_.push_back(std::byte{v}); }
  void u16(std::uint16_t v) { little_endian(v, 2); }
  void u32(std::uint32_t v) { little_endian(v, 4); }
  void u64(std::uint64_t v) { little_endian(v, 8); }
  void raw(std::span<const std::byte> bytes) { out_.insert(out_.end(), bytes.begin(), bytes.end()); }
  /// uint32 length + UTF-8 bytes.
  void string(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(std::as_bytes(std::span(s.data(), s.size())));
  }
  /// uint32 length + bytes.
  void bytes32(std::span<const std::byte> bytes) {
    u32(static_cast<std::uint32_t>(bytes.size()));
    raw(bytes);
  }

  /// Writes the opcode and a placeholder length; end_record() patches it.
  std::size_t begin_record(Opcode op) {
    u8(static_cast<std::uint8_t>(op));
    const std::size_t at = out_.size();
    u64(0);
    return at;
  }
  /// `trailing_bytes`: content the caller writes after this buffer (a chunk's compressed data).
  void end_record(std::size_t length_at, std::size_t trailing_bytes = 0) {
    patch(length_at, out_.size() - length_at - 8 + trailing_bytes, 8);
  }

  /// A uint32 byte-length prefix (maps, arrays); end_prefix32() patches it.
  std::size_t begin_prefix32() {
    const std::size_t at = out_.size();
    u32(0);
    return at;
  }
  void end_prefix32(std::size_t at) { patch(at, out_.size() - at - 4, 4); }

  [[nodiscard]] std::size_t size() const { return out_.size(); }

 private:
  void little_endian(std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out_.push_back(std::byte(static_cast<std::uint8_t>(v >> (8 * i))));
  }
  void patch(std::size_t at, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) {
      out_[at + static_cast<std::size_t>(i)] = std::byte(static_cast<std::uint8_t>(v >> (8 * i)));
    }
  }
  std::vector<std::byte>& out_;
};

}  // namespace vlpground::mcap::detail
