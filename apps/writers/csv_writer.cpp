#include "writers/csv_writer.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "writers/label_access.hpp"
#include "writers/output_path.hpp"

namespace vlpground::cli {
namespace {

constexpr std::int64_t kHourNs = 3'600'000'000'000;
constexpr std::size_t kMaxRowBytes = 192;

struct Out {
  char* p;
  void text(const char* s) {
    const std::size_t n = std::strlen(s);
    std::memcpy(p, s, n);
    p += n;
  }
  void integer(std::int64_t v) { p = std::to_chars(p, p + 24, v).ptr; }
  void fixed(double v, int decimals) {
    p = std::to_chars(p, p + 40, v, std::chars_format::fixed, decimals).ptr;
  }
  void comma() { *p++ = ','; }
};

}  // namespace

CsvWriter::CsvWriter(const std::string& path) : path_(path) {
  if (path == "-") {
    file_ = stdout;
  } else {
    create_parent_directories(path);
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) {
      throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
    }
  }
  std::fprintf(file_, "%s\n", kCsvHeader);
  flush();
  buffer_.resize(std::size_t{1} << 22);
}

CsvWriter::~CsvWriter() {
  if (file_ != nullptr && file_ != stdout) std::fclose(file_);
}

void CsvWriter::flush() {
  if (std::fflush(file_) != 0 || std::ferror(file_) != 0) {
    throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  }
}

void CsvWriter::close() {
  if (file_ == nullptr) return;
  std::FILE* f = std::exchange(file_, nullptr);
  if (f == stdout) {
    if (std::fflush(f) != 0 || std::ferror(f) != 0) {
      throw std::runtime_error("cannot write to stdout: " + std::string(std::strerror(errno)));
    }
    return;
  }
  const bool failed = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || failed) {
    throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  }
}

void CsvWriter::write(const Frame& frame, const GroundResult& ground) {
  if (file_ == nullptr) throw std::logic_error("CsvWriter::write after close");
  Out out{buffer_.data()};
  const char* const limit = buffer_.data() + buffer_.size() - kMaxRowBytes;
  const auto flush_buffer = [&] {
    const auto n = static_cast<std::size_t>(out.p - buffer_.data());
    if (std::fwrite(buffer_.data(), 1, n, file_) != n) {
      throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
    }
    out.p = buffer_.data();
  };
  const auto sequence = static_cast<std::int64_t>(frame.meta.sequence);
  std::uint8_t ring_of_laser[kLasers] = {};
  for (int r = 0; r < kLasers; ++r)
    ring_of_laser[frame.laser_of_ring[r]] = static_cast<std::uint8_t>(r);

  for (int col = 0; col < frame.columns(); ++col) {
    const std::int64_t column_ns = frame.column_time_ns[static_cast<std::size_t>(col)];
    for (int laser = 0; laser < kLasers; ++laser) {
      const int ring = ring_of_laser[laser];
      const std::size_t cell = frame.index(ring, col);
      // Firing time past the top of the hour, exact in integer nanoseconds.
      const std::int64_t past_hour_ns =
          ((column_ns + laser * kFiringIntervalNs) % kHourNs + kHourNs) % kHourNs;
      for (int l = 0; l < frame.layers(); ++l) {
        const ReturnLayer& layer = frame.layer[l];
        if (layer.valid[cell] == 0) continue;
        if (out.p > limit) flush_buffer();
        out.integer(sequence);
        out.comma();
        out.integer(laser);
        out.comma();
        out.integer(ring);
        out.comma();
        out.integer(l);
        out.comma();
        out.integer(past_hour_ns / 1000);
        *out.p++ = '.';
        const std::int64_t frac = past_hour_ns % 1000;
        *out.p++ = static_cast<char>('0' + frac / 100);
        *out.p++ = static_cast<char>('0' + frac / 10 % 10);
        *out.p++ = static_cast<char>('0' + frac % 10);
        out.comma();
        out.fixed(layer.azimuth_deg[cell], 3);
        out.comma();
        out.fixed(layer.range_m[cell], 3);
        out.comma();
        out.fixed(layer.x_m[cell], 4);
        out.comma();
        out.fixed(layer.y_m[cell], 4);
        out.comma();
        out.fixed(layer.z_m[cell], 4);
        out.comma();
        out.integer(layer.intensity[cell]);
        out.comma();
        const bool is_ground = label_of(ground, l, ring, col) == GroundLabel::ground;
        *out.p++ = is_ground ? '1' : '0';
        *out.p++ = '\n';
      }
    }
  }
  flush_buffer();
  flush();
}

}  // namespace vlpground::cli
