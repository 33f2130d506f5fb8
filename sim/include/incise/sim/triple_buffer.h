// A triple buffer: one writer publishes whole values (the sim's snapshots), one reader takes the newest
// complete one (the viewer, a recorder), neither ever waits for the other and the reader never sees a value
// that is half written.
//
// Shapes: three T, constructed up front (default-constructed, or copies of `initial`).
// Threads: exactly one writer thread calls writeSlot() and publish(); exactly one reader thread at a time
// calls update() and read(). The viewer owns the reader end. A second consumer does not share it: give it
// its own TripleBuffer (the writer publishes into both), or let the one reader copy out what others need.
// Values may be large (std::vector members): publish() and update() only exchange indices, so they never
// copy, allocate or block. writeSlot() returns a slot holding an OLDER value (published two or more
// publishes ago, or the initial one): the writer overwrites it completely, reusing its capacity
// (assign/resize into it), so that after the first few frames filling a slot allocates nothing either.
// Cost: O(1) for publish/update/read. Failure: nothing here throws.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace incise::sim {

// Scheme: three slots. The writer owns one (it fills it), the reader owns one (it reads it), the third is
// the "back" slot. publish() swaps the writer's slot with the back slot and sets a "new data" bit; update()
// swaps the reader's slot with the back slot when that bit is set. Both swaps are one atomic exchange of a
// byte holding the back slot's index and the bit (acq_rel: the writer's stores to a slot happen before the
// reader's loads from it, and the reader's loads happen before the writer reuses the slot).
template <typename T>
class TripleBuffer {
 public:
  // Three default-constructed values; read() returns one of them until the first update() that succeeds.
  TripleBuffer() = default;
  // Three copies of `initial` (e.g. vectors already reserved to their working size, so that the writer's
  // first fills do not allocate); read() returns `initial` until the first successful update().
  explicit TripleBuffer(const T& initial) : slots_{Slot{initial}, Slot{initial}, Slot{initial}} {}

  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  // Writer thread only. The slot to fill before the next publish(); stays the same slot until then.
  T& writeSlot() noexcept { return slots_[write_].value; }

  // Writer thread only. Makes the slot returned by writeSlot() the newest value and hands the writer another
  // slot. Never blocks, never allocates.
  void publish() noexcept {
    const std::uint8_t old = state_.exchange(static_cast<std::uint8_t>(write_ | kNewData), std::memory_order_acq_rel);
    write_ = static_cast<std::uint8_t>(old & kIndexMask);
  }

  // Writer thread only. writeSlot() = value; publish(). Allocates only if T's copy assignment does.
  void publish(const T& value) {
    writeSlot() = value;
    publish();
  }

  // Reader thread only. Takes the newest published value if there is one the reader has not taken yet:
  // true when read() now returns a newer value, false when nothing was published since the last update().
  bool update() noexcept {
    if ((state_.load(std::memory_order_relaxed) & kNewData) == 0) return false;
    // Once set, only this thread clears the bit, so the exchange is sure to get fresh data.
    const std::uint8_t old = state_.exchange(read_, std::memory_order_acq_rel);
    read_ = static_cast<std::uint8_t>(old & kIndexMask);
    return true;
  }

  // Reader thread only. The value taken by the last successful update(); valid until the next update().
  const T& read() const noexcept { return slots_[read_].value; }

 private:
  static constexpr std::size_t kCacheLineBytes = 64;
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kNewData = 0x4;

  // Separate lines, so the writer filling its slot does not slow the reader reading its own.
  struct alignas(kCacheLineBytes) Slot {
    T value{};
  };

  std::array<Slot, 3> slots_{};
  alignas(kCacheLineBytes) std::atomic<std::uint8_t> state_{2};  // back slot 2, no new data
  alignas(kCacheLineBytes) std::uint8_t write_ = 1;              // writer-owned
  alignas(kCacheLineBytes) std::uint8_t read_ = 0;               // reader-owned
};

}  // namespace incise::sim
