#include "vlpground/driver/packet_queue_source.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "packet_filter.hpp"

namespace vlpground {
namespace {

std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct Slot {
  std::array<std::uint8_t, driver_detail::kDataPacketBytes> bytes{};
  std::size_t size = 0;
  PacketKind kind = PacketKind::data;
  SourceAddress source;
  std::int64_t receive_ns = 0;
  std::int64_t steady_receive_ns = 0;
};

}  // namespace

void PushSourceConfig::validate() const {
  if (capacity_packets < 2 || capacity_packets > 1'000'000) {
    throw std::invalid_argument("push source: capacity_packets must be in [2, 1000000], got " +
                                std::to_string(capacity_packets));
  }
}

struct PacketQueueSource::Impl {
  explicit Impl(const PushSourceConfig& c) : config(c) {
    config.validate();
    slots.resize(static_cast<std::size_t>(config.capacity_packets));
  }

  PushSourceConfig config;
  std::vector<Slot> slots;  // ring: `count` queued packets from `head`
  std::size_t head = 0, count = 0;
  bool closed = false, stopped = false;
  std::mutex mutex;
  std::condition_variable not_empty, not_full;

  // Producer-side counts (any thread), folded into `counters` by the reader.
  std::atomic<std::uint64_t> pushed{0}, data{0}, position{0}, wrong_size{0}, full{0};
  SourceCounters counters;
  Slot current;  // the packet handed out by the latest next()

  void refresh_counters() {
    counters.records = pushed.load(std::memory_order_relaxed);
    counters.data_packets = data.load(std::memory_order_relaxed);
    counters.position_packets = position.load(std::memory_order_relaxed);
    counters.skipped_wrong_size = wrong_size.load(std::memory_order_relaxed);
    counters.queue_full = full.load(std::memory_order_relaxed);
  }
};

PacketQueueSource::PacketQueueSource(const PushSourceConfig& config)
    : impl_(std::make_unique<Impl>(config)) {}

PacketQueueSource::~PacketQueueSource() = default;

PushResult PacketQueueSource::push(std::span<const std::byte> payload,
                                   std::int64_t receive_time_ns, PacketPort port,
                                   const SourceAddress& from) {
  Impl& q = *impl_;
  const std::size_t want = port == PacketKind::data ? driver_detail::kDataPacketBytes
                                                    : driver_detail::kPositionPacketBytes;
  if (payload.size() != want) {
    q.pushed.fetch_add(1, std::memory_order_relaxed);
    q.wrong_size.fetch_add(1, std::memory_order_relaxed);
    return PushResult::wrong_size;
  }
  std::unique_lock lock(q.mutex);
  if (q.stopped || q.closed) return PushResult::closed;
  q.pushed.fetch_add(1, std::memory_order_relaxed);
  if (q.count == q.slots.size()) {
    if (!q.config.block_when_full) {
      q.full.fetch_add(1, std::memory_order_relaxed);
      return PushResult::full;
    }
    q.not_full.wait(lock, [&] { return q.count < q.slots.size() || q.stopped || q.closed; });
    if (q.stopped || q.closed) return PushResult::closed;
  }
  Slot& slot = q.slots[(q.head + q.count) % q.slots.size()];
  std::memcpy(slot.bytes.data(), payload.data(), payload.size());
  slot.size = payload.size();
  slot.kind = port;
  slot.source = from;
  slot.receive_ns = receive_time_ns;
  slot.steady_receive_ns = steady_now_ns();
  ++q.count;
  (port == PacketKind::data ? q.data : q.position).fetch_add(1, std::memory_order_relaxed);
  lock.unlock();
  q.not_empty.notify_one();
  return PushResult::queued;
}

void PacketQueueSource::close() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->closed = true;
  }
  impl_->not_empty.notify_all();
  impl_->not_full.notify_all();
}

SourceStatus PacketQueueSource::next(PacketView& out, int timeout_ms) {
  Impl& q = *impl_;
  std::unique_lock lock(q.mutex);
  const auto ready = [&] { return q.count > 0 || q.stopped || q.closed; };
  if (timeout_ms < 0) {
    q.not_empty.wait(lock, ready);
  } else if (!q.not_empty.wait_for(lock, std::chrono::milliseconds(timeout_ms), ready)) {
    q.refresh_counters();
    return SourceStatus::timeout;
  }
  q.refresh_counters();
  if (q.stopped) return SourceStatus::stopped;
  if (q.count == 0) return SourceStatus::end_of_file;  // closed and drained
  q.current = q.slots[q.head];
  q.head = (q.head + 1) % q.slots.size();
  --q.count;
  lock.unlock();
  q.not_full.notify_one();
  out.bytes = std::span<const std::uint8_t>(q.current.bytes.data(), q.current.size);
  out.kind = q.current.kind;
  out.source = q.current.source;
  out.receive_ns = q.current.receive_ns;
  out.steady_receive_ns = q.current.steady_receive_ns;
  return SourceStatus::packet;
}

void PacketQueueSource::request_stop() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopped = true;
  }
  impl_->not_empty.notify_all();
  impl_->not_full.notify_all();
}

const SourceCounters& PacketQueueSource::counters() const { return impl_->counters; }

bool PacketQueueSource::is_live() const { return !impl_->config.block_when_full; }

std::string PacketQueueSource::describe() const {
  return "push queue (" + std::to_string(impl_->slots.size()) + " packets, " +
         (impl_->config.block_when_full ? "blocking" : "refusing") + " when full)";
}

std::uint64_t PacketQueueSource::queue_full_count() const {
  return impl_->full.load(std::memory_order_relaxed);
}

}  // namespace vlpground
