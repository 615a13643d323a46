// FrameReader: a synchronous CaptureReader + GroundDetector driven by Python's iteration.
// Decoding and detection run with the GIL released; live reads wait in bounded slices and
// check for signals between them, so Ctrl-C (KeyboardInterrupt) stops a notebook cleanly.
#include <pybind11/stl.h>

#include <chrono>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "conversions.hpp"
#include "pool.hpp"
#include "py_frame.hpp"

namespace vlpground::python {
namespace {

using py::literals::operator""_a;
using Clock = std::chrono::steady_clock;

constexpr int kLiveWaitMs = 100;     // longest wait without checking for Ctrl-C
constexpr int kReplayWaitMs = 1000;  // paced replays only; file reads never wait
constexpr std::size_t kPooledFrames = 4;

struct ReaderLimits {
  std::uint64_t max_frames = 0;  // 0: no limit
  std::uint64_t first_frame = 0;  // frames before this sequence are read, not detected
  double duration_s = 0;         // 0: no limit
  double idle_timeout_s = 0;     // 0: wait for packets without limit
};

class FrameReader {
 public:
  FrameReader(std::unique_ptr<PacketSource> source, const DecoderConfig& decoder,
              const AssemblerConfig& assembler, const DetectorConfig& detector,
              ReaderLimits limits)
      : live_(source->is_live()),
        description_(source->describe()),
        reader_(std::make_unique<CaptureReader>(std::move(source), decoder, assembler)),
        detector_(detector),
        method_(method_name(detector)),
        limits_(limits),
        started_(Clock::now()),
        last_frame_(started_) {
    const int capacity = assembler.capacity_columns;
    frames_ = Pool<Frame>::create([capacity] { return std::make_unique<Frame>(capacity); },
                                  kPooledFrames);
    results_ = Pool<GroundResult>::create(
        [capacity] {
          auto r = std::make_unique<GroundResult>();
          r->reserve(capacity);
          return r;
        },
        kPooledFrames);
    reader_->on_position([this](const PositionPacket& p) {
      gps_.has_position = true;
      gps_.last = p;
    });
    reader_->on_warning([this](const std::string& w) { pending_warnings_.push_back(w); });
  }

  PyFrame next() {
    if (finished_ || (limits_.max_frames > 0 && delivered_ >= limits_.max_frames)) {
      finished_ = true;
      throw py::stop_iteration();
    }
    std::shared_ptr<Frame> frame = frames_->acquire();
    std::shared_ptr<GroundResult> ground = results_->acquire();
    auto meta = std::make_shared<PyMeta>();
    while (true) {
      ReadStatus status = ReadStatus::stopped;
      {
        py::gil_scoped_release release;
        const std::lock_guard lock(mutex_);
        status = read_frame(*frame);
        if (status == ReadStatus::frame) {
          detector_.detect(*frame, *ground);
          meta->frame = frame->meta;
          meta->gps = gps_;
          meta->counters = reader_->counters();
        }
      }
      forward_warnings();
      if (status == ReadStatus::frame) {
        ++delivered_;
        last_frame_ = Clock::now();
        return PyFrame{std::move(frame), std::move(ground), std::move(meta), method_};
      }
      if (status == ReadStatus::timeout) {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        check_time_limits();
        continue;
      }
      finished_ = true;
      if (status == ReadStatus::end_of_input) check_something_decoded();
      throw py::stop_iteration();
    }
  }

  void stop() {
    const std::lock_guard lock(stop_mutex_);
    if (reader_) reader_->request_stop();
  }

  /// Stops and releases the source (socket or file) at once; counters stay readable.
  void close() {
    stop();
    py::gil_scoped_release release;
    const std::lock_guard lock(mutex_);
    const std::lock_guard stop_lock(stop_mutex_);
    if (!reader_) return;
    final_counters_ = reader_->counters();
    reader_.reset();
    finished_ = true;
  }

  /// Reads the rest of the input without detection; returns the frames it held.
  std::uint64_t skip_to_end() {
    std::uint64_t skipped = 0;
    auto frame = frames_->acquire();
    while (!finished_) {
      ReadStatus status = ReadStatus::stopped;
      {
        py::gil_scoped_release release;
        const std::lock_guard lock(mutex_);
        status = read_frame(*frame);
      }
      forward_warnings();
      if (status == ReadStatus::frame) {
        ++skipped;
      } else if (status == ReadStatus::timeout) {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        check_time_limits();
      } else {
        finished_ = true;
        if (status == ReadStatus::end_of_input) check_something_decoded();
      }
    }
    return skipped;
  }

  [[nodiscard]] CaptureCounters counters() {
    py::gil_scoped_release release;
    const std::lock_guard lock(mutex_);
    return counters_locked();
  }

  [[nodiscard]] const std::string& description() const { return description_; }
  [[nodiscard]] bool live() const { return live_; }
  [[nodiscard]] std::uint64_t delivered() const { return delivered_; }
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  // Next frame at or after limits_.first_frame (earlier ones are assembled, then dropped).
  ReadStatus read_frame(Frame& frame) {
    while (true) {
      if (!reader_) return ReadStatus::stopped;
      const ReadStatus status = reader_->next(frame, live_ ? kLiveWaitMs : kReplayWaitMs);
      if (status != ReadStatus::frame) return status;
      ++frames_read_;
      if (frame.meta.sequence >= limits_.first_frame) return status;
    }
  }

  // The reader's counters (or the last ones, once closed); the caller excludes next().
  [[nodiscard]] CaptureCounters counters_locked() const {
    return reader_ ? reader_->counters() : final_counters_;
  }

  void forward_warnings() {
    for (const auto& w : pending_warnings_) {
      warnings_.push_back(w);
      if (PyErr_WarnEx(PyExc_RuntimeWarning, (description_ + ": " + w).c_str(), 1) != 0) {
        pending_warnings_.clear();
        throw py::error_already_set();
      }
    }
    pending_warnings_.clear();
  }

  void check_time_limits() {
    const auto now = Clock::now();
    const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    if (limits_.duration_s > 0 && seconds(now - started_) >= limits_.duration_s) {
      finished_ = true;
      throw py::stop_iteration();
    }
    if (limits_.idle_timeout_s > 0 && seconds(now - last_frame_) >= limits_.idle_timeout_s) {
      finished_ = true;
      const auto data = counters_locked().source.data_packets;
      const std::string message = description_ + ": no frame for " +
                                  std::to_string(limits_.idle_timeout_s) + " s (" +
                                  std::to_string(data) + " data packets received so far)";
      PyErr_SetString(PyExc_TimeoutError, message.c_str());
      throw py::error_already_set();
    }
  }

  // A capture that produced no frame is an error (not a VLP-16 capture, truncated, empty),
  // as for the CLI, not an empty result.
  void check_something_decoded() {
    if (frames_read_ > 0) return;
    const CaptureCounters c = counters_locked();
    std::string why = warnings_.empty() ? "" : ": " + warnings_.back();
    throw std::runtime_error(
        description_ + ": no VLP-16 frame decoded (" + std::to_string(c.source.records) +
        " records, " + std::to_string(c.source.data_packets) + " data packets, " +
        std::to_string(c.source.position_packets) + " position packets, " +
        std::to_string(c.source.truncated) + " truncated)" + why);
  }

  bool live_;
  std::string description_;
  std::mutex mutex_;  // one next() at a time
  std::mutex stop_mutex_;  // guards reader_'s lifetime against stop() from other threads
  std::unique_ptr<CaptureReader> reader_;
  CaptureCounters final_counters_;
  GroundDetector detector_;
  std::string method_;
  ReaderLimits limits_;
  std::shared_ptr<Pool<Frame>> frames_;
  std::shared_ptr<Pool<GroundResult>> results_;
  GpsState gps_;
  std::vector<std::string> pending_warnings_;
  std::vector<std::string> warnings_;
  std::uint64_t delivered_ = 0;
  std::uint64_t frames_read_ = 0;  // assembled, delivered or not
  bool finished_ = false;
  Clock::time_point started_;
  Clock::time_point last_frame_;
};

DecoderConfig decoder_config(const std::string& calibration, const std::optional<std::string>& model) {
  DecoderConfig d;
  d.calibration_file = calibration;
  if (model) d.force_model = parse_model(*model);
  d.validate();
  return d;
}

AssemblerConfig assembler_config(double cut_angle_deg) {
  if (!(cut_angle_deg >= 0.0 && cut_angle_deg < 360.0)) {
    throw py::value_error("cut_angle_deg must be in [0, 360), got " + std::to_string(cut_angle_deg));
  }
  AssemblerConfig a;
  a.cut_angle_deg = cut_angle_deg;
  return a;
}

std::uint16_t port_number(int port, const char* name) {
  if (port < 1 || port > 65535) {
    throw py::value_error(std::string(name) + " must be in [1, 65535], got " + std::to_string(port));
  }
  return static_cast<std::uint16_t>(port);
}

std::unique_ptr<FrameReader> open_pcap(const std::string& path, const DetectorConfig& detector,
                                       const std::string& calibration,
                                       const std::optional<std::string>& model, double cut_angle_deg,
                                       const std::string& sensor_ip, int port, int position_port,
                                       bool loop, std::uint64_t max_frames,
                                       std::uint64_t first_frame) {
  PcapSourceConfig pcap;
  pcap.path = path;
  pcap.data_port = port_number(port, "port");
  pcap.position_port = port_number(position_port, "position_port");
  pcap.sensor_address = sensor_ip;
  pcap.loop = loop;
  const DecoderConfig decoder = decoder_config(calibration, model);
  const AssemblerConfig assembler = assembler_config(cut_angle_deg);
  detector.validate();
  std::unique_ptr<PacketSource> source;
  {
    py::gil_scoped_release release;
    source = open_pcap_source(pcap);
  }
  return std::make_unique<FrameReader>(std::move(source), decoder, assembler, detector,
                                       ReaderLimits{max_frames, first_frame, 0.0, 0.0});
}

std::unique_ptr<FrameReader> open_live(int port, const std::string& bind, int position_port,
                                       const std::string& sensor_ip, const std::string& multicast,
                                       bool reuse_address, const DetectorConfig& detector,
                                       const std::string& calibration,
                                       const std::optional<std::string>& model, double cut_angle_deg,
                                       std::uint64_t max_frames, double duration_s,
                                       double timeout_s) {
  UdpSourceConfig udp;
  udp.bind_address = bind;
  udp.data_port = port_number(port, "port");
  udp.position_port =
      position_port == 0 ? std::uint16_t{0} : port_number(position_port, "position_port");
  udp.sensor_address = sensor_ip;
  udp.multicast_group = multicast;
  udp.reuse_address = reuse_address;
  const DecoderConfig decoder = decoder_config(calibration, model);
  const AssemblerConfig assembler = assembler_config(cut_angle_deg);
  detector.validate();
  if (duration_s < 0 || timeout_s < 0) throw py::value_error("duration_s and timeout_s must be >= 0");
  auto source = open_udp_source(udp);
  return std::make_unique<FrameReader>(std::move(source), decoder, assembler, detector,
                                       ReaderLimits{max_frames, 0, duration_s, timeout_s});
}

}  // namespace

void bind_reader(py::module_& m) {
  py::class_<FrameReader>(m, "FrameReader",
                          "Iterator of labelled frames from a capture or a live socket "
                          "(see vlpground.read_pcap and vlpground.live). Use as a context "
                          "manager or call stop() to release the socket or file.")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &FrameReader::next)
      .def("stop", &FrameReader::stop,
           "End the iteration: the next (or a blocked) __next__ raises StopIteration. Callable "
           "from any thread.")
      .def("skip_to_end", &FrameReader::skip_to_end,
           "Reads the rest of the input without ground detection (fast) and returns how many "
           "frames it held; the iteration is then over.")
      .def("__enter__", [](py::object self) { return self; })
      .def("close", &FrameReader::close,
           "Stops and releases the socket or file at once (also done when the reader is "
           "garbage-collected, and by `with`).")
      .def("__exit__", [](FrameReader& r, const py::args&) { r.close(); })
      .def_property_readonly("counters", [](FrameReader& r) { return counters_dict(r.counters()); },
                             "Source, decoder and assembler counters so far.")
      .def_property_readonly("frames", &FrameReader::delivered, "Frames handed out so far.")
      .def_property_readonly("live", &FrameReader::live)
      .def_property_readonly("source", &FrameReader::description,
                             "One-line description of the input.")
      .def_property_readonly("warnings", &FrameReader::warnings,
                             "Distinct reader warnings so far (also issued as RuntimeWarning).");

  m.def("_open_pcap", &open_pcap, "path"_a, "detector"_a, "calibration"_a, "model"_a,
        "cut_angle_deg"_a, "sensor_ip"_a, "port"_a, "position_port"_a, "loop"_a, "max_frames"_a,
        "first_frame"_a);
  m.def("_open_live", &open_live, "port"_a, "bind"_a, "position_port"_a, "sensor_ip"_a,
        "multicast"_a, "reuse_address"_a, "detector"_a, "calibration"_a, "model"_a,
        "cut_angle_deg"_a, "max_frames"_a, "duration_s"_a, "timeout_s"_a);
}

}  // namespace vlpground::python
