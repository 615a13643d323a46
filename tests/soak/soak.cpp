// Soak and fault test: a MultiPipeline on loopback fed by the simulator's emitter at 10x real
// time for N seconds, faults injected, every counter checked at the end.
//
//   front (127.0.0.2): an urban capture in strongest mode, then a dual one continuing its
//                      clock (a mode switch mid-stream), then the strongest one again (a
//                      sensor restart: time jumps back), and so on;
//   rear  (127.0.0.3): a traffic-jam capture replayed again and again (a restart each time);
//   both:              loss, reordering, truncated packets and junk datagrams of every size
//                      (0..2199 bytes), interleaved on one data port;
//   stranger (127.0.0.9): datagrams from an address no sensor has.
//
// Fails (exit 1) on a lost counter (every datagram sent must be accounted for: read by the
// router or dropped by the kernel; routed = passed on + wrong size; passed on = decoded by
// the sensor's pipeline + refused by a full queue; decoded = used + skipped), a frame cut
// wrong (a complete frame not spanning one rotation from the cut angle), unexplained time
// going backwards, RSS growth beyond --max-rss-growth-mb after warm-up (a leak), or a crash.
// Prints frames, drops and latency per sensor.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "vlpground/multi_pipeline.hpp"
#include "vlpground/sim/udp_emitter.hpp"

using namespace vlpground;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  double seconds = 60;
  double rate = 10;
  double max_rss_growth_mb = 24;  // 0 = no RSS check (sanitizer builds)
  std::uint64_t seed = 1;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--seconds" && has_value) {
      o.seconds = std::atof(argv[++i]);
    } else if (arg == "--rate" && has_value) {
      o.rate = std::atof(argv[++i]);
    } else if (arg == "--max-rss-growth-mb" && has_value) {
      o.max_rss_growth_mb = std::atof(argv[++i]);
    } else if (arg == "--seed" && has_value) {
      o.seed = std::strtoull(argv[++i], nullptr, 10);
    } else {
      std::fprintf(stderr,
                   "usage: vlpground_soak [--seconds N (60)] [--rate X (10)] "
                   "[--max-rss-growth-mb M (24; 0 = off)] [--seed S]\n");
      std::exit(2);
    }
  }
  if (!(o.seconds > 0) || !(o.rate > 0)) {
    std::fprintf(stderr, "vlpground_soak: --seconds and --rate must be positive\n");
    std::exit(2);
  }
  return o;
}

double rss_mb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t n = sizeof a;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n) != 0) {
    std::perror("vlpground_soak: free port");
    std::exit(1);
  }
  ::close(fd);
  return ntohs(a.sin_port);
}

struct Failures {
  std::vector<std::string> reasons;
  void check(bool ok, const std::string& what) {
    if (!ok) reasons.push_back(what);
  }
};

// Per sensor, on that sensor's detection thread only.
struct FrameChecks {
  std::uint64_t frames = 0, complete = 0, cut_wrong = 0, time_backwards = 0, stream_changes = 0;
  std::uint64_t dual = 0;
  std::int64_t last_time_ns = 0, last_first_time_ns = 0;
  TimeSource last_source = TimeSource::host_clock;
  std::uint64_t next_sequence = 0;
  bool after_change = true;
  std::string first_time_error;
  std::string first_cut_error;

  // A clock re-base: the first GPS time (the simulated captures are from 2023) replaced the
  // host clock after a frame was already out: the frame's time source changes (the step
  // is arbitrary when the sensor clock was blended onto the host clock), or a later GPS
  // hour moves time by whole hours (plus at most a rotation).
  bool rebased(const FrameMeta& m) const {
    if (m.time_source != last_source) return true;
    constexpr std::int64_t kHourNs = 3'600'000'000'000;
    const std::int64_t back = last_first_time_ns - m.first_time_ns;
    const std::int64_t rest = back % kHourNs;
    return back >= kHourNs && (rest < 1'000'000'000 || kHourNs - rest < 1'000'000'000);
  }

  void check(const Frame& f) {
    ++frames;
    const FrameMeta& m = f.meta;
    dual += m.mode == ReturnMode::dual ? 1 : 0;
    if (m.end == FrameEnd::stream_change) ++stream_changes;
    // Time only goes back across a restart: a stream change, or a silence (the emitter or the
    // router stalled across the restart, so the frame in progress ended by the clock first),
    // also when the frame that ended there was dropped (a gap in the sequence numbers).
    const bool gap = m.sequence != next_sequence;
    if (m.first_time_ns < last_time_ns && !after_change && !gap && !rebased(m) &&
        time_backwards++ == 0) {
      char text[160];
      std::snprintf(text, sizeof text, "frame %llu starts %.3f s before the previous one ended",
                    static_cast<unsigned long long>(m.sequence),
                    static_cast<double>(last_time_ns - m.first_time_ns) * 1e-9);
      first_time_error = text;
    }
    last_time_ns = m.last_time_ns;
    last_first_time_ns = m.first_time_ns;
    last_source = m.time_source;
    next_sequence = m.sequence + 1;
    after_change = m.end == FrameEnd::stream_change || m.end == FrameEnd::silence;
    if (!m.complete || m.end != FrameEnd::cut) return;
    ++complete;
    // One rotation from the cut (0 deg) to just before the next: 60/rpm seconds of firings
    // on the 55.296 us grid, first column at the cut, last column just before it.
    const double period_s = 60.0 / m.rpm;
    const double expected_columns = period_s / 55.296e-6;
    const int n = f.columns();
    const double first_az = f.column_azimuth_deg[0];
    const double last_az = f.column_azimuth_deg[static_cast<std::size_t>(n - 1)];
    const double step_deg = 360.0 / expected_columns;
    const bool columns_ok = std::fabs(n - expected_columns) <= 0.01 * expected_columns + 2;
    const bool first_ok = first_az < 2 * step_deg;
    const bool last_ok = last_az > 360.0 - 2 * step_deg;
    const double span_s = static_cast<double>(m.last_time_ns - m.first_time_ns) * 1e-9;
    const bool span_ok = std::fabs(span_s - period_s) <= 0.02 * period_s;
    if (columns_ok && first_ok && last_ok && span_ok) return;
    if (cut_wrong++ == 0) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "frame %llu: %d columns (expected %.0f), azimuth %.2f..%.2f deg, %.4f s "
                    "(expected %.4f)",
                    static_cast<unsigned long long>(m.sequence), n, expected_columns, first_az,
                    last_az, span_s, period_s);
      first_cut_error = text;
    }
  }
};

sim::Simulator make_sim(sim::SceneKind scene, ReturnMode mode, std::uint64_t seed,
                        std::int64_t start_utc_ns = sim::kDefaultStartUtcNs) {
  sim::SimConfig c;
  c.scene = scene;
  c.mode = mode;
  c.seed = seed;
  c.frames = 10;  // 1 s of capture: 0.1 s at 10x, so modes and restarts change often
  c.start_utc_ns = start_utc_ns;
  return sim::Simulator(c);
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  const std::uint16_t data_port = free_port();
  std::uint16_t position_port = free_port();
  while (position_port == data_port) position_port = free_port();

  std::fprintf(stderr, "soak: preparing captures\n");
  const sim::Simulator strongest = make_sim(sim::SceneKind::urban, ReturnMode::strongest, 1);
  const std::int64_t strongest_end_ns =
      sim::kDefaultStartUtcNs +
      static_cast<std::int64_t>(strongest.packet_count()) * strongest.packet_period_ns();
  sim::PreparedStream front_strongest(strongest);
  sim::PreparedStream front_dual(
      make_sim(sim::SceneKind::urban, ReturnMode::dual, 3, strongest_end_ns));
  sim::PreparedStream rear(make_sim(sim::SceneKind::jam, ReturnMode::strongest, 2));

  MultiPipelineConfig config;
  config.bind_address = "127.0.0.1";
  config.sensors = {parse_sensor_spec("front=127.0.0.2:" + std::to_string(data_port)),
                    parse_sensor_spec("rear=127.0.0.3:" + std::to_string(data_port) +
                                      "@-2.0,0,0.2,0,0,180")};
  for (SensorConfig& s : config.sensors) s.position_port = position_port;
  config.receive_buffer_bytes = 16 * 1024 * 1024;
  MultiPipeline multi(config);
  FrameChecks checks[2];
  multi.on_frame([&](const LabelledFrame& f) { checks[f.sensor_index].check(f.frame); });
  std::atomic<std::uint64_t> warnings{0};
  multi.on_diagnostics([&](std::size_t, const Diagnostic& d) {
    if (d.kind == DiagnosticKind::warning) ++warnings;
  });
  multi.start();

  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(options.seconds));
  auto running = [&] { return Clock::now() < deadline; };
  auto stop_now = [&] { return !running(); };
  sim::UdpStreamConfig base;
  base.data_port = data_port;
  base.position_port = position_port;
  base.rate = options.rate;
  base.faults = {.loss = 0.002, .reorder = 0.002, .truncate = 0.002, .junk = 0.03, .seed = 0};

  sim::UdpStreamStats sent_front, sent_rear;
  std::uint64_t plays_front = 0, plays_rear = 0;
  std::thread front_thread([&] {
    sim::UdpStreamConfig c = base;
    c.source_address = "127.0.0.2";
    while (running()) {
      c.faults.seed = options.seed * 1000 + plays_front++;
      sent_front += ((plays_front % 2) != 0 ? front_strongest : front_dual).play(c, stop_now);
    }
  });
  std::thread rear_thread([&] {
    sim::UdpStreamConfig c = base;
    c.source_address = "127.0.0.3";
    while (running()) {
      c.faults.seed = options.seed * 2000 + plays_rear++;
      sent_rear += rear.play(c, stop_now);
    }
  });
  std::uint64_t stranger_sent = 0;
  std::thread stranger_thread([&] {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in self{}, to{};
    self.sin_family = to.sin_family = AF_INET;
    inet_pton(AF_INET, "127.0.0.9", &self.sin_addr);
    inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    to.sin_port = htons(data_port);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&self), sizeof self) != 0) return;
    std::vector<std::uint8_t> packet(1206, 0xEE);
    while (running()) {
      if (::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&to),
                   sizeof to) == static_cast<ssize_t>(packet.size())) {
        ++stranger_sent;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));  // pacing, not synchronisation
    }
    ::close(fd);
  });

  // RSS after warm-up (pools, queues, detector workspaces grown), then at the end.
  const auto warm = start + (deadline - start) / 5;
  std::this_thread::sleep_until(warm);
  const double rss_warm = rss_mb();
  front_thread.join();
  rear_thread.join();
  stranger_thread.join();
  const double rss_end = rss_mb();

  const std::uint64_t sent = sent_front.datagrams() + sent_rear.datagrams() + stranger_sent;
  const auto drain_deadline = Clock::now() + std::chrono::seconds(10);
  while (Clock::now() < drain_deadline) {  // the router reads what is still in the sockets
    const UdpRouterCounters r = multi.stats().router;
    if (r.records + r.kernel_drops >= sent) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  multi.stop();
  Failures fail;
  fail.check(multi.wait_for(30'000), "the pipelines did not end within 30 s of stop()");
  const MultiPipelineStats stats = multi.stats();
  const double elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();

  // Every datagram accounted for.
  const UdpRouterCounters& router = stats.router;
  fail.check(router.records + router.kernel_drops == sent,
             "sent " + std::to_string(sent) + " datagrams, router read " +
                 std::to_string(router.records) + " + kernel dropped " +
                 std::to_string(router.kernel_drops));
  fail.check(router.accounted() == router.records, "router: datagrams not in any counter");
  // The kernel's drops (a full socket buffer) cannot be told apart by sender: the stranger's
  // datagrams read must be those sent, less at most the datagrams the kernel dropped.
  fail.check(router.unknown_source <= stranger_sent &&
                 router.unknown_source + router.kernel_drops >= stranger_sent,
             "unknown source " + std::to_string(router.unknown_source) + " != stranger sent " +
                 std::to_string(stranger_sent) + " (kernel dropped " +
                 std::to_string(router.kernel_drops) + ")");
  const sim::UdpStreamStats* sent_by[2] = {&sent_front, &sent_rear};
  std::printf("soak: %.0f s at %.0fx real time, 2 sensors on one port, faults injected\n",
              elapsed_s, options.rate);
  std::printf("  datagrams  sent %llu, read %llu, kernel drops %llu, unknown source %llu\n",
              static_cast<unsigned long long>(sent), static_cast<unsigned long long>(router.records),
              static_cast<unsigned long long>(router.kernel_drops),
              static_cast<unsigned long long>(router.unknown_source));
  for (std::size_t i = 0; i < 2; ++i) {
    const SensorStats& s = stats.sensors[i];
    const SourceCounters& routed = router.sensors[i];
    const SourceCounters& read = s.pipeline.capture.source;
    const AssemblerCounters& a = s.pipeline.capture.assembler;
    const FrameChecks& c = checks[i];
    const std::string who = s.name + ": ";
    const sim::UdpStreamStats& tx = *sent_by[i];
    fail.check(routed.records <= tx.datagrams(), who + "more routed than sent");
    fail.check(routed.records == routed.data_packets + routed.position_packets +
                                     routed.skipped_wrong_size,
               who + "routed datagrams not in any counter");
    fail.check(routed.data_packets + routed.position_packets ==
                   read.data_packets + read.position_packets + s.queue_full + s.after_end,
               who + "packets lost between router and pipeline");
    fail.check(read.data_packets == a.packets_used + a.packets_skipped(),
               who + "data packets neither used nor counted as skipped");
    fail.check(s.pipeline.frames_assembled == s.pipeline.frames_delivered + s.pipeline.frames_dropped,
               who + "frames neither delivered nor counted as dropped");
    fail.check(c.frames == s.pipeline.frames_delivered, who + "frames seen != frames delivered");
    fail.check(c.cut_wrong == 0, who + std::to_string(c.cut_wrong) + " frames cut wrong, first: " +
                                     c.first_cut_error);
    fail.check(c.time_backwards == 0,
               who + std::to_string(c.time_backwards) + " frames went back in time, first: " +
                   c.first_time_error);
    fail.check(a.capacity_overflows == 0, who + "frames ran out of columns");
    fail.check(c.complete > 0, who + "no complete frame");
    fail.check(tx.truncated > 0 && tx.junk > 0 && tx.lost > 0 && tx.reordered > 0,
               who + "not every fault was injected");
    if (i == 0) fail.check(c.dual > 0 && c.dual < c.frames, who + "no mode switch seen");
    fail.check(c.stream_changes > 0, who + "no restart seen");
    const LatencyStats& l = s.pipeline.latency;
    std::printf(
        "  %-6s frames %llu delivered (%llu complete, %llu dual, %llu at stream changes), "
        "%llu dropped, %llu incomplete\n"
        "         packets %llu used, %llu skipped (%llu reordered, %llu duplicate), %llu lost "
        "(gaps), queue full %llu; wrong size %llu\n"
        "         sent: %llu data, %llu lost, %llu reordered, %llu truncated, %llu junk\n"
        "         latency p50 %.2f ms, p99 %.2f ms, max %.2f ms; detect p50 %.2f ms\n",
        s.name.c_str(), static_cast<unsigned long long>(s.pipeline.frames_delivered),
        static_cast<unsigned long long>(c.complete), static_cast<unsigned long long>(c.dual),
        static_cast<unsigned long long>(c.stream_changes),
        static_cast<unsigned long long>(s.pipeline.frames_dropped),
        static_cast<unsigned long long>(s.pipeline.incomplete_frames),
        static_cast<unsigned long long>(a.packets_used),
        static_cast<unsigned long long>(a.packets_skipped()),
        static_cast<unsigned long long>(a.reordered_packets),
        static_cast<unsigned long long>(a.duplicate_packets),
        static_cast<unsigned long long>(a.packets_lost),
        static_cast<unsigned long long>(s.queue_full),
        static_cast<unsigned long long>(routed.skipped_wrong_size),
        static_cast<unsigned long long>(tx.data_packets), static_cast<unsigned long long>(tx.lost),
        static_cast<unsigned long long>(tx.reordered), static_cast<unsigned long long>(tx.truncated),
        static_cast<unsigned long long>(tx.junk), l.p50_ms, l.p99_ms, l.max_ms,
        s.pipeline.detect.p50_ms);
  }
  std::printf("  rss        %.1f MB after warm-up, %.1f MB at the end (limit +%.0f MB)\n", rss_warm,
              rss_end, options.max_rss_growth_mb);
  if (options.max_rss_growth_mb > 0) {
    fail.check(rss_end - rss_warm <= options.max_rss_growth_mb,
               "RSS grew by " + std::to_string(rss_end - rss_warm) + " MB");
  }
  if (fail.reasons.empty()) {
    std::printf("soak: PASS\n");
    return 0;
  }
  for (const std::string& r : fail.reasons) std::printf("soak: FAIL: %s\n", r.c_str());
  return 1;
}
