// One rotation of a VLP-16 as a 16 x N range image (structure of arrays).
//
// Rows are rings sorted by elevation (row 0 = lowest beam), columns are firing sequences in
// time order. Cell (ring, col) lives at index ring * stride() + col in every per-cell array.
// Storage is allocated once for `capacity_columns`; clear() and the assembler never
// reallocate, so frames can be pooled and swapped without touching the heap.
//
// Thread-safety: a Frame is a plain value; one writer at a time, or many readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "vlpground/types.hpp"

namespace vlpground {

struct SensorModel;  // vlpground/driver/sensor_model.hpp

/// Default column capacity: a full rotation at 300 rpm (~3617 sequences) plus margin.
inline constexpr int kDefaultFrameCapacity = 4096;

/// Provenance of a column that no packet carried (lost or outside the sensor's FOV).
inline constexpr std::uint64_t kNoPacketIndex = ~std::uint64_t{0};
inline constexpr std::uint8_t kNoColumnInPacket = 0xFF;

/// Why the assembler ended a frame.
enum class FrameEnd : std::uint8_t {
  cut,            // the next firing crossed the cut angle (the normal case)
  end_of_input,   // flush(): end of file or caller request
  silence,        // no packet for longer than the silence timeout
  gap,            // a packet gap too large to fill with invalid columns
  capacity,       // the frame ran out of columns
  stream_change,  // return mode or model changed, or time jumped backwards
};

/// Per-cell arrays of one return layer.
struct ReturnLayer {
  std::vector<float> range_m;         // 0 where there is no return
  std::vector<float> x_m, y_m, z_m;   // sensor frame: x forward, y left, z up
  std::vector<float> azimuth_deg;     // precise azimuth of this firing, [0, 360)
  std::vector<float> time_offset_us;  // firing time relative to FrameMeta::first_time_ns
  std::vector<std::uint8_t> intensity;
  std::vector<std::uint8_t> valid;  // 1 = a return with a distance, 0 = none / lost

  void resize(std::size_t cells);
};

/// Frame-level metadata filled by the rotation assembler.
struct FrameMeta {
  std::uint64_t sequence = 0;      // frame counter, starts at 0, +1 per emitted frame
  std::int64_t first_time_ns = 0;  // absolute time of the first firing (ns since epoch)
  std::int64_t last_time_ns = 0;   // absolute time of the last firing
  double rpm = 0.0;                // measured over this frame
  ReturnMode mode = ReturnMode::strongest;
  Model model = Model::vlp16;
  std::uint32_t packets_used = 0;         // data packets that contributed firings
  std::uint32_t packets_lost = 0;         // estimated from timestamp / azimuth gaps
  std::uint32_t packets_skipped = 0;      // malformed / duplicate / out-of-order packets
  std::uint32_t columns_lost = 0;         // columns left invalid because their packet was lost
  bool complete = false;                  // a full rotation from cut to cut
  std::uint32_t columns_outside_fov = 0;  // invalid columns where a FOV-restricted sensor is silent
  FrameEnd end = FrameEnd::cut;
  // Receive time (host steady clock, ns) of the packet that completed the frame; the
  // pipeline measures latency from it.
  std::int64_t completed_receive_ns = 0;
  TimeSource time_source = TimeSource::host_clock;  // of the frame's times (all on one base)
  // The geometry the frame was decoded with (built-in or a calibration file: see
  // SensorModel::source); shared, never copied per frame. Set by CaptureReader (and so the
  // pipeline); null for frames assembled by hand.
  std::shared_ptr<const SensorModel> calibration;
};

class Frame {
 public:
  explicit Frame(int capacity_columns = kDefaultFrameCapacity) { reserve(capacity_columns); }

  /// (Re)allocates storage for `capacity_columns`; the only allocating call.
  void reserve(int capacity_columns);
  /// Empties the frame (columns() == 0) without releasing storage.
  void clear();

  [[nodiscard]] int capacity() const { return capacity_; }
  /// Row stride of the per-cell arrays: capacity padded so that rows do not sit a power of
  /// two apart (16 rows 16 KiB apart alias in the caches and made filling 3x slower).
  [[nodiscard]] int stride() const { return stride_; }
  [[nodiscard]] int columns() const { return columns_; }
  [[nodiscard]] std::size_t index(int ring, int col) const {
    return static_cast<std::size_t>(ring) * static_cast<std::size_t>(stride_) +
           static_cast<std::size_t>(col);
  }
  /// Number of return layers in use: 2 in dual mode, else 1.
  [[nodiscard]] int layers() const { return meta.mode == ReturnMode::dual ? 2 : 1; }

  /// Appends one invalid column and returns its index, or -1 when the frame is full.
  int append_column();
  /// Appends a column without clearing it (the caller writes every cell of it and its
  /// per-column values); returns its index, or -1 when the frame is full.
  int append_column_for_overwrite() { return columns_ < capacity_ ? columns_++ : -1; }

  // Per-cell data, [kStrongestLayer] and [kLastLayer] (dual only).
  ReturnLayer layer[2];
  // Per cell (dual mode): 1 when the strongest and last return are the same echo.
  std::vector<std::uint8_t> same_echo;
  // Laser id (firing order 0..15) of each ring, fixed by the sensor model.
  std::uint8_t laser_of_ring[kLasers] = {};

  // Per column.
  std::vector<float> column_azimuth_deg;     // azimuth of the sequence's first firing
  std::vector<std::int64_t> column_time_ns;  // absolute time of the first firing
  std::vector<std::uint8_t> column_valid;    // 0 for columns lost with their packet
  // Provenance (for ground-truth alignment): index of the data packet that carried the
  // column (DecodedPacket::packet_index) and the column's position in that packet.
  std::vector<std::uint64_t> column_packet_index;
  std::vector<std::uint8_t> column_in_packet;

  FrameMeta meta;

 private:
  int capacity_ = 0;
  int stride_ = 0;
  int columns_ = 0;
};

}  // namespace vlpground
