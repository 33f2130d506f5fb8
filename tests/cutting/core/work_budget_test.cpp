#include "incise/core/work_budget.h"

#include <catch2/catch.hpp>

using incise::core::WorkBudget;

TEST_CASE("work_budget: units alone end after that many takes", "[cutting]") {
  WorkBudget b(3);
  for (int i = 0; i < 3; ++i) {
    REQUIRE_FALSE(b.spent());
    b.take();
  }
  CHECK(b.spent());
  CHECK_FALSE(b.deadlineHit());
}

TEST_CASE("work_budget: no units and no deadline never end", "[cutting]") {
  for (WorkBudget b : {WorkBudget(0), WorkBudget::unlimited()}) {
    for (int i = 0; i < 100000; ++i) b.take();
    CHECK_FALSE(b.spent());
  }
}

TEST_CASE("work_budget: a deadline that has passed ends it at the next take, whatever the units left", "[cutting]") {
  WorkBudget b(1000, WorkBudget::Clock::now());
  REQUIRE_FALSE(b.spent());  // the clock is read only when a unit is taken
  b.take();
  CHECK(b.spent());
  CHECK(b.deadlineHit());
}

TEST_CASE("work_budget: a deadline far ahead leaves the units in charge", "[cutting]") {
  WorkBudget b(2, WorkBudget::Clock::now() + std::chrono::hours(1));
  b.take();
  CHECK_FALSE(b.spent());
  b.take();
  CHECK(b.spent());
  CHECK_FALSE(b.deadlineHit());
}

TEST_CASE("work_budget: several units at once, what is left, and whether anything was taken", "[cutting]") {
  WorkBudget b(10);
  CHECK(b.untouched());
  CHECK(b.remaining() == 10);
  b.take(4);
  CHECK_FALSE(b.untouched());
  CHECK(b.remaining() == 6);
  b.take(9);  // more than is left: spent, and the overdraft shows
  CHECK(b.spent());
  CHECK(b.remaining() == -3);
  WorkBudget late(100, WorkBudget::Clock::now());
  late.take(2);  // the deadline is read as by take()
  CHECK(late.spent());
  CHECK(late.deadlineHit());
  CHECK_FALSE(late.untouched());
  CHECK(WorkBudget::unlimited().remaining() > 1000000);
}

TEST_CASE("work_budget: a step is afforded when enough is left, or when nothing was done yet", "[cutting]") {
  WorkBudget b(5);
  CHECK(b.affords(9));  // untouched: a step larger than the whole budget still runs
  b.take(2);
  CHECK(b.affords(3));
  CHECK_FALSE(b.affords(4));
}

TEST_CASE("work_budget: work counted in items takes one unit per so many items", "[cutting]") {
  WorkBudget b(2);
  size_t item = 0;
  while (b.takeEvery(item, 4)) ++item;
  CHECK(item == 8);  // items 0-3 on the first unit, 4-7 on the second; item 8 needs a third
  CHECK(b.spent());
  CHECK(b.remaining() == 0);
  WorkBudget all = WorkBudget::unlimited();
  for (size_t i = 0; i < 1000; ++i) REQUIRE(all.takeEvery(i, 3));
}
