#include "vlpground/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>

#include "frame_pool.hpp"
#include "latency_histogram.hpp"

namespace vlpground {
namespace {

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double ms_since(std::int64_t from_ns, std::int64_t to_ns) {
  return static_cast<double>(to_ns - from_ns) * 1e-6;
}

std::uint64_t count_returns(const Frame& f) {
  std::uint64_t n = 0;
  const int layers = f.layers();
  for (int l = 0; l < layers; ++l) {
    const auto& valid = f.layer[l].valid;
    for (int ring = 0; ring < kLasers; ++ring) {
      const std::size_t row = f.index(ring, 0);
      for (int c = 0; c < f.columns(); ++c) n += valid[row + static_cast<std::size_t>(c)];
    }
  }
  return n;
}

}  // namespace

LabelledFrame::LabelledFrame(int capacity_columns) : frame(capacity_columns) {
  ground.reserve(frame.stride());  // the detector sizes results by the frame's row stride
}

void PipelineConfig::validate() const {
  if (queue_frames < 1 || queue_frames > 256) {
    throw std::invalid_argument("PipelineConfig.queue_frames must be in [1, 256], got " +
                                std::to_string(queue_frames));
  }
  if (lease_frames < 0 || lease_frames > 256) {
    throw std::invalid_argument("PipelineConfig.lease_frames must be in [0, 256], got " +
                                std::to_string(lease_frames));
  }
  if (read_timeout_ms < 1 || read_timeout_ms > 60'000) {
    throw std::invalid_argument("PipelineConfig.read_timeout_ms must be in [1, 60000], got " +
                                std::to_string(read_timeout_ms));
  }
  if (pcap) {
    pcap->validate();
  } else {
    udp.validate();
  }
  decoder.validate();
  assembler.validate();
  detector.validate();
}

struct Pipeline::Impl {
  using Slot = detail::FramePool::Slot;

  explicit Impl(PipelineConfig c)
      : config(std::move(c)),
        pool(std::make_shared<detail::FramePool>(
            config.queue_frames + 2 + config.lease_frames, config.queue_frames,
            config.assembler.capacity_columns)),
        detector(config.detector) {}

  PipelineConfig config;
  std::unique_ptr<PacketSource> injected_source;
  FrameCallback frame_cb;
  FrameLeaseCallback lease_cb;
  TelemetryCallback telemetry_cb;
  DiagnosticsCallback diagnostics_cb;

  std::unique_ptr<CaptureReader> reader;
  std::shared_ptr<detail::FramePool> pool;  // shared with the leases
  GroundDetector detector;
  bool pull = false;  // no frame callback: frames wait for next()
  std::uint64_t next_index = 0;  // delivered_index of the next hand-out (stats_mutex)
  bool live = false;
  bool started = false;
  std::atomic<bool> stop_requested{false};

  std::thread reader_thread, detector_thread;
  std::mutex join_mutex;
  std::mutex done_mutex;
  std::condition_variable done_cv;
  bool reader_done = false, detector_done = false;

  mutable std::mutex stats_mutex;
  PipelineStats counters;  // latency/detect filled from the histograms in snapshot()
  detail::LatencyHistogram latency, detect_time;
  std::int64_t start_ns = 0;

  std::mutex diagnostics_mutex;

  PipelineStats snapshot() const {
    std::lock_guard lock(stats_mutex);
    PipelineStats s = counters;
    s.latency = latency.summary();
    s.detect = detect_time.summary();
    s.elapsed_s = start_ns == 0 ? 0.0 : ms_since(start_ns, steady_now_ns()) * 1e-3;
    return s;
  }

  void diagnose(DiagnosticKind kind, std::string message) {
    if (!diagnostics_cb) return;
    Diagnostic d{kind, std::move(message), snapshot()};
    std::lock_guard lock(diagnostics_mutex);
    try {
      diagnostics_cb(d);
    } catch (...) {
      // A throwing diagnostics callback must not take the pipeline down; nothing to report to.
    }
  }

  void request_stop() {
    stop_requested = true;
    pool->stop();
    if (reader) reader->request_stop();
  }

  void update_capture_counters() {
    const CaptureCounters c = reader->counters();
    const double progress = reader->source().progress();
    std::lock_guard lock(stats_mutex);
    counters.capture = c;
    counters.progress = progress;
  }

  bool drop_oldest() const {
    switch (config.backpressure) {
      case Backpressure::block:
        return false;
      case Backpressure::drop_oldest:
        return true;
      case Backpressure::automatic:
        break;
    }
    return live;
  }

  void run_reader() {
    try {
      read_frames();
    } catch (const std::exception& e) {
      diagnose(DiagnosticKind::source_error, std::string("reader failed: ") + e.what());
    } catch (...) {
      diagnose(DiagnosticKind::source_error, "reader failed: unknown exception");
    }
    update_capture_counters();
    pool->close_detection();
    mark_done(reader_done);
  }

  void read_frames() {
    const bool drop = drop_oldest();
    Slot* filling = pool->first_free();
    while (!stop_requested) {
      Frame& frame = detail::FramePool::frame(filling).frame;
      const ReadStatus status = reader->next(frame, config.read_timeout_ms);
      update_capture_counters();
      if (status == ReadStatus::end_of_input || status == ReadStatus::stopped) return;
      if (status != ReadStatus::frame) continue;
      int dropped = 0;
      filling = pool->publish(filling, drop, dropped);
      std::uint64_t total_dropped = 0;
      {
        // Counted once queued, so a reader of the stats never sees a frame that is neither
        // in the queue nor counted as dropped.
        std::lock_guard lock(stats_mutex);
        ++counters.frames_assembled;
        counters.frames_dropped += static_cast<std::uint64_t>(dropped);
        total_dropped = counters.frames_dropped;
      }
      if (dropped > 0) {
        diagnose(DiagnosticKind::frame_dropped,
                 "detector or program behind: dropped the oldest pending frame (" +
                     std::to_string(total_dropped) + " dropped so far)");
      }
      if (filling == nullptr) return;  // stopped while blocked
    }
  }

  void run_detector() {
    while (Slot* slot = pool->pop_for_detection()) {
      detect(detail::FramePool::frame(slot));
      if (pull) {
        pool->push_ready(slot);
      } else {
        deliver_to_callbacks(slot);
      }
    }
    pool->close_ready();
    {
      std::unique_lock lock(done_mutex);
      done_cv.wait(lock, [&] { return reader_done; });
    }
    {
      std::lock_guard lock(stats_mutex);
      counters.finished = true;
    }
    diagnose(DiagnosticKind::finished, stop_requested ? "stopped" : "end of input");
    mark_done(detector_done);
  }

  void detect(LabelledFrame& f) {
    const std::int64_t t0 = steady_now_ns();
    detector.detect(f.frame, f.ground);
    f.timings = FrameTimings{};
    f.timings.detect_ms = ms_since(t0, steady_now_ns());
    f.sensor_index = config.sensor_index;
    if (f.sensor_name != config.sensor_name) f.sensor_name = config.sensor_name;  // once per slot
    std::lock_guard lock(stats_mutex);
    detect_time.record(f.timings.detect_ms);
  }

  // Stamps and counts a frame as it reaches the program; returns its lease. Counting here
  // (not at detection) keeps frames_delivered exact when ready frames are dropped.
  FrameLease hand_out(Slot* slot) {
    LabelledFrame& f = detail::FramePool::frame(slot);
    const bool has_stamp = f.frame.meta.completed_receive_ns > 0;
    if (has_stamp) f.timings.latency_ms = ms_since(f.frame.meta.completed_receive_ns, steady_now_ns());
    const std::uint64_t returns = count_returns(f.frame);
    bool reached_max = false;
    {
      std::lock_guard lock(stats_mutex);
      f.delivered_index = next_index++;
      if (f.frame.meta.end == FrameEnd::silence) {
        ++counters.silence_frames;
        counters.silence_latency_max_ms =
            std::max(counters.silence_latency_max_ms, f.timings.latency_ms);
      } else if (has_stamp) {
        latency.record(f.timings.latency_ms);
      }
      ++counters.frames_delivered;
      counters.incomplete_frames += f.frame.meta.complete ? 0 : 1;
      counters.returns += returns;
      counters.ground_returns += f.ground.ground_returns;
      reached_max = config.max_frames != 0 && next_index >= config.max_frames;
    }
    FrameLease lease = pool->lease(slot);
    if (reached_max) request_stop();
    return lease;
  }

  void deliver_to_callbacks(Slot* slot) {
    const FrameLease lease = hand_out(slot);
    try {
      if (frame_cb) frame_cb(*lease);
      if (lease_cb) lease_cb(lease);
    } catch (const std::exception& e) {
      note_callback_exception(std::string("frame callback threw: ") + e.what());
    } catch (...) {
      note_callback_exception("frame callback threw a non-std exception");
    }
  }

  void note_callback_exception(std::string message) {
    {
      std::lock_guard lock(stats_mutex);
      ++counters.callback_exceptions;
    }
    diagnose(DiagnosticKind::callback_exception, std::move(message));
  }

  void mark_done(bool& flag) {
    {
      std::lock_guard lock(done_mutex);
      flag = true;
    }
    done_cv.notify_all();
  }

  void open_reader() {
    std::unique_ptr<PacketSource> source = std::move(injected_source);
    if (!source) {
      source = config.pcap ? open_pcap_source(*config.pcap) : open_udp_source(config.udp);
    }
    live = source->is_live();
    reader = std::make_unique<CaptureReader>(std::move(source), config.decoder, config.assembler);
    reader->on_warning([this](const std::string& w) { diagnose(DiagnosticKind::warning, w); });
    if (telemetry_cb) {
      reader->on_position([this](const PositionPacket& p) {
        try {
          telemetry_cb(p);
        } catch (const std::exception& e) {
          diagnose(DiagnosticKind::callback_exception,
                   std::string("telemetry callback threw: ") + e.what());
        } catch (...) {
          diagnose(DiagnosticKind::callback_exception, "telemetry callback threw");
        }
      });
    }
  }

  void join() {
    if (std::this_thread::get_id() == detector_thread.get_id() ||
        std::this_thread::get_id() == reader_thread.get_id()) {
      throw std::logic_error("Pipeline::wait() called from a pipeline callback");
    }
    std::lock_guard lock(join_mutex);
    if (reader_thread.joinable()) reader_thread.join();
    if (detector_thread.joinable()) detector_thread.join();
  }
};

Pipeline::Pipeline(PipelineConfig config) : Pipeline(std::move(config), nullptr) {}

Pipeline::Pipeline(PipelineConfig config, std::unique_ptr<PacketSource> source) {
  if (!source)
    config.validate();
  else {
    config.decoder.validate();
    config.assembler.validate();
    if (config.queue_frames < 1) throw std::invalid_argument("queue_frames must be >= 1");
  }
  impl_ = std::make_unique<Impl>(std::move(config));
  impl_->injected_source = std::move(source);
}

Pipeline::~Pipeline() {
  impl_->request_stop();
  impl_->join();
}

void Pipeline::on_frame(FrameCallback callback) { impl_->frame_cb = std::move(callback); }
void Pipeline::on_frame_lease(FrameLeaseCallback callback) {
  impl_->lease_cb = std::move(callback);
}
void Pipeline::on_telemetry(TelemetryCallback callback) {
  impl_->telemetry_cb = std::move(callback);
}
void Pipeline::on_diagnostics(DiagnosticsCallback callback) {
  impl_->diagnostics_cb = std::move(callback);
}

void Pipeline::start() {
  if (impl_->started) throw std::logic_error("Pipeline::start() called twice");
  impl_->started = true;
  impl_->pull = !impl_->frame_cb && !impl_->lease_cb;
  impl_->open_reader();
  {
    std::lock_guard lock(impl_->stats_mutex);
    impl_->counters.live = impl_->live;
    impl_->start_ns = steady_now_ns();
  }
  if (impl_->stop_requested) impl_->request_stop();  // stop() raced ahead of start()
  impl_->reader_thread = std::thread([this] { impl_->run_reader(); });
  impl_->detector_thread = std::thread([this] { impl_->run_detector(); });
}

void Pipeline::stop() { impl_->request_stop(); }

void Pipeline::wait() {
  if (!impl_->started) return;
  impl_->join();
}

bool Pipeline::wait_for(int timeout_ms) {
  if (!impl_->started) return true;
  {
    std::unique_lock lock(impl_->done_mutex);
    const bool done = impl_->done_cv.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] {
      return impl_->reader_done && impl_->detector_done;
    });
    if (!done) return false;
  }
  impl_->join();
  return true;
}

FrameLease Pipeline::next(std::chrono::milliseconds timeout) {
  if (!impl_->started) throw std::logic_error("Pipeline::next() called before start()");
  if (!impl_->pull) {
    throw std::logic_error("Pipeline::next() called while frames go to a frame callback");
  }
  Impl::Slot* slot = impl_->pool->take_ready(timeout);
  if (slot == nullptr) return nullptr;
  return impl_->hand_out(slot);
}

bool Pipeline::at_end() const { return impl_->started && impl_->pool->ready_drained(); }

PipelineStats Pipeline::stats() const { return impl_->snapshot(); }

}  // namespace vlpground
