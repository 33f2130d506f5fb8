#include "incise/devices/pose_source.h"

#include <catch2/catch.hpp>

#include "trace_fixture.h"

using Catch::Matchers::Contains;
using incise::devices::PoseSample;
using incise::devices::PoseSource;
using incise::devices::VectorPoseSource;

TEST_CASE("pose_source: a VectorPoseSource returns its samples in order, then nullopt for good", "[devices]") {
  const std::vector<PoseSample> samples =
      incise::devices::testing::randomSamples(7, 5, incise::devices::testing::Pressure::Sometimes);
  VectorPoseSource vector_source(samples);
  PoseSource& source = vector_source;
  for (const PoseSample& expected : samples) {
    const std::optional<PoseSample> got = source.next();
    REQUIRE(got);
    CHECK(*got == expected);
  }
  CHECK_FALSE(source.next());
  CHECK_FALSE(source.next());
  CHECK(vector_source.consumed() == samples.size());
  CHECK_THAT(source.describe(), Contains("5 of 5"));
}

TEST_CASE("pose_source: an empty VectorPoseSource ends at once", "[devices]") {
  VectorPoseSource source({});
  CHECK_FALSE(source.next());
}

TEST_CASE("pose_sample: equality compares every field exactly", "[devices]") {
  PoseSample a{.time_s = 1.0,
               .tip_m = {0.1, 0.2, 0.3},
               .orientation = Eigen::Quaterniond(1, 0, 0, 0),
               .buttons = 3,
               .pressure = 0.5};
  CHECK(a == a);
  PoseSample b = a;
  b.time_s = std::nextafter(1.0, 2.0);
  CHECK_FALSE(a == b);
  b = a;
  b.tip_m.z() = 0.30000000000000004;
  CHECK_FALSE(a == b);
  b = a;
  b.orientation = Eigen::Quaterniond(-1, 0, 0, 0);  // same rotation, different sample
  CHECK_FALSE(a == b);
  b = a;
  b.buttons = 1;
  CHECK_FALSE(a == b);
  b = a;
  b.pressure.reset();
  CHECK_FALSE(a == b);
  CHECK(b != a);
}
