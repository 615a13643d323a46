// One CSV row per return with a distance; flushed after every frame so an interrupted run
// leaves a valid file. Rows are formatted into a reused buffer (no iostream per field).
//
// Thread-safety: one thread at a time.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::cli {

inline constexpr const char* kCsvHeader =
    "frame,laser_id,ring,return,timestamp_us,azimuth_deg,distance_m,x,y,z,intensity,ground";

class CsvWriter {
 public:
  /// Creates (truncates) `path`, and its missing parent directories, and writes the header;
  /// "-" writes to stdout. Throws std::runtime_error.
  explicit CsvWriter(const std::string& path);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Appends the frame's returns (column order, then laser id, then return 0/1) and flushes.
  void write(const Frame& frame, const GroundResult& ground);
  /// Flushes and closes the file; throws std::runtime_error when that fails. Idempotent.
  void close();

 private:
  void flush();

  std::FILE* file_ = nullptr;
  std::string path_;
  std::vector<char> buffer_;
};

}  // namespace vlpground::cli
