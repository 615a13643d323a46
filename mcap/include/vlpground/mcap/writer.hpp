// vlpground::mcap::Writer: writes MCAP files (https://mcap.dev/spec), the container that
// Foxglove and Lichtblick open.
//
// Layout: magic, Header, then the data section (Schema and Channel records as they are
// added, Chunk records each followed by its MessageIndex records), DataEnd, a Summary section
// (Schema, Channel, ChunkIndex, Statistics records, grouped by opcode), SummaryOffset records,
// Footer, magic. Chunks are compressed with zstd or lz4 (frame format) or stored.
//
// Crash behaviour: every Schema and Channel record, and every chunk with its message indexes,
// is handed to the operating system (write(2)) as soon as it is complete, so a process killed
// at any time leaves a file that a streaming reader reads up to the last complete chunk.
// flush() closes the open chunk early; call it once per frame to lose at most one frame.
// Only close() writes the summary that makes the file seekable (indexed readers need it).
//
// Allocation: after the first chunk (warm-up) writing a message allocates nothing; buffers
// keep their capacity. The summary's chunk index grows by one entry per chunk (capacity for
// WriterConfig::expected_chunks entries is reserved up front).
//
// Thread-safety: none; one thread at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vlpground::mcap {

/// Chunk compression. MCAP names: "zstd", "lz4", "" (none).
enum class Compression : std::uint8_t { zstd, lz4, none };

/// "zstd", "lz4" or "none" (the CLI spelling; the file stores "" for none).
[[nodiscard]] std::string_view to_string(Compression compression);
/// Parses "zstd", "lz4" or "none"; nullopt otherwise.
[[nodiscard]] std::optional<Compression> parse_compression(std::string_view text);

struct WriterConfig {
  Compression compression = Compression::zstd;
  /// A chunk is closed once its uncompressed records reach this size (flush() closes it
  /// earlier). Bounds the data a crash can lose and the reader's memory per chunk.
  std::size_t chunk_size_bytes = 4u << 20;
  /// zstd level (1..19; 0 = zstd's default, 3) or lz4 level (0 = fast, 3..12 = HC).
  int compression_level = 0;
  std::string profile;  // Header.profile; "" for custom profiles (protobuf, JSON)
  std::string library = "vlpground";
  /// fsync(2) after every chunk: survives power loss, not only a crash. Costs a disk sync
  /// per chunk, so it is off by default (a crash or kill loses nothing flushed either way).
  bool sync_each_chunk = false;
  /// ChunkIndex entries reserved at open(); more grow the index (amortised).
  std::size_t expected_chunks = 4096;

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

struct WriterStats {
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  std::uint64_t uncompressed_bytes = 0;  // chunk records before compression
  std::uint64_t file_bytes = 0;          // bytes written to the file so far
};

using Metadata = std::vector<std::pair<std::string, std::string>>;

class Writer {
 public:
  Writer();
  /// Calls close(); errors there are swallowed (call close() yourself to see them).
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Creates (truncates) `path` and writes the magic and Header. Throws std::runtime_error
  /// naming the path and the reason; std::invalid_argument for a bad config;
  /// std::logic_error when already open.
  void open(const std::string& path, WriterConfig config = {});

  /// Registers a schema and writes its record. Returns its id (1, 2, ...; 0 means "no
  /// schema" in MCAP).
  std::uint16_t add_schema(std::string_view name, std::string_view encoding,
                           std::span<const std::byte> data);
  /// Registers a channel and writes its record. `schema_id` 0 = schemaless.
  /// Returns its id (0, 1, ...). Throws std::invalid_argument for an unknown schema id.
  std::uint16_t add_channel(std::uint16_t schema_id, std::string_view topic,
                            std::string_view message_encoding, const Metadata& metadata = {});

  /// Appends one message to the open chunk (closing the chunk when it reaches its size).
  /// Times are ns (MCAP leaves the epoch to the producer; we use the Unix epoch).
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
             std::span<const std::byte> data);

  /// Closes the open chunk (if any): writes it and its message indexes to the file.
  void flush();

  /// flush(), then DataEnd, the summary, the footer and the closing magic; closes the file.
  /// Idempotent. Throws std::runtime_error when a write fails.
  void close();

  [[nodiscard]] bool is_open() const;
  [[nodiscard]] WriterStats stats() const;
  [[nodiscard]] const std::string& path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vlpground::mcap
