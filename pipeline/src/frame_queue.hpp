// Bounded FIFO of preallocated frames between the reader and the detector thread.
//
// The pool holds depth + 2 frames: one being filled by the reader, up to `depth` pending, one
// being detected. So after any push there is always a free frame for the reader; nothing is
// allocated after construction.
//
// Thread-safety: one producer (push) and one consumer (pop/release); stop() and close() from
// any thread.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "vlpground/frame.hpp"

namespace vlpground::detail {

class FrameQueue {
 public:
  FrameQueue(int depth, int capacity_columns);

  /// The reader's first frame to fill. Never blocks.
  Frame* first_free();

  /// Publishes `full`. When the queue is full: with `drop_oldest` the oldest pending frame is
  /// recycled (`dropped` set), else blocks until the consumer makes room. Returns the next
  /// frame to fill, or nullptr when stopped while blocked.
  Frame* push(Frame* full, bool drop_oldest, bool& dropped);

  /// Next pending frame; blocks until one is available. nullptr after stop(), or after
  /// close() once the queue is drained.
  Frame* pop();
  /// Gives a popped frame back to the pool.
  void release(Frame* frame);

  void close();  // no more pushes: pop() drains, then returns nullptr
  void stop();   // wakes every waiter; pending frames are discarded

 private:
  std::vector<std::unique_ptr<Frame>> storage_;
  std::vector<Frame*> free_;     // stack, capacity reserved
  std::vector<Frame*> pending_;  // ring of `depth` entries
  std::size_t head_ = 0, count_ = 0;
  bool closed_ = false, stopped_ = false;
  std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
};

}  // namespace vlpground::detail
