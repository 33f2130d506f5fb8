// Points in a plain list of tets (physics/src/surface_embedding.cpp: TetLocator) against the model's own
// locator, and a cut surface's vertices embedded on their own side of the cut.
#include "incise/physics/surface_embedding.h"

#include <random>
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
