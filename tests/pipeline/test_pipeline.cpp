#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "fake_source.hpp"
#include "test_data.hpp"
#include "vlpground/driver/capture_reader.hpp"
#include "vlpground/driver/sensor_model.hpp"
#include "vlpground/pipeline.hpp"

using namespace vlpground;
using test::FakeSource;

namespace {

constexpr int kRotations = 12;
constexpr int kPackets = kRotations * FakeSource::kPacketsPerRotation;
constexpr int kShortRotations = 6;  // stop tests: many iterations, short runs
constexpr int kShortPackets = kShortRotations * FakeSource::kPacketsPerRotation;

PipelineConfig fast_config() {
  PipelineConfig c;
  c.detector.hypotheses = 40;  // keep the suite quick; the detector is not under test here
  return c;
}

struct Recorded {
  std::vector<std::uint64_t> sequence;
  std::vector<int> columns;
  std::vector<std::uint64_t> delivered_index;
};

// Frames of the fake capture read directly (no pipeline): the reference.
Recorded read_directly(int packets) {
  CaptureReader reader(std::make_unique<FakeSource>(packets, false));
  Frame frame;
  Recorded r;
  while (reader.next(frame) == ReadStatus::frame) {
    r.sequence.push_back(frame.meta.sequence);
    r.columns.push_back(frame.columns());
  }
  return r;
}

// Bounded wait on a predicate signalled through `cv` (guards against hangs, not a timing test).
template <class Pred>
bool wait_until(std::mutex& m, std::condition_variable& cv, Pred pred) {
  std::unique_lock lock(m);
  return cv.wait_for(lock, std::chrono::seconds(30), pred);
}

}  // namespace

TEST_CASE("replay delivers every frame in order, labelled") {
  const Recorded expected = read_directly(kPackets);
  REQUIRE(expected.sequence.size() >= kRotations - 1);

  Pipeline p(fast_config(), std::make_unique<FakeSource>(kPackets, false));
  Recorded got;
  std::uint64_t labelled_cells = 0;
  p.on_frame([&](const LabelledFrame& f) {
    got.sequence.push_back(f.frame.meta.sequence);
    got.columns.push_back(f.frame.columns());
    got.delivered_index.push_back(f.delivered_index);
    REQUIRE(f.ground.columns == f.frame.columns());
    labelled_cells += f.ground.ground_returns + f.ground.obstacle_returns;
  });
  p.start();
  p.wait();
  CHECK(got.sequence == expected.sequence);
  CHECK(got.columns == expected.columns);
  for (std::size_t i = 0; i < got.delivered_index.size(); ++i) CHECK(got.delivered_index[i] == i);
  const PipelineStats s = p.stats();
  CHECK(s.finished);
  CHECK_FALSE(s.live);
  CHECK(s.frames_dropped == 0);
  CHECK(s.frames_delivered == expected.sequence.size());
  CHECK(s.capture.source.data_packets == static_cast<std::uint64_t>(kPackets));
  CHECK(s.returns == labelled_cells);
  CHECK(s.detect.samples == s.frames_delivered);
  CHECK(s.latency.samples == s.frames_delivered);
  CHECK(s.latency.p50_ms <= s.latency.p99_ms);
  CHECK(s.latency.p99_ms <= s.latency.max_ms);
}

TEST_CASE("an exception in the frame callback is reported and the pipeline goes on") {
  const std::size_t total = read_directly(kPackets).sequence.size();
  Pipeline p(fast_config(), std::make_unique<FakeSource>(kPackets, false));
  std::size_t calls = 0;
  std::vector<std::string> reports;
  p.on_frame([&](const LabelledFrame& f) {
    ++calls;
    if (f.delivered_index == 1) throw std::runtime_error("boom");
    if (f.delivered_index == 3) throw 42;
  });
  p.on_diagnostics([&](const Diagnostic& d) {
    if (d.kind == DiagnosticKind::callback_exception) {
      CHECK(d.code == ErrorCode::callback_exception);
      reports.push_back(d.message);
    }
  });
  p.start();
  p.wait();
  CHECK(calls == total);
  CHECK(p.stats().callback_exceptions == 2);
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].find("boom") != std::string::npos);
}

TEST_CASE("max_frames stops after exactly that many frames") {
  PipelineConfig c = fast_config();
  c.max_frames = 3;
  Pipeline p(c, std::make_unique<FakeSource>(kPackets, false));
  int calls = 0;
  p.on_frame([&](const LabelledFrame&) { ++calls; });
  p.start();
  p.wait();
  CHECK(calls == 3);
}

TEST_CASE("stop() from inside the callback at random frames ends delivery there") {
  const auto total = static_cast<int>(read_directly(kShortPackets).sequence.size());
  std::mt19937 rng(12345);
  for (int iteration = 0; iteration < 12; ++iteration) {
    const int stop_at = std::uniform_int_distribution<int>(0, total - 1)(rng);
    PipelineConfig c = fast_config();
    c.backpressure = Backpressure::block;  // explicit: even the live source loses no frame
    Pipeline p(c, std::make_unique<FakeSource>(kShortPackets, iteration % 2 == 0));
    int calls = 0;
    p.on_frame([&](const LabelledFrame& f) {
      ++calls;
      if (static_cast<int>(f.delivered_index) == stop_at) p.stop();
    });
    p.start();
    p.wait();
    INFO("iteration " << iteration << " stop_at " << stop_at);
    CHECK(calls == stop_at + 1);
    CHECK(p.stats().finished);
    CHECK(p.stats().frames_dropped == 0);
  }
}

TEST_CASE("stop() from another thread at random moments joins cleanly") {
  std::mt19937 rng(777);
  for (int iteration = 0; iteration < 18; ++iteration) {
    auto source = std::make_unique<FakeSource>(kShortPackets, iteration % 2 == 1);
    const FakeSource* raw = source.get();
    Pipeline p(fast_config(), std::move(source));
    std::mutex m;
    std::condition_variable cv;
    std::uint64_t last_index = 0;
    int calls = 0;
    bool ordered = true;
    p.on_frame([&](const LabelledFrame& f) {
      std::lock_guard lock(m);
      if (calls > 0 && f.delivered_index != last_index + 1) ordered = false;
      last_index = f.delivered_index;
      ++calls;
      cv.notify_all();
    });
    bool finished = false;
    p.on_diagnostics([&](const Diagnostic& d) {
      if (d.kind != DiagnosticKind::finished) return;
      std::lock_guard lock(m);
      finished = true;
      cv.notify_all();
    });
    const int frames_before_stop = std::uniform_int_distribution<int>(0, kShortRotations - 2)(rng);
    const int mode = iteration % 3;  // 0: stop, 1: stop + wait, 2: destructor only
    p.start();
    if (frames_before_stop > 0) {
      REQUIRE(wait_until(m, cv, [&] { return calls >= frames_before_stop || finished; }));
    }
    INFO("iteration " << iteration << " stop after " << frames_before_stop << " frames, "
                      << raw->served() << " packets");
    if (mode != 2) p.stop();
    if (mode == 1) {
      p.wait();
      CHECK(p.stats().finished);
    }
    std::lock_guard lock(m);
    CHECK(ordered);
  }
}

TEST_CASE("live sources drop the oldest pending frame when the detector falls behind") {
  const std::size_t total = read_directly(kPackets).sequence.size();
  PipelineConfig c = fast_config();
  c.queue_frames = 2;
  auto source = std::make_unique<FakeSource>(kPackets, true);
  // The reader stops after the first frame until the detector holds it, so the detector's
  // first frame is frame 0 whatever the thread scheduling.
  std::mutex m;
  std::condition_variable cv;
  bool detector_busy = false;
  source->hold_before(2 * FakeSource::kPacketsPerRotation, [&] {
    std::unique_lock lock(m);
    cv.wait(lock, [&] { return detector_busy; });
  });
  Pipeline p(c, std::move(source));
  std::vector<std::uint64_t> sequences;
  std::vector<std::string> drop_reports;
  p.on_frame([&](const LabelledFrame& f) {
    if (f.delivered_index == 0) {
      {
        std::lock_guard lock(m);
        detector_busy = true;
      }
      cv.notify_all();
      // Hold the detector until the reader has queued (or dropped) every frame.
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      while (p.stats().frames_assembled < total && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::yield();
      }
    }
    sequences.push_back(f.frame.meta.sequence);
  });
  p.on_diagnostics([&](const Diagnostic& d) {
    if (d.kind == DiagnosticKind::frame_dropped) {
      CHECK(d.code == ErrorCode::frame_dropped);
      drop_reports.push_back(d.message);
    }
  });
  p.start();
  p.wait();
  const PipelineStats s = p.stats();
  CHECK(s.live);
  CHECK(s.frames_assembled == total);
  // The first frame was being detected; of the rest only the newest `queue_frames` survive.
  REQUIRE(sequences.size() == 3);
  CHECK(sequences[0] == 0);
  CHECK(sequences[1] == total - 2);
  CHECK(sequences[2] == total - 1);
  CHECK(s.frames_dropped == total - 3);
  CHECK(drop_reports.size() == s.frames_dropped);
}

TEST_CASE("replay sources block instead of dropping") {
  const std::size_t total = read_directly(kPackets).sequence.size();
  PipelineConfig c = fast_config();
  c.queue_frames = 1;
  Pipeline p(c, std::make_unique<FakeSource>(kPackets, false));
  std::size_t calls = 0;
  p.on_frame([&](const LabelledFrame&) { ++calls; });
  p.start();
  p.wait();
  CHECK(calls == total);
  CHECK(p.stats().frames_dropped == 0);
}

TEST_CASE("a shared sim capture replays through the pipeline like a CaptureReader") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  PcapSourceConfig sc;
  sc.path = pcap->string();
  std::vector<int> expected;
  {
    CaptureReader reader(open_pcap_source(sc));
    Frame frame;
    while (reader.next(frame) == ReadStatus::frame) expected.push_back(frame.columns());
  }
  PipelineConfig c = fast_config();
  c.source = sc;
  Pipeline p(c);
  std::vector<int> got;
  p.on_frame([&](const LabelledFrame& f) { got.push_back(f.frame.columns()); });
  p.start();
  p.wait();
  CHECK(got == expected);
  CHECK(p.stats().progress == Approx(1.0));
}

TEST_CASE("bad configuration is rejected with a clear message") {
  PipelineConfig c;
  c.queue_frames = 0;
  CHECK_THROWS_WITH(Pipeline(c), Catch::Contains("queue_frames"));
  PipelineConfig missing;
  PcapSourceConfig absent;
  absent.path = "/nonexistent/file.pcap";
  missing.source = absent;
  Pipeline p(missing);
  CHECK_THROWS_AS(p.start(), std::runtime_error);
  try {
    Pipeline again(missing);
    again.start();
    FAIL("opened a missing file");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::cannot_open_file);
    CHECK(e.code().category().name() == std::string("vlpground"));
    CHECK(std::string(e.what()).find("/nonexistent/file.pcap") != std::string::npos);
  }
}

TEST_CASE("errors: every code has a message in the vlpground category") {
  for (int v = static_cast<int>(ErrorCode::cannot_open_file);
       v <= static_cast<int>(ErrorCode::source_failed); ++v) {
    const std::error_code code = static_cast<ErrorCode>(v);
    INFO(v);
    CHECK(code.category() == error_category());
    CHECK(code.message() != "unknown vlpground error");
    CHECK(static_cast<bool>(code));
  }
  CHECK_FALSE(std::error_code{});  // "no error": the `finished` diagnostic's code
}

TEST_CASE("push source config: packets pushed from elsewhere become labelled frames") {
  const Recorded expected = read_directly(kPackets);
  PipelineConfig c = fast_config();
  PushSourceConfig push;
  push.block_when_full = true;  // a recording played in: nothing may be lost
  push.capacity_packets = 64;
  c.source = push;
  Pipeline p(c);
  CHECK(describe(c.source) == "push queue");
  PacketQueueSource& queue = p.packet_queue();
  std::vector<std::uint64_t> sequences;
  bool calibrated = true, host_time = true;
  p.on_frame([&](const LabelledFrame& f) {
    sequences.push_back(f.frame.meta.sequence);
    calibrated = calibrated && f.frame.meta.calibration != nullptr &&
                 f.frame.meta.calibration->source == "built-in";
    host_time = host_time && f.frame.meta.time_source == TimeSource::host_clock;
  });
  p.start();
  std::thread feeder([&] {
    FakeSource packets(kPackets, false);  // the "other middleware"
    PacketView view;
    while (packets.next(view, 0) == SourceStatus::packet) {
      queue.push(std::as_bytes(view.bytes), view.receive_ns, view.kind);
    }
    queue.close();
  });
  p.wait();
  feeder.join();
  CHECK(sequences == expected.sequence);
  CHECK(calibrated);
  CHECK(host_time);
  CHECK(p.stats().capture.source.queue_full == 0);
  CHECK_FALSE(p.stats().live);
}

TEST_CASE("push source config: a full queue is reported once with its code and counted") {
  PipelineConfig c = fast_config();
  PushSourceConfig push;
  push.capacity_packets = 8;  // refuses when full: a live feed
  c.source = push;
  Pipeline p(c);
  std::vector<std::error_code> codes;
  p.on_diagnostics([&](const Diagnostic& d) {
    if (d.kind == DiagnosticKind::warning) codes.push_back(d.code);
  });
  p.on_frame([](const LabelledFrame&) {});
  // Fill the queue before start(): the reader cannot have drained it yet.
  FakeSource packets(20, false);
  PacketView view;
  std::uint64_t refused = 0;
  while (packets.next(view, 0) == SourceStatus::packet) {
    refused += p.packet_queue().push(std::as_bytes(view.bytes), view.receive_ns, view.kind) ==
               PushResult::full;
  }
  p.packet_queue().close();
  p.start();
  p.wait();
  CHECK(refused == 12);
  CHECK(p.stats().capture.source.queue_full == 12);
  CHECK(std::count(codes.begin(), codes.end(), make_error_code(ErrorCode::queue_full)) == 1);
  CHECK(p.stats().live);
  CHECK_THROWS_AS(Pipeline(fast_config()).packet_queue(), std::logic_error);
}
