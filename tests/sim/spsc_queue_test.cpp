#include <incise/sim/spsc_queue.h>

#include <catch2/catch.hpp>

#include <cstdint>
#include <thread>

using incise::sim::SpscQueue;

TEST_CASE("spsc_queue: elements come out in the order they went in", "[sim]") {
  SpscQueue<int, 8> queue;
  for (int i = 1; i <= 5; ++i) REQUIRE(queue.tryPush(i));
  CHECK(queue.sizeApprox() == 5);
  for (int i = 1; i <= 5; ++i) {
    int out = 0;
    REQUIRE(queue.tryPop(out));
    CHECK(out == i);
  }
  CHECK(queue.sizeApprox() == 0);
}

TEST_CASE("spsc_queue: a full queue refuses pushes and an empty one refuses pops", "[sim]") {
  SpscQueue<int, 4> queue;
  int out = -1;
  CHECK_FALSE(queue.tryPop(out));
  CHECK(out == -1);
  CHECK_FALSE(queue.tryPop().has_value());

  for (int i = 0; i < 4; ++i) REQUIRE(queue.tryPush(i));
  CHECK(queue.sizeApprox() == 4);
  CHECK_FALSE(queue.tryPush(99));  // full: refused, nothing overwritten
  CHECK(queue.sizeApprox() == 4);
  CHECK(queue.tryPop() == std::optional<int>(0));
  CHECK(queue.tryPush(4));  // one slot free again
  CHECK_FALSE(queue.tryPush(5));
  for (int i = 1; i <= 4; ++i) CHECK(queue.tryPop() == std::optional<int>(i));
  CHECK_FALSE(queue.tryPop(out));

  SECTION("the ring wraps around many times without losing order") {
    int next_in = 0;
    int next_out = 0;
    for (int round = 0; round < 100; ++round) {
      while (queue.tryPush(next_in)) ++next_in;
      CHECK(queue.sizeApprox() == 4);
      for (int i = 0; i < 3; ++i) {
        REQUIRE(queue.tryPop(out));
        CHECK(out == next_out++);
      }
    }
  }
}

TEST_CASE("spsc_queue: drainLatest empties the queue and keeps only the newest element", "[sim]") {
  SpscQueue<int, 8> queue;
  int latest = -1;
  CHECK(queue.drainLatest(latest) == 0);
  CHECK(latest == -1);  // untouched when empty
  for (int i = 1; i <= 3; ++i) REQUIRE(queue.tryPush(i));
  CHECK(queue.drainLatest(latest) == 3);
  CHECK(latest == 3);
  CHECK(queue.sizeApprox() == 0);
  CHECK(queue.drainLatest(latest) == 0);
  CHECK(latest == 3);
  // Still usable after a drain, across the wrap.
  for (int i = 10; i < 18; ++i) REQUIRE(queue.tryPush(i));
  CHECK(queue.drainLatest(latest) == 8);
  CHECK(latest == 17);
}

TEST_CASE("spsc_queue: a producer thread's 10^6 sequence numbers all reach a consumer thread, in order", "[sim]") {
  constexpr std::uint64_t kCount = 1'000'000;
  SpscQueue<std::uint64_t, 1024> queue;
  std::uint64_t full_retries = 0;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount; ++i) {
      while (!queue.tryPush(i)) {  // back-pressure: retry until the consumer makes room
        ++full_retries;
        std::this_thread::yield();
      }
    }
  });
  std::uint64_t received = 0;
  std::uint64_t out_of_order = 0;
  std::uint64_t value = 0;
  while (received < kCount) {
    if (!queue.tryPop(value)) {
      std::this_thread::yield();
      continue;
    }
    if (value != received) ++out_of_order;
    ++received;
  }
  producer.join();
  CHECK(received == kCount);
  CHECK(out_of_order == 0);
  CHECK(value == kCount - 1);
  CHECK(queue.sizeApprox() == 0);
  INFO("producer found the queue full " << full_retries << " times");
}
