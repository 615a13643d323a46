#include "chunk_compressor.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <stdexcept>
#include <string>

namespace vlpground::mcap::detail {
namespace {

ZSTD_CCtx* zstd_ctx(void* p) { return static_cast<ZSTD_CCtx*>(p); }
LZ4F_cctx* lz4_ctx(void* p) { return static_cast<LZ4F_cctx*>(p); }

void check_lz4(std::size_t code, const char* step) {
  if (LZ4F_isError(code)) {
    throw std::runtime_error(std::string("mcap: lz4 ") + step + ": " + LZ4F_getErrorName(code));
  }
}

}  // namespace

ChunkCompressor::ChunkCompressor(Compression compression, int level)
    : compression_(compression), level_(level) {
  if (compression_ == Compression::zstd) {
    zstd_ = ZSTD_createCCtx();
    if (zstd_ == nullptr) throw std::runtime_error("mcap: cannot create a zstd context");
  } else if (compression_ == Compression::lz4) {
    LZ4F_cctx* ctx = nullptr;
    check_lz4(LZ4F_createCompressionContext(&ctx, LZ4F_VERSION), "context");
    lz4_ = ctx;
  }
}

ChunkCompressor::~ChunkCompressor() {
  if (zstd_ != nullptr) ZSTD_freeCCtx(zstd_ctx(zstd_));
  if (lz4_ != nullptr) LZ4F_freeCompressionContext(lz4_ctx(lz4_));
}

std::span<const std::byte> ChunkCompressor::compress(std::span<const std::byte> records) {
  switch (compression_) {
    case Compression::zstd:
      return compress_zstd(records);
    case Compression::lz4:
      return compress_lz4(records);
    case Compression::none:
      break;
  }
  return records;
}

std::span<const std::byte> ChunkCompressor::compress_zstd(std::span<const std::byte> records) {
  const std::size_t bound = ZSTD_compressBound(records.size());
  if (out_.size() < bound) out_.resize(bound);
  const std::size_t n = ZSTD_compressCCtx(zstd_ctx(zstd_), out_.data(), out_.size(),
                                          records.data(), records.size(),
                                          level_ == 0 ? ZSTD_CLEVEL_DEFAULT : level_);
  if (ZSTD_isError(n) != 0) {
    throw std::runtime_error(std::string("mcap: zstd: ") + ZSTD_getErrorName(n));
  }
  return {out_.data(), n};
}

std::span<const std::byte> ChunkCompressor::compress_lz4(std::span<const std::byte> records) {
  LZ4F_preferences_t prefs{};
  prefs.compressionLevel = level_;
  prefs.frameInfo.contentSize = records.size();  // lets readers size their buffer
  prefs.frameInfo.blockSizeID = LZ4F_max4MB;
  const std::size_t bound =
      LZ4F_HEADER_SIZE_MAX + LZ4F_compressBound(records.size(), &prefs) + LZ4F_compressBound(0, &prefs);
  if (out_.size() < bound) out_.resize(bound);
  std::size_t used = LZ4F_compressBegin(lz4_ctx(lz4_), out_.data(), out_.size(), &prefs);
  check_lz4(used, "begin");
  std::size_t n = LZ4F_compressUpdate(lz4_ctx(lz4_), out_.data() + used, out_.size() - used,
                                      records.data(), records.size(), nullptr);
  check_lz4(n, "compress");
  used += n;
  n = LZ4F_compressEnd(lz4_ctx(lz4_), out_.data() + used, out_.size() - used, nullptr);
  check_lz4(n, "end");
  used += n;
  return {out_.data(), used};
}

}  // namespace vlpground::mcap::detail
