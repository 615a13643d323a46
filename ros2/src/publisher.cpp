// Slots and the publisher thread. Three slots: one the thread is writing, one waiting for
// it (the newest encoded frame), and one free for the caller to encode into, so publish()
// never waits for DDS.
#include "vlpground/ros2/publisher.hpp"

#include <pthread.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "dds_cloud_writer.hpp"
#include "vlpground/outputs/pointcloud2.hpp"

namespace vlpground::ros2 {
namespace {

constexpr int kSlots = 3;
constexpr int kNone = -1;
constexpr outputs::CloudKind kKinds[3] = {outputs::CloudKind::organized,
                                          outputs::CloudKind::ground_only,
                                          outputs::CloudKind::obstacle_only};

// Threads inherit their creator's signal mask: while this guard lives, the threads created
// (Cyclone DDS's and the publisher thread) get every asynchronous signal blocked, so SIGINT
// and SIGTERM reach the application's own handling instead of killing it from a DDS thread.
class BlockAsyncSignals {
 public:
  BlockAsyncSignals() {
    sigset_t all;
    sigfillset(&all);
    for (const int sync : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGABRT}) sigdelset(&all, sync);
    pthread_sigmask(SIG_BLOCK, &all, &old_);
  }
  ~BlockAsyncSignals() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  BlockAsyncSignals(const BlockAsyncSignals&) = delete;
  BlockAsyncSignals& operator=(const BlockAsyncSignals&) = delete;

 private:
  sigset_t old_{};
};

struct Slot {
  std::array<std::vector<std::uint8_t>, 3> bytes;  // per topic (unused topics stay empty)
  std::array<outputs::CloudShape, 3> shape{};
  std::int64_t stamp_ns = 0;
};

}  // namespace

struct Ros2Publisher::Impl {
  Ros2Config config;
  detail::DdsCloudWriters dds;
  std::array<Slot, kSlots> slots;

  mutable std::mutex mutex;
  std::condition_variable wake;  // a frame is ready, or stopping
  std::condition_variable idle;  // the thread finished a frame
  int writing = kNone, ready = kNone;
  bool stopping = false, finished = false;
  Ros2Stats counts;
  std::thread thread;

  explicit Impl(const Ros2Config& c) : config(c), dds(c) {
    for (Slot& slot : slots) {
      for (std::size_t t = 0; t < 3; ++t) {
        if (dds.has_topic(t)) slot.bytes[t].resize(outputs::max_cloud_bytes(c.capacity_columns));
      }
    }
    thread = std::thread([this] { run(); });
  }

  int free_slot() const {
    for (int s = 0; s < kSlots; ++s) {
      if (s != writing && s != ready) return s;
    }
    return kNone;  // unreachable with three slots and one thread
  }

  void encode(Slot& slot, const Frame& frame, const GroundResult& ground) {
    slot.stamp_ns = frame.meta.first_time_ns;
    const std::size_t needed = outputs::max_cloud_bytes(frame);
    for (std::size_t t = 0; t < 3; ++t) {
      if (!dds.has_topic(t)) continue;
      if (slot.bytes[t].size() < needed) slot.bytes[t].resize(needed);  // warm-up only
      slot.shape[t] = outputs::encode_pointcloud2(frame, ground, kKinds[t], slot.bytes[t]);
    }
  }

  void run() {
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [this] { return ready != kNone || stopping; });
      if (ready == kNone) return;  // stopping with nothing left
      writing = ready;
      ready = kNone;
      idle.notify_all();  // a publish() waiting under WhenBusy::wait may go on
      Slot& slot = slots[static_cast<std::size_t>(writing)];
      lock.unlock();
      bool ok = true;
      for (std::size_t t = 0; t < 3; ++t) {
        if (!dds.has_topic(t)) continue;
        ok = dds.write(t, slot.stamp_ns, slot.shape[t], slot.bytes[t]) ==
                 detail::WriteResult::ok &&
             ok;
      }
      lock.lock();
      writing = kNone;
      if (ok) {
        ++counts.frames_published;
      } else {
        ++counts.write_errors;
      }
      idle.notify_all();
    }
  }

  void stop_thread() {
    {
      std::lock_guard lock(mutex);
      stopping = true;
    }
    wake.notify_all();
    if (thread.joinable()) thread.join();
  }
};

Ros2Publisher::Ros2Publisher(const Ros2Config& config) {
  config.validate();
  const BlockAsyncSignals in_created_threads;
  impl_ = std::make_unique<Impl>(config);
}

Ros2Publisher::~Ros2Publisher() {
  finish(0);
  impl_->stop_thread();
}

void Ros2Publisher::publish(const Frame& frame, const GroundResult& ground) {
  Impl& m = *impl_;
  int slot;
  {
    std::unique_lock lock(m.mutex);
    if (m.finished) throw std::logic_error("Ros2Publisher::publish after finish()");
    ++m.counts.frames_offered;
    if (m.config.when_busy == WhenBusy::wait) {
      m.idle.wait(lock, [&m] { return m.ready == kNone; });
    }
    slot = m.free_slot();
  }
  // The thread touches only the `writing` and `ready` slots: this one is ours.
  m.encode(m.slots[static_cast<std::size_t>(slot)], frame, ground);
  {
    std::lock_guard lock(m.mutex);
    if (m.ready != kNone) ++m.counts.frames_skipped;  // the older waiting frame is dropped
    m.ready = slot;
  }
  m.wake.notify_one();
}

bool Ros2Publisher::wait_for_subscribers(std::uint32_t count, int timeout_ms) {
  return impl_->dds.wait_matched(count, timeout_ms);
}

bool Ros2Publisher::finish(int timeout_ms) {
  Impl& m = *impl_;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  bool drained;
  {
    std::unique_lock lock(m.mutex);
    m.finished = true;
    drained = m.idle.wait_until(lock, deadline,
                                [&m] { return m.ready == kNone && m.writing == kNone; });
  }
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline - std::chrono::steady_clock::now());
  const bool acked = m.dds.wait_for_acks(static_cast<int>(std::max<long>(0, left.count())));
  return drained && acked;
}

Ros2Stats Ros2Publisher::stats() const {
  std::lock_guard lock(impl_->mutex);
  Ros2Stats s = impl_->counts;
  s.matched_subscribers = impl_->dds.matched();
  return s;
}

const Ros2Config& Ros2Publisher::config() const { return impl_->config; }

}  // namespace vlpground::ros2
