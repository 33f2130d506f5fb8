// The viewer's copy of the tissue (viewer/src/surface_model.cpp): kept up to date from the mirror's changes
// as the cut grows, it ends the same as one built at once from the final mesh; a simulated tissue's tets
// drawn where the physics put their nodes.
#include "incise/viewer/surface_model.h"

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "viewer_fixture.h"

using namespace incise;

TEST_CASE("surface_model: updated after every pull, it ends as a model built from the final mesh", "[viewer]") {
  viewer::SurfaceModel followed;
  std::size_t updates_with_changes = 0, max_dirty = 0;
  const auto run =
      test::followRun("bunny-straight", std::numeric_limits<double>::infinity(), [&](test::FollowedRun& r) {
        if (!followed.update(r.mirror)) return;
        if (!followed.dirty().all && !followed.dirty().vertices.empty()) ++updates_with_changes;
        if (!followed.dirty().all) max_dirty = std::max(max_dirty, followed.dirty().vertices.size());
        followed.clearDirty();
      });
  REQUIRE(run->mirror.exact());
  viewer::SurfaceModel fresh;
  sim::GeometryMirror copy;
  sim::copyGeometry(*run->world, 0, copy);
  REQUIRE(fresh.update(copy));
  CHECK(fresh.dirty().all);
  CHECK_FALSE(fresh.textured());               // a tissue without texture coordinates
  CHECK(updates_with_changes > 50);            // many frames, each with a few changes
  CHECK(max_dirty < fresh.vertexCount() / 4);  // only what changed, never the whole mesh
  REQUIRE(followed.vertexCount() == fresh.vertexCount());
  REQUIRE(followed.faceCount() == fresh.faceCount());
  CHECK(followed.positions() == fresh.positions());
  CHECK(followed.indices() == fresh.indices());
  CHECK(followed.faceKinds() == fresh.faceKinds());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < fresh.normals().size(); ++i)
    differing += std::abs(followed.normals()[i] - fresh.normals()[i]) > 1e-5f;  // sums in another order
  CHECK(differing == 0);
  const mesh::MeshSummary summary = mesh::summarize(run->world->tissue());
  CHECK(fresh.liveFaces() == static_cast<std::size_t>(summary.faces));
  CHECK(fresh.wallFaces() == static_cast<std::size_t>(summary.wall_faces));
  CHECK(followed.wallFaces() == fresh.wallFaces());
}

TEST_CASE("surface_model: skin normals point out of the tissue and leave the walls out", "[viewer]") {
  const auto run = test::followRun("bunny-straight");
  viewer::SurfaceModel model;
  REQUIRE(model.update(run->mirror));
  const mesh::TriMesh& m = run->world->tissue().mesh();
  std::size_t checked = 0, outward = 0, zero_on_wall_only = 0;
  mesh::TriMesh mesh = m;
  mesh.update_face_normals();
  for (const auto v : m.vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    const Eigen::Vector3f n(&model.normals()[3 * i]);
    bool skin = false;
    for (auto f = m.cvf_iter(v); f.is_valid(); ++f)
      skin = skin || run->world->tissue().kind(*f) != mesh::FaceKind::Wall;
    if (!skin) {
      zero_on_wall_only += n.norm() == 0.0f;
      continue;
    }
    ++checked;
    // Against OpenMesh's own vertex normal of the uncut parts: the same direction.
    if (run->world->tissue().kind(v) == mesh::VertexKind::Original) {
      const auto on = mesh.calc_vertex_normal(v);
      outward += n.cast<double>().dot(Eigen::Vector3d(on[0], on[1], on[2])) > 0.99;
    } else {
      ++outward;
    }
  }
  CHECK(checked > 300);
  CHECK(zero_on_wall_only > 50);  // the walls' inner vertices: drawn flat, no smooth normal
  CHECK(outward == checked);
  CHECK(model.wallFaces() > 100);
}

TEST_CASE("surface_model: a simulated tissue's tets are drawn where the physics' last step put their nodes",
          "[viewer]") {
  // The tensioned pad after its stroke: the tets' boundary from the mirror, its nodes at the positions the
  // physics thread published (what `incise view` and `train` draw), not at rest.
  const auto run = test::followRun("pad-tension");
  REQUIRE(run->mirror.tets().complete());
  sim::TissuePhysics& physics = *run->world->physics();
  const sim::PhysicsState* state = physics.latestState();
  REQUIRE(state != nullptr);
  CHECK(state->step == physics.stepsDone());
  viewer::SurfaceModel rest, simulated;
  REQUIRE(rest.update(run->mirror.tets()));
  REQUIRE(simulated.update(run->mirror.tets(), *state));
  CHECK_FALSE(simulated.update(run->mirror.tets(), *state));  // nothing new: not rebuilt
  REQUIRE(simulated.vertexCount() == rest.vertexCount());
  CHECK(simulated.indices() == rest.indices());
  CHECK(simulated.faceKinds() == rest.faceKinds());
  REQUIRE(state->nodes <= simulated.vertexCount());
  std::size_t at_state = 0, moved = 0;
  for (std::size_t n = 0; n < state->nodes; ++n) {
    const Eigen::Vector3f drawn(&simulated.positions()[3 * n]), at_rest(&rest.positions()[3 * n]);
    at_state += (drawn - state->x_m[n].cast<float>()).norm() == 0.0f;
    moved += (drawn - at_rest).norm() > 0.0005f;
  }
  INFO(state->nodes << " nodes, " << moved << " drawn more than 0.5 mm from rest");
  CHECK(at_state == state->nodes);
  CHECK(moved > 100);
}

TEST_CASE(
    "surface_model: a textured tissue's texture coordinates and materials follow every pull, the dirty "
    "faces name them",
    "[viewer]") {
  viewer::SurfaceModel followed;
  std::vector<float> uploaded;  // what a renderer holds, updated as SceneRenderer::upload does
  std::vector<std::uint8_t> uploaded_materials;
  std::size_t partial_updates = 0;
  test::FollowOptions f;
  f.edit_scenario = [](sim::Scenario& s) { s.texture.given = s.texture.box_map = true; };
  f.edit_tissue = test::twoMaterials;
  f.seed = true;  // as the viewer: the textured bunny's sweep would take most of the run
  f.each_pull = [&](test::FollowedRun& r) {
    if (!followed.update(r.mirror)) return;
    REQUIRE(followed.faceTexCoords().size() == 6 * followed.faceCount());
    REQUIRE(followed.faceMaterials().size() == followed.faceCount());
    if (followed.dirty().all) {
      uploaded = followed.faceTexCoords();
      uploaded_materials = followed.faceMaterials();
    } else {  // new faces are among the dirty ones
      ++partial_updates;
      uploaded.resize(followed.faceTexCoords().size(), -1.0f);
      uploaded_materials.resize(followed.faceCount(), 254);
      for (const std::uint32_t face : followed.dirty().faces) {
        std::copy_n(&followed.faceTexCoords()[6 * face], 6, &uploaded[6 * face]);
        uploaded_materials[face] = followed.faceMaterials()[face];
      }
    }
    followed.clearDirty();
  };
  const auto run = test::followRun("bunny-straight", f);
  REQUIRE(run->world->incisions() == 1);
  CHECK(partial_updates > 50);
  sim::GeometryMirror copy;
  sim::copyGeometry(*run->world, 0, copy);
  viewer::SurfaceModel fresh;
  REQUIRE(fresh.update(copy));
  REQUIRE(fresh.textured());
  CHECK(followed.faceTexCoords() == fresh.faceTexCoords());
  CHECK(followed.faceMaterials() == fresh.faceMaterials());
  CHECK(uploaded == fresh.faceTexCoords());
  CHECK(uploaded_materials == fresh.faceMaterials());
  // Each live face's corners and material as the tissue has them (floats).
  const mesh::SurfaceMesh& tissue = run->world->tissue();
  std::size_t faces = 0, exact = 0, per_material[2] = {0, 0};
  for (const auto face : tissue.mesh().faces()) {
    if (tissue.mesh().status(face).deleted()) continue;
    const mesh::FaceCorners corners = mesh::faceCorners(tissue, face);
    const auto i = static_cast<std::size_t>(face.idx());
    bool same = fresh.faceMaterials()[i] == tissue.material(face);
    for (std::size_t c = 0; c < 3; ++c) {
      const std::uint32_t v = fresh.indices()[3 * i + c];
      const auto uv = corners.at(mesh::TriMesh::VertexHandle(static_cast<int>(v)));
      same = same && uv && fresh.faceTexCoords()[6 * i + 2 * c] == static_cast<float>(uv->x()) &&
             fresh.faceTexCoords()[6 * i + 2 * c + 1] == static_cast<float>(uv->y());
    }
    ++faces, exact += same;
    if (tissue.material(face) == 0 || tissue.material(face) == 1) ++per_material[tissue.material(face)];
  }
  CHECK(faces > 1000);
  CHECK(exact == faces);
  CHECK(per_material[0] > 1000);
  CHECK(per_material[1] > 1000);
}
