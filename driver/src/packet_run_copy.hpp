// Copies a run of a decoded packet's columns into a frame's range image (private to the
// driver). A ring's cells of consecutive columns are contiguous in both the DecodedPacket
// (LaserRows) and the Frame (rows), so a run is 16 short row copies per array.
//
// Thread-safety: pure function of its arguments.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vlpground/driver/packet_decoder.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::driver_detail {

/// Writes every per-cell array of frame columns [first_col, first_col + count) from packet
/// columns [first_in_packet, first_in_packet + count). Time offsets are relative to
/// frame.meta.first_time_ns. The per-column arrays are the caller's.
void copy_packet_run(const DecodedPacket& packet, int first_in_packet, int count, int first_col,
                     Frame& frame);

}  // namespace vlpground::driver_detail
