#include "frame_pool.hpp"

#include <cstddef>
#include <new>
#include <stdexcept>

namespace vlpground::detail {

struct FramePool::Slot {
  explicit Slot(int capacity_columns) : labelled(capacity_columns) {}
  LabelledFrame labelled;
  // The lease's shared_ptr control block (pointer, two counts, deleter, allocator: about
  // 48 bytes with libstdc++); larger blocks fall back to the heap.
  alignas(std::max_align_t) std::byte control[128];
};

namespace {

struct NoDelete {
  void operator()(const LabelledFrame*) const noexcept {}
};

// Places a lease's control block in its slot; its deallocate() (the control block's last
// act) hands the slot back to the pool, so the slot is never reused while the block lives.
template <class T>
struct SlotAllocator {
  using value_type = T;
  std::shared_ptr<FramePool> pool;
  FramePool::Slot* slot = nullptr;
  std::byte* control = nullptr;

  SlotAllocator(std::shared_ptr<FramePool> p, FramePool::Slot* s, std::byte* c)
      : pool(std::move(p)), slot(s), control(c) {}
  template <class U>
  SlotAllocator(const SlotAllocator<U>& other)  // NOLINT: implicit, as allocators rebind
      : pool(other.pool), slot(other.slot), control(other.control) {}

  T* allocate(std::size_t n) {
    if (n * sizeof(T) <= 128 && alignof(T) <= alignof(std::max_align_t)) {
      return reinterpret_cast<T*>(control);
    }
    return static_cast<T*>(::operator new(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept {
    if (reinterpret_cast<std::byte*>(p) != control) ::operator delete(p);
    pool->release(slot);
  }
  template <class U>
  bool operator==(const SlotAllocator<U>& other) const noexcept {
    return slot == other.slot;
  }
};

}  // namespace

FramePool::FramePool(int slots, int depth, int capacity_columns) {
  if (depth < 1 || slots < depth + 2) {
    throw std::invalid_argument("FramePool: needs depth >= 1 and slots >= depth + 2");
  }
  const auto count = static_cast<std::size_t>(slots);
  storage_.reserve(count);
  free_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    storage_.push_back(std::make_unique<Slot>(capacity_columns));
    free_.push_back(storage_.back().get());
  }
  detect_.items.assign(static_cast<std::size_t>(depth), nullptr);
  ready_.items.assign(count, nullptr);
}

FramePool::~FramePool() = default;

LabelledFrame& FramePool::frame(Slot* slot) { return slot->labelled; }

FramePool::Slot* FramePool::first_free() {
  std::unique_lock lock(mutex_);
  int dropped = 0;
  return take_free_locked(lock, false, dropped);
}

FramePool::Slot* FramePool::publish(Slot* filled, bool drop_oldest, int& dropped) {
  dropped = 0;
  std::unique_lock lock(mutex_);
  if (detect_.full()) {
    if (drop_oldest) {
      free_.push_back(detect_.pop());
      ++dropped;
    } else {
      room_cv_.wait(lock, [&] { return !detect_.full() || stopped_; });
      if (stopped_) return nullptr;
    }
  }
  detect_.push(filled);
  detect_cv_.notify_one();
  return take_free_locked(lock, drop_oldest, dropped);
}

// With drop_oldest a slot is always found: the detection FIFO holds at least the frame
// just published.
FramePool::Slot* FramePool::take_free_locked(std::unique_lock<std::mutex>& lock,
                                             bool drop_oldest, int& dropped) {
  if (free_.empty() && drop_oldest) {
    free_.push_back(ready_.count > 0 ? ready_.pop() : detect_.pop());
    ++dropped;
  }
  room_cv_.wait(lock, [&] { return !free_.empty() || stopped_; });
  if (stopped_) return nullptr;
  Slot* slot = free_.back();
  free_.pop_back();
  return slot;
}

FramePool::Slot* FramePool::pop_for_detection() {
  std::unique_lock lock(mutex_);
  detect_cv_.wait(lock, [&] { return detect_.count > 0 || stopped_ || detect_closed_; });
  if (stopped_ || detect_.count == 0) return nullptr;
  Slot* slot = detect_.pop();
  room_cv_.notify_one();
  return slot;
}

void FramePool::push_ready(Slot* slot) {
  {
    std::lock_guard lock(mutex_);
    ready_.push(slot);
  }
  ready_cv_.notify_one();
}

FramePool::Slot* FramePool::take_ready(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_cv_.wait_for(lock, timeout, [&] { return ready_.count > 0 || stopped_ || ready_closed_; });
  if (stopped_ || ready_.count == 0) return nullptr;
  return ready_.pop();
}

void FramePool::release(Slot* slot) {
  {
    std::lock_guard lock(mutex_);
    free_.push_back(slot);
  }
  room_cv_.notify_one();
}

std::shared_ptr<const LabelledFrame> FramePool::lease(Slot* slot) {
  return std::shared_ptr<const LabelledFrame>(
      &slot->labelled, NoDelete{}, SlotAllocator<char>(shared_from_this(), slot, slot->control));
}

void FramePool::close_detection() {
  {
    std::lock_guard lock(mutex_);
    detect_closed_ = true;
  }
  detect_cv_.notify_all();
}

void FramePool::close_ready() {
  {
    std::lock_guard lock(mutex_);
    ready_closed_ = true;
  }
  ready_cv_.notify_all();
}

void FramePool::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  detect_cv_.notify_all();
  ready_cv_.notify_all();
  room_cv_.notify_all();
}

bool FramePool::ready_drained() {
  std::lock_guard lock(mutex_);
  return stopped_ || (ready_closed_ && ready_.count == 0);
}

int FramePool::in_use() {
  std::lock_guard lock(mutex_);
  return static_cast<int>(storage_.size() - free_.size());
}

}  // namespace vlpground::detail
