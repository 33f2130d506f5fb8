#include "incise/incision/surface_cutter.h"

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "incise/mesh/surface_query.h"
#include "incise/mesh/vertex_grid.h"
#include "stroke_fixture.h"
#include "surface_cutter_internal.h"  // detail::deleteFace (cutting/incision/src)

using namespace incise;
using namespace incise::incision;
using Catch::Matchers::Contains;
using incise::incision::testing::backStroke;
using incise::incision::testing::bunny;

namespace {

// Lattice sizes for a mesh resolution: the lattice must be wider than the mesh's edges.
CutterOptions optionsFor(int subdivisions) {
  CutterOptions options;
  if (subdivisions == 0) {  // the 3674-triangle bunny: edges of about 2.5 mm
    options.incision.alpha_m = 0.004;
    options.incision.opening_m = 0.003;
    options.incision.spacing_m = 0.001;
    options.incision.beta_m = 0.003;
    options.incision.depth_m = 0.006;
  }
  return options;
}

struct CutRun {
  int topology_checks = 0;
  int steps_with_columns = 0;
};

// Runs the stroke sample by sample; after every sample that changed the topology, the mesh must be a closed
// two-manifold with the Euler characteristic it started with.
CutRun cutCheckingEverySample(mesh::SurfaceMesh& mesh, SurfaceCutter& cutter, const Stroke& stroke) {
  const int euler = mesh::checkManifold(mesh.mesh()).euler_characteristic;
  CutRun run;
  const auto check = [&](const CutStep& step) {
    REQUIRE_FALSE(step.failed);
    if (step.edges_split + step.vertices_duplicated + step.wall_faces == 0) return;
    ++run.topology_checks;
    const mesh::ManifoldReport report = mesh::checkManifold(mesh.mesh());
    INFO(report.first_problem);
    REQUIRE(report.closed_two_manifold);
    REQUIRE(report.euler_characteristic == euler);
  };
  check(cutter.begin(stroke.first, stroke.blade_direction));
  for (const StrokeSample& sample : stroke.samples) {
    const CutStep step = cutter.extend(sample);
    REQUIRE(step.sample == SampleStatus::Accepted);
    if (step.columns > 0) ++run.steps_with_columns;
    check(step);
  }
  check(cutter.finish());
  return run;
}

std::string objBytes(const mesh::SurfaceMesh& mesh, const std::string& name) {
  const incise::test::TempDir dir;
  mesh::saveObj(mesh, dir.path() / (name + ".obj"));
  return incise::test::readFile(dir.path() / (name + ".obj"));
}

// Every face whose vertices are all bound to the incision and inside the cut's parameter window must lie
// on one side of u = 1/2.
int facesCrossingTheCut(const mesh::SurfaceMesh& mesh, const SurfaceCutter& cutter) {
  const Incision& incision = *cutter.incision();
  int crossing = 0;
  for (const auto f : mesh.mesh().faces()) {
    if (mesh.mesh().status(f).deleted()) continue;
    bool minus = false, plus = false, inside = true;
    for (auto v = mesh.mesh().cfv_iter(f); v.is_valid(); ++v) {
      const auto b = cutter.binding(*v);
      if (!b) {
        inside = false;
        break;
      }
      inside = inside && b->uvw[1] > incision.startV() + 1.0 && b->uvw[1] < incision.lastStationV() - 1.0 &&
               b->uvw[2] < incision.bottomW() - 0.1;
      minus = minus || b->side == -1;
      plus = plus || b->side == 1;
    }
    if (inside && minus && plus) ++crossing;
  }
  return crossing;
}

}  // namespace

TEST_CASE("surface_cutter: every sample leaves a closed two-manifold with its Euler characteristic", "[cutting]") {
  for (const int subdivisions : {0, 2}) {
    INFO("bunny subdivided " << subdivisions << " times");
    mesh::SurfaceMesh mesh = bunny(subdivisions);
    SurfaceCutter cutter(mesh, optionsFor(subdivisions));
    const Stroke stroke = backStroke(mesh);
    REQUIRE(stroke.samples.size() == 1000);
    const CutRun run = cutCheckingEverySample(mesh, cutter, stroke);
    REQUIRE(run.topology_checks > 10);
    REQUIRE(cutter.stats().vertices_duplicated > 5);  // a real cut happened
    REQUIRE(mesh::summarize(mesh).wall_faces > 0);
  }
}

TEST_CASE("surface_cutter: with no opening the skin splits into lips that touch, nothing moves", "[cutting]") {
  // incision.opening_m 0: a simulated tissue's own tension opens the wound (sim's scenarios allow it only
  // there); the cut is the split, the seam and the walls, at rest.
  const mesh::SurfaceMesh original = bunny(2);
  mesh::SurfaceMesh mesh = original;
  CutterOptions options = optionsFor(2);
  options.incision.opening_m = 0.0;
  SurfaceCutter cutter(mesh, options);
  const Stroke stroke = backStroke(mesh);
  const CutRun run = cutCheckingEverySample(mesh, cutter, stroke);
  cutter.advance(stroke.samples.back().time_s + 1.0);
  REQUIRE(run.topology_checks > 10);
  REQUIRE(cutter.stats().vertices_duplicated > 20);
  REQUIRE(mesh::summarize(mesh).wall_faces > 0);
  REQUIRE(facesCrossingTheCut(mesh, cutter) == 0);
  for (const auto v : original.mesh().vertices())
    REQUIRE(mesh.mesh().point(mesh::TriMesh::VertexHandle(v.idx())) == original.mesh().point(v));
  // Every seam vertex has its twin on the other lip at the same point.
  mesh::VertexGrid grid(0.001);
  int seam = 0;
  for (const auto v : mesh.mesh().vertices())
    if (mesh.kind(v) == mesh::VertexKind::Seam) grid.insert(v.idx(), mesh::toEigen(mesh.mesh().point(v))), ++seam;
  REQUIRE(seam > 40);
  int lone = 0;
  for (const auto v : mesh.mesh().vertices()) {
    if (mesh.kind(v) != mesh::VertexKind::Seam) continue;
    const Eigen::Vector3d p = mesh::toEigen(mesh.mesh().point(v));
    std::vector<int> near;
    grid.query(Eigen::AlignedBox3d(p, p), near);
    int twins = 0;
    for (const int other : near)
      twins += other != v.idx() && mesh::toEigen(mesh.mesh().point(mesh::TriMesh::VertexHandle(other))) == p;
    lone += twins == 0;
  }
  // The cut's two ends: a seam vertex there is one vertex shared by both lips.
  INFO(seam << " seam vertices, " << lone << " without a twin");
  REQUIRE(lone <= 2);
}

TEST_CASE("surface_cutter: no face crosses the discontinuity inside the cut", "[cutting]") {
  mesh::SurfaceMesh mesh = bunny(2);
  SurfaceCutter cutter(mesh, optionsFor(2));
  const Stroke stroke = backStroke(mesh);
  // Before cutting, faces do cross u = 1/2 (so the check below is not empty by construction).
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.finish();
  REQUIRE(facesCrossingTheCut(mesh, cutter) == 0);
  REQUIRE(cutter.stats().edges_split > 20);
}

// Every bottom vertex of the cut lies the blade's depth below the original surface (closest distance).
static void checkGrooveDepth(int subdivisions) {
  const mesh::SurfaceMesh original = bunny(subdivisions);
  mesh::SurfaceMesh mesh = original;
  CutterOptions options = optionsFor(subdivisions);
  SurfaceCutter cutter(mesh, options);
  const Stroke stroke = backStroke(mesh);
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.finish();
  cutter.advance(stroke.samples.back().time_s + 1.0);  // fully opened

  mesh::VertexGrid grid(0.002);
  for (const auto v : original.mesh().vertices()) grid.insert(v.idx(), mesh::toEigen(original.mesh().point(v)));
  int bottoms = 0;
  for (const auto v : mesh.mesh().vertices()) {
    const auto b = cutter.binding(v);
    if (!b || b->side != 2) continue;
    ++bottoms;
    const Eigen::Vector3d p = mesh::toEigen(mesh.mesh().point(v));
    const auto surface = mesh::closestSurfacePoint(original.mesh(), grid, p, 0.02);
    REQUIRE(surface);
    INFO("bottom vertex " << v.idx() << " at " << p.transpose());
    REQUIRE(surface->distance_m == Approx(options.incision.depth_m).epsilon(0.05));
  }
  REQUIRE(bottoms > 20);
}

// Vertices farther from every stroke sample than the lattice reaches are bit for bit where they were.
static void checkFarVerticesUnchanged(int subdivisions) {
  const mesh::SurfaceMesh original = bunny(subdivisions);
  mesh::SurfaceMesh mesh = original;
  const CutterOptions options = optionsFor(subdivisions);
  SurfaceCutter cutter(mesh, options);
  const Stroke stroke = backStroke(mesh);
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.finish();
  cutter.advance(10.0);
  const IncisionOptions& o = options.incision;
  // Half the lattice's width or height plus `order` columns.
  const double reach_m =
      std::max((o.across_controls / 2) * o.alpha_m, (o.normal_controls / 2) * o.beta_m) + o.order * o.spacing_m + 0.001;
  int far = 0, moved_near = 0;
  for (const auto v : original.mesh().vertices()) {
    const Eigen::Vector3d p = mesh::toEigen(original.mesh().point(v));
    double nearest_m = (stroke.first.point_m - p).norm();
    for (const auto& s : stroke.samples) nearest_m = std::min(nearest_m, (s.point_m - p).norm());
    const bool same = mesh.mesh().point(v) == original.mesh().point(v);
    if (nearest_m > reach_m) {
      ++far;
      REQUIRE(same);
    } else if (!same) {
      ++moved_near;
    }
  }
  REQUIRE(far > static_cast<int>(original.mesh().n_vertices()) * 2 / 3);
  REQUIRE(moved_near > 50);
}

TEST_CASE("surface_cutter: the groove is as deep as the blade, within 5%", "[cutting]") { checkGrooveDepth(2); }

TEST_CASE("surface_cutter: vertices beyond the lattice's support are unchanged bit for bit", "[cutting]") {
  checkFarVerticesUnchanged(2);
}

TEST_CASE("surface_cutter: on a subdivided bunny of more than 100k triangles every check holds", "[cutting][slow]") {
  mesh::SurfaceMesh mesh = bunny(3);
  REQUIRE(mesh.mesh().n_faces() >= 100000);
  SurfaceCutter cutter(mesh, optionsFor(3));
  const CutRun run = cutCheckingEverySample(mesh, cutter, backStroke(mesh));
  REQUIRE(run.topology_checks > 50);
  REQUIRE(facesCrossingTheCut(mesh, cutter) == 0);
  checkGrooveDepth(3);
  checkFarVerticesUnchanged(3);
  // Grown sample by sample or cut from all samples at once: the same mesh, byte for byte.
  mesh::SurfaceMesh whole = bunny(3);
  SurfaceCutter once(whole, optionsFor(3));
  const Stroke stroke = backStroke(whole);
  once.begin(stroke.first, stroke.blade_direction);
  once.extend(stroke.samples);
  once.finish();
  cutter.advance(stroke.samples.back().time_s);
  REQUIRE(objBytes(mesh, "grown235k") == objBytes(whole, "once235k"));
}

TEST_CASE("surface_cutter: the same samples give the same bytes", "[cutting]") {
  std::string bytes[2];
  for (auto& b : bytes) {
    mesh::SurfaceMesh mesh = bunny(2);
    SurfaceCutter cutter(mesh, optionsFor(2));
    const Stroke stroke = backStroke(mesh, 0.03, 0.004);
    cutter.begin(stroke.first, stroke.blade_direction);
    for (const auto& s : stroke.samples) cutter.extend(s);
    cutter.finish();
    b = objBytes(mesh, "determinism");
  }
  REQUIRE(bytes[0].size() > 1000);
  REQUIRE(bytes[0] == bytes[1]);
}

TEST_CASE("surface_cutter: growing sample by sample equals one cut from all samples", "[cutting]") {
  mesh::SurfaceMesh grown = bunny(2), whole = grown;
  SurfaceCutter grow(grown, optionsFor(2)), once(whole, optionsFor(2));
  const Stroke stroke = backStroke(grown, 0.04, -0.005);
  grow.begin(stroke.first, stroke.blade_direction);
  for (const auto& s : stroke.samples) grow.extend(s);
  once.begin(stroke.first, stroke.blade_direction);
  once.extend(stroke.samples);
  // Same time of the wound's response: the last sample's. Same topology, element for element.
  REQUIRE(grown.mesh().n_vertices() == whole.mesh().n_vertices());
  REQUIRE(grown.mesh().n_faces() == whole.mesh().n_faces());
  for (const auto f : grown.mesh().faces()) {
    REQUIRE(grown.mesh().status(f).deleted() == whole.mesh().status(f).deleted());
    if (grown.mesh().status(f).deleted()) continue;
    auto a = grown.mesh().cfv_iter(f);
    auto b = whole.mesh().cfv_iter(mesh::TriMesh::FaceHandle(f.idx()));
    for (int i = 0; i < 3; ++i, ++a, ++b) REQUIRE(a->idx() == b->idx());
  }
  double worst = 0.0;
  for (const auto v : grown.mesh().vertices())
    worst = std::max(worst, (mesh::toEigen(grown.mesh().point(v)) -
                             mesh::toEigen(whole.mesh().point(mesh::TriMesh::VertexHandle(v.idx()))))
                                .norm());
  REQUIRE(worst <= 1e-9);
  REQUIRE(grow.stats().vertices_duplicated == once.stats().vertices_duplicated);
  REQUIRE(grow.stats().vertices_duplicated > 10);
}

TEST_CASE("surface_cutter: a later stroke cuts across an earlier one", "[cutting]") {
  mesh::SurfaceMesh mesh = bunny(2);
  SurfaceCutter cutter(mesh, optionsFor(2));
  const Stroke first = backStroke(mesh, 0.03);
  cutCheckingEverySample(mesh, cutter, first);
  cutter.advance(first.samples.back().time_s + 1.0);
  const int walls_after_first = mesh::summarize(mesh).wall_faces;
  // Across the first groove, along z, and a third one beside it that crosses nothing.
  const Stroke across = backStroke(mesh, 0.02, 0.0, Eigen::Vector3d(0.0, 0.0, 0.005), Eigen::Vector3d::UnitZ(), 2.0);
  const CutRun run = cutCheckingEverySample(mesh, cutter, across);
  REQUIRE(run.topology_checks > 5);
  const Stroke beside = backStroke(mesh, 0.015, 0.0, Eigen::Vector3d(0.004, 0.0, 0.03), Eigen::Vector3d::UnitX(), 4.0);
  cutCheckingEverySample(mesh, cutter, beside);
  REQUIRE(cutter.stats().incisions == 3);
  REQUIRE(mesh::summarize(mesh).wall_faces > walls_after_first);
  REQUIRE(mesh::checkManifold(mesh.mesh()).closed_two_manifold);
}

TEST_CASE("surface_cutter: bad samples are skipped or refused and never break the mesh", "[cutting]") {
  mesh::SurfaceMesh mesh = bunny(2);
  SurfaceCutter cutter(mesh, optionsFor(2));
  const Stroke stroke = backStroke(mesh, 0.02);
  const auto& s = stroke.samples;

  StrokeSample nan_first = stroke.first;
  nan_first.point_m.x() = NAN;
  REQUIRE(cutter.begin(nan_first, stroke.blade_direction).sample == SampleStatus::RefusedNaN);
  StrokeSample flat_first = stroke.first;
  flat_first.normal.setZero();
  REQUIRE(cutter.begin(flat_first, stroke.blade_direction).sample == SampleStatus::RefusedNormal);
  REQUIRE_FALSE(cutter.active());

  cutter.begin(stroke.first, stroke.blade_direction);
  for (size_t k = 0; k < 200; ++k) REQUIRE(cutter.extend(s[k]).sample == SampleStatus::Accepted);
  StrokeSample bad = s[200];
  bad.point_m.y() = NAN;
  REQUIRE(cutter.extend(bad).sample == SampleStatus::RefusedNaN);
  bad = s[200];
  bad.normal.setZero();
  REQUIRE(cutter.extend(bad).sample == SampleStatus::RefusedNormal);
  bad = s[200];
  bad.time_s = NAN;
  REQUIRE(cutter.extend(bad).sample == SampleStatus::RefusedNaN);
  REQUIRE(cutter.extend(s[199]).sample == SampleStatus::SkippedTime);  // stands still, at the same time
  bad = s[199];
  bad.time_s = s[200].time_s;
  REQUIRE(cutter.extend(bad).sample == SampleStatus::SkippedStill);  // stands still, time moves on
  bad = s[150];
  bad.time_s = s[200].time_s;
  REQUIRE(cutter.extend(bad).sample == SampleStatus::SkippedBackward);
  bad = s[200];
  bad.point_m.x() += 0.004;  // a 4 mm jump inside 1 ms, still on the surface's level
  bad.point_m = s[200].point_m + Eigen::Vector3d(0.0, 0.0, 0.006);
  const CutStep jump = cutter.extend(bad);
  REQUIRE((jump.sample == SampleStatus::SkippedJump || jump.left_surface));
  for (size_t k = 200; k < 300; ++k) REQUIRE(cutter.extend(s[k]).sample == SampleStatus::Accepted);
  REQUIRE(mesh::checkManifold(mesh.mesh()).closed_two_manifold);

  // Leaving the surface ends the incision; the mesh stays closed and later samples are not used.
  bad = s[300];
  bad.point_m += 0.03 * stroke.first.normal;
  const CutStep off = cutter.extend(bad);
  REQUIRE(off.left_surface);
  REQUIRE_FALSE(cutter.active());
  REQUIRE(cutter.extend(s[301]).sample == SampleStatus::Ended);
  const mesh::ManifoldReport report = mesh::checkManifold(mesh.mesh());
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
  REQUIRE(cutter.stats().failure.empty());
}

TEST_CASE("surface_cutter: bad options and meshes are refused at load", "[cutting]") {
  mesh::SurfaceMesh mesh = bunny(0);
  CutterOptions zero_depth;
  zero_depth.incision.depth_m = 0.0;
  REQUIRE_THROWS_WITH(SurfaceCutter(mesh, zero_depth), Contains("depth_m = 0"));
  CutterOptions too_wide;
  too_wide.incision.opening_m = 0.02;
  REQUIRE_THROWS_WITH(SurfaceCutter(mesh, too_wide), Contains("Theorem 1") && Contains("opening_m = 0.02"));
  CutterOptions nan_alpha;
  nan_alpha.incision.alpha_m = NAN;
  REQUIRE_THROWS_WITH(SurfaceCutter(mesh, nan_alpha), Contains("alpha_m = nan"));

  mesh::SurfaceMesh open = bunny(0);
  open.mesh().delete_face(mesh::TriMesh::FaceHandle(17), /*delete_isolated_vertices=*/false);
  REQUIRE_THROWS_AS(SurfaceCutter(open, CutterOptions{}), mesh::MeshError);
  REQUIRE_THROWS_WITH(SurfaceCutter(open, CutterOptions{}), Contains("not a closed two-manifold") && Contains("edge"));
}

TEST_CASE("surface_cutter: new elements record what they are", "[cutting]") {
  mesh::SurfaceMesh mesh = bunny(2);
  SurfaceCutter cutter(mesh, optionsFor(2));
  const Stroke stroke = backStroke(mesh, 0.02);
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.finish();
  const mesh::MeshSummary summary = mesh::summarize(mesh);
  REQUIRE(summary.closed_two_manifold);
  REQUIRE(summary.euler_characteristic == 2);
  REQUIRE(summary.seam_vertices >= 2 * cutter.stats().vertices_duplicated);
  REQUIRE(summary.wall_vertices == cutter.stats().vertices_duplicated * (2 * optionsFor(2).wall_rows - 1));
  REQUIRE(summary.split_faces > 0);
  REQUIRE(summary.wall_faces > 0);
  // Every wall face has a Wall or Seam vertex only: walls hang from the lips.
  for (const auto f : mesh.mesh().faces()) {
    if (mesh.mesh().status(f).deleted() || mesh.kind(f) != mesh::FaceKind::Wall) continue;
    for (auto v = mesh.mesh().cfv_iter(f); v.is_valid(); ++v) REQUIRE(mesh.kind(*v) != mesh::VertexKind::Original);
  }
  REQUIRE_THAT(objBytes(mesh, "kinds"), Contains("g wall"));
  REQUIRE_THAT(mesh::toJson(summary), Contains("\"wall_faces\""));
}

TEST_CASE("surface_cutter: a work budget per call changes when the cut appears, not what it is", "[cutting]") {
  mesh::SurfaceMesh free_mesh = bunny(2), budget_mesh = free_mesh;
  CutterOptions budgeted = optionsFor(2);
  budgeted.max_inversions_per_call = 3;
  SurfaceCutter unlimited(free_mesh, optionsFor(2)), limited(budget_mesh, budgeted);
  const Stroke stroke = backStroke(free_mesh, 0.03);
  unlimited.begin(stroke.first, stroke.blade_direction);
  limited.begin(stroke.first, stroke.blade_direction);
  bool lagged = false;
  for (const auto& s : stroke.samples) {
    unlimited.extend(s);
    limited.extend(s);
    lagged = lagged || limited.pending();
  }
  REQUIRE(lagged);  // the budget did hold work back
  unlimited.finish();
  limited.finish();
  int calls = 0;
  while (limited.pending() && calls < 100000) limited.advance(stroke.samples.back().time_s), ++calls;
  REQUIRE_FALSE(limited.pending());
  REQUIRE(objBytes(free_mesh, "unlimited") == objBytes(budget_mesh, "limited"));
}

// What begin() would do at once with the settled incision's vertices (the grid moves and, with
// refinement, their coarse flags: O(its bound vertices), up to 1 ms in a frame) prepareBegin() does in
// budgeted calls first; the next incision cuts the same bytes as when begin() does it all.
TEST_CASE("surface_cutter: prepareBegin re-indexes the settled incision in budgeted calls, the same bytes",
          "[cutting]") {
  const auto refine = GENERATE(CutterOptions::Refine::Off, CutterOptions::Refine::Linear);
  mesh::SurfaceMesh direct_mesh = bunny(2), prepared_mesh = direct_mesh;
  CutterOptions options = optionsFor(2);
  options.refine = refine;
  options.max_inversions_per_call = 1;
  SurfaceCutter direct(direct_mesh, options), prepared(prepared_mesh, options);
  const Stroke first = backStroke(direct_mesh, 0.03);
  const Stroke across =
      backStroke(direct_mesh, 0.02, 0.0, Eigen::Vector3d(0.0, 0.0, 0.005), Eigen::Vector3d::UnitZ(), 2.0);
  for (SurfaceCutter* c : {&direct, &prepared}) {
    c->begin(first.first, first.blade_direction);
    c->extend(first.samples);
    c->finish(FinishWork::Later);
  }
  int settle_calls = 0, reindex_calls = 0;
  while (!prepared.settleStep() && settle_calls < 100000) ++settle_calls;
  while (!prepared.prepareBegin() && reindex_calls < 100000) ++reindex_calls;
  INFO(settle_calls << " settle calls, " << reindex_calls << " re-index calls");
  CHECK(reindex_calls > 20);  // hundreds of bound vertices, 8 grid moves (or 4 vertices' flags) a call
  for (SurfaceCutter* c : {&direct, &prepared}) {
    c->begin(across.first, across.blade_direction);  // direct: settles and re-indexes here, at once
    c->extend(across.samples);
    c->settle();
  }
  REQUIRE(direct.stats().incisions == 2);
  REQUIRE(direct.stats().vertices_duplicated > prepared.stats().vertices_duplicated / 2);
  REQUIRE(objBytes(direct_mesh, "direct") == objBytes(prepared_mesh, "prepared"));
}

// A column's grid query is charged to the budget (one unit per 64 vertices found), so a call that
// starts a column does not also bind a budget's worth of vertices; and so are its crossings' split (one unit
// per 16 vertices bound in it). With one unit a call, a call that starts a column binds none, a call that
// binds a vertex splits no crossing, and the cut is still the unlimited one.
TEST_CASE("surface_cutter: a column's grid query and crossings are work the budget counts", "[cutting]") {
  mesh::SurfaceMesh free_mesh = bunny(2), budget_mesh = free_mesh;
  CutterOptions budgeted = optionsFor(2);
  budgeted.max_inversions_per_call = 1;
  SurfaceCutter unlimited(free_mesh, optionsFor(2)), limited(budget_mesh, budgeted);
  const Stroke stroke = backStroke(free_mesh, 0.03);
  unlimited.begin(stroke.first, stroke.blade_direction);
  int columns_started = 0, bound = 0, splits = 0;
  const auto check = [&](const CutStep& step) {
    columns_started += step.columns;
    bound += step.vertices_bound;
    if (step.columns > 0) REQUIRE(step.vertices_bound == 0);
    if (step.vertices_bound > 0) REQUIRE(step.edges_split == 0);
    REQUIRE(step.vertices_bound <= 1);
    splits += step.edges_split;
  };
  check(limited.begin(stroke.first, stroke.blade_direction));
  for (const auto& s : stroke.samples) {
    unlimited.extend(s);
    check(limited.extend(s));
  }
  unlimited.finish();
  check(limited.finish());
  for (int calls = 0; limited.pending() && calls < 100000; ++calls)
    check(limited.advance(stroke.samples.back().time_s));
  REQUIRE_FALSE(limited.pending());
  REQUIRE(columns_started > 10);
  REQUIRE(bound > 100);
  REQUIRE(splits > 10);
  REQUIRE(objBytes(free_mesh, "unlimited") == objBytes(budget_mesh, "limited"));
}

// What an incision uses is reserved at load; an incision that outgrows it still cuts, the same
// bytes, and counts each growth (CutStats::reserve_overflows), which the default reserve never needs here.
TEST_CASE("surface_cutter: a reserve too small grows, is counted, and cuts the same bytes", "[cutting]") {
  std::string bytes[2];
  int overflows[2] = {-1, -1};
  for (const int reserve : {CutterOptions{}.reserved_bound_vertices, 64}) {
    const int run = reserve == 64 ? 1 : 0;
    mesh::SurfaceMesh mesh = bunny(2);
    CutterOptions options = optionsFor(2);
    options.reserved_bound_vertices = reserve;
    SurfaceCutter cutter(mesh, options);
    const Stroke first = backStroke(mesh, 0.03);
    cutCheckingEverySample(mesh, cutter, first);
    const Stroke across = backStroke(mesh, 0.02, 0.0, Eigen::Vector3d(0.0, 0.0, 0.005), Eigen::Vector3d::UnitZ(), 2.0);
    cutCheckingEverySample(mesh, cutter, across);
    cutter.settle();
    REQUIRE(cutter.stats().incisions == 2);
    REQUIRE(cutter.stats().vertices_duplicated > 20);
    bytes[run] = objBytes(mesh, "reserve");
    overflows[run] = cutter.stats().reserve_overflows;
  }
  CHECK(overflows[0] == 0);
  CHECK(overflows[1] > 0);
  REQUIRE(bytes[0] == bytes[1]);
  CutterOptions bad;
  bad.reserved_bound_vertices = 63;
  mesh::SurfaceMesh mesh = bunny(0);
  REQUIRE_THROWS_WITH(SurfaceCutter(mesh, bad), Contains("reserved_bound_vertices = 63"));
}

// The cutter deletes faces without OpenMesh's delete_face (which allocates two vectors a call): the same
// connectivity, halfedge by halfedge, on a mesh whose faces are deleted one after another until some
// vertices are isolated.
TEST_CASE("surface_cutter: its face deletion leaves what OpenMesh's delete_face leaves", "[cutting]") {
  mesh::SurfaceMesh a = bunny(0), b = bunny(0);
  mesh::TriMesh& ma = a.mesh();
  mesh::TriMesh& mb = b.mesh();
  for (int f = 0; f < 600; ++f) {
    ma.delete_face(mesh::TriMesh::FaceHandle(f), false);
    detail::deleteFace(mb, mesh::TriMesh::FaceHandle(f));
  }
  int isolated = 0;
  for (const auto v : ma.vertices()) {
    REQUIRE(ma.halfedge_handle(v) == mb.halfedge_handle(v));
    REQUIRE(ma.status(v).deleted() == mb.status(v).deleted());
    isolated += ma.is_isolated(v) ? 1 : 0;
  }
  REQUIRE(isolated > 0);
  for (const auto h : ma.all_halfedges()) {
    REQUIRE(ma.next_halfedge_handle(h) == mb.next_halfedge_handle(h));
    REQUIRE(ma.prev_halfedge_handle(h) == mb.prev_halfedge_handle(h));
    REQUIRE(ma.face_handle(h) == mb.face_handle(h));
    REQUIRE(ma.status(h).deleted() == mb.status(h).deleted());
  }
  for (const auto e : ma.all_edges()) REQUIRE(ma.status(e).deleted() == mb.status(e).deleted());
  for (const auto f : ma.all_faces()) REQUIRE(ma.status(f).deleted() == mb.status(f).deleted());
}
