// The geometry stream (sim/src/geometry_stream.cpp) and its reader's copy (sim/src/geometry_mirror.cpp):
// a mirror rebuilt from the stream equals the replay's final mesh bit for bit — fast, in real time with
// the reader on another thread, with a reader that falls behind, and with one that re-syncs mid-run.
#include "incise/sim/geometry_stream.h"
#include "incise/sim/geometry_mirror.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <thread>

#include "incise/devices/trace_csv.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/simulation.h"
#include "incise/tets/tet_cutter.h"
#include "incise/tets/tet_mesh.h"
#include "shipped_scenario.h"

using namespace incise;

namespace {

using Loaded = test::ShippedScenario;
Loaded shipped(const char* name) { return test::loadShipped(name); }

sim::ReplayOptions options(const Loaded& l, sim::ReplayPace pace, sim::GeometryStream& stream) {
  sim::ReplayOptions o;
  o.pace = pace;
  o.period_us = l.scenario.periodUs();
  o.settle_s = l.scenario.settle_s;
  o.geometry = &stream;
  return o;
}

// The mirror as a SurfaceMesh (live faces in index order), for the geometry hash replay reports.
mesh::SurfaceMesh rebuild(const sim::GeometryMirror& mirror) {
  mesh::SurfaceMesh mesh;
  for (std::size_t v = 0; v < mirror.positions_m().size(); ++v) {
    const auto& p = mirror.positions_m()[v];
    mesh.addVertex({p[0], p[1], p[2]}, static_cast<mesh::VertexKind>(mirror.vertexKind()[v]));
  }
  for (std::size_t f = 0; f < mirror.faces().size(); ++f) {
    if (mirror.faceKind()[f] == sim::kDeletedFace) continue;
    const auto& t = mirror.faces()[f];
    mesh.addFace(mesh::TriMesh::VertexHandle(t[0]), mesh::TriMesh::VertexHandle(t[1]),
                 mesh::TriMesh::VertexHandle(t[2]), static_cast<mesh::FaceKind>(mirror.faceKind()[f]));
  }
  return mesh;
}

// Every vertex position bit for bit, every face's vertices (in OpenMesh's order) and kind, deleted faces.
void requireSameMesh(const sim::GeometryMirror& mirror, const mesh::SurfaceMesh& tissue) {
  const mesh::TriMesh& m = tissue.mesh();
  REQUIRE(mirror.exact());
  REQUIRE(mirror.positions_m().size() == m.n_vertices());
  REQUIRE(mirror.faces().size() == m.n_faces());
  std::size_t differing = 0;
  for (const auto v : m.all_vertices()) {
    const auto& p = m.point(v);
    const auto& q = mirror.positions_m()[static_cast<std::size_t>(v.idx())];
    if (std::memcmp(p.data(), q.data(), sizeof q) != 0 ||
        mirror.vertexKind()[static_cast<std::size_t>(v.idx())] != static_cast<std::uint8_t>(tissue.kind(v)))
      ++differing;
  }
  for (const auto f : m.all_faces()) {
    const auto i = static_cast<std::size_t>(f.idx());
    if (m.status(f).deleted()) {
      differing += mirror.faceKind()[i] != sim::kDeletedFace;
      continue;
    }
    int k = 0;
    for (auto v = m.cfv_iter(f); v.is_valid(); ++v)
      differing += mirror.faces()[i][static_cast<std::size_t>(k++)] != v->idx();
    differing += mirror.faceKind()[i] != static_cast<std::uint8_t>(tissue.kind(f));
  }
  CHECK(differing == 0);
  CHECK(mesh::geometryHash(rebuild(mirror)) == mesh::geometryHash(tissue));
}

// Faces name only vertices the copy has: what a reader sees at a frame's end is a mesh, not a torn state.
bool facesValid(const sim::GeometryMirror& mirror) {
  const auto n = static_cast<std::int32_t>(mirror.positions_m().size());
  for (std::size_t f = 0; f < mirror.faces().size(); ++f) {
    if (mirror.faceKind()[f] == sim::kDeletedFace) continue;
    for (const std::int32_t v : mirror.faces()[f])
      if (v < 0 || v >= n) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("geometry_stream: a mirror pulled after every fast frame ends as the replay's mesh, bit for bit", "[sim]") {
  Loaded l = shipped("bunny-straight");
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  std::int64_t changed_frames = 0;
  o.geometry_reader = [&] {
    mirror.pull(stream);
    if (!mirror.changedVertices().empty()) ++changed_frames;
    mirror.clearChanges();
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  REQUIRE(l.world->cutter().stats().vertices_duplicated > 50);
  CHECK(mirror.frame() == report.frames - 1);
  CHECK(changed_frames > 100);  // the cut reaches the reader as it grows, not only at the end
  CHECK(report.geometry.resets == 1);
  requireSameMesh(mirror, l.world->tissue());
}

TEST_CASE("geometry_stream: a textured tissue's faces carry their corners' texture coordinates to the mirror",
          "[sim]") {
  Loaded l = shipped("bunny-straight");
  mesh::SurfaceMesh tissue = l.world->tissue();
  tissue.addTexCoords();  // a planar map: every corner its vertex's (x, z) over 5 cm
  for (const auto h : tissue.mesh().halfedges()) {
    if (tissue.mesh().is_boundary(h)) continue;
    const auto& p = tissue.mesh().point(tissue.mesh().to_vertex_handle(h));
    tissue.setTexCoord(h, Eigen::Vector2d(p[0] / 0.05, p[2] / 0.05));
  }
  sim::World world(std::move(tissue), l.scenario.world);
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  o.geometry_reader = [&] {
    mirror.pull(stream);
    mirror.clearChanges();
  };
  const sim::ReplayReport report = sim::replay(world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  REQUIRE(world.cutter().stats().vertices_duplicated > 50);
  requireSameMesh(mirror, world.tissue());
  const mesh::SurfaceMesh& cut = world.tissue();
  const mesh::TriMesh& m = cut.mesh();
  REQUIRE(mirror.faceTexCoords().size() == m.n_faces());
  std::size_t differing = 0, walls = 0;
  for (const auto f : m.faces()) {  // live faces: each corner's coordinate as a float, in the Face record's order
    const auto& uv = mirror.faceTexCoords()[static_cast<std::size_t>(f.idx())];
    auto h = m.halfedge_handle(f);
    for (std::size_t k = 0; k < 3; ++k, h = m.next_halfedge_handle(h)) {
      const Eigen::Vector2d c = cut.texCoord(h);
      differing += uv[2 * k] != static_cast<float>(c.x()) || uv[2 * k + 1] != static_cast<float>(c.y());
    }
    walls += cut.kind(f) == mesh::FaceKind::Wall;
  }
  CHECK(walls > 100);  // the walls' own coordinates among them
  CHECK(differing == 0);
}

TEST_CASE("geometry_stream: a reader that falls behind stalls the stream, loses nothing and ends exact", "[sim]") {
  Loaded l = shipped("bunny-straight");
  sim::GeometryStreamOptions small;
  small.ring_records = 4096;
  small.records_per_frame = 512;
  sim::GeometryStream stream(small);
  sim::GeometryMirror mirror;
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  int calls = 0;
  bool always_valid = true;
  o.geometry_reader = [&] {
    if (++calls % 40 != 0) return;  // reads every 40 frames only: the ring fills up in between
    mirror.pull(stream);
    always_valid = always_valid && facesValid(mirror);
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  CHECK(report.geometry.stalled_frames > 100);
  CHECK(always_valid);
  requireSameMesh(mirror, l.world->tissue());
}

TEST_CASE("geometry_stream: a reader that drops its copy mid-run re-syncs and ends exact", "[sim]") {
  Loaded l = shipped("bunny-straight");
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  int calls = 0;
  o.geometry_reader = [&] {
    if (++calls == 700) mirror.restart();  // mid-stroke: the cut is growing
    mirror.pull(stream);
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  CHECK(report.geometry.resets == 2);
  CHECK(mirror.resets() == 2);
  requireSameMesh(mirror, l.world->tissue());
}

TEST_CASE("geometry_stream: without a reader the stream sends nothing and the replay is unchanged", "[sim]") {
  Loaded with = shipped("bunny-straight");
  Loaded without = shipped("bunny-straight");
  sim::GeometryStream stream;
  sim::ReplayOptions o = options(with, sim::ReplayPace::Fast, stream);
  o.flush_timeout_ms = 10;
  const sim::ReplayReport a = sim::replay(*with.world, with.poses, o);
  o.geometry = nullptr;
  const sim::ReplayReport b = sim::replay(*without.world, without.poses, o);
  CHECK_FALSE(a.geometry_flushed);
  CHECK(a.geometry.records == 0);
  CHECK(a.frames == b.frames);
  CHECK(mesh::geometryHash(with.world->tissue()) == mesh::geometryHash(without.world->tissue()));
}

TEST_CASE("geometry_stream: bad options are refused with the value", "[sim]") {
  sim::GeometryStreamOptions o;
  o.ring_records = 1000;
  CHECK_THROWS_WITH(sim::GeometryStream(o), Catch::Contains("ring_records = 1000"));
  o.ring_records = 1024;
  o.records_per_frame = 0;
  CHECK_THROWS_WITH(sim::GeometryStream(o), Catch::Contains("records_per_frame = 0"));
}

TEST_CASE("geometry_stream: a reader thread follows a real-time replay and rebuilds its final mesh bit for bit",
          "[sim][threads]") {
  Loaded l = shipped("bunny-straight");
  sim::GeometryStream stream;
  sim::ReplayOptions o = options(l, sim::ReplayPace::RealTime, stream);
  auto times = std::make_unique<sim::FrameTimesQueue>();  // every frame's timings, for the same reader (a HUD)
  o.times = times.get();
  std::atomic<bool> done{false};
  sim::GeometryMirror mirror;
  bool always_valid = true, times_in_order = true;
  int pulls_with_changes = 0;
  std::int64_t next_time = 0, timed_geometry = 0;
  const auto popTimes = [&] {
    sim::FrameTimes t;
    while (times->tryPop(t)) {
      times_in_order = times_in_order && t.frame == next_time++;
      timed_geometry += t.geometry_us > 0.0f;
    }
  };
  std::thread reader([&] {  // a viewer's thread: pulls at its own pace, never waited for
    while (!done.load(std::memory_order_acquire)) {
      if (mirror.pull(stream) > 0 && !mirror.changedVertices().empty()) ++pulls_with_changes;
      mirror.clearChanges();
      always_valid = always_valid && facesValid(mirror);
      popTimes();
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
    mirror.pull(stream);  // what flush() wrote last
    popTimes();
  });
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  done.store(true, std::memory_order_release);
  reader.join();
  REQUIRE(report.geometry_flushed);
  CHECK(always_valid);
  CHECK(pulls_with_changes > 20);
  CHECK(mirror.frame() == report.frames - 1);
  CHECK(times_in_order);
  CHECK(next_time == report.frames);  // every frame's timings, once, in order
  CHECK(timed_geometry > report.frames / 2);
  requireSameMesh(mirror, l.world->tissue());
}

TEST_CASE("geometry_stream: a mirror seeded before the run follows without any sweep and ends exact", "[sim]") {
  Loaded l = shipped("bunny-straight");
  sim::GeometryStreamOptions small;
  small.records_per_frame = 64;  // far less than the mesh: a sweep would take hundreds of frames
  sim::GeometryStream stream(small);
  sim::GeometryMirror mirror;
  stream.seed(*l.world, mirror);
  REQUIRE(mirror.exact());
  REQUIRE(mirror.complete());
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  std::int64_t max_backlog = 0, frames_complete = 0, frames = 0;
  o.geometry_reader = [&] {
    mirror.pull(stream);
    ++frames;
    frames_complete += mirror.complete();
    max_backlog = std::max<std::int64_t>(max_backlog, mirror.backlog());
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  CHECK(report.geometry.resets == 0);
  CHECK(frames_complete == frames);  // drawable from the first frame on
  CHECK(max_backlog > 64);           // more changes than budget: they waited in line, none was lost
  requireSameMesh(mirror, l.world->tissue());
}

namespace {

// A triangle by its corners' positions, starting at the lexicographically smallest corner (orientation
// kept), so that two meshes numbered differently compare.
using Corners = std::array<std::array<double, 3>, 3>;
std::vector<Corners> canonical(const std::vector<std::array<double, 3>>& positions_m,
                               const std::vector<std::array<int, 3>>& faces) {
  std::vector<Corners> out;
  out.reserve(faces.size());
  for (const auto& f : faces) {
    Corners c = {positions_m[static_cast<std::size_t>(f[0])], positions_m[static_cast<std::size_t>(f[1])],
                 positions_m[static_cast<std::size_t>(f[2])]};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The mirror's tet boundary against the tet cutter's (compacted) mesh's boundary, positions bit for bit.
void requireSameTetBoundary(const sim::GeometryMirror& mirror, const tets::TetCutter& tets) {
  REQUIRE(mirror.tets().exact());
  const tets::TetView view = tets.view();
  CHECK(mirror.tets().tetCount() == view.mesh.tets.size());
  std::vector<std::array<double, 3>> nodes;
  for (const Eigen::Vector3d& x : view.mesh.nodes_m) nodes.push_back({x[0], x[1], x[2]});
  std::vector<std::array<int, 3>> mirrored;
  for (const auto& f : mirror.tets().boundary()) mirrored.push_back({f[0], f[1], f[2]});
  const std::vector<Corners> expected = canonical(nodes, tets::boundaryFaces(view.mesh));
  const std::vector<Corners> got = canonical(mirror.tets().positions_m(), mirrored);
  REQUIRE(got.size() == expected.size());
  CHECK(std::memcmp(got.data(), expected.data(), got.size() * sizeof(Corners)) == 0);
}

}  // namespace

TEST_CASE("geometry_stream: a reader thread follows a real-time tet replay and rebuilds its tet boundary bit for bit",
          "[sim][threads][tets]") {
  Loaded l = shipped("bunny-tets");
  REQUIRE(l.world->tets());
  sim::GeometryStream stream;
  sim::ReplayOptions o = options(l, sim::ReplayPace::RealTime, stream);
  std::atomic<bool> done{false};
  sim::GeometryMirror mirror;
  std::uint64_t versions_seen = 0, last_version = 0;
  std::thread reader([&] {  // a viewer's thread
    while (!done.load(std::memory_order_acquire)) {
      mirror.pull(stream);
      mirror.clearChanges();
      if (mirror.tets().version() != last_version) last_version = mirror.tets().version(), ++versions_seen;
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
    mirror.pull(stream);
  });
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  done.store(true, std::memory_order_release);
  reader.join();
  REQUIRE(report.geometry_flushed);
  CHECK(versions_seen > 20);  // the tets changed under the reader's eyes, not only at the end
  CHECK(mirror.tets().resets() == 1);
  CHECK(l.world->tets()->stats().tets_cut > 0);
  requireSameMesh(mirror, l.world->tissue());
  requireSameTetBoundary(mirror, *l.world->tets());
}

TEST_CASE("geometry_stream: a second incision keeps the tets' numbering, the reader follows it and ends exact",
          "[sim][tets]") {
  Loaded l = shipped("bunny-tets");
  l.poses = devices::TraceReader::readAll(std::string(INCISE_SCENARIOS_DIR) + "/traces/bunny-crossing.csv");
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  stream.seed(*l.world, mirror);
  REQUIRE(mirror.tets().exact());
  const std::size_t boundary_at_start = mirror.tets().boundary().size();
  REQUIRE(boundary_at_start > 1000);
  sim::ReplayOptions o = options(l, sim::ReplayPace::Fast, stream);
  std::int64_t frames = 0, frames_tets_complete = 0;
  o.geometry_reader = [&] {
    mirror.pull(stream);
    ++frames;
    frames_tets_complete += mirror.tets().complete();
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  REQUIRE(report.geometry_flushed);
  CHECK(l.world->incisions() >= 2);
  CHECK(l.world->tets()->stats().rebased_tets > 100);          // the second incision rebased the first's tets
  CHECK(mirror.tets().resets() == 1);                          // the seed's only: no renumbering, no re-sync
  CHECK(frames_tets_complete == frames);                       // drawable in every frame
  CHECK(mirror.tets().boundary().size() > boundary_at_start);  // the wounds' walls
  requireSameMesh(mirror, l.world->tissue());
  requireSameTetBoundary(mirror, *l.world->tets());
}
