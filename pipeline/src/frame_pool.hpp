// The pipeline's preallocated labelled frames and the queues they move through.
//
// A slot is free, being filled by the reader, pending detection (a bounded FIFO of `depth`),
// being detected, ready for Pipeline::next() (pull mode), or leased to the program. Leases
// are std::shared_ptr<const LabelledFrame> whose control block lives inside the slot (a
// custom allocator), so handing one out allocates nothing; when the last copy of a lease
// goes, the allocator's deallocate() returns the slot to the free list. The pool is shared
// with its leases, so a lease may outlive the Pipeline.
//
// Backpressure (see publish()): with `drop_oldest` the reader never waits: a full detection
// FIFO loses its oldest frame, and when no slot is free the oldest frame waiting for next()
// (else the oldest pending detection) is recycled. Without it the reader waits.
//
// Thread-safety: every method may be called from any thread (one mutex; frame-rate traffic).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "vlpground/pipeline.hpp"

namespace vlpground::detail {

class FramePool : public std::enable_shared_from_this<FramePool> {
 public:
  struct Slot;

  /// `slots` >= depth + 2 frames of `capacity_columns`; `depth` pending detections.
  FramePool(int slots, int depth, int capacity_columns);
  ~FramePool();
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;

  /// The reader's first slot to fill (never blocks: the pool starts all free).
  Slot* first_free();
  /// Queues `filled` for detection and returns the next slot to fill; nullptr when stopped
  /// while waiting. `dropped` receives the number of frames recycled to make room.
  Slot* publish(Slot* filled, bool drop_oldest, int& dropped);
  /// Next slot to detect; blocks. nullptr after stop(), or after close_detection() once
  /// drained.
  Slot* pop_for_detection();
  /// Pull mode: a detected slot waits for take_ready().
  void push_ready(Slot* slot);
  /// Pull mode: the oldest ready slot, waiting up to `timeout`; nullptr on timeout, after
  /// stop(), or after close_ready() once drained.
  Slot* take_ready(std::chrono::milliseconds timeout);
  /// Returns a slot to the free list (also what a lease's last release does).
  void release(Slot* slot);
  /// A lease on `slot` (allocation-free). The slot comes back when every copy is gone.
  std::shared_ptr<const LabelledFrame> lease(Slot* slot);

  void close_detection();  // the reader ended: pop_for_detection() drains, then nullptr
  void close_ready();      // the detector ended: take_ready() drains, then nullptr
  void stop();             // wakes every waiter; queued frames are discarded
  /// True once close_ready() or stop() was called and no ready slot is left.
  [[nodiscard]] bool ready_drained();
  /// Slots not free (being filled, queued, detected, ready or leased); for tests.
  [[nodiscard]] int in_use();

  static LabelledFrame& frame(Slot* slot);

 private:
  // A FIFO of slots in a preallocated ring.
  struct Ring {
    std::vector<Slot*> items;
    std::size_t head = 0, count = 0;
    void push(Slot* s) { items[(head + count++) % items.size()] = s; }
    Slot* pop() {
      Slot* s = items[head];
      head = (head + 1) % items.size();
      --count;
      return s;
    }
    [[nodiscard]] bool full() const { return count == items.size(); }
  };

  Slot* take_free_locked(std::unique_lock<std::mutex>& lock, bool drop_oldest, int& dropped);

  std::vector<std::unique_ptr<Slot>> storage_;
  std::vector<Slot*> free_;  // stack, capacity reserved
  Ring detect_, ready_;
  bool detect_closed_ = false, ready_closed_ = false, stopped_ = false;
  std::mutex mutex_;
  std::condition_variable detect_cv_, ready_cv_, room_cv_;
};

}  // namespace vlpground::detail
