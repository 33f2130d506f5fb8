// A simulated tissue's surface embedded in the mirrored tets on the viewer's side (viewer/src/
// skin_embedding.cpp): followed pull by pull while the tensioned pad is cut, it puts every vertex where
// `replay` puts it in cut.obj (TissuePhysics::deformedSurface, over the model's own locator), each lip with
// its own side; SurfaceModel draws it so.
#include "incise/viewer/skin_embedding.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "incise/physics/tissue_model.h"
#include "incise/viewer/surface_model.h"
#include "viewer_fixture.h"

using namespace incise;

namespace {

// How far the embedding's positions at the state are from the sim's surface as simulated: a vertex inside
// its tet at rest must be where the sim puts it (within 1 nm); one outside every tet (its weights
// extrapolated from the nearest tet) may have been given another tet at the same distance (two tets
// sharing the nearest face or edge: a tie either locator may break its own way), so it must be as far
// out as the sim's and within 1% of that distance of the sim's position.
struct Difference {
  double max_m = 0.0;
  std::size_t over = 0, compared = 0, outside = 0;
};

Difference againstSim(const std::vector<std::array<double, 3>>& drawn_m, const viewer::SkinEmbedding& mine,
                      const std::vector<physics::Embedded>& theirs, const mesh::SurfaceMesh& simulated) {
  Difference d;
  const mesh::TriMesh& m = simulated.mesh();
  REQUIRE(drawn_m.size() == m.n_vertices());
  for (const auto v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    const auto i = static_cast<std::size_t>(v.idx());
    const double e = (Eigen::Vector3d(drawn_m[i][0], drawn_m[i][1], drawn_m[i][2]) - mesh::toEigen(m.point(v))).norm();
    const double out_m = theirs[i].outside_m;
    const bool ok = out_m == 0.0 ? e <= 1e-9 : std::abs(mine.vertex(i).outside_m - out_m) <= 1e-12 && e <= 0.01 * out_m;
    d.max_m = std::max(d.max_m, e);
    d.over += !ok, d.outside += out_m > 0.0, ++d.compared;
  }
  return d;
}

// A run of `name` (up to stop_after_s) followed by an embedding updated after every pull, and a fresh one
// at the end, both compared with the sim's surface as simulated at the physics' last published state.
struct Followed {
  std::unique_ptr<test::FollowedRun> run;
  viewer::SkinEmbedding followed, fresh;
  const sim::PhysicsState* state = nullptr;
  std::vector<std::array<double, 3>> drawn_m, fresh_m;
  Difference d, f;
  std::size_t updates = 0;

  explicit Followed(const std::string& name, double stop_after_s = std::numeric_limits<double>::infinity()) {
    run = test::followRun(name, stop_after_s,
                          [&](test::FollowedRun& r) { updates += followed.update(r.mirror) ? 1 : 0; });
    REQUIRE(run->mirror.complete());
    REQUIRE(run->mirror.tets().complete());
    followed.update(run->mirror);
    REQUIRE(fresh.update(run->mirror));
    sim::TissuePhysics& physics = *run->world->physics();
    state = physics.latestState();
    REQUIRE(state != nullptr);
    REQUIRE(state->step == physics.stepsDone());
    const mesh::SurfaceMesh simulated = physics.deformedSurface(run->world->tissue());
    const std::vector<physics::Embedded> theirs = physics.embedSurface(run->world->tissue());
    followed.positions(run->mirror, *state, drawn_m);
    fresh.positions(run->mirror, *state, fresh_m);
    d = againstSim(drawn_m, followed, theirs, simulated);
    f = againstSim(fresh_m, fresh, theirs, simulated);
  }
};

}  // namespace

TEST_CASE("skin_embedding: the tensioned pad's skin drawn as simulated is replay's cut.obj, lips apart", "[viewer]") {
  // Followed after every pull while the pad is cut (the embedding kept up to date as the tets and the
  // surface change), and once more from scratch at the end: both put each vertex where the sim does.
  const Followed r("pad-tension");
  const auto& run = r.run;
  const viewer::SkinEmbedding& followed = r.followed;
  const auto& drawn_m = r.drawn_m;
  INFO(r.d.compared << " vertices; followed: " << r.updates << " updates, " << followed.rebuilds()
                    << " locator builds, max " << r.d.max_m << " m, " << r.d.over << " apart; fresh: max " << r.f.max_m
                    << " m, " << r.f.over << " over");
  CHECK(r.updates > 10);
  CHECK(followed.rebuilds() > 1);
  CHECK(followed.embedded() == r.d.compared);
  CHECK(r.d.over == 0);
  CHECK(r.f.over == 0);

  // The wound gapes: its lips' vertices, at one place at rest, are apart as simulated.
  std::map<std::array<double, 3>, std::vector<std::size_t>> at_rest_m;
  for (std::size_t v = 0; v < run->mirror.positions_m().size(); ++v)
    if (followed.vertex(v).nodes[0] >= 0) at_rest_m[run->mirror.positions_m()[v]].push_back(v);
  double widest_m = 0.0;
  for (const auto& [p, same] : at_rest_m)
    for (const std::size_t u : same)
      for (const std::size_t v : same) {
        const Eigen::Vector3d a(drawn_m[u][0], drawn_m[u][1], drawn_m[u][2]);
        widest_m = std::max(widest_m, (a - Eigen::Vector3d(drawn_m[v][0], drawn_m[v][1], drawn_m[v][2])).norm());
      }
  INFO("lip vertices coincident at rest are up to " << widest_m << " m apart as simulated");
  CHECK(widest_m > 5e-4);

  // The physics behind the cut (its state without the cut's last 100 nodes): a vertex whose tet has such a
  // node moves with the nodes the state holds, much nearer where it ends than at rest; the others are as
  // before.
  sim::PhysicsState behind = *r.state;
  REQUIRE(behind.nodes > 100);
  behind.nodes -= 100;
  std::vector<std::array<double, 3>> behind_m;
  followed.positions(run->mirror, behind, behind_m);
  double error_m = 0.0, at_rest_error_m = 0.0;
  std::size_t waiting = 0, same = 0;
  for (std::size_t v = 0; v < behind_m.size(); ++v) {
    const physics::Embedded& e = followed.vertex(v);
    if (e.nodes[0] < 0) continue;
    const Eigen::Vector3d now(drawn_m[v][0], drawn_m[v][1], drawn_m[v][2]);
    const auto distance = [&](const std::array<double, 3>& p) {
      return (Eigen::Vector3d(p[0], p[1], p[2]) - now).norm();
    };
    if (std::all_of(e.nodes.begin(), e.nodes.end(),
                    [&](int n) { return static_cast<std::size_t>(n) < behind.nodes; })) {
      same += behind_m[v] == drawn_m[v];
      continue;
    }
    ++waiting;
    error_m += distance(behind_m[v]), at_rest_error_m += distance(run->mirror.positions_m()[v]);
  }
  INFO(waiting << " vertices wait for nodes: mean " << error_m / waiting * 1e3 << " mm from where they end, at rest "
               << at_rest_error_m / waiting * 1e3 << " mm");
  CHECK(waiting > 10);
  CHECK(same + waiting == followed.embedded());
  CHECK(error_m < 0.5 * at_rest_error_m);

  // Drawn: the mirror's faces, each vertex where the embedding puts it.
  viewer::SurfaceModel model, at_rest;
  REQUIRE(model.update(run->mirror, followed, *r.state));
  CHECK_FALSE(model.update(run->mirror, followed, *r.state));  // nothing new: not rebuilt
  REQUIRE(at_rest.update(run->mirror));
  CHECK(model.indices() == at_rest.indices());
  CHECK(model.faceKinds() == at_rest.faceKinds());
  REQUIRE(model.vertexCount() == drawn_m.size());
  std::size_t as_embedded = 0;
  for (std::size_t v = 0; v < drawn_m.size(); ++v)
    as_embedded += Eigen::Vector3f(&model.positions()[3 * v]) ==
                   Eigen::Vector3f(float(drawn_m[v][0]), float(drawn_m[v][1]), float(drawn_m[v][2]));
  CHECK(as_embedded == drawn_m.size());
}

TEST_CASE("skin_embedding: the soft bunny's fine skin follows its coarser tets as the sim puts it", "[viewer][slow]") {
  // The tet bunny: its skin refined ahead of the cut has vertices inside tets (not on their boundary). 8 s in
  // Release, 90 s under the sanitizers (its physics steps): [slow].
  const Followed r("bunny-tets-soft", 1.0);
  INFO(r.d.compared << " vertices, " << r.run->mirror.tets().tetCount() << " tets; followed: " << r.updates
                    << " updates, max " << r.d.max_m << " m, " << r.d.over << " apart (" << r.d.outside
                    << " outside every tet); fresh: max " << r.f.max_m << " m, " << r.f.over << " apart");
  std::size_t moved = 0;
  for (std::size_t v = 0; v < r.drawn_m.size(); ++v) {
    const auto& a = r.drawn_m[v];
    const auto& b = r.run->mirror.positions_m()[v];
    moved += std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) > 1e-4;
  }
  INFO(moved << " vertices drawn over 0.1 mm from rest");
  CHECK(moved > r.d.compared / 4);
  CHECK(r.run->world->incisions() >= 1);
  CHECK(r.followed.embedded() == r.d.compared);
  CHECK(r.d.over == 0);
  CHECK(r.f.over == 0);
}
