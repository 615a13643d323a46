// What the runners (one sensor: pipeline_runner.cpp, several: multi_runner.cpp) share:
// Ctrl-C and --duration turned into a stop call from a dedicated thread, and the first error
// of any frame sink.
#pragma once

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <ctime>
#include <functional>
#include <mutex>
#include <string>
#include <memory>
#include <thread>
#include <vector>

#include "frontends/frame_sink.hpp"

namespace vlpground::cli {

// Blocks SIGINT/SIGTERM/SIGUSR1 in every thread (call before creating any) and turns them,
// or the deadline, into a stop call from a dedicated thread. SIGUSR1 ends the watcher.
class StopOnSignal {
 public:
  StopOnSignal() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    sigaddset(&set_, SIGUSR1);
    pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  }
  /// `stop` runs on the watcher thread.
  void watch(std::function<void()> stop, double duration_s) {
    thread_ = std::thread([this, stop = std::move(stop), duration_s] {
      using Clock = std::chrono::steady_clock;
      const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                               std::chrono::duration<double>(duration_s));
      bool timed = duration_s > 0;
      while (true) {
        int sig = 0;
        if (timed) {
          const auto left = std::max(deadline - Clock::now(), Clock::duration::zero());
          const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
          const timespec limit{static_cast<time_t>(ns / 1'000'000'000),
                               static_cast<long>(ns % 1'000'000'000)};
          sig = sigtimedwait(&set_, nullptr, &limit);
        } else {
          sig = sigwaitinfo(&set_, nullptr);
        }
        if (sig == SIGUSR1) return;
        if (sig == SIGINT || sig == SIGTERM) {
          interrupted_ = true;
          stop();
        } else if (sig == -1 && errno == EAGAIN) {
          timed = false;  // --duration reached
          stop();
        }
      }
    });
  }
  void finish() {
    if (!thread_.joinable()) return;
    pthread_kill(thread_.native_handle(), SIGUSR1);
    thread_.join();
  }
  ~StopOnSignal() { finish(); }
  [[nodiscard]] bool interrupted() const { return interrupted_; }

 private:
  sigset_t set_{};
  std::thread thread_;
  std::atomic<bool> interrupted_{false};
};

// `--frames N` of replay and live (one sensor or several): N full rotations
// (FrameMeta::complete) unless --partial, when every frame counts. The pipeline's own
// max_frames counts every frame, so it gets N only with --partial; otherwise this counts.
class RotationLimit {
 public:
  RotationLimit(std::uint64_t max_frames, bool partial) : wanted_(partial ? 0 : max_frames) {}
  /// What to put in PipelineConfig::max_frames.
  static std::uint64_t pipeline_max_frames(std::uint64_t max_frames, bool partial) {
    return partial ? max_frames : 0;
  }
  /// On the frame's detection thread: false for a frame that comes after the N-th rotation
  /// (not output); `stop` is called with the N-th.
  bool admit(const FrameMeta& meta, const std::function<void()>& stop) {
    if (wanted_ != 0 && rotations_ >= wanted_) return false;
    if (meta.complete && ++rotations_ == wanted_) stop();
    return true;
  }
  [[nodiscard]] bool counts_rotations() const { return wanted_ != 0; }

 private:
  std::uint64_t wanted_ = 0;  // 0: no limit here
  std::uint64_t rotations_ = 0;
};

// A looped replay whose --frames counts full rotations ends when the file gives none: when,
// at an incomplete frame, the reader has wrapped `queue + 3` more times since the last full
// rotation was seen (a file with a rotation per pass has more than `queue` of them ready by
// then, so at least one would have been delivered).
class LoopWithoutRotation {
 public:
  LoopWithoutRotation(bool active, int queue_frames)
      : active_(active), passes_(static_cast<std::uint64_t>(std::max(queue_frames, 1)) + 3) {}
  /// On the detection thread, per frame; `wraps()` reads the reader's wrap count (called
  /// at incomplete frames only). True once the run is to end.
  template <class Wraps>
  bool check(const FrameMeta& meta, const Wraps& wraps) {
    if (!active_ || ended_) return ended_;
    if (meta.complete) {
      rotation_seen_ = true;
      return false;
    }
    const std::uint64_t now = wraps();
    if (rotation_seen_) {
      since_ = now;  // at or after the rotation: a later baseline only delays the verdict
      rotation_seen_ = false;
    }
    ended_ = now >= since_ + passes_;
    return ended_;
  }
  [[nodiscard]] bool ended() const { return ended_; }

 private:
  bool active_ = false;
  std::uint64_t passes_ = 0;
  bool rotation_seen_ = false;
  std::uint64_t since_ = 0;  // reader's wraps when a full rotation was last seen
  bool ended_ = false;
};

// The first error of any sink; the run stops on it.
class SinkErrors {
 public:
  void record(const std::string& message) {
    std::lock_guard lock(mutex_);
    if (first_.empty()) first_ = message;
  }
  [[nodiscard]] std::string first() const {
    std::lock_guard lock(mutex_);
    return first_;
  }

 private:
  mutable std::mutex mutex_;
  std::string first_;
};

/// Frame sinks of one pipeline; a sink that throws is recorded, left out from then on, and
/// `stop` is called. write() runs on that pipeline's detection thread only.
class SinkSet {
 public:
  explicit SinkSet(std::vector<std::unique_ptr<FrameSink>> sinks) : sinks_(std::move(sinks)) {
    for (auto& s : sinks_) working_.push_back(s.get());
  }
  void write(const LabelledFrame& f, SinkErrors& errors, const std::function<void()>& stop) {
    for (auto*& sink : working_) {
      if (sink == nullptr) continue;
      try {
        sink->write(f);
      } catch (const std::exception& e) {
        errors.record(e.what());
        sink = nullptr;
        stop();
      }
    }
  }
  void on_stats(const PipelineStats& stats) {
    for (auto& sink : sinks_) sink->on_stats(stats);
  }
  /// On the acquisition thread.
  void on_position(const PositionPacket& packet) {
    for (auto& sink : sinks_) sink->on_position(packet);
  }
  /// After the pipeline ended: the final counters (a recording keeps them), then finish, for
  /// the sinks that have not failed.
  void finish(const PipelineStats& final_stats, SinkErrors& errors) {
    for (std::size_t i = 0; i < sinks_.size(); ++i) {
      if (working_[i] == nullptr) continue;  // failed: its error is already recorded
      try {
        sinks_[i]->on_stats(final_stats);
        sinks_[i]->finish();
      } catch (const std::exception& e) {
        errors.record(e.what());
      }
    }
  }

 private:
  std::vector<std::unique_ptr<FrameSink>> sinks_;
  std::vector<FrameSink*> working_;
};

}  // namespace vlpground::cli
