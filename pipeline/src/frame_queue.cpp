#include "frame_queue.hpp"

#include <stdexcept>

namespace vlpground::detail {

FrameQueue::FrameQueue(int depth, int capacity_columns) {
  if (depth < 1) throw std::invalid_argument("FrameQueue: depth must be >= 1");
  const auto pool = static_cast<std::size_t>(depth) + 2;
  storage_.reserve(pool);
  free_.reserve(pool);
  for (std::size_t i = 0; i < pool; ++i) {
    storage_.push_back(std::make_unique<Frame>(capacity_columns));
    free_.push_back(storage_.back().get());
  }
  pending_.assign(static_cast<std::size_t>(depth), nullptr);
}

Frame* FrameQueue::first_free() {
  std::lock_guard lock(mutex_);
  Frame* f = free_.back();
  free_.pop_back();
  return f;
}

Frame* FrameQueue::push(Frame* full, bool drop_oldest, bool& dropped) {
  dropped = false;
  std::unique_lock lock(mutex_);
  const std::size_t depth = pending_.size();
  if (count_ == depth) {
    if (drop_oldest) {
      free_.push_back(pending_[head_]);
      head_ = (head_ + 1) % depth;
      --count_;
      dropped = true;
    } else {
      not_full_.wait(lock, [&] { return count_ < depth || stopped_; });
      if (stopped_) return nullptr;
    }
  }
  pending_[(head_ + count_) % depth] = full;
  ++count_;
  Frame* next = free_.back();  // invariant: never empty here (see header)
  free_.pop_back();
  lock.unlock();
  not_empty_.notify_one();
  return next;
}

Frame* FrameQueue::pop() {
  std::unique_lock lock(mutex_);
  not_empty_.wait(lock, [&] { return count_ > 0 || stopped_ || closed_; });
  if (stopped_ || count_ == 0) return nullptr;
  Frame* f = pending_[head_];
  head_ = (head_ + 1) % pending_.size();
  --count_;
  lock.unlock();
  not_full_.notify_one();
  return f;
}

void FrameQueue::release(Frame* frame) {
  std::lock_guard lock(mutex_);
  free_.push_back(frame);
}

void FrameQueue::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  not_empty_.notify_all();
}

void FrameQueue::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  not_empty_.notify_all();
  not_full_.notify_all();
}

}  // namespace vlpground::detail
