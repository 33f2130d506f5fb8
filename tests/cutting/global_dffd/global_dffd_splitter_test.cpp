// Tests for cutting/global_dffd/src/global_dffd_splitter.cpp (DffdSplitter: the split of a moving model, kept when no
// vertex changed side) and deformSplit's mapping on oneTBB's workers: every frame's split is compared with
// a full split, field by field and bit for bit, and the mapping with map() vertex by vertex.
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>

#include "incise/global_dffd/global_dffd.h"
#include "incise/mesh/shapes.h"

namespace incise::global_dffd {
namespace {

using Model = ModelArrays;

Model moved(const Model& model, const Eigen::Vector3d& offset_m) {
  Model out = model;
  for (auto& p : out.positions_m) p += offset_m;
  return out;
}

// Two vertical bars 36 mm apart (two planes); the spheres below reach across both.
GlobalDffd twoBars() {
  GlobalDffdOptions o;
  o.controls = {32, 16, 8};
  o.margin_m = 0.02;
  o.kernel_width = 4.0;
  o.clearance_m = 0.0005;
  const auto bar = [](double x_m, const char* name) {
    return Obstacle{
        name, mesh::makeCylinder(Eigen::Vector3d(x_m, 0.0, -0.03), Eigen::Vector3d(0.0, 0.0, 0.06), 0.003, 32, 4, 2)};
  };
  return GlobalDffd({bar(-0.018, "left"), bar(0.018, "right")}, o);
}

void requireSameSplit(const DffdSplit& a, const DffdSplit& b) {
  REQUIRE(a.rest_m == b.rest_m);
  REQUIRE(a.faces == b.faces);
  REQUIRE(a.source_vertex == b.source_vertex);
  REQUIRE(a.source_edge == b.source_edge);
  REQUIRE(a.side == b.side);
  REQUIRE(a.plane == b.plane);
  REQUIRE(a.left_open == b.left_open);
  REQUIRE(a == b);  // DffdSplit's own comparison agrees
}

// deformSplit (threads) against map() (this thread), vertex by vertex.
void requireMappedAsMap(const DffdSplit& split, const GlobalDffd& dffd) {
  std::vector<Eigen::Vector3d> out(split.rest_m.size());
  deformSplit(split, dffd, out);
  for (size_t v = 0; v < out.size(); ++v) REQUIRE(out[v] == dffd.map(split.rest_m[v], split.side[v]));
}

}  // namespace

TEST_CASE("global_dffd_splitter: a model moving along the planes keeps its connectivity, same bits as a full split",
          "[cutting]") {
  const GlobalDffd dffd = twoBars();
  const Model sphere = modelArrays(mesh::makeSphere(Eigen::Vector3d(0.0, -0.01, 0.0), 0.022, 4));
  REQUIRE(sphere.positions_m.size() > 2048);  // more than one of deformSplit's blocks
  DffdSplitter splitter;
  for (int frame = 0; frame < 12; ++frame) {
    const Model now = moved(sphere, Eigen::Vector3d(0.0, 0.0017 * frame, 0.0003 * frame));  // y and z only
    const DffdSplit& split = splitter.split(now.positions_m, now.triangles, dffd);
    CHECK(splitter.keptConnectivity() == (frame > 0));
    requireSameSplit(split, splitAtDiscontinuities(now.positions_m, now.triangles, dffd));
    REQUIRE(std::count(split.side.begin(), split.side.end(), 1) > 0);  // both planes cut the sphere
    requireMappedAsMap(split, dffd);
  }
}

TEST_CASE("global_dffd_splitter: a vertex that changes side, or reaches or leaves a plane, splits again", "[cutting]") {
  const GlobalDffd dffd = twoBars();
  const Model sphere = modelArrays(mesh::makeSphere(Eigen::Vector3d(0.0, 0.0, 0.0), 0.022, 3));
  DffdSplitter splitter;
  splitter.split(sphere.positions_m, sphere.triangles, dffd);
  SECTION("the whole model moves across u") {
    const Model across = moved(sphere, Eigen::Vector3d(0.002, 0.0, 0.0));
    requireSameSplit(splitter.split(across.positions_m, across.triangles, dffd),
                     splitAtDiscontinuities(across.positions_m, across.triangles, dffd));
    CHECK_FALSE(splitter.keptConnectivity());
  }
  SECTION("one vertex is put on a plane, moves along it, then leaves it") {
    Model on = sphere;
    on.positions_m[7].x() = dffd.obstacles()[0].u + 2e-11;  // within the snap distance: put on the plane
    requireSameSplit(splitter.split(on.positions_m, on.triangles, dffd),
                     splitAtDiscontinuities(on.positions_m, on.triangles, dffd));
    CHECK_FALSE(splitter.keptConnectivity());
    const Model along = moved(on, Eigen::Vector3d(0.0, 0.001, 0.0));
    requireSameSplit(splitter.split(along.positions_m, along.triangles, dffd),
                     splitAtDiscontinuities(along.positions_m, along.triangles, dffd));
    CHECK(splitter.keptConnectivity());
    Model off = along;
    off.positions_m[7].x() += 1e-6;  // far beyond the snap distance (1e-9 of the box)
    requireSameSplit(splitter.split(off.positions_m, off.triangles, dffd),
                     splitAtDiscontinuities(off.positions_m, off.triangles, dffd));
    CHECK_FALSE(splitter.keptConnectivity());
  }
  SECTION("a vertex that becomes NaN, then a number again") {
    // The vertex of largest x: on the + side of both planes, as a NaN would be if it were taken as a number.
    const auto rightmost = std::max_element(sphere.positions_m.begin(), sphere.positions_m.end(),
                                            [](const auto& a, const auto& b) { return a.x() < b.x(); });
    Model nan = sphere;
    nan.positions_m[static_cast<size_t>(rightmost - sphere.positions_m.begin())].x() =
        std::numeric_limits<double>::quiet_NaN();
    splitter.split(nan.positions_m, nan.triangles, dffd);
    CHECK_FALSE(splitter.keptConnectivity());
    const DffdSplit& back = splitter.split(sphere.positions_m, sphere.triangles, dffd);
    CHECK_FALSE(splitter.keptConnectivity());
    requireSameSplit(back, splitAtDiscontinuities(sphere.positions_m, sphere.triangles, dffd));
  }
  SECTION("other triangles with the same positions") {
    Model flipped = sphere;
    std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
    splitter.split(flipped.positions_m, flipped.triangles, dffd);
    CHECK_FALSE(splitter.keptConnectivity());
  }
  SECTION("a crossing face's four-sided piece whose shorter diagonal changes splits again") {
    // One triangle across the left plane: a alone on the - side, b and c beyond it. Its piece beyond is
    // split along the shorter diagonal, p-c or b-q (p on a-b, q on c-a), which c's move along y changes.
    const double u = dffd.obstacles()[0].u;
    const auto triangle = [&](double y_c_m) {
      return Model{{{u - 0.004, 0.0, 0.0}, {u + 0.004, 0.002, 0.0}, {u + 0.004, y_c_m, 0.001}}, {{0, 1, 2}}};
    };
    const Model long_pc = triangle(0.010), short_pc = triangle(0.001);
    REQUIRE(splitAtDiscontinuities(long_pc.positions_m, long_pc.triangles, dffd).faces.size() == 3);
    REQUIRE(splitAtDiscontinuities(long_pc.positions_m, long_pc.triangles, dffd).faces !=
            splitAtDiscontinuities(short_pc.positions_m, short_pc.triangles, dffd).faces);
    DffdSplitter one;
    one.split(long_pc.positions_m, long_pc.triangles, dffd);
    requireSameSplit(one.split(short_pc.positions_m, short_pc.triangles, dffd),
                     splitAtDiscontinuities(short_pc.positions_m, short_pc.triangles, dffd));
    CHECK_FALSE(one.keptConnectivity());
    const Model nearby = triangle(0.0012);  // the same diagonal: kept
    requireSameSplit(one.split(nearby.positions_m, nearby.triangles, dffd),
                     splitAtDiscontinuities(nearby.positions_m, nearby.triangles, dffd));
    CHECK(one.keptConnectivity());
  }
  SECTION("Openings::Close always splits in full") {
    for (int round = 0; round < 2; ++round) {
      requireSameSplit(splitter.split(sphere.positions_m, sphere.triangles, dffd, Openings::Close),
                       splitAtDiscontinuities(sphere.positions_m, sphere.triangles, dffd, Openings::Close));
      CHECK_FALSE(splitter.keptConnectivity());
    }
  }
  SECTION("a triangle out of range throws, and the next call splits in full") {
    Model bad = sphere;
    bad.triangles[5][0] = static_cast<int>(bad.positions_m.size());
    CHECK_THROWS_AS(splitter.split(bad.positions_m, bad.triangles, dffd), DffdError);
    requireSameSplit(splitter.split(sphere.positions_m, sphere.triangles, dffd),
                     splitAtDiscontinuities(sphere.positions_m, sphere.triangles, dffd));
    CHECK_FALSE(splitter.keptConnectivity());
  }
}

}  // namespace incise::global_dffd
