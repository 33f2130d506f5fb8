// Points in a plain list of tets (physics/src/surface_embedding.cpp: TetLocator) against the model's own
// locator, and a cut surface's vertices embedded on their own side of the cut.
#include "incise/physics/surface_embedding.h"

#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include <catch2/catch.hpp>

#include "physics_fixture.h"

using namespace incise;
using namespace incise::physics;

namespace {

std::vector<LocatorTet> locatorTets(const tets::TetMesh& mesh, const std::vector<int>& sides = {}) {
  std::vector<LocatorTet> out;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    out.push_back({{mesh.tets[t][0], mesh.tets[t][1], mesh.tets[t][2], mesh.tets[t][3]},
                   {static_cast<int>(t), sides.empty() ? 0 : sides[t]}});
  return out;
}

}  // namespace

TEST_CASE("surface_embedding: a tet locator finds the tets and weights the model's locator finds", "[physics]") {
  const testing::Grid g =
      testing::grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.03), Eigen::Vector3i(4, 2, 6));
  Boundary b;
  b.fixed_boxes = {testing::plane(1, 0.0)};
  const TissueModel model(g.mesh, Material{}, b, ModelOptions{});
  TetLocator locator;
  locator.build(g.mesh.nodes_m, locatorTets(g.mesh));
  REQUIRE(locator.size() == g.mesh.tets.size());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(-0.002, 0.022), y(-0.002, 0.012), z(-0.002, 0.032);
  int inside = 0, outside = 0, none = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(x(random), y(random), z(random));
    const std::optional<Embedded> mine = locator.locate(p, {}, 1e-3), theirs = model.locate(p, {}, 1e-3);
    REQUIRE(mine.has_value() == theirs.has_value());
    if (!mine) {
      ++none;
      continue;
    }
    (mine->outside_m > 0.0 ? outside : inside) += 1;
    CHECK(mine->element.base_tet == theirs->element.base_tet);
    CHECK(mine->nodes == theirs->nodes);
    for (std::size_t k = 0; k < 4; ++k) CHECK(mine->weights[k] == Approx(theirs->weights[k]).margin(1e-12));
    CHECK(mine->outside_m == Approx(theirs->outside_m).margin(1e-15));
    CHECK(embeddedPosition(*mine, g.mesh.nodes_m).isApprox(p, 1e-12));
  }
  INFO(inside << " inside, " << outside << " within 1 mm outside, " << none << " farther");
  CHECK(inside > 1000);
  CHECK(outside > 50);
  CHECK(none > 10);
  // A filter keeps tets out; a point with no admitted tet within reach has none.
  const Eigen::Vector3d centre(0.0101, 0.0051, 0.0151);
  const int holder = locator.locate(centre, {}, 0.0)->element.base_tet;
  const auto others = [&](const ElementInfo& e) { return e.base_tet != holder; };
  const std::optional<Embedded> elsewhere = locator.locate(centre, others, 1e-3);
  REQUIRE(elsewhere);
  CHECK(elsewhere->element.base_tet != holder);
  CHECK_FALSE(locator.locate(Eigen::Vector3d(0.1, 0.1, 0.1), {}, 1e-3));
  CHECK_FALSE(locator.locate(Eigen::Vector3d(NAN, 0.0, 0.0), {}, 1e-3));
}

TEST_CASE("surface_embedding: a tet locator finds the nearest tet several grid cells away", "[physics]") {
  // Cells of about 1 mm (the tets' mean edge) and points up to 6 mm off the block: the search goes out ring
  // by ring of cells and must stop neither before the nearest tet nor at a farther one found first. Against
  // the model's locator, which measures every tet within its reach. A tet farther than max_distance_m is
  // none; an unbounded reach still ends (nothing passes the filter).
  const testing::Grid g =
      testing::grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.006, 0.004, 0.008), Eigen::Vector3i(6, 4, 8));
  Boundary b;
  b.fixed_boxes = {testing::plane(1, 0.0)};
  const TissueModel model(g.mesh, Material{}, b, ModelOptions{});
  TetLocator locator;
  locator.build(g.mesh.nodes_m, locatorTets(g.mesh));
  std::mt19937 random(5);
  std::uniform_real_distribution<double> x(-0.006, 0.012), y(-0.006, 0.010), z(-0.006, 0.014);
  const auto odd = [](const ElementInfo& e) { return e.base_tet % 2 == 1; };
  int far = 0;
  for (int i = 0; i < 1500; ++i) {
    const Eigen::Vector3d p(x(random), y(random), z(random));
    for (const bool filtered : {false, true}) {
      const ElementFilter filter = filtered ? ElementFilter(odd) : ElementFilter();
      const std::optional<Embedded> mine = locator.locate(p, filter, 0.006), theirs = model.locate(p, filter, 0.006);
      INFO("point " << i << " at " << p.transpose() << (filtered ? ", odd tets only" : ""));
      REQUIRE(mine.has_value() == theirs.has_value());
      if (!mine) continue;
      CHECK(mine->outside_m == Approx(theirs->outside_m).margin(1e-15));
      CHECK((embeddedPosition(*mine, g.mesh.nodes_m) - embeddedPosition(*theirs, g.mesh.nodes_m)).norm() < 1e-12);
      far += mine->outside_m > 0.002 ? 1 : 0;
    }
  }
  CHECK(far > 300);  // most of the outside points are more than two cells away
  const Eigen::Vector3d beyond(0.03, 0.03, 0.03);
  CHECK_FALSE(locator.locate(beyond, {}, 0.01));
  const std::optional<Embedded> unbounded = locator.locate(beyond, {}, std::numeric_limits<double>::infinity());
  REQUIRE(unbounded);
  CHECK(unbounded->outside_m == Approx((beyond - Eigen::Vector3d(0.006, 0.004, 0.008)).norm()).epsilon(1e-12));
  CHECK_FALSE(locator.locate(
      beyond, [](const ElementInfo&) { return false; }, std::numeric_limits<double>::infinity()));
}

TEST_CASE("surface_embedding: a tet locator reached by updates answers as one built at once", "[physics]") {
  // The viewer's locator takes the pieces of the base tets a cut changed, not all of them again: the same
  // tets, however entered, give the same tet and weights, also where a point lies on tets equally (a grid
  // node, edge or face shared by several: ties go to the smaller key).
  const testing::Grid g =
      testing::grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.03), Eigen::Vector3i(4, 2, 6));
  std::vector<LocatorTet> all = locatorTets(g.mesh);
  for (std::size_t t = 0; t < all.size(); ++t) all[t].key = static_cast<std::int64_t>(t);
  TetLocator whole, grown;
  whole.build(g.mesh.nodes_m, all);
  // The first half built, a third of it taken out; then put back in reverse order with the second half.
  const std::size_t half = all.size() / 2, third = half / 3;
  std::vector<int> slots, more;
  grown.build(g.mesh.nodes_m, std::span<const LocatorTet>(all).first(half), &slots);
  REQUIRE(slots.size() == half);
  const std::vector<int> removed(slots.begin(), slots.begin() + static_cast<std::ptrdiff_t>(third));
  std::vector<LocatorTet> added(all.rend() - static_cast<std::ptrdiff_t>(third), all.rend());
  added.insert(added.end(), all.begin() + static_cast<std::ptrdiff_t>(half), all.end());
  grown.update(g.mesh.nodes_m, removed, added, more);
  REQUIRE(more.size() == added.size());
  REQUIRE(grown.size() == whole.size());
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(-0.002, 0.022), y(-0.002, 0.012), z(-0.002, 0.032);
  std::uniform_int_distribution<int> node_x(0, 4), node_y(0, 2), node_z(0, 6);
  const auto odd = [](const ElementInfo& e) { return e.base_tet % 2 == 1; };
  int on_nodes = 0;
  for (int i = 0; i < 3000; ++i) {
    // Every third point a grid node (5 mm steps), every third a point on a grid plane, the rest anywhere.
    Eigen::Vector3d p(x(random), y(random), z(random));
    if (i % 3 == 0) p = Eigen::Vector3d(0.005 * node_x(random), 0.005 * node_y(random), 0.005 * node_z(random));
    if (i % 3 == 1) p.x() = 0.005 * node_x(random);
    for (const bool filtered : {false, true}) {
      const ElementFilter filter = filtered ? ElementFilter(odd) : ElementFilter();
      const std::optional<Embedded> a = whole.locate(p, filter, 1e-3), b = grown.locate(p, filter, 1e-3);
      INFO("point " << i << " at " << p.transpose() << (filtered ? ", odd tets only" : ""));
      REQUIRE(a.has_value() == b.has_value());
      if (!a) continue;
      REQUIRE(a->nodes == b->nodes);
      REQUIRE(a->weights == b->weights);
      REQUIRE(a->element.base_tet == b->element.base_tet);
      REQUIRE(a->outside_m == b->outside_m);
      on_nodes += i % 3 == 0 ? 1 : 0;
    }
  }
  CHECK(on_nodes > 1000);
}

TEST_CASE("surface_embedding: a vertex on a cut goes with the tets of its own side", "[physics]") {
  // The grid's tets at x < 10 mm on side -1, the others on side +1 (a cut along the plane x = 10 mm): a
  // vertex on that plane, whose probe lies on one side, is embedded in a tet of that side, whichever side
  // the locator's rounding would give the point itself.
  const testing::Grid g =
      testing::grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.02), Eigen::Vector3i(4, 2, 4));
  std::vector<int> sides;
  for (const auto& t : g.mesh.tets) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const int n : t) c += 0.25 * g.mesh.nodes_m[static_cast<std::size_t>(n)];
    sides.push_back(c.x() < 0.01 ? -1 : +1);
  }
  TetLocator locator;
  locator.build(g.mesh.nodes_m, locatorTets(g.mesh, sides));
  const Eigen::Vector3d on_cut(0.01, 0.0071, 0.0093);
  for (const int side : {-1, +1}) {
    const Eigen::Vector3d beside = on_cut + Eigen::Vector3d(0.001 * side, -0.0005, 0.0);
    const std::optional<Embedded> e = embedSurfaceVertex(locator, on_cut, beside);
    REQUIRE(e);
    CHECK(e->element.side == side);
    CHECK(e->outside_m == 0.0);
    CHECK(embeddedPosition(*e, g.mesh.nodes_m).isApprox(on_cut, 1e-12));
  }
  // The probe: halfway to the neighbours' centroid, behind the normal by a quarter of their spread.
  const std::vector<Eigen::Vector3d> ring = {
      {0.001, 0.0, 0.0}, {-0.001, 0.0, 0.0}, {0.0, 0.0, 0.001}, {0.0, 0.0, -0.001}};
  CHECK(probeBeside(Eigen::Vector3d::Zero(), ring, Eigen::Vector3d(0.0, 3.0, 0.0), 3.0)
            .isApprox(Eigen::Vector3d(0.0, -0.00025, 0.0), 1e-12));
  // Faces whose normals cancel (a fold): the sum's direction is rounding noise; the point goes past the
  // fold's tip, away from the neighbours.
  const std::vector<Eigen::Vector3d> fold = {
      {0.0, 0.001, 0.0}, {0.0, 0.001, 0.0}, {0.0, 0.0, 0.001}, {0.0, 0.0, -0.001}};
  CHECK(probeBeside(Eigen::Vector3d::Zero(), fold, Eigen::Vector3d(2e-25, 0.0, 0.0), 6e-7)
            .isApprox(Eigen::Vector3d(0.0, -0.00025, 0.0), 1e-12));
  CHECK(probeBeside(Eigen::Vector3d::Ones(), {}, Eigen::Vector3d::UnitY(), 1.0) == Eigen::Vector3d::Ones());
}
