// The Python-side frame: shared, immutable decoded data plus the labels of one detection.
// Arrays handed to numpy are views over this memory (kept alive by a capsule holding a
// shared_ptr), read-only, with the frame's row stride.
//
// Thread-safety: a PyFrame is immutable after construction; share freely.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <string>

#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/driver/position_packet.hpp"
#include "vlpground/frame.hpp"

namespace vlpground::python {

/// The GPS state known when a frame completed: the latest position packet, if any.
struct GpsState {
  bool has_position = false;
  PositionPacket last;
};

/// Frame metadata as Python sees it: the assembler's FrameMeta, the GPS state and a snapshot
/// of the reader's counters taken when the frame was handed out.
struct PyMeta {
  FrameMeta frame;
  GpsState gps;
  CaptureCounters counters;
};

struct PyFrame {
  std::shared_ptr<const Frame> frame;
  std::shared_ptr<const GroundResult> ground;
  std::shared_ptr<const PyMeta> meta;
  std::string method;  // detector method that produced `ground`
};

}  // namespace vlpground::python
