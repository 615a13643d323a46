// Assembles decoded firing columns into complete rotations (16 x N range images), cutting
// at a configured azimuth at the firing, never at the packet.
//
// Behaviour in brief (details in rotation_assembler.cpp):
// - A frame starts with the first column whose azimuth crossed the cut angle and ends just
//   before the next such column: every firing lands in exactly one frame. The first partial
//   rotation of a stream (before the first cut) is emitted too, marked incomplete.
// - Timestamp gaps of more than 1.5 packet periods are packet loss: the missing firings
//   become invalid columns (time on the 55.296 us grid, azimuth interpolated). A gap whose
//   azimuth span exceeds `max_gap_fill_deg` ends the frame (incomplete) instead. A gap that
//   recurs at the same azimuths rotation after rotation is a FOV-restricted sensor (it sends
//   nothing outside its sector, packets inside keep their period): it is filled the same
//   way but counted as `columns_outside_fov`, not as loss, and the frame stays complete.
// - Duplicates (same stamp as the newest packet) and reordered packets (older stamps) are
//   dropped and counted; there is no reorder buffer, a late packet's columns stay invalid.
// - A silence longer than `silence_timeout_ms` (in stamps, or on the steady clock through
//   expire()) ends the frame in progress, marked incomplete.
// - A packet whose time was re-based (DecodedPacket::time_rebase_ns: the hour now comes from
//   GPS instead of the host clock) moves the frame in progress to the new clock instead of
//   splitting it.
// - `complete` means the frame spans a whole rotation from cut to cut (lost columns inside
//   it are filled and counted in meta.columns_lost).
//
// Thread-safety: one RotationAssembler per thread.
#pragma once

#include <array>
#include <cstdint>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/frame.hpp"

namespace vlpground {

struct AssemblerConfig {
  double cut_angle_deg = 0.0;       // frames start at the first firing at/after this azimuth
  double silence_timeout_ms = 200;  // a longer gap ends the frame in progress (incomplete)
  double max_gap_fill_deg = 180.0;  // a loss gap spanning more azimuth ends the frame
  int capacity_columns = kDefaultFrameCapacity;

  /// Throws std::invalid_argument with a clear message.
  void validate() const;
};

struct AssemblerCounters {
  std::uint64_t frames = 0;
  std::uint64_t incomplete_frames = 0;
  std::uint64_t packets_used = 0;
  std::uint64_t packets_lost = 0;       // inferred from timestamp gaps
  std::uint64_t duplicate_packets = 0;  // same timestamp as one already used
  std::uint64_t reordered_packets = 0;  // older than the newest used (dropped, counted)
  std::uint64_t columns_lost = 0;
  std::uint64_t off_grid_packets = 0;  // newer by less than half a period (not VLP-16 timing)
  std::uint64_t skipped_upstream = 0;  // note_skipped_packet() calls
  std::uint64_t columns_outside_fov = 0;
  std::uint64_t silences = 0;            // frames ended by silence
  std::uint64_t large_gaps = 0;          // frames ended by a gap too large to fill
  std::uint64_t capacity_overflows = 0;  // frames ended because they were full
  std::uint64_t stream_changes = 0;      // mode/model change or time jumping backwards
  std::uint64_t azimuth_jumps = 0;       // firing-to-firing steps > 10 deg (frame incomplete)
  std::uint64_t frames_dropped = 0;      // ready frames overwritten because pop() was not called
  std::uint64_t clock_rebases = 0;       // frames in progress moved to a new hour reference
  std::uint64_t discarded_packets = 0;   // used in a frame that discard_frame() threw away

  /// Every data packet given to push() or note_skipped_packet() is in exactly one of these.
  [[nodiscard]] std::uint64_t packets_skipped() const {
    return duplicate_packets + reordered_packets + off_grid_packets + skipped_upstream +
           discarded_packets;
  }
};

class RotationAssembler {
 public:
  explicit RotationAssembler(const AssemblerConfig& config = {});

  /// Ring order (laser id of each elevation-sorted row) used for `model`; defaults to the
  /// built-in VLP-16 / Hi-Res order. CaptureReader passes the decoder's (calibrated) model.
  void set_laser_of_ring(Model model, const std::array<std::uint8_t, kLasers>& laser_of_ring);

  /// Adds one decoded packet. When this completes a frame, swaps it into `out` (whose old
  /// storage becomes a spare) and returns true. Never allocates as long as `out` has the
  /// configured capacity. `steady_receive_ns` (host steady clock) becomes the frame's
  /// completed_receive_ns; when negative, packet.receive_ns is used.
  /// Rarely one packet completes two frames (a silence or stream change followed by a cut in
  /// the same packet): the second waits for pop(). Callers that push by hand should drain
  /// with `while (pop(out))` after a true push (CaptureReader does).
  bool push(const DecodedPacket& packet, Frame& out, std::int64_t steady_receive_ns = -1);

  /// Hands out a frame completed earlier but not yet returned. False when none waits.
  bool pop(Frame& out);

  /// Emits waiting frames first, then the frame in progress, marked incomplete
  /// (end of input). Call until it returns false to drain everything.
  bool flush(Frame& out);

  /// Flushes the frame in progress (marked incomplete, end = silence) when no packet came for
  /// longer than the silence timeout before `steady_now_ns`. Returns true when it emitted.
  bool expire(std::int64_t steady_now_ns, Frame& out);

  /// Throws away the frame in progress (not emitted) and restarts the stream: for packets
  /// found afterwards not to be VLP-16 data. Its packets move from packets_used to
  /// discarded_packets.
  void discard_frame();

  /// Counts a packet skipped upstream (malformed, filtered) against the frame in progress.
  void note_skipped_packet();

  [[nodiscard]] const AssemblerCounters& counters() const { return counters_; }
  [[nodiscard]] const AssemblerConfig& config() const { return config_; }
  /// Rotation rate measured over the latest packet, degrees per second (0 before any).
  [[nodiscard]] double rate_deg_per_s() const { return rate_deg_per_ns_ * 1e9; }

 private:
  struct ColumnSource;
  void handle_gap(const DecodedPacket& packet, std::int64_t delta_ns);
  void rebase_time(std::int64_t shift_ns);
  void add_column(const ColumnSource& source);
  void write_column_header(int col, const ColumnSource& source);
  void extend_pending_run(int col, const ColumnSource& source);
  void write_pending_run();
  void write_empty_cells(int col, const ColumnSource& source);
  void begin_frame(const ColumnSource& source, bool at_cut);
  void finish_frame(bool complete, FrameEnd end);
  void restart_stream();
  bool deliver(Frame& out);

  AssemblerConfig config_;
  AssemblerCounters counters_;
  std::array<std::array<std::uint8_t, kLasers>, 2> laser_of_ring_{};  // by Model
  Frame current_;
  std::array<Frame, 2> ready_;  // completed frames waiting for hand-off (FIFO)
  int ready_head_ = 0;
  int ready_count_ = 0;
  std::uint64_t next_sequence_ = 0;

  // Stream state (reset by restart_stream()).
  bool have_packet_ = false;
  std::int64_t last_packet_time_ns_ = 0;  // newest packet used
  std::int64_t last_seen_time_ns_ = 0;    // newest packet used or found off-grid
  ReturnMode mode_ = ReturnMode::strongest;
  Model model_ = Model::vlp16;
  TimeSource time_source_ = TimeSource::host_clock;  // of the newest packet
  bool have_column_ = false;
  std::int64_t last_column_time_ns_ = 0;
  double last_column_az_deg_ = 0.0;
  double rate_deg_per_ns_ = 0.0;
  bool have_gap_ = false;  // previous gap's azimuths, to recognise a FOV sector
  double gap_start_deg_ = 0.0, gap_end_deg_ = 0.0;

  // Columns of the packet being pushed whose cells are not yet copied into current_.
  struct PendingRun {
    const DecodedPacket* packet = nullptr;
    int first_in_packet = 0;
    int first_col = 0;  // frame column of the first
    int count = 0;
  };
  PendingRun pending_;

  // Frame-in-progress state.
  bool frame_at_cut_ = false;     // started at a cut (else a partial start)
  double frame_advance_deg_ = 0;  // unwrapped azimuth advance since the first column
  bool packet_in_frame_ = false;  // the packet being pushed already counted in meta
  std::int64_t steady_ns_ = 0;    // steady receive time of the newest packet
};

}  // namespace vlpground
