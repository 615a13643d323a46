// A small free list of large objects (frames, detection results): a shared_ptr handed out
// returns its object to the pool when the last reference (often a numpy view) dies, so
// reading frame after frame does not allocate once the pool is warm.
//
// Thread-safety: acquire() and the return path may run on any thread.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace vlpground::python {

template <class T>
class Pool : public std::enable_shared_from_this<Pool<T>> {
 public:
  /// `make` builds a new object when none is free; at most `keep` idle objects are kept.
  static std::shared_ptr<Pool> create(std::function<std::unique_ptr<T>()> make, std::size_t keep) {
    return std::shared_ptr<Pool>(new Pool(std::move(make), keep));
  }

  std::shared_ptr<T> acquire() {
    std::unique_ptr<T> item;
    {
      const std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        item = std::move(free_.back());
        free_.pop_back();
      }
    }
    if (!item) item = make_();
    std::weak_ptr<Pool> weak = this->shared_from_this();
    return std::shared_ptr<T>(item.release(), [weak](T* p) {
      std::unique_ptr<T> owned(p);
      if (const auto pool = weak.lock()) pool->give_back(std::move(owned));
    });
  }

 private:
  Pool(std::function<std::unique_ptr<T>()> make, std::size_t keep)
      : make_(std::move(make)), keep_(keep) {}

  void give_back(std::unique_ptr<T> item) {
    const std::lock_guard lock(mutex_);
    if (free_.size() < keep_) free_.push_back(std::move(item));
  }

  std::function<std::unique_ptr<T>()> make_;
  std::size_t keep_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace vlpground::python
