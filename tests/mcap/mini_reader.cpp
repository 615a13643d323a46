#include "mini_reader.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace vlpground::test::mcap {

std::span<const std::byte> Fields::take(std::size_t n) {
  if (n > body_.size() - pos_) throw std::runtime_error("record field overruns its record");
  auto s = body_.subspan(pos_, n);
  pos_ += n;
  return s;
}

namespace {
std::uint64_t le(std::span<const std::byte> s) {
  std::uint64_t v = 0;
  for (std::size_t i = s.size(); i-- > 0;) v = (v << 8) | std::to_integer<std::uint64_t>(s[i]);
  return v;
}
}  // namespace

std::uint8_t Fields::u8() { return static_cast<std::uint8_t>(le(take(1))); }
std::uint16_t Fields::u16() { return static_cast<std::uint16_t>(le(take(2))); }
std::uint32_t Fields::u32() { return static_cast<std::uint32_t>(le(take(4))); }
std::uint64_t Fields::u64() { return le(take(8)); }
std::string Fields::string() {
  auto s = take(u32());
  return {reinterpret_cast<const char*>(s.data()), s.size()};
}
std::span<const std::byte> Fields::bytes32() { return take(u32()); }
std::span<const std::byte> Fields::bytes64() { return take(u64()); }
std::span<const std::byte> Fields::rest() { return take(body_.size() - pos_); }

std::vector<Record> split_records(std::span<const std::byte> data, std::uint64_t offset) {
  std::vector<Record> out;
  std::size_t pos = 0;
  while (data.size() - pos >= 9) {
    Fields f(data.subspan(pos, 9));
    const std::uint8_t op = f.u8();
    const std::uint64_t len = f.u64();
    if (len > data.size() - pos - 9) break;
    out.push_back({op, offset + pos, data.subspan(pos + 9, len)});
    pos += 9 + len;
  }
  return out;
}

std::vector<std::byte> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(chars.size());
  std::memcpy(bytes.data(), chars.data(), chars.size());
  return bytes;
}

std::uint32_t crc32(std::span<const std::byte> bytes) {
  return static_cast<std::uint32_t>(
      ::crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

std::vector<std::byte> chunk_records(std::span<const std::byte> chunk_body) {
  Fields f(chunk_body);
  f.u64();
  f.u64();
  const std::uint64_t size = f.u64();
  const std::uint32_t crc = f.u32();
  const std::string compression = f.string();
  const auto data = f.bytes64();
  std::vector<std::byte> out(size);
  if (compression.empty()) {
    out.assign(data.begin(), data.end());
  } else if (compression == "zstd") {
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
    if (ZSTD_isError(n) != 0 || n != size) throw std::runtime_error("zstd chunk does not decompress");
  } else if (compression == "lz4") {
    LZ4F_dctx* ctx = nullptr;
    LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION);
    std::size_t dst = out.size(), src = data.size();
    const std::size_t rc = LZ4F_decompress(ctx, out.data(), &dst, data.data(), &src, nullptr);
    LZ4F_freeDecompressionContext(ctx);
    if (LZ4F_isError(rc) != 0 || rc != 0 || dst != size) {
      throw std::runtime_error("lz4 chunk does not decompress");
    }
  } else {
    throw std::runtime_error("unknown compression " + compression);
  }
  if (out.size() != size) throw std::runtime_error("chunk size mismatch");
  if (crc != 0 && crc32(out) != crc) throw std::runtime_error("chunk CRC mismatch");
  return out;
}

std::vector<Message> stream_messages(std::span<const std::byte> file, int* chunks) {
  std::vector<Message> out;
  int complete = 0;
  if (chunks != nullptr) *chunks = 0;
  if (file.size() < 8) return out;
  for (const Record& r : split_records(file.subspan(8), 8)) {
    if (r.opcode != 0x06) continue;
    ++complete;
    const auto records = chunk_records(r.body);
    for (const Record& m : split_records(records)) {
      if (m.opcode != 0x05) continue;
      Fields f(m.body);
      Message msg{};
      msg.channel_id = f.u16();
      msg.sequence = f.u32();
      msg.log_time = f.u64();
      msg.publish_time = f.u64();
      auto d = f.rest();
      msg.data.assign(d.begin(), d.end());
      out.push_back(std::move(msg));
    }
  }
  if (chunks != nullptr) *chunks = complete;
  return out;
}

}  // namespace vlpground::test::mcap
