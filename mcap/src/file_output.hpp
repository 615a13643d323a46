// An append-only file written with write(2) (no user-space buffer: what was written survives
// the process), tracking the offset and a running CRC-32 (zlib) that can be restarted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace vlpground::mcap::detail {

/// CRC-32 as MCAP uses it (zlib's polynomial), continuing from `crc` (0 to start).
std::uint32_t crc32(std::uint32_t crc, std::span<const std::byte> bytes);

class FileOutput {
 public:
  FileOutput() = default;
  ~FileOutput();
  FileOutput(const FileOutput&) = delete;
  FileOutput& operator=(const FileOutput&) = delete;

  /// Creates/truncates `path`; throws std::runtime_error naming it and the reason.
  void open(const std::string& path);
  /// Writes everything (retries short writes and EINTR); throws std::runtime_error.
  void write(std::span<const std::byte> bytes);
  /// fsync(2); throws std::runtime_error.
  void sync();
  /// Closes the descriptor; throws std::runtime_error when close(2) reports an error.
  void close();

  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  /// A write or sync failed: the file may end in a torn record.
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::uint64_t offset() const { return offset_; }
  [[nodiscard]] std::uint32_t crc() const { return crc_; }
  void restart_crc() { crc_ = 0; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(const char* what);
  int fd_ = -1;
  bool failed_ = false;
  std::uint64_t offset_ = 0;
  std::uint32_t crc_ = 0;
  std::string path_;
};

}  // namespace vlpground::mcap::detail
