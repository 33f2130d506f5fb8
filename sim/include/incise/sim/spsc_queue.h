// A bounded lock-free single-producer single-consumer ring buffer: how pose samples travel from a device
// thread (HID, trace player, mouse) to the sim thread without locks, waits or allocation.
//
// Shapes: Capacity >= 1 slots of T, all constructed up front (T default-constructible); a push copies into a
// slot, a pop copies out of it. T's copy assignment must not throw (static_assert) and should not allocate
// (plain data: poses, timestamps, buttons) so that both ends stay real-time safe.
// Threads: exactly one producer thread calls tryPush(); exactly one consumer thread calls tryPop() and
// drainLatest(); sizeApprox() and capacity() may be called from any thread. The two ends may be different
// threads or the same one.
// Cost: O(1) per push or pop (one slot copy); drainLatest is O(1) whatever the backlog (only the newest slot
// is copied). Never blocks, never allocates after construction.
// Failure: tryPush returns false when full, the pops return false / nullopt / 0 when empty; nothing throws.
// The indices count pushes and pops in std::size_t; they would wrap after 2^64 operations (centuries at 1 MHz).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <optional>
#include <type_traits>

namespace incise::sim {

// Head and tail live on separate cache lines, each end caching the other's index, so the ends touch each
// other's line only when the queue looks full (producer) or empty (consumer). Memory order: the producer's
// release store of the tail publishes the slot it wrote; the consumer's release store of the head hands the
// slots it read back to the producer.
template <typename T, std::size_t Capacity>
class SpscQueue {
  static_assert(Capacity >= 1, "SpscQueue needs at least one slot");
  static_assert(std::is_default_constructible_v<T>, "SpscQueue constructs all its slots up front");
  static_assert(std::is_nothrow_copy_assignable_v<T>, "tryPush/tryPop must not throw on the real-time threads");

 public:
  SpscQueue() = default;
  SpscQueue(const SpscQueue&) = delete;
  SpscQueue& operator=(const SpscQueue&) = delete;

  static constexpr std::size_t capacity() noexcept { return Capacity; }

  // Producer thread only. Copies `value` into the queue; false (and nothing changes) when it is full.
  bool tryPush(const T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_cache_ == Capacity) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail - head_cache_ == Capacity) return false;
    }
    slots_[tail % Capacity] = value;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // Consumer thread only. Copies the oldest element into `out` and removes it; false (out untouched) when empty.
  bool tryPop(T& out) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_cache_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head == tail_cache_) return false;
    }
    out = slots_[head % Capacity];
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Consumer thread only. The oldest element, or nullopt when empty.
  std::optional<T> tryPop() noexcept(std::is_nothrow_copy_constructible_v<T>) {
    std::optional<T> out(std::in_place);
    if (!tryPop(*out)) return std::nullopt;
    return out;
  }

  // Consumer thread only. Empties the queue, writing only the newest element into `out` (the sim wants the
  // latest pose, not the backlog). Returns how many elements were removed: 0 means empty, out untouched.
  std::size_t drainLatest(T& out) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    tail_cache_ = tail;
    if (tail == head) return 0;
    out = slots_[(tail - 1) % Capacity];
    head_.store(tail, std::memory_order_release);
    return tail - head;
  }

  // Any thread. The number of queued elements at some instant during the call, in [0, Capacity]; exact when
  // neither end is active.
  std::size_t sizeApprox() const noexcept {
    // Head first: head only grows and never passes tail, so tail read afterwards is >= the head read.
    const std::size_t head = head_.load(std::memory_order_acquire);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    const std::size_t size = tail - head;
    return size > Capacity ? Capacity : size;
  }

 private:
  static constexpr std::size_t kCacheLineBytes = 64;

  // Producer's line: its own index and its last view of the consumer's.
  alignas(kCacheLineBytes) std::atomic<std::size_t> tail_{0};
  std::size_t head_cache_ = 0;
  // Consumer's line.
  alignas(kCacheLineBytes) std::atomic<std::size_t> head_{0};
  std::size_t tail_cache_ = 0;
  alignas(kCacheLineBytes) std::array<T, Capacity> slots_{};
};

}  // namespace incise::sim
