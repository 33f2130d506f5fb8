#include "incise/incision/incision.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "incise/bspline/knot_vector.h"

using namespace incise;
using namespace incise::incision;
using Catch::Matchers::Contains;

namespace {

// A straight stroke along +x on the plane y = 0 (normal +y), 1 kHz at 5 cm/s, `count` samples after the first.
std::vector<StrokeSample> planeStroke(int count, double t0_s = 0.0) {
  std::vector<StrokeSample> samples;
  for (int k = 0; k <= count; ++k)
    samples.push_back({Eigen::Vector3d(0.00005 * k, 0.0, 0.0), Eigen::Vector3d::UnitY(), t0_s + 0.001 * k});
  return samples;
}

Incision planeIncision(int count, const IncisionOptions& options = {}) {
  const auto samples = planeStroke(count);
  Incision incision(options, samples[0], Eigen::Vector3d::UnitX());
  for (size_t k = 1; k < samples.size(); ++k) REQUIRE(incision.extend(samples[k]) == SampleStatus::Accepted);
  return incision;
}

// The unit normal of column j's rows (Eq. 2: row k - row k + 1 = beta_j N_j), read from the lattice.
Eigen::Vector3d columnNormal(const Incision& incision, int column) {
  const int n = incision.options().normal_controls;
  return (incision.rest().control(2, column, n / 2 - 1) - incision.rest().control(2, column, n / 2)).normalized();
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

TEST_CASE("incision: the stroke is resampled into stations every spacing", "[cutting]") {
  Incision incision = planeIncision(400);  // 20 mm at 0.5 mm spacing: stations 0 .. 40
  // Laid along the samples smoothed over a spacing of travel: the last station waits for the stroke's end.
  REQUIRE(incision.stationCount() == 40);
  REQUIRE(incision.finalColumns() == incision.options().order - 1 + 39);
  incision.finish();
  REQUIRE(incision.stationCount() == 41);
}

TEST_CASE("incision: the lattice follows Eq. (2) and F0(1/2, v, 1/2) follows the stroke", "[cutting]") {
  const IncisionOptions options;
  const Incision incision = planeIncision(400, options);
  const bspline::BSplineVolume& rest = incision.rest();
  // o knots at u = 1/2: a potential C^-1 discontinuity.
  REQUIRE(bspline::knotMultiplicity(rest.knots(0), 0.5) == options.order);
  // On a plane along +x with normal +y: T = x, N = y, S = T x N = z. The middle plane is the stroke, the
  // planes step by alpha along -S, rows by beta along -N (Eq. 2).
  const int column = options.order - 1 + 20;  // station 20, at x = 10 mm
  const Eigen::Vector3d g(0.010, 0.0, 0.0);
  const int n = options.normal_controls;
  REQUIRE((rest.control(0, column, n / 2) - (g + 2.0 * options.alpha_m * Eigen::Vector3d::UnitZ())).norm() < 1e-15);
  REQUIRE((rest.control(0, column, 0) - rest.control(0, column, n / 2) -
           (n / 2) * options.beta_m * Eigen::Vector3d::UnitY())
              .norm() < 1e-15);
  // Along the middle of the lattice, F0 reproduces the straight stroke (uniform B-splines have linear precision).
  for (double v = incision.startV() + 1.0; v < incision.finalEndV() - 1.0; v += 0.37) {
    const Eigen::Vector3d p = rest.evaluate(0.5, v, 0.5);
    REQUIRE(std::abs(p.y()) < 1e-12);
    REQUIRE(std::abs(p.z()) < 1e-12);
    REQUIRE(p.x() == Approx((v - incision.startV()) * options.spacing_m).margin(1e-12));
  }
  // The blade's depth in w: F0(1/2, v, bottomW) lies depth_m below the surface.
  REQUIRE(rest.evaluate(0.5, incision.startV() + 5.0, incision.bottomW()).y() ==
          Approx(-options.depth_m).margin(1e-12));
  // The undeformed lattice's planes are in order along u (-S = -z here), the two cut planes coincide.
  for (int j = 0; j < incision.finalColumns(); ++j)
    for (int i = 0; i + 1 < rest.controlCounts()[0]; ++i)
      REQUIRE(rest.control(i + 1, j, 2).z() <= rest.control(i, j, 2).z());
}

TEST_CASE("incision: the rows' normals turn at most a spacing at their ends, never far from the surface's",
          "[cutting]") {
  // Guards against a faceted scan's normals (jumps of 5-13 degrees from face to face) swinging the rows 6 mm
  // down by a spacing and more from column to column: the walls' strips twisted and crossed each other.
  const IncisionOptions options;
  const double reach_m = (options.normal_controls / 2) * options.beta_m;  // the blade at full depth
  const double max_turn = options.spacing_m / reach_m;
  const double tilt = 5.0 * M_PI / 180.0;
  SECTION("a flat stroke whose normals zigzag by 10 degrees every 3 mm") {
    std::vector<StrokeSample> samples;
    for (int k = 0; k <= 400; ++k) {
      const double a = (k / 60) % 2 ? tilt : -tilt;
      samples.push_back(
          {Eigen::Vector3d(0.00005 * k, 0.0, 0.0), Eigen::Vector3d(0.0, std::cos(a), std::sin(a)), 0.001 * k});
    }
    Incision incision(options, samples[0], Eigen::Vector3d::UnitX());
    for (size_t k = 1; k < samples.size(); ++k) REQUIRE(incision.extend(samples[k]) == SampleStatus::Accepted);
    double largest = 0.0;
    for (int j = options.order; j < incision.finalColumns(); ++j)
      largest = std::max(largest, angleBetween(columnNormal(incision, j - 1), columnNormal(incision, j)));
    REQUIRE(largest <= max_turn + 1e-12);
    REQUIRE(largest > 0.9 * max_turn);  // it does turn, as far as it may
  }
  // A stroke round a cylinder of radius r (its axis z), 0.01 rad a sample, 2 rad in all.
  const auto roundCylinder = [](const IncisionOptions& o, double radius_m) {
    std::vector<StrokeSample> samples;
    for (int k = 0; k <= 200; ++k) {
      const double a = 0.01 * k;
      const Eigen::Vector3d normal(std::sin(a), std::cos(a), 0.0);
      samples.push_back({radius_m * normal, normal, 0.001 * k});
    }
    Incision incision(o, samples[0], Eigen::Vector3d::UnitX());
    for (size_t k = 1; k < samples.size(); ++k) REQUIRE(incision.extend(samples[k]) == SampleStatus::Accepted);
    incision.finish();
    return incision;
  };
  SECTION("a stroke round a cylinder of radius 4 mm, the blade 2.5 mm deep: the rows at most 0.15 rad behind") {
    IncisionOptions shallow = options;
    shallow.depth_m = 0.0025;
    const Incision incision = roundCylinder(shallow, 0.004);
    const int last = options.order - 1 + incision.stationCount() - 1;
    for (int j = options.order - 1; j <= last; ++j) {
      const Eigen::Vector3d g = incision.rest().control(2, j, options.normal_controls / 2);
      const Eigen::Vector3d surface = Eigen::Vector3d(g.x(), g.y(), 0.0).normalized();
      // 0.15 rad from the station's normal, the samples' smoothed, which is within 0.005 of the surface's.
      REQUIRE(angleBetween(columnNormal(incision, j), surface) <= 0.155);
    }
    // The last station is 1.875 rad round (7.5 mm): the rows have turned with the surface.
    REQUIRE(angleBetween(columnNormal(incision, last), Eigen::Vector3d::UnitY()) > 1.875 - 0.155);
  }
  SECTION("round a ridge of radius 2 mm, the blade 4 mm deep: neighbouring rows meet 1.5 depths down") {
    // Rows a spacing apart that turn by more than spacing / depth cross before the blade's depth (the
    // ridge's focal point, 2 mm down): the walls' strips would cross each other. They turn at most
    // spacing / (1.5 depth), so the floor keeps a third of the stations' spacing.
    const Incision incision = roundCylinder(options, 0.002);
    const double fold_turn = options.spacing_m / (1.5 * options.depth_m);
    const int last = options.order - 1 + incision.stationCount() - 1;
    double largest = 0.0;
    for (int j = options.order; j <= last; ++j)
      largest = std::max(largest, angleBetween(columnNormal(incision, j - 1), columnNormal(incision, j)));
    REQUIRE(largest <= fold_turn + 1e-9);
    REQUIRE(largest > 0.9 * fold_turn);  // it turns as fast as it may, behind the surface
  }
  SECTION("a flat stroke: the rows along the samples' normal, exactly") {
    const Incision incision = planeIncision(400, options);
    for (int j = 0; j < incision.finalColumns(); ++j) REQUIRE(columnNormal(incision, j) == Eigen::Vector3d::UnitY());
  }
}

TEST_CASE("incision: the opening grows with the time response and settles at the full width", "[cutting]") {
  const IncisionOptions options;
  Incision incision = planeIncision(400, options);
  std::vector<int> changed;
  const Eigen::Vector3d uvw(0.5, incision.startV() + 12.0, 0.5);  // on the surface, station 12 (t = 12 ms)
  const double t_station_s = 0.012;
  double previous_m = -1.0;
  for (const double dt_s : {0.0, 0.01, 0.02, 0.03, 0.05, 0.2}) {
    incision.updateOpening(t_station_s + dt_s + 0.004, changed);  // +4 ms: every column of the support started
    const double gap_m = (incision.displacementAt(uvw, -1) - incision.displacementAt(uvw, 1)).norm();
    REQUIRE(gap_m >= previous_m);
    previous_m = gap_m;
  }
  // Settled: about the full opening at the surface (the depth profile rounds it a little), symmetric.
  REQUIRE(previous_m == Approx(options.opening_m).epsilon(0.15));
  INFO("minus " << incision.displacementAt(uvw, -1).transpose() << " plus "
                << incision.displacementAt(uvw, 1).transpose());
  REQUIRE((incision.displacementAt(uvw, -1) + incision.displacementAt(uvw, 1)).norm() <=
          1e-10);                                            // up to the lips' epsilon
  REQUIRE(incision.displacementAt(uvw, 2).norm() <= 1e-10);  // the bottom of the cut stays where it was
  // Settled columns do not change again.
  changed.clear();
  incision.updateOpening(0.5, changed);
  incision.updateOpening(0.6, changed);
  changed.clear();
  incision.updateOpening(0.7, changed);
  REQUIRE(changed.empty());
}

TEST_CASE("incision: the displacement vanishes on the lattice's boundary", "[cutting]") {
  Incision incision = planeIncision(400);
  std::vector<int> changed;
  incision.updateOpening(1.0, changed);
  REQUIRE_FALSE(changed.empty());
  for (double v = incision.startV(); v < incision.finalEndV() - 1.0; v += 0.5) {
    REQUIRE(incision.displacement().evaluate(0.0, v, 0.5).norm() == 0.0);
    REQUIRE(incision.displacement().evaluate(1.0, v, 0.5).norm() == 0.0);
    REQUIRE(incision.displacement().evaluate(0.3, v, 1.0).norm() == 0.0);  // below the blade
  }
  // The fully opened lattice keeps the u-order of its control points (Theorem 1).
  bspline::BSplineVolume opened = incision.rest();
  for (int k = 0; k < incision.options().normal_controls; ++k)
    for (int j = 0; j < incision.finalColumns(); ++j)
      for (int i = 0; i < opened.controlCounts()[0]; ++i)
        opened.setControl(i, j, k, opened.control(i, j, k) + incision.displacement().control(i, j, k));
  // On the plane stroke u runs along -z: compare the z order by mirroring.
  for (int k = 0; k < incision.options().normal_controls; ++k)
    for (int j = 0; j < incision.finalColumns(); ++j)
      for (int i = 0; i + 1 < opened.controlCounts()[0]; ++i)
        if (i != 3) REQUIRE(opened.control(i + 1, j, k).z() < opened.control(i, j, k).z());
}

TEST_CASE("incision: grouping samples into calls does not change the lattice", "[cutting]") {
  const auto samples = planeStroke(300);
  Incision one_by_one(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
  for (size_t k = 1; k < samples.size(); ++k) one_by_one.extend(samples[k]);
  Incision in_jumps(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
  for (size_t k = 7; k < samples.size(); k += 7) in_jumps.extend(samples[k]);
  in_jumps.extend(samples.back());
  REQUIRE(one_by_one.stationCount() == in_jumps.stationCount());
  for (int j = 0; j < one_by_one.finalColumns(); ++j)
    for (int k = 0; k < 7; ++k)
      REQUIRE((one_by_one.rest().control(2, j, k) - in_jumps.rest().control(2, j, k)).norm() < 1e-15);
}

TEST_CASE("incision: bad samples and options come back as statuses or load-time errors", "[cutting]") {
  auto samples = planeStroke(50);
  Incision incision(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
  REQUIRE(incision.extend(samples[1]) == SampleStatus::Accepted);
  StrokeSample s = samples[2];
  s.point_m.z() = NAN;
  REQUIRE(incision.extend(s) == SampleStatus::RefusedNaN);
  s = samples[2];
  s.normal.setZero();
  REQUIRE(incision.extend(s) == SampleStatus::RefusedNormal);
  s = samples[1];
  REQUIRE(incision.extend(s) == SampleStatus::SkippedTime);
  s.time_s = samples[2].time_s;
  REQUIRE(incision.extend(s) == SampleStatus::SkippedStill);
  s = samples[2];
  s.point_m.x() = -0.001;
  REQUIRE(incision.extend(s) == SampleStatus::SkippedBackward);
  s = samples[2];
  s.point_m.x() = 0.05;
  REQUIRE(incision.extend(s) == SampleStatus::SkippedJump);
  s = samples[2];
  s.normal = Eigen::Vector3d::UnitX();  // along the step: no side direction
  REQUIRE(incision.extend(s) == SampleStatus::RefusedNormal);
  REQUIRE(incision.extend(samples[2]) == SampleStatus::Accepted);
  incision.finish();
  REQUIRE(incision.extend(samples[3]) == SampleStatus::Ended);

  IncisionOptions bad;
  bad.depth_m = 0.0;
  REQUIRE_THROWS_WITH(Incision::validateOptions(bad), Contains("depth_m = 0"));
  bad = IncisionOptions{};
  bad.depth_m = 0.02;
  REQUIRE_THROWS_WITH(Incision::validateOptions(bad), Contains("depth_m = 0.02") && Contains("below the surface"));
  bad = IncisionOptions{};
  bad.across_controls = 6;
  REQUIRE_THROWS_WITH(Incision::validateOptions(bad), Contains("across_controls = 6"));
  bad = IncisionOptions{};
  bad.opening_m = 0.01;
  REQUIRE_THROWS_WITH(Incision::validateOptions(bad), Contains("Theorem 1"));
  REQUIRE_THROWS_WITH(Incision(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitY()), Contains("blade_direction"));
}

TEST_CASE("incision: a full lattice ends the incision", "[cutting]") {
  IncisionOptions options;
  options.max_columns = 40;
  const auto samples = planeStroke(1000);
  Incision incision(options, samples[0], Eigen::Vector3d::UnitX());
  SampleStatus last = SampleStatus::Accepted;
  for (size_t k = 1; k < samples.size() && last == SampleStatus::Accepted; ++k) last = incision.extend(samples[k]);
  REQUIRE(last == SampleStatus::Ended);
  REQUIRE(incision.finished());
  REQUIRE(incision.finalColumns() <= options.max_columns);
}

namespace {

// Rows beyond x = 5 mm may reach 1 mm deep; records the direction it was asked along.
struct ShallowBeyond5mm final : RowLimit {
  mutable Eigen::Vector3d inward = Eigen::Vector3d::Zero();
  double rowDepth(const Eigen::Vector3d& point_m, const Eigen::Vector3d& direction,
                  double want_m) const noexcept override {
    inward = direction;
    return point_m.x() > 0.005 ? std::min(want_m, 0.001) : want_m;
  }
};

}  // namespace

TEST_CASE("incision: a row limit makes the stations it limits shallower, counted, and a restart keeps it",
          "[cutting]") {
  const IncisionOptions options;
  const auto samples = planeStroke(400);  // 20 mm: stations 0 .. 40 at x = 0, 0.5, .. 20 mm
  Incision incision(options, samples[0], Eigen::Vector3d::UnitX());
  const ShallowBeyond5mm limit;
  incision.limitRows(&limit);
  for (int round = 0; round < 2; ++round) {
    incision.restart(samples[0], Eigen::Vector3d::UnitX());
    for (size_t k = 1; k < samples.size(); ++k) REQUIRE(incision.extend(samples[k]) == SampleStatus::Accepted);
    incision.finish();
    REQUIRE((limit.inward - Eigen::Vector3d(0.0, -1.0, 0.0)).norm() < 1e-12);  // along -N
    REQUIRE(incision.rowLimitedStations() == 30);                              // x = 5.5 .. 20 mm
    // The blade's depth at w = bottomW(): full before 5 mm, 1 mm from 5.5 mm on (station s is v = startV + s).
    const bspline::BSplineVolume& rest = incision.rest();
    const double v0 = incision.startV();
    REQUIRE(rest.evaluate(0.5, v0 + 4.0, incision.bottomW()).y() == Approx(-options.depth_m).margin(1e-12));
    REQUIRE(rest.evaluate(0.5, v0 + 20.0, incision.bottomW()).y() == Approx(-0.001).margin(1e-12));
  }
  incision.limitRows(nullptr);
  incision.restart(samples[0], Eigen::Vector3d::UnitX());
  for (size_t k = 1; k < samples.size(); ++k) REQUIRE(incision.extend(samples[k]) == SampleStatus::Accepted);
  REQUIRE(incision.rowLimitedStations() == 0);
  REQUIRE(incision.rest().evaluate(0.5, incision.startV() + 20.0, incision.bottomW()).y() ==
          Approx(-options.depth_m).margin(1e-12));
}

TEST_CASE("incision: a stroke that turns at a corner sharper than the lattice follows ends there", "[cutting]") {
  // On the plane y = 0: 6 mm along +x, then on at `turn_deg` from it. The columns' frames take a station's
  // tangent across its two neighbours, so a kink of K degrees turns them K/2 at each of two stations.
  const auto kinked = [](double turn_deg, double first_m) {
    const double turn = turn_deg * 3.14159265358979 / 180.0;
    const Eigen::Vector3d second(std::cos(turn), 0.0, std::sin(turn));
    std::vector<StrokeSample> samples;
    const int before = static_cast<int>(std::lround(first_m / 0.00005));
    for (int k = 0; k <= before; ++k)
      samples.push_back({Eigen::Vector3d(0.00005 * k, 0.0, 0.0), Eigen::Vector3d::UnitY(), 0.001 * k});
    const Eigen::Vector3d corner = samples.back().point_m;
    for (int k = 1; k <= 80; ++k)
      samples.push_back({corner + 0.00005 * k * second, Eigen::Vector3d::UnitY(), 0.001 * (before + k)});
    return samples;
  };
  const auto run = [](const std::vector<StrokeSample>& samples, Incision& incision, size_t& ended_at) {
    ended_at = 0;
    for (size_t k = 1; k < samples.size() && ended_at == 0; ++k) {
      const SampleStatus status = incision.extend(samples[k]);
      if (status == SampleStatus::EndedAtCorner)
        ended_at = k;
      else
        REQUIRE(status == SampleStatus::Accepted);
    }
  };
  for (const double turn_deg : {90.0, 110.0}) {
    const auto samples = kinked(turn_deg, 0.006);
    Incision incision(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
    size_t ended_at = 0;
    run(samples, incision, ended_at);
    INFO("kink " << turn_deg << " degrees");
    REQUIRE(ended_at > 120);  // after the corner (sample 120)...
    CHECK(incision.finished());
    CHECK(incision.extend(samples[ended_at + 1]) == SampleStatus::Ended);
    // ...at the first station beyond it, which is not made: the last station is the corner's. The stations'
    // path (the samples smoothed over a spacing) comes to it about a spacing after the samples.
    CHECK(ended_at <= 120 + 30);
    CHECK(incision.stationCount() == 13);  // stations every 0.5 mm from 0 to 6 mm
    CHECK(std::string(toString(SampleStatus::EndedAtCorner)).find("corner") != std::string::npos);
  }
  // Turns one lattice follows (the stations' path, the samples smoothed over a spacing, rounds a kink of 75
  // degrees to 35 degrees or less between neighbouring stations' frames).
  for (const double turn_deg : {30.0, 60.0, 75.0}) {
    const auto samples = kinked(turn_deg, 0.006);
    Incision incision(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
    size_t ended_at = 0;
    run(samples, incision, ended_at);
    CHECK(ended_at == 0);
    CHECK_FALSE(incision.finished());
  }
  {  // a corner the path has turned past before the wound could open (5 stations): the incision goes on
    const auto samples = kinked(90.0, 0.001);
    Incision incision(IncisionOptions{}, samples[0], Eigen::Vector3d::UnitX());
    size_t ended_at = 0;
    run(samples, incision, ended_at);
    CHECK(ended_at == 0);
  }
}
