// Compresses chunk records with zstd or lz4 (frame format, as MCAP requires) into a reused
// buffer. Contexts and buffers are kept between chunks: no allocation once warmed up.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vlpground/mcap/writer.hpp"

namespace vlpground::mcap::detail {

class ChunkCompressor {
 public:
  ChunkCompressor(Compression compression, int level);
  ~ChunkCompressor();
  ChunkCompressor(const ChunkCompressor&) = delete;
  ChunkCompressor& operator=(const ChunkCompressor&) = delete;

  /// The compressed bytes of `records` (or `records` itself for Compression::none), valid
  /// until the next call. Throws std::runtime_error when the library reports an error.
  std::span<const std::byte> compress(std::span<const std::byte> records);

 private:
  std::span<const std::byte> compress_zstd(std::span<const std::byte> records);
  std::span<const std::byte> compress_lz4(std::span<const std::byte> records);

  Compression compression_;
  int level_;
  void* zstd_ = nullptr;  // ZSTD_CCtx
  void* lz4_ = nullptr;   // LZ4F_cctx
  std::vector<std::byte> out_;
};

}  // namespace vlpground::mcap::detail
