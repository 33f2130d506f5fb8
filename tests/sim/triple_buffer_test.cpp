#include <incise/sim/triple_buffer.h>

#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <set>
#include <thread>
#include <vector>

using incise::sim::TripleBuffer;

TEST_CASE("triple_buffer: the reader sees the initial value until a publish, then the newest value", "[sim]") {
  TripleBuffer<int> buffer(7);
  CHECK(buffer.read() == 7);
  CHECK_FALSE(buffer.update());
  CHECK(buffer.read() == 7);

  buffer.writeSlot() = 1;
  buffer.publish();
  buffer.writeSlot() = 2;
  buffer.publish();  // 1 was never read: the reader skips it
  CHECK(buffer.update());
  CHECK(buffer.read() == 2);
  CHECK_FALSE(buffer.update());  // nothing newer
  CHECK(buffer.read() == 2);

  buffer.publish(3);
  CHECK(buffer.read() == 2);  // not before update()
  CHECK(buffer.update());
  CHECK(buffer.read() == 3);
}

TEST_CASE("triple_buffer: the writer's slot is never the one the reader holds", "[sim]") {
  TripleBuffer<int> buffer;
  for (int i = 0; i < 50; ++i) {
    CHECK(&buffer.writeSlot() != &buffer.read());
    buffer.writeSlot() = i;
    if (i % 3 != 0) buffer.publish();
    CHECK(&buffer.writeSlot() != &buffer.read());
    if (i % 2 == 0) buffer.update();
  }
}

TEST_CASE("triple_buffer: large values are published without reallocating their storage", "[sim]") {
  std::vector<double> initial;
  initial.reserve(10'000);
  TripleBuffer<std::vector<double>> buffer(initial);
  std::set<const double*> storage;
  for (int i = 0; i < 100; ++i) {
    std::vector<double>& slot = buffer.writeSlot();
    slot.assign(10'000, static_cast<double>(i));  // fits the reserved capacity: no allocation
    storage.insert(slot.data());
    buffer.publish();
    if (i % 2 == 0) {
      REQUIRE(buffer.update());
      CHECK(buffer.read().size() == 10'000);
      CHECK(buffer.read().front() == static_cast<double>(i));
    }
  }
  // Only the three buffers ever reserved: nothing was allocated while publishing.
  CHECK(storage.size() == 3);
}

namespace {

struct Stamp {
  std::uint64_t counter = 0;
  std::array<std::uint64_t, 64> copies{};  // all equal to counter when the value is whole
};

}  // namespace

TEST_CASE("triple_buffer: a reader thread never sees a torn value while a writer thread publishes 10^5", "[sim]") {
  constexpr std::uint64_t kCount = 100'000;
  TripleBuffer<Stamp> buffer;
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= kCount; ++i) {
      Stamp& slot = buffer.writeSlot();
      slot.counter = i;
      slot.copies.fill(i);
      buffer.publish();
    }
  });
  std::uint64_t last = 0;
  std::uint64_t torn = 0;
  std::uint64_t backwards = 0;
  std::uint64_t updates = 0;
  while (last < kCount) {
    if (!buffer.update()) {
      std::this_thread::yield();
      continue;
    }
    ++updates;
    const Stamp& value = buffer.read();
    for (std::uint64_t copy : value.copies)
      if (copy != value.counter) ++torn;
    if (value.counter < last) ++backwards;
    last = value.counter;
  }
  writer.join();
  CHECK(torn == 0);
  CHECK(backwards == 0);
  CHECK(last == kCount);
  CHECK(updates >= 1);
  INFO(updates << " updates for " << kCount << " publishes");
}
