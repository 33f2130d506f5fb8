// Tests for cutting/global_dffd/src/global_dffd*.cpp (the lattice, the split, the openings): a sphere moving along v
// through a cylinder splits around it and re-forms; identity away from the obstacle; a bound split
// re-deforms exactly; Theorem 1's guard; obstacles too close, not monotone, open or outside the lattice
// refused with their name (and DffdError's fields).
#include "incise/global_dffd/global_dffd.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <catch2/catch.hpp>

#include "global_dffd/global_dffd_fixture.h"

#include "incise/mesh/self_intersection.h"
#include "incise/mesh/shapes.h"

namespace incise::global_dffd {
namespace {

using Catch::Matchers::Contains;

using fixture::bar;
using fixture::options;

// Distance from the bar's axis minus its radius (the signed distance to the bar where z is inside it).
double barDistance(const Eigen::Vector3d& p, double x_m = 0.0) { return std::hypot(p.x() - x_m, p.y()) - 0.005; }

TEST_CASE("global_dffd: the discontinuity sits at the obstacle's centre and F is the identity away from it",
          "[cutting]") {
  const GlobalDffd dffd({bar()}, options());
  REQUIRE(dffd.obstacles().size() == 1);
  const DffdObstacle& o = dffd.obstacles()[0];
  CHECK(std::abs(o.u) < 1e-12);
  CHECK(o.i_plus == o.i_minus + 1);
  CHECK(o.max_move_m > 0.005);
  // Far from the bar in u (beyond the kernel's reach) and outside the box: unchanged.
  double worst = 0;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.024, 0.01, 0.0), Eigen::Vector3d(-0.024, -0.015, 0.01),
                                   Eigen::Vector3d(0.1, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 0.2)})
    worst = std::max(worst, (dffd.map(p) - p).norm());
  CHECK(worst <= 1e-12);
  CHECK(dffd.minJacobian() > 0.0);
}

TEST_CASE("global_dffd: a sphere moving through a bar splits around it without penetrating and re-forms", "[cutting]") {
  const GlobalDffd dffd({bar()}, options());
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.012, 3);
  double worst_m = INFINITY;
  int frames_split = 0;
  for (int frame = 0; frame <= 12; ++frame) {
    const double y = -0.04 + 0.08 * frame / 12.0;
    mesh::SurfaceMesh moved = sphere;
    for (const auto v : moved.mesh().vertices()) moved.mesh().point(v)[1] += y;
    const DffdSplit split = splitAtDiscontinuities(moved, dffd);
    const mesh::SurfaceMesh out = deformSplit(split, dffd);
    const int loops = boundaryLoops(out.mesh());
    // The sphere crosses the plane x = 0 in one circle: two lips once it is split, else closed.
    const bool crossing = std::count(split.side.begin(), split.side.end(), 1) > 0;
    CHECK(loops == (crossing ? 2 : 0));
    frames_split += crossing;
    for (const auto v : out.mesh().vertices()) {
      const Eigen::Vector3d p = mesh::toEigen(out.mesh().point(v));
      if (std::abs(p.z()) < 0.03) worst_m = std::min(worst_m, barDistance(p));
    }
    CHECK(worstPenetration(out.mesh(), {bar()}) <= 1e-6);
  }
  // The measure itself: the sphere's own vertices lie inside a sphere one and a half times as large.
  const double depth = worstPenetration(sphere.mesh(), {{"big", mesh::makeSphere(Eigen::Vector3d::Zero(), 0.018, 3)}});
  CHECK(depth > 0.005);
  CHECK(depth < 0.0061);
  INFO("smallest signed distance to the bar " << worst_m);
  CHECK(frames_split >= 5);
  CHECK(worst_m >= -1e-6);
}

TEST_CASE("global_dffd: the open output welds the lips F leaves together: no faces touching across a crack",
          "[cutting]") {
  const GlobalDffd dffd({bar()}, options());
  // Centred on the bar: split all round, two lips (two pieces, each with one opening). Partly where F moved:
  // one opening, a slit whose ends are welded. Beyond the box (F the identity): split, but nothing opens.
  struct Expect {
    double y_m;
    int openings;
  };
  for (const Expect e : {Expect{0.0, 2}, Expect{0.015, 1}, Expect{0.08, 0}}) {
    INFO("sphere centre y " << e.y_m);
    const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, e.y_m, 0.001), 0.012, 3);
    const DffdSplit split = splitAtDiscontinuities(sphere, dffd);
    std::vector<Eigen::Vector3d> positions(split.rest_m.size());
    deformSplit(split, dffd, positions);
    const mesh::SurfaceMesh cracked = split.surface(positions), welded = weldClosedLips(split, positions);
    const size_t touching = mesh::findSelfIntersections(cracked.mesh()).size();
    INFO(touching << " pairs of faces touch across the unwelded crack");
    if (e.y_m > 0.0) CHECK(touching > 0);
    CHECK(mesh::findSelfIntersections(welded.mesh()).empty());
    const mesh::ManifoldReport report = mesh::checkManifold(welded.mesh());
    INFO(report.first_problem);
    CHECK(report.non_manifold_vertices == 0);
    CHECK(report.non_manifold_edges == 0);
    CHECK(boundaryLoops(welded.mesh()) == e.openings);
    CHECK(report.components == (e.openings == 2 ? 2 : 1));
    CHECK(report.euler_characteristic == 2 * report.components - e.openings);  // discs or a sphere with a hole
    CHECK(welded.mesh().n_faces() == split.faces.size());
    CHECK(worstPenetration(welded.mesh(), {bar()}) <= 1e-6);
    // Every output vertex is one of the split's, where deformSplit put it.
    std::vector<Eigen::Vector3d> kept;
    for (const auto v : welded.mesh().vertices()) kept.push_back(mesh::toEigen(welded.mesh().point(v)));
    size_t k = 0;
    for (size_t v = 0; v < positions.size() && k < kept.size(); ++v) k += positions[v] == kept[k];
    CHECK(k == kept.size());
  }
  std::vector<Eigen::Vector3d> too_few(3);
  CHECK_THROWS_AS(
      weldClosedLips(splitAtDiscontinuities(mesh::makeSphere(Eigen::Vector3d::Zero(), 0.012, 2), dffd), too_few),
      DffdError);
}

TEST_CASE("global_dffd: split vertices are duplicated with an index map back to the model", "[cutting]") {
  const GlobalDffd dffd({bar()}, options());
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.012, 2);
  const DffdSplit split = splitAtDiscontinuities(sphere, dffd);
  const mesh::SurfaceMesh split_mesh = split.surface();
  const mesh::TriMesh& m = split_mesh.mesh();
  REQUIRE(split.source_vertex.size() == m.n_vertices());
  int minus = 0, plus = 0;
  for (size_t v = 0; v < m.n_vertices(); ++v) {
    if (split.source_vertex[v] >= 0)  // the model's vertex (snapped onto the plane if within 1e-9 of the box)
      CHECK((mesh::toEigen(m.point(mesh::TriMesh::VertexHandle(static_cast<int>(v)))) -
             mesh::toEigen(sphere.mesh().point(mesh::TriMesh::VertexHandle(split.source_vertex[v]))))
                .norm() <= 1e-9 * dffd.box().sizes().maxCoeff());
    else
      CHECK(split.source_edge[v][0] >= 0);
    if (split.side[v] != 0)
      CHECK(m.point(mesh::TriMesh::VertexHandle(static_cast<int>(v)))[0] == dffd.obstacles()[0].u);
    minus += split.side[v]<0, plus += split.side[v]> 0;
  }
  CHECK(minus == plus);
  CHECK(minus > 10);
  // Every face lies on one side of the plane.
  const double u = dffd.obstacles()[0].u;
  for (const auto f : m.faces()) {
    bool l = false, r = false;
    for (auto v = m.cfv_iter(f); v.is_valid(); ++v) l = l || m.point(*v)[0] < u, r = r || m.point(*v)[0] > u;
    CHECK_FALSE((l && r));
  }
}

TEST_CASE("global_dffd: stitched and capped outputs are closed", "[cutting]") {
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, 0.004, 0.0), 0.012, 3);
  SECTION("stitched: the openings zipped, F's discontinuity planes moved to w_s") {
    GlobalDffd dffd({bar()}, options());
    const DffdSplit split = splitAtDiscontinuities(sphere, dffd, Openings::Close);
    CHECK(split.left_open == 0);
    dffd.stitch(0, stitchLevel(split, dffd, 0));
    const mesh::SurfaceMesh out = deformSplit(split, dffd);
    CHECK(boundaryLoops(out.mesh()) == 0);
    const mesh::ManifoldReport report = mesh::checkManifold(out.mesh());
    INFO(report.first_problem);
    CHECK(report.closed_two_manifold);
    CHECK(worstPenetration(out.mesh(), {bar()}) <= 1e-6);  // the seams stay clear of the bar
    // det J is 0 on the seam (each plane drawn into a curve, up to rounding: about -1e-20), never folded.
    CHECK(dffd.minJacobian() > -1e-9);
  }
  SECTION("capped: the section capped where F separates the sides, closed, none inside the bar") {
    const GlobalDffd dffd({bar()}, options());
    const mesh::SurfaceMesh out = cappedDeform(sphere, dffd);
    const mesh::ManifoldReport report = mesh::checkManifold(out.mesh());
    INFO(report.first_problem);
    CHECK(report.closed_two_manifold);
    double worst_m = INFINITY;
    for (const auto v : out.mesh().vertices())
      worst_m = std::min(worst_m, barDistance(mesh::toEigen(out.mesh().point(v))));
    CHECK(worst_m >= -1e-6);
  }
}

TEST_CASE("global_dffd: capped, only where F separates the sides: closed, no faces crossing, caps apart", "[cutting]") {
  // A slab wider than the lattice box (y beyond it) moving past the bar: the plane x = 0 cuts all of it,
  // but F separates the sides only near the bar. A cap over the whole section would lie on the other
  // side's cap wherever F does not (hundreds of pairs of faces crossing).
  const GlobalDffd dffd({bar()}, options());
  for (const double y_m : {-0.03, -0.012, 0.0, 0.012}) {
    INFO("slab at y " << y_m);
    const Eigen::AlignedBox3d slab(Eigen::Vector3d(-0.02, y_m - 0.02, -0.004),
                                   Eigen::Vector3d(0.02, y_m + 0.02, 0.004));
    const mesh::SurfaceMesh out = cappedDeform(mesh::makeBox(slab, Eigen::Vector3i(20, 20, 4)), dffd);
    const mesh::ManifoldReport report = mesh::checkManifold(out.mesh());
    INFO(report.first_problem);
    CHECK(report.closed_two_manifold);
    CHECK(mesh::findSelfIntersections(out.mesh()).empty());
    CHECK(worstPenetration(out.mesh(), {bar()}) <= 1e-6);
    // Caps only where the sides part: each cap vertex is off the plane x = 0 unless both caps share it.
    int walls = 0, on_plane = 0;
    for (const auto f : out.mesh().faces()) {
      if (out.kind(f) != mesh::FaceKind::Wall) continue;
      ++walls;
      for (const auto v : out.mesh().fv_range(f)) on_plane += out.mesh().point(v)[0] == 0.0;
    }
    CHECK(walls > 0);
    CHECK(on_plane < walls);
  }
}

TEST_CASE("global_dffd: splitting from arrays into a reused split gives the same split", "[cutting]") {
  const GlobalDffd dffd({bar()}, options());
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, 0.003, 0.0), 0.012, 3);
  const auto [positions, faces] = modelArrays(sphere);
  const DffdSplit reference = splitAtDiscontinuities(sphere, dffd, Openings::Close);
  DffdSplit reused;
  for (int round = 0; round < 3; ++round) {  // a second scene in between: the buffers must not leak into it
    splitAtDiscontinuities(positions, faces, dffd, Openings::Close, reused);
    CHECK(reused.rest_m == reference.rest_m);
    CHECK(reused.faces == reference.faces);
    CHECK(reused.side == reference.side);
    CHECK(reused.source_vertex == reference.source_vertex);
    const mesh::SurfaceMesh other = mesh::makeSphere(Eigen::Vector3d(0.002, -0.004, 0.0), 0.01, 2);
    splitAtDiscontinuities(other, dffd);
  }
  std::vector<Eigen::Vector3d> deformed(reused.rest_m.size());
  deformSplit(reused, dffd, deformed);
  const mesh::SurfaceMesh as_mesh = deformSplit(reference, dffd);
  for (const auto v : as_mesh.mesh().vertices())
    CHECK(mesh::toEigen(as_mesh.mesh().point(v)) == deformed[static_cast<size_t>(v.idx())]);
  CHECK_THROWS_AS(deformSplit(reused, dffd, std::span(deformed).first(3)), DffdError);
}

TEST_CASE("global_dffd: a model with a degenerate face, or open where closure is needed, is refused", "[cutting]") {
  mesh::SurfaceMesh flat =
      mesh::makeBox(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.01), Eigen::Vector3d::Constant(0.01)));
  const auto v = *flat.mesh().vertices_begin();
  auto p = flat.mesh().point(v);
  for (auto n = flat.mesh().vv_iter(v); n.is_valid(); ++n) p = flat.mesh().point(*n);  // onto a neighbour
  flat.mesh().set_point(v, p);
  REQUIRE_THROWS_WITH(validateModel(flat, ModelClosure::MayBeOpen), Contains("degenerate face"));
  mesh::SurfaceMesh open = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.01, 1);
  open.mesh().delete_face(*open.mesh().faces_begin());
  open.mesh().garbage_collection();
  CHECK_NOTHROW(validateModel(open, ModelClosure::MayBeOpen));
  REQUIRE_THROWS_WITH(validateModel(open, ModelClosure::Closed), Contains("not a closed two-manifold"));
}

TEST_CASE("global_dffd: knots at the obstacle's v-extremes close the lips behind it sooner (Figure 4)", "[cutting]") {
  // The widest gap between the two lips of a split vertex beyond the bar's far side in v (y > radius).
  const auto gapBehind = [](VKnots v_knots) {
    GlobalDffdOptions o = options();
    o.v_knots = v_knots;
    const GlobalDffd dffd({bar()}, o);
    const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, 0.004, 0.0), 0.012, 4);
    const DffdSplit split = splitAtDiscontinuities(sphere, dffd);
    std::vector<Eigen::Vector3d> out(split.rest_m.size());
    deformSplit(split, dffd, out);
    std::map<std::pair<double, double>, std::array<int, 2>> lips;  // (y, z) at rest -> - and + copies
    for (size_t v = 0; v < out.size(); ++v)
      if (split.side[v] != 0)
        lips[{split.rest_m[v].y(), split.rest_m[v].z()}][split.side[v] < 0 ? 0 : 1] = static_cast<int>(v);
    double widest = 0;
    for (const auto& [yz, pair] : lips)
      if (yz.first > 0.0065)
        widest = std::max(widest, (out[static_cast<size_t>(pair[0])] - out[static_cast<size_t>(pair[1])]).norm());
    return widest;
  };
  const double with = gapBehind(VKnots::AtObstacleExtremes), without = gapBehind(VKnots::None);
  INFO("gap behind the bar: " << with << " m with the v-knots, " << without << " m without");
  CHECK(with < without);
}

TEST_CASE("global_dffd: the same scene gives the same bytes", "[cutting]") {
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, 0.002, 0.001), 0.012, 2);
  const GlobalDffd a({bar()}, options()), b({bar()}, options());
  const mesh::SurfaceMesh x = deformSplit(splitAtDiscontinuities(sphere, a), a);
  const mesh::SurfaceMesh y = deformSplit(splitAtDiscontinuities(sphere, b), b);
  REQUIRE(x.mesh().n_vertices() == y.mesh().n_vertices());
  for (const auto v : x.mesh().vertices()) CHECK(x.mesh().point(v) == y.mesh().point(v));
}

TEST_CASE("global_dffd: a bound split re-deforms to exactly the positions deformSplit gives", "[cutting]") {
  GlobalDffd dffd({bar()}, options());
  // Centred on the bar, and half out of the box along v (those vertices keep their rest position).
  for (const double y : {0.002, 0.022}) {
    const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, y, 0.001), 0.012, 3);
    const DffdSplit split = splitAtDiscontinuities(sphere, dffd, Openings::Close);
    const DffdBinding binding(split, dffd);
    REQUIRE(binding.size() == split.rest_m.size());
    CHECK(binding.bound() > 0);
    if (y > 0.01) CHECK(binding.bound() < binding.size());
    GlobalDffd stitched = dffd;
    stitched.stitch(0, stitchLevel(split, stitched, 0));
    for (const GlobalDffd* f : {&dffd, &stitched}) {  // F changed, the split did not
      const mesh::SurfaceMesh expected = deformSplit(split, *f);
      std::vector<Eigen::Vector3d> out(binding.size(), Eigen::Vector3d::Constant(NAN));
      binding.deform(*f, out);
      int differ = 0;
      for (const auto v : expected.mesh().vertices())
        differ += mesh::toEigen(expected.mesh().point(v)) != out[static_cast<size_t>(v.idx())];
      CHECK(differ == 0);
    }
  }
  // A lattice with other knots, or the wrong number of outputs: refused, nothing written.
  const DffdSplit split = splitAtDiscontinuities(mesh::makeSphere(Eigen::Vector3d::Zero(), 0.012, 2), dffd);
  const DffdBinding binding(split, dffd);
  GlobalDffdOptions other = options();
  other.controls = {28, 16, 8};
  std::vector<Eigen::Vector3d> out(binding.size(), Eigen::Vector3d::Zero());
  REQUIRE_THROWS_WITH(binding.deform(GlobalDffd({bar()}, other), out), Contains("not the one the split was bound to"));
  CHECK(out[0] == Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> short_out(binding.size() - 1);
  REQUIRE_THROWS_AS(binding.deform(dffd, short_out), DffdError);
}

TEST_CASE("global_dffd: a kernel that would fold the lattice is refused, or widened until it does not", "[cutting]") {
  GlobalDffdOptions o = options();
  o.kernel_width = 1.0;
  REQUIRE_THROWS_WITH(GlobalDffd({bar()}, o), Contains("obstacle 'bar'") && Contains("Theorem 1"));
  o.on_fold = FoldPolicy::Widen;
  const GlobalDffd widened({bar()}, o);
  CHECK(widened.obstacles()[0].kernel_width > 1.0);
  CHECK(widened.minJacobian() > 0.0);
  o.kernel = DffdKernel::Gaussian;
  o.kernel_width = 8.0;
  o.on_fold = FoldPolicy::Refuse;
  CHECK(GlobalDffd({bar()}, o).minJacobian() > 0.0);
}

TEST_CASE("global_dffd: obstacles too close, not monotone, open or outside the box are refused by name", "[cutting]") {
  REQUIRE_THROWS_WITH(GlobalDffd({bar(-0.008, "left"), bar(0.008, "right")}, options()),
                      Contains("'left' and 'right' are too close") && Contains("control spacings are needed"));
  try {
    const GlobalDffd refused({bar(-0.008, "left"), bar(0.008, "right")}, options());
    FAIL("obstacles too close were accepted");
  } catch (const DffdError& e) {  // the same in fields: the kind, the obstacles and the controls asked for
    CHECK(e.kind == DffdErrorKind::TooClose);
    CHECK(e.obstacle == "left");
    CHECK(e.other_obstacle == "right");
    CHECK(e.controls_needed > options().controls[0]);
    CHECK_THAT(e.what(), Contains("to at least " + std::to_string(e.controls_needed) + ")"));
  }
  // A U-shaped prism opening towards -y: a line along u through its arms enters it twice.
  const std::vector<Eigen::Vector2d> u_shape = {{-0.01, -0.01}, {-0.006, -0.01}, {-0.006, 0.004}, {0.006, 0.004},
                                                {0.006, -0.01}, {0.01, -0.01},   {0.01, 0.01},    {-0.01, 0.01}};
  REQUIRE_THROWS_WITH(GlobalDffd({{"horseshoe", mesh::makePrism(u_shape, -0.01, 0.01)}}, options()),
                      Contains("'horseshoe' is not monotone in v"));
  mesh::SurfaceMesh open =
      mesh::makeBox(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.01), Eigen::Vector3d::Constant(0.01)));
  open.mesh().delete_face(*open.mesh().faces_begin());
  open.mesh().garbage_collection();
  REQUIRE_THROWS_WITH(GlobalDffd({{"lid-less", open}}, options()), Contains("'lid-less': not a closed two-manifold"));
  GlobalDffdOptions small = options();
  small.box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.004), Eigen::Vector3d::Constant(0.004));
  REQUIRE_THROWS_WITH(GlobalDffd({bar()}, small), Contains("'bar' lies outside the lattice box"));
  try {
    const GlobalDffd refused({bar()}, small);
  } catch (const DffdError& e) {
    CHECK(e.kind == DffdErrorKind::ObstacleOutsideBox);
    CHECK(e.obstacle == "bar");
  }
  GlobalDffdOptions bad = options();
  bad.kernel_width = 0;
  REQUIRE_THROWS_AS(GlobalDffd({bar()}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace incise::global_dffd
