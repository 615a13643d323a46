#include <stdexcept>
#include <string>

#include "vlpground/mcap/writer.hpp"

namespace vlpground::mcap {

std::string_view to_string(Compression compression) {
  switch (compression) {
    case Compression::zstd:
      return "zstd";
    case Compression::lz4:
      return "lz4";
    case Compression::none:
      break;
  }
  return "none";
}

std::optional<Compression> parse_compression(std::string_view text) {
  for (const Compression c : {Compression::zstd, Compression::lz4, Compression::none}) {
    if (text == to_string(c)) return c;
  }
  return std::nullopt;
}

void WriterConfig::validate() const {
  if (chunk_size_bytes == 0) {
    throw std::invalid_argument("mcap: chunk_size_bytes must be > 0");
  }
  if (compression == Compression::zstd && (compression_level < 0 || compression_level > 19)) {
    throw std::invalid_argument("mcap: zstd compression level must be 0 (default) or 1..19, got " +
                                std::to_string(compression_level));
  }
  if (compression == Compression::lz4 && (compression_level < 0 || compression_level > 12)) {
    throw std::invalid_argument("mcap: lz4 compression level must be 0..12, got " +
                                std::to_string(compression_level));
  }
}

}  // namespace vlpground::mcap
