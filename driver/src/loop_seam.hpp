// Joins the end of a looped capture to its start as if the file were one continuous
// recording (private to the pcap source).
//
// Each later pass starts at the data packet that continues the rotation where the previous
// pass ended (the first one whose first azimuth lies within one packet's advance after the
// previous pass's last firing); the packets before it are skipped and counted. The pass is
// shifted in time so that this packet comes one packet period after the previous pass's last
// one: on the sensor's clock (PacketView::stamp_offset_ns, added to the packet stamps by the
// decoder) and on the capture stamps (receive_ns). The rotation assembler then sees an
// ordinary next packet: frames are cut only at the cut angle and every rotation is full.
//
// A capture covering less than one rotation plus two packets cannot be joined that way: its
// passes follow one another in time (one packet period apart on the sensor's clock) without
// skipping, and the azimuth jumps at the seam.
//
// Thread-safety: owned by one PcapSource.
#pragma once

#include <cstdint>
#include <span>

namespace vlpground::driver_detail {

class LoopSeam {
 public:
  /// A data packet delivered in the current pass (1206 bytes), with its capture stamp.
  void note_data(std::span<const std::uint8_t> payload, std::int64_t record_ns);
  /// The pass read its last record. `first_record_ns`, `last_record_ns` and `records` are
  /// the capture stamps of the pass's records and their number (for a capture without a
  /// joinable rotation: the shift of the capture stamps is its span plus the mean spacing).
  void end_pass(std::int64_t first_record_ns, std::int64_t last_record_ns, std::uint64_t records);
  /// True while a later pass looks for the packet where the rotation continues.
  [[nodiscard]] bool joining() const { return joining_; }
  /// While joining(): true when this data packet continues the rotation (the shifts now
  /// place it one period after the previous pass); false when it is to be skipped.
  bool join_at(std::span<const std::uint8_t> payload, std::int64_t record_ns);

  [[nodiscard]] std::int64_t stamp_shift_ns() const { return stamp_shift_ns_; }
  [[nodiscard]] std::int64_t receive_shift_ns() const { return receive_shift_ns_; }

 private:
  void shift_to_follow(std::uint32_t stamp_us, std::int64_t record_ns);

  // The previous data packet delivered (the last one of the pass at its end).
  bool have_data_ = false;
  std::uint32_t last_stamp_us_ = 0;
  std::int64_t last_record_ns_ = 0;
  double last_first_deg_ = 0.0;  // azimuth of its first block
  double last_final_deg_ = 0.0;  // azimuth of its last block
  double step_deg_ = 0.0;        // azimuth advance per packet (from the previous packet)
  bool dual_ = false;
  std::uint32_t first_stamp_us_ = 0;  // first data packet of the file

  bool first_pass_ = true;
  double covered_deg_ = 0.0;  // azimuth swept by the first pass
  bool joinable_ = false;     // the file covers more than a rotation: passes can be joined
  bool joining_ = false;
  std::uint64_t skipped_ = 0;  // in the current join

  std::int64_t stamp_shift_ns_ = 0;
  std::int64_t receive_shift_ns_ = 0;
};

}  // namespace vlpground::driver_detail
