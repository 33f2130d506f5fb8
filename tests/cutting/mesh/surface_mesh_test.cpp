// Tests for cutting/mesh/src/surface_mesh.cpp, surface_mesh_io.cpp and surface_mesh_check.cpp: OBJ loading and
// its error messages, the closed-two-manifold check, OBJ/PLY saving, kinds, the JSON summary, Loop
// subdivision of the bunny, and texture coordinates (read, written, subdivided).
#include "incise/mesh/surface_mesh.h"
#include "incise/mesh/self_intersection.h"
#include "incise/mesh/shapes.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "mesh_fixture.h"
#include "support/temp_dir.h"

namespace incise::mesh {
namespace {

namespace fs = std::filesystem;
using incise::test::readFile;
using incise::test::TempDir;

const fs::path kBunny = fs::path(INCISE_SCENARIOS_DIR) / "meshes" / "bunny.obj";
constexpr int kBunnyVertices = 1839;
constexpr int kBunnyFaces = 3674;

using test::loadError;

const std::string kTetVertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
// Outward-facing (counter-clockwise seen from outside), one face per line; lines 5..8 of the file.
const std::string kTetFaces[4] = {"f 1 3 2\n", "f 1 2 4\n", "f 1 4 3\n", "f 2 3 4\n"};
const std::string kTet = kTetVertices + kTetFaces[0] + kTetFaces[1] + kTetFaces[2] + kTetFaces[3];

SurfaceMesh tetrahedron() {
  SurfaceMesh s;
  const auto v0 = s.addVertex({0, 0, 0}), v1 = s.addVertex({1, 0, 0}), v2 = s.addVertex({0, 1, 0}),
             v3 = s.addVertex({0, 0, 1});
  s.addFace(v0, v2, v1);
  s.addFace(v0, v1, v3);
  s.addFace(v0, v3, v2);
  s.addFace(v1, v2, v3);
  return s;
}

TEST_CASE("surface_mesh: the bunny loads as a closed two-manifold of genus 0", "[cutting]") {
  const SurfaceMesh bunny = loadSurfaceMesh(kBunny);
  REQUIRE(bunny.mesh().n_vertices() == kBunnyVertices);
  REQUIRE(bunny.mesh().n_faces() == kBunnyFaces);
  const ManifoldReport report = checkManifold(bunny.mesh());
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
  REQUIRE(report.components == 1);
  REQUIRE(report.boundary_edges == 0);
  REQUIRE(report.non_manifold_vertices == 0);
  REQUIRE(report.non_manifold_edges == 0);
  REQUIRE(report.degenerate_faces == 0);
  REQUIRE(report.first_problem.empty());
  for (const auto v : bunny.mesh().vertices()) REQUIRE(bunny.kind(v) == VertexKind::Original);
  for (const auto f : bunny.mesh().faces()) REQUIRE(bunny.kind(f) == FaceKind::Original);
}

TEST_CASE("surface_mesh: the scale argument multiplies positions and must be finite and positive", "[cutting]") {
  const SurfaceMesh metres = loadSurfaceMesh(kBunny);
  const SurfaceMesh millimetres = loadSurfaceMesh(kBunny, 0.001);
  const auto v = TriMesh::VertexHandle(7);
  REQUIRE(toEigen(millimetres.mesh().point(v)) == toEigen(metres.mesh().point(v)) * 0.001);
  REQUIRE_THROWS_AS(loadSurfaceMesh(kBunny, 0.0), std::invalid_argument);
  REQUIRE_THROWS_AS(loadSurfaceMesh(kBunny, std::nan("")), std::invalid_argument);
}

TEST_CASE("surface_mesh: two Loop subdivisions of the bunny give 58,784 triangles, closed with chi = 2", "[cutting]") {
  const TriMesh mesh = subdivideLoop(loadSurfaceMesh(kBunny).mesh(), 2);
  REQUIRE(mesh.n_faces() == 58784);
  const ManifoldReport report = checkManifold(mesh);
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
  REQUIRE(report.components == 1);
}

TEST_CASE("surface_mesh: three Loop subdivisions of the bunny give 235,136 triangles, closed with chi = 2",
          "[cutting]") {
  const TriMesh mesh = subdivideLoop(loadSurfaceMesh(kBunny).mesh(), 3);
  const ManifoldReport report = checkManifold(mesh);
  REQUIRE(mesh.n_faces() == 235136);
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
}

TEST_CASE("surface_mesh: four Loop subdivisions of the bunny give 940,544 triangles, closed with chi = 2",
          "[cutting]") {
  const TriMesh mesh = subdivideLoop(loadSurfaceMesh(kBunny).mesh(), 4);
  const ManifoldReport report = checkManifold(mesh);
  REQUIRE(mesh.n_faces() == 940544);
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
}

TEST_CASE("surface_mesh: subdivided() keeps a closed mesh closed and makes every kind Original", "[cutting]") {
  SurfaceMesh tet = tetrahedron();
  tet.setKind(TriMesh::VertexHandle(0), VertexKind::Seam);
  tet.setKind(TriMesh::FaceHandle(1), FaceKind::Wall);
  const SurfaceMesh fine = subdivided(tet, 1);
  REQUIRE(fine.mesh().n_faces() == 16);
  REQUIRE(checkManifold(fine.mesh()).closed_two_manifold);
  for (const auto v : fine.mesh().vertices()) REQUIRE(fine.kind(v) == VertexKind::Original);
  for (const auto f : fine.mesh().faces()) REQUIRE(fine.kind(f) == FaceKind::Original);
  REQUIRE(subdivideLoop(tet.mesh(), 0).n_faces() == 4);
  REQUIRE_THROWS_AS(subdivideLoop(tet.mesh(), -1), std::invalid_argument);
}

TEST_CASE("surface_mesh: OBJ slash forms, negative indices, polygons, comments and ignored statements load",
          "[cutting]") {
  TempDir dir;
  const std::string cube =
      "# a unit cube of quads\nmtllib cube.mtl\no cube\ng side\ns off\nusemtl skin\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv +1 1 1 1.0\nv 0 1 1 0.5 0.5 0.5\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
      "f 1/1 4/2 3/3 2/4\n"
      "f 5//1 6//1 7//1 8//1   # top\n"
      "f -8 -7 -3 -4\n"
      "f 4/4/1 8/3/1 7/2/1 3/1/1\n"
      "f 1 5 8 4\r\n"
      "f 2 3 7 6\n";
  const SurfaceMesh mesh = loadSurfaceMesh(dir.write("cube.obj", cube));
  REQUIRE(mesh.mesh().n_vertices() == 8);
  REQUIRE(mesh.mesh().n_faces() == 12);
  const ManifoldReport report = checkManifold(mesh.mesh());
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
  // The fan a b c d -> (a b c), (a c d), in file order.
  const auto f0 = mesh.mesh().fv_range(TriMesh::FaceHandle(0));
  std::vector<int> first(3);
  std::transform(f0.begin(), f0.end(), first.begin(), [](auto v) { return v.idx(); });
  std::rotate(first.begin(), std::min_element(first.begin(), first.end()), first.end());
  REQUIRE(first == std::vector<int>{0, 3, 2});
}

TEST_CASE("surface_mesh: an open surface is rejected, naming a boundary edge and the face's file:line", "[cutting]") {
  TempDir dir;
  const fs::path p = dir.write("open.obj", kTetVertices + kTetFaces[0] + kTetFaces[1] + kTetFaces[2]);
  const std::string message = loadError(p);
  INFO(message);
  // Edges (2, 3), (2, 4), (3, 4) have one face each; (2, 3) comes first, from face 0 on line 5.
  REQUIRE_THAT(message, Catch::Contains(p.string() + ":5: open surface: edge (2, 3) has 1 face (face 0 at line 5)"));
  REQUIRE_THAT(message, Catch::Contains("3 boundary edges in all"));
  REQUIRE_THAT(message, Catch::Contains("1-based"));
}

TEST_CASE("surface_mesh: three triangles on one edge are rejected as a non-manifold edge", "[cutting]") {
  TempDir dir;
  const fs::path p = dir.write("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  const std::string message = loadError(p);
  INFO(message);
  REQUIRE_THAT(message, Catch::Contains(p.string() + ":6: non-manifold edge (1, 2) shared by 3 faces"));
  REQUIRE_THAT(message, Catch::Contains("face 0 at line 6, face 1 at line 7, face 2 at line 8"));
}

TEST_CASE("surface_mesh: two tetrahedra sharing only a vertex are rejected as a non-manifold vertex", "[cutting]") {
  TempDir dir;
  // The second tetrahedron is the first moved up by 1 in z: its vertex 1 is the first one's vertex 4.
  const std::string second = "v 1 0 1\nv 0 1 1\nv 0 0 2\nf 4 6 5\nf 4 5 7\nf 4 7 6\nf 5 6 7\n";
  const fs::path p = dir.write("pinched.obj", kTet + second);
  const std::string message = loadError(p);
  INFO(message);
  REQUIRE_THAT(message, Catch::Contains(p.string() + ":4: non-manifold vertex 4: its 6 faces form 2 separate fans"));
}

TEST_CASE("surface_mesh: a flipped face is rejected as inconsistent orientation", "[cutting]") {
  TempDir dir;
  const fs::path p = dir.write("flipped.obj", kTetVertices + kTetFaces[0] + kTetFaces[1] + kTetFaces[2] + "f 2 4 3\n");
  const std::string message = loadError(p);
  INFO(message);
  REQUIRE_THAT(message, Catch::Contains("inconsistent orientation at edge (2, 3)"));
  REQUIRE_THAT(message, Catch::Contains("face 0 at line 5, face 3 at line 8"));
}

TEST_CASE("surface_mesh: degenerate faces (repeated vertex, zero area) are rejected with file:line", "[cutting]") {
  TempDir dir;
  const fs::path repeated = dir.write("repeated.obj", kTetVertices + "f 1 2 2\n" + kTetFaces[1]);
  std::string message = loadError(repeated);
  INFO(message);
  REQUIRE_THAT(message, Catch::Contains(repeated.string() + ":5: degenerate face 0: vertex 2 repeated"));
  const fs::path flat = dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  message = loadError(flat);
  REQUIRE_THAT(message, Catch::Contains(flat.string() + ":4: degenerate face 0: zero area"));
}

TEST_CASE("surface_mesh: a face index out of range is reported with file:line and the vertex count", "[cutting]") {
  TempDir dir;
  const fs::path p = dir.write("range.obj", kTet + "f 1 2 9\n");
  const std::string message = loadError(p);
  REQUIRE_THAT(message, Catch::Equals(p.string() + ":9: face index 9 out of range (4 vertices)"));
  const fs::path back = dir.write("back.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -3\n");
  REQUIRE_THAT(loadError(back), Catch::Contains(back.string() + ":3: face index -3 out of range"));
  const fs::path zero = dir.write("zero.obj", kTetVertices + "f 0 1 2\n");
  REQUIRE_THAT(loadError(zero), Catch::Contains(zero.string() + ":5: face index 0 is invalid"));
  const fs::path word = dir.write("word.obj", kTetVertices + "f 1 2 x\n");
  REQUIRE_THAT(loadError(word), Catch::Contains(word.string() + ":5: face index 'x' is not an integer"));
}

TEST_CASE("surface_mesh: bad coordinates (NaN, not a number, too few) are reported with file:line", "[cutting]") {
  TempDir dir;
  const fs::path nan = dir.write("nan.obj", "v 0 0 0\nv nan 0 0\n");
  REQUIRE_THAT(loadError(nan), Catch::Equals(nan.string() + ":2: coordinate 'nan' is not finite"));
  const fs::path inf = dir.write("inf.obj", "v 0 0 0\nv 0 1e999 0\n");
  REQUIRE_THAT(loadError(inf), Catch::Contains(inf.string() + ":2: coordinate '1e999'"));
  const fs::path word = dir.write("word.obj", "# header\nv 1 abc 0\n");
  REQUIRE_THAT(loadError(word), Catch::Equals(word.string() + ":2: coordinate 'abc' is not a number"));
  const fs::path trailing = dir.write("trailing.obj", "v 1 2.5x 0\n");
  REQUIRE_THAT(loadError(trailing), Catch::Contains(":1: coordinate '2.5x' is not a number"));
  const fs::path short_line = dir.write("short.obj", "v 1 2\n");
  REQUIRE_THAT(loadError(short_line), Catch::Contains(short_line.string() + ":1: expected 3 coordinates"));
  const fs::path statement = dir.write("line.obj", kTet + "l 1 2\n");
  REQUIRE_THAT(loadError(statement), Catch::Contains(statement.string() + ":9: unsupported OBJ statement 'l'"));
}

TEST_CASE("surface_mesh: a missing file, an unknown format and an empty file are MeshErrors", "[cutting]") {
  TempDir dir;
  const fs::path missing = dir.path() / "missing.obj";
  REQUIRE_THAT(loadError(missing), Catch::Contains(missing.string() + ": cannot open"));
  REQUIRE_THAT(loadError(dir.path() / "missing.ply"), Catch::Contains("missing.ply: cannot open"));
  REQUIRE_THAT(loadError(dir.write("mesh.xyz", kTet)), Catch::Contains("unsupported mesh format '.xyz'"));
  REQUIRE_THAT(loadError(dir.write("empty.obj", "# nothing\n")), Catch::Contains("empty.obj: no faces"));
}

TEST_CASE("surface_mesh: an unreferenced vertex is rejected, naming it", "[cutting]") {
  TempDir dir;
  const fs::path p =
      dir.write("extra.obj", kTetVertices + "v 5 5 5\n" + kTetFaces[0] + kTetFaces[1] + kTetFaces[2] + kTetFaces[3]);
  const std::string message = loadError(p);
  REQUIRE_THAT(message, Catch::Contains(p.string() + ":5: unreferenced vertex 5 (used by no face); 1 unreferenced"));
}

TEST_CASE("surface_mesh: OFF goes through the same closed-manifold check, 0-based vertex numbers", "[cutting]") {
  TempDir dir;
  const std::string verts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const SurfaceMesh tet =
      loadSurfaceMesh(dir.write("tet.off", "OFF\n4 4 6\n" + verts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
  REQUIRE(tet.mesh().n_faces() == 4);
  REQUIRE(checkManifold(tet.mesh()).closed_two_manifold);
  const fs::path open = dir.write("open.off", "OFF\n4 3 0\n" + verts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  REQUIRE_THAT(loadError(open), Catch::Contains(open.string() + ":7: open surface: edge (1, 2) has 1 face"));
  REQUIRE_THAT(loadError(open), Catch::Contains("(vertex numbers 0-based, as in the file)"));
  const fs::path fin =
      dir.write("fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  REQUIRE_THAT(loadError(fin), Catch::Contains(fin.string() + ":8: non-manifold edge (0, 1) shared by 3 faces"));
}

// Found by tests/fuzz/fuzz_surface_mesh: OpenMesh's PLY reader never returned from these headers (an element
// count that is not a number; no end_header; bytes stuck to end_header; a format version 'ly'; an ASCII body
// cut short), or reserved 8 GB for a count of 2e9.
// They are refused (MeshError naming the file) by incise's own PLY reader.
TEST_CASE("surface_mesh: a PLY header with a bad element line or without its end is a MeshError, not a hang",
          "[cutting]") {
  TempDir dir;
  const fs::path count = dir.write("count.ply", "ply\nformat ascii 1.0\nelement v float x\nend_header\n");
  REQUIRE_THAT(loadError(count), Catch::Contains("count.ply:3: expected 'element NAME COUNT'"));
  const fs::path endless = dir.write("endless.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  REQUIRE_THAT(loadError(endless), Catch::Contains("endless.ply: the PLY header has no 'end_header' line"));
  const fs::path stuck = dir.write("stuck.ply", std::string("ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
                                                            "property float x\nend_header\xff\xff\n\0\0\x80\x3f",
                                                            87));
  REQUIRE_THAT(loadError(stuck), Catch::Contains("stuck.ply:5: unknown PLY header line"));
  const fs::path format = dir.write("format.ply",
                                    "ply\nformat binary_little_endian ly\nformat binary_little_endian "
                                    "1.0\nelement vertex 6\nend_header\n");
  REQUIRE_THAT(loadError(format), Catch::Contains("format.ply:2: expected 'format ENCODING 1.0'"));
  const fs::path orphan =
      dir.write("orphan.ply", "ply\nformat binary_little_endian 1.0\n\nproperty float x\nend_header\n");
  REQUIRE_THAT(loadError(orphan), Catch::Contains("orphan.ply:4: a property before any element"));
  // The ASCII body: OpenMesh read on from a failed stream (the fuzzer's octahedron had its last faces cut short).
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string verts = "1 0 0\n-1 0 0\n0 1 0\n";
  REQUIRE_THAT(loadError(dir.write("short.ply", header + verts + "3 0 1\n")),
               Catch::Contains("short.ply: the file ends inside face 0"));
  REQUIRE_THAT(loadError(dir.write("nan.ply", header + "1 0 nan\n")),
               Catch::Contains("nan.ply:10: vertex 0: coordinate 'nan' is not finite"));
  REQUIRE_THAT(loadError(dir.write("minus.ply", header + verts + "-1 0 1 2\n")),
               Catch::Contains("minus.ply:13: face 0: negative list length -1"));
  const fs::path many = dir.write("many.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\n"
                                  "end_header\n0\n");
  REQUIRE_THAT(loadError(many), Catch::Contains("many.ply: the PLY vertex element has no property 'y'"));
}

// Found by tests/fuzz/fuzz_surface_mesh: OpenMesh's OFF reader took the face count -1 as 4294967295 and read
// on for ever (the fuzzer's octahedron, a vertex line lost so that "0 0 -1" became a face); a header's counts
// are reserved as they are (a count of -1: 2^32 - 1 vertices). They are refused (MeshError naming the file) by incise's own OFF reader.
TEST_CASE("surface_mesh: an OFF face with a bad vertex count, or counts the file cannot hold, is a MeshError",
          "[cutting]") {
  TempDir dir;
  const std::string verts = "1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n";
  const fs::path minus = dir.write("minus.off", "OFF\n6 3 0\n1 8 0\n" + verts + "0 0 -1\n3 0 2 4\n-1 0 0\n");
  REQUIRE_THAT(loadError(minus), Catch::Contains("minus.off:9: face 0: '0' is not a vertex count"));
  const fs::path huge = dir.write("huge.off", "OFF\n6 2000000000 0\n" + verts);
  REQUIRE_THAT(loadError(huge), Catch::Contains("huge.off: the file ends after 5 of the 6 vertices"));
  // OpenMesh took its counts from the second line, "-1 0 0", and reserved 2^32 - 1 vertices (the fuzzer's input).
  const fs::path second = dir.write("second.off",
                                    "OFF\x02"
                                    "6vertex 0 0\n-1 0 0\n0\xd0 1 0\n0\"-1 0\n");
  REQUIRE_THAT(loadError(second), Catch::Contains("second.off:1: expected the OFF header"));
  const fs::path glued = dir.write("glued.off", "OFF\n6-1 0\n0 0 1\n0 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  REQUIRE_THAT(loadError(glued), Catch::Contains("glued.off:2: the vertex count '6-1' is not a count"));
  const fs::path binary =
      dir.write("binary.off", std::string("OFF BINARY 513 \x98\xea\x35\x00\xb0\x60\x00\x00 3\n", 26));
  REQUIRE_THAT(loadError(binary), Catch::Contains("binary.off:1: binary OFF is not supported"));
  const fs::path glued_binary = dir.write("glued-binary.off", "OFF\bBINARYfa6 8 0\n2 0 0\n-1 0 -1 0\n0 0 1\n");
  REQUIRE_THAT(loadError(glued_binary), Catch::Contains("glued-binary.off:1: expected the OFF header"));
  const fs::path few = dir.write("few.off", "OFF\n6 8 0\n" + verts + "0 0 -1\n3 0 23 1 2 6\n3 3 1 4\n");
  REQUIRE_THAT(loadError(few), Catch::Contains("few.off:9: face 0 has index 23 but there are 6 vertices"));
}

TEST_CASE("surface_mesh: kinds default to Original and stay in sync through addVertex, addFace and copies",
          "[cutting]") {
  SurfaceMesh s;
  const auto a = s.addVertex({0, 0, 0}), b = s.addVertex({1, 0, 0}, VertexKind::Seam),
             c = s.addVertex({0, 1, 0}, VertexKind::Wall);
  const auto direct = s.mesh().add_vertex(toOpenMesh({0, 0, 1}));
  REQUIRE(s.kind(a) == VertexKind::Original);
  REQUIRE(s.kind(b) == VertexKind::Seam);
  REQUIRE(s.kind(c) == VertexKind::Wall);
  REQUIRE(s.kind(direct) == VertexKind::Original);
  const auto f = s.addFace(a, b, c, FaceKind::Wall), g = s.addFace(a, direct, b);
  REQUIRE(s.kind(f) == FaceKind::Wall);
  REQUIRE(s.kind(g) == FaceKind::Original);
  s.setKind(g, FaceKind::Split);
  s.setKind(a, VertexKind::Seam);

  SurfaceMesh copy = s;
  copy.setKind(g, FaceKind::Original);
  REQUIRE(copy.kind(f) == FaceKind::Wall);
  REQUIRE(s.kind(g) == FaceKind::Split);  // the copy's properties are its own
  const SurfaceMesh adopted(s.mesh());    // a TriMesh copied out of a SurfaceMesh keeps its kinds
  REQUIRE(adopted.kind(a) == VertexKind::Seam);
  REQUIRE(adopted.kind(g) == FaceKind::Split);

  REQUIRE_THROWS_AS(s.kind(TriMesh::VertexHandle(99)), std::out_of_range);
  REQUIRE_THROWS_AS(s.setKind(TriMesh::FaceHandle(), FaceKind::Wall), std::out_of_range);
  REQUIRE_THROWS_AS(s.addVertex({0, std::nan(""), 0}), std::invalid_argument);
  REQUIRE_THROWS_AS(s.addFace(a, a, b), MeshError);
  REQUIRE(s.mesh().n_faces() == 2);
  REQUIRE(std::string(toString(VertexKind::Seam)) == "seam");
  REQUIRE(std::string(toString(FaceKind::Split)) == "split");
  REQUIRE(std::string(toString(FaceKind::Wall)) == "wall");
  REQUIRE(std::string(toString(VertexKind::Original)) == "original");
}

TEST_CASE("surface_mesh: addFace refuses a face OpenMesh cannot add and leaves the mesh unchanged", "[cutting]") {
  SurfaceMesh s = tetrahedron();
  // A second fan at the closed tetrahedron's vertex 3 would make it non-manifold.
  const auto p = s.addVertex({1, 0, 1}), q = s.addVertex({0, 1, 1});
  REQUIRE_THROWS_AS(s.addFace(TriMesh::VertexHandle(3), p, q), MeshError);
  REQUIRE(s.mesh().n_faces() == 4);
}

TEST_CASE("surface_mesh: checkManifold counts boundary, pinched vertices, degenerate faces and components",
          "[cutting]") {
  SECTION("a deleted face leaves 3 boundary edges, before and after garbage collection") {
    SurfaceMesh tet = tetrahedron();
    const bool delete_isolated_vertices = false;  // there are none: every vertex keeps two faces
    tet.mesh().delete_face(TriMesh::FaceHandle(3), delete_isolated_vertices);
    for (int pass = 0; pass < 2; ++pass) {
      const ManifoldReport r = checkManifold(tet.mesh());
      REQUIRE_FALSE(r.closed_two_manifold);
      REQUIRE(r.boundary_edges == 3);
      REQUIRE(r.euler_characteristic == 1);  // 4 - 6 + 3: a disc
      REQUIRE(r.components == 1);
      REQUIRE_THAT(r.first_problem, Catch::StartsWith("boundary edge"));
      tet.mesh().garbage_collection();
    }
  }
  SECTION("two triangles sharing only a vertex: a pinched, non-manifold vertex") {
    SurfaceMesh s;
    const auto o = s.addVertex({0, 0, 0});
    s.addFace(o, s.addVertex({1, 0, 0}), s.addVertex({0, 1, 0}));
    s.addFace(o, s.addVertex({-1, 0, 0}), s.addVertex({0, -1, 0}));
    const ManifoldReport r = checkManifold(s.mesh());
    REQUIRE(r.non_manifold_vertices == 1);
    REQUIRE(r.boundary_edges == 6);
    REQUIRE(r.components == 1);
  }
  SECTION("a zero-area face") {
    SurfaceMesh tet = tetrahedron();
    tet.mesh().set_point(TriMesh::VertexHandle(3), toOpenMesh({0.5, 0.5, 0.0}));
    const ManifoldReport r = checkManifold(tet.mesh());
    REQUIRE_FALSE(r.closed_two_manifold);
    REQUIRE(r.degenerate_faces >= 1);
    REQUIRE_THAT(r.first_problem, Catch::Contains("zero area"));
  }
  SECTION("two separate tetrahedra: two components, chi = 4") {
    SurfaceMesh s = tetrahedron();
    const SurfaceMesh t = tetrahedron();
    for (const auto v : t.mesh().vertices()) s.addVertex(toEigen(t.mesh().point(v)) + Eigen::Vector3d(3, 0, 0));
    for (const auto f : t.mesh().faces()) {
      std::vector<TriMesh::VertexHandle> w;
      for (const auto v : t.mesh().fv_range(f)) w.emplace_back(v.idx() + 4);
      s.addFace(w[0], w[1], w[2]);
    }
    const ManifoldReport r = checkManifold(s.mesh());
    REQUIRE(r.closed_two_manifold);
    REQUIRE(r.components == 2);
    REQUIRE(r.euler_characteristic == 4);
  }
  SECTION("an empty mesh is not a closed two-manifold") {
    const ManifoldReport r = checkManifold(TriMesh());
    REQUIRE_FALSE(r.closed_two_manifold);
    REQUIRE(r.first_problem == "empty mesh (no faces)");
  }
}

TEST_CASE("surface_mesh: saveObj round-trips the bunny exactly", "[cutting]") {
  TempDir dir;
  const SurfaceMesh bunny = loadSurfaceMesh(kBunny);
  const fs::path p = dir.path() / "bunny-out.obj";
  saveObj(bunny, p);
  REQUIRE_FALSE(fs::exists(p.string() + ".tmp"));
  const SurfaceMesh back = loadSurfaceMesh(p);
  REQUIRE(back.mesh().n_vertices() == bunny.mesh().n_vertices());
  REQUIRE(back.mesh().n_faces() == bunny.mesh().n_faces());
  for (const auto v : bunny.mesh().vertices()) REQUIRE(back.mesh().point(v) == bunny.mesh().point(v));
  for (const auto f : bunny.mesh().faces()) {
    const auto a = bunny.mesh().fv_range(f), b = back.mesh().fv_range(f);
    REQUIRE(std::equal(a.begin(), a.end(), b.begin()));
  }
}

TEST_CASE("surface_mesh: saveObj puts Wall faces into a 'g wall' group", "[cutting]") {
  TempDir dir;
  SurfaceMesh bunny = loadSurfaceMesh(kBunny);
  const fs::path plain = dir.path() / "plain.obj";
  saveObj(bunny, plain);
  REQUIRE(readFile(plain).find("g wall") == std::string::npos);
  for (int f = 0; f < 10; ++f) bunny.setKind(TriMesh::FaceHandle(f), FaceKind::Wall);
  bunny.setKind(TriMesh::FaceHandle(10), FaceKind::Split);
  const fs::path p = dir.path() / "walls.obj";
  saveObj(bunny, p);
  const std::string text = readFile(p);
  const auto tissue = text.find("\ng tissue\n"), wall = text.find("\ng wall\n");
  REQUIRE(tissue != std::string::npos);
  REQUIRE(wall != std::string::npos);
  REQUIRE(tissue < wall);
  REQUIRE(std::count(text.begin() + static_cast<std::ptrdiff_t>(wall), text.end(), 'f') == 10);
  const SurfaceMesh back = loadSurfaceMesh(p);  // reordered faces, same closed surface
  REQUIRE(back.mesh().n_faces() == kBunnyFaces);
  REQUIRE(checkManifold(back.mesh()).closed_two_manifold);
}

TEST_CASE("surface_mesh: savePly writes per-vertex and per-face kind properties and loads back", "[cutting]") {
  TempDir dir;
  SurfaceMesh bunny = loadSurfaceMesh(kBunny);
  bunny.setKind(TriMesh::FaceHandle(0), FaceKind::Wall);
  bunny.setKind(TriMesh::FaceHandle(1), FaceKind::Split);
  bunny.setKind(TriMesh::VertexHandle(0), VertexKind::Seam);
  const fs::path p = dir.path() / "bunny.ply";
  savePly(bunny, p);
  const std::string text = readFile(p);
  const std::string header = text.substr(0, text.find("end_header\n"));
  REQUIRE_THAT(header, Catch::Contains("element vertex 1839\nproperty double x\nproperty double y\n"
                                       "property double z\nproperty uchar kind\n"));
  REQUIRE_THAT(header, Catch::Contains("element face 3674\nproperty list uchar int vertex_indices\n"
                                       "property uchar kind\n"));
  std::istringstream body(text.substr(text.find("end_header\n") + 11));
  std::string line;
  std::getline(body, line);
  REQUIRE(line.back() == '1');  // vertex 0: seam
  for (int v = 1; v < kBunnyVertices; ++v) std::getline(body, line);
  std::getline(body, line);
  REQUIRE(line.substr(line.size() - 2) == " 2");  // face 0: wall
  std::getline(body, line);
  REQUIRE(line.substr(line.size() - 2) == " 1");  // face 1: split
  const SurfaceMesh back = loadSurfaceMesh(p);
  REQUIRE(back.mesh().n_vertices() == kBunnyVertices);
  REQUIRE(back.mesh().n_faces() == kBunnyFaces);
  REQUIRE(checkManifold(back.mesh()).closed_two_manifold);
}

TEST_CASE("surface_mesh: saving the same mesh twice gives identical bytes", "[cutting]") {
  TempDir dir;
  SurfaceMesh bunny = loadSurfaceMesh(kBunny);
  bunny.setKind(TriMesh::FaceHandle(5), FaceKind::Wall);
  saveObj(bunny, dir.path() / "a.obj");
  saveObj(bunny, dir.path() / "b.obj");
  savePly(bunny, dir.path() / "a.ply");
  savePly(bunny, dir.path() / "b.ply");
  REQUIRE(readFile(dir.path() / "a.obj") == readFile(dir.path() / "b.obj"));
  REQUIRE(readFile(dir.path() / "a.ply") == readFile(dir.path() / "b.ply"));
  REQUIRE(readFile(dir.path() / "a.obj").size() > 100000);
}

TEST_CASE("surface_mesh: saving skips deleted elements and re-indexes the rest", "[cutting]") {
  TempDir dir;
  SurfaceMesh tet = tetrahedron();
  tet.mesh().delete_vertex(TriMesh::VertexHandle(0));  // takes its 3 faces along
  const fs::path p = dir.path() / "rest.obj";
  saveObj(tet, p);
  const std::string text = readFile(p);
  REQUIRE(std::count(text.begin(), text.end(), '\n') == 6);  // comment, 3 vertices, group, face
  REQUIRE_THAT(text, Catch::Contains("\nv 0 1 0\nv 0 0 1\ng tissue"));
  REQUIRE_THAT(text, Catch::EndsWith("g tissue\nf 1 2 3\n"));
  savePly(tet, dir.path() / "rest.ply");
  REQUIRE_THAT(readFile(dir.path() / "rest.ply"), Catch::EndsWith("3 0 1 2 0\n"));
}

TEST_CASE("surface_mesh: a failed save throws MeshError naming the path and leaves no .tmp", "[cutting]") {
  TempDir dir;
  const SurfaceMesh tet = tetrahedron();
  const fs::path nowhere = dir.path() / "no-such-dir" / "out.obj";
  try {
    saveObj(tet, nowhere);
    FAIL("saveObj into a missing directory did not throw");
  } catch (const MeshError& e) {
    REQUIRE_THAT(e.what(), Catch::Contains(nowhere.string()));
  }
  REQUIRE_THROWS_AS(savePly(tet, dir.path() / "no-such-dir" / "out.ply"), MeshError);
  // The target is a non-empty directory: the .tmp is written, the rename fails, the .tmp goes away.
  const fs::path blocked = dir.path() / "blocked.obj";
  fs::create_directories(blocked / "inside");
  REQUIRE_THROWS_AS(saveObj(tet, blocked), MeshError);
  REQUIRE_FALSE(fs::exists(blocked.string() + ".tmp"));
  REQUIRE(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1);
  SurfaceMesh bad = tetrahedron();
  bad.mesh().set_point(TriMesh::VertexHandle(2), OpenMesh::Vec3d(0, std::nan(""), 0));
  REQUIRE_THROWS_AS(saveObj(bad, dir.path() / "bad.obj"), MeshError);
  REQUIRE_FALSE(fs::exists(dir.path() / "bad.obj.tmp"));
}

TEST_CASE("surface_mesh: summarize counts kinds and toJson writes every field", "[cutting]") {
  SurfaceMesh tet = tetrahedron();
  tet.setKind(TriMesh::FaceHandle(0), FaceKind::Wall);
  tet.setKind(TriMesh::FaceHandle(1), FaceKind::Split);
  tet.setKind(TriMesh::FaceHandle(2), FaceKind::Split);
  tet.setKind(TriMesh::VertexHandle(1), VertexKind::Seam);
  tet.setKind(TriMesh::VertexHandle(2), VertexKind::Wall);
  const MeshSummary s = summarize(tet);
  REQUIRE(s.vertices == 4);
  REQUIRE(s.faces == 4);
  REQUIRE(s.wall_faces == 1);
  REQUIRE(s.split_faces == 2);
  REQUIRE(s.seam_vertices == 1);
  REQUIRE(s.wall_vertices == 1);
  REQUIRE(s.boundary_edges == 0);
  REQUIRE(s.euler_characteristic == 2);
  REQUIRE(s.closed_two_manifold);
  REQUIRE(s.self_intersections == 0);
  REQUIRE(toJson(s) ==
          "{\n  \"vertices\": 4,\n  \"faces\": 4,\n  \"wall_faces\": 1,\n  \"split_faces\": 2,\n"
          "  \"seam_vertices\": 1,\n  \"wall_vertices\": 1,\n  \"boundary_edges\": 0,\n"
          "  \"euler_characteristic\": 2,\n  \"closed_two_manifold\": true,\n  \"self_intersections\": 0\n}");
}

TEST_CASE("surface_mesh: summarize counts the pairs of faces that cross", "[cutting]") {
  // Two closed boxes, one through the other: every crossing pair is counted; apart, none.
  const SurfaceMesh box = makeBox(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), 1);
  const SurfaceMesh two =
      merge({box, makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(0.5, 0.25, 0.25), Eigen::Vector3d(1.5, 0.75, 0.75)), 1)});
  const SurfaceMesh apart =
      merge({box, makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(3, 1, 1)), 1)});
  REQUIRE(summarize(two).closed_two_manifold);
  CHECK(summarize(two).self_intersections > 0);
  CHECK(summarize(two).self_intersections == static_cast<int>(findSelfIntersections(two.mesh()).size()));
  CHECK(summarize(apart).self_intersections == 0);
}

}  // namespace
}  // namespace incise::mesh

// ---------------------------------------------------------------------------------------------------------
// Texture coordinates

// A unit cube of 8 vertices and 6 quads, each quad mapped onto its own rectangle of a 3 x 2 atlas: every cube
// vertex has three texture coordinates (one per face around it), every cube edge is a texture seam.
// With `materials`: `mtllib cube.mtl`, the first two quads `usemtl skin`, the others `usemtl nail`.
std::string texturedCubeObj(bool materials = false) {
  std::ostringstream obj;
  obj.precision(17);
  if (materials) obj << "mtllib cube.mtl\nusemtl skin\n";
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) obj << "v " << x << ' ' << y << ' ' << z << '\n';
  const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int f = 0; f < 6; ++f) {  // a 0.25 x 0.375 rectangle each, apart from the others
    const double u0 = (f % 3) / 3.0, v0 = (f / 3) / 2.0;
    obj << "vt " << u0 << ' ' << v0 << "\nvt " << u0 + 0.25 << ' ' << v0 << "\nvt " << u0 + 0.25 << ' ' << v0 + 0.375
        << "\nvt " << u0 << ' ' << v0 + 0.375 << '\n';
  }
  for (int f = 0; f < 6; ++f) {
    if (materials && f == 2) obj << "usemtl nail\n";
    obj << 'f';
    for (int k = 0; k < 4; ++k) obj << ' ' << quads[f][k] << '/' << 4 * f + k + 1 << "/1";
    obj << '\n';
  }
  return obj.str();
}

SurfaceMesh loadText(const TempDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.path() / name) << text;
  return loadSurfaceMesh(dir.path() / name);
}

// The distinct texture coordinates of each vertex's corners.
std::vector<std::vector<Eigen::Vector2d>> coordinatesAt(const SurfaceMesh& s) {
  std::vector<std::vector<Eigen::Vector2d>> at(s.mesh().n_vertices());
  for (const auto f : s.mesh().faces())
    for (const auto h : s.mesh().fh_range(f)) {
      auto& list = at[static_cast<size_t>(s.mesh().to_vertex_handle(h).idx())];
      const Eigen::Vector2d uv = s.texCoord(h);
      if (std::none_of(list.begin(), list.end(), [&](const Eigen::Vector2d& o) { return (o - uv).norm() < 1e-12; }))
        list.push_back(uv);
    }
  return at;
}

// The sum of the faces' signed areas in texture space.
double textureArea(const SurfaceMesh& s) {
  double area = 0.0;
  for (const auto f : s.mesh().faces()) {
    const FaceCorners c = faceCorners(s, f);
    const Eigen::Vector2d a = c.uv[1] - c.uv[0], b = c.uv[2] - c.uv[0];
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  return area;
}

TEST_CASE("surface_mesh: an OBJ's texture coordinates are read per corner, seams kept, and written back", "[cutting]") {
  const TempDir dir;
  const SurfaceMesh cube = loadText(dir, "cube.obj", texturedCubeObj());
  REQUIRE(cube.hasTexCoords());
  REQUIRE(cube.mesh().n_faces() == 12);
  // Each cube vertex lies on three faces of the atlas: three coordinates, one per quad around it.
  for (const auto& list : coordinatesAt(cube)) CHECK(list.size() == 3);
  CHECK(textureArea(cube) == Approx(6 * 0.25 * 0.375));  // the atlas's six rectangles, counter-clockwise
  // Quad 1 (v 1 3 4 2 with vt 1..4): vertex 4 (index 3) has vt 3 = (0.25, 0.375) in its faces.
  bool found = false;
  for (const auto f : cube.mesh().faces()) {
    const FaceCorners c = faceCorners(cube, f);
    if (c.at(TriMesh::VertexHandle(0)) && c.at(TriMesh::VertexHandle(2)) && c.at(TriMesh::VertexHandle(3)) &&
        (*c.at(TriMesh::VertexHandle(0)) - Eigen::Vector2d(0, 0)).norm() < 1e-12) {
      found = true;
      CHECK((*c.at(TriMesh::VertexHandle(3)) - Eigen::Vector2d(0.25, 0.375)).norm() < 1e-12);
    }
  }
  CHECK(found);

  saveObj(cube, dir.path() / "out.obj");
  const std::string text = readFile(dir.path() / "out.obj");
  CHECK(std::count(text.begin(), text.end(), '/') == 36);  // every corner of the 12 faces as v/vt
  CHECK(text.find("\nvt ") != std::string::npos);
  const SurfaceMesh again = loadSurfaceMesh(dir.path() / "out.obj");
  REQUIRE(again.hasTexCoords());
  for (const auto f : cube.mesh().faces()) {
    const FaceCorners a = faceCorners(cube, f), b = faceCorners(again, f);
    for (size_t i = 0; i < 3; ++i) CHECK(b.at(a.vertex[i]) == a.uv[i]);  // bit for bit (%.17g)
  }
  saveObj(again, dir.path() / "again.obj");
  CHECK(readFile(dir.path() / "again.obj") == text);
}

TEST_CASE("surface_mesh: a mesh without texture coordinates has none and is written as before", "[cutting]") {
  const TempDir dir;
  const SurfaceMesh tet = loadText(dir, "tet.obj", kTet);
  CHECK_FALSE(tet.hasTexCoords());
  CHECK_THROWS_AS(tet.texCoord(TriMesh::HalfedgeHandle(0)), std::logic_error);
  saveObj(tet, dir.path() / "out.obj");
  const std::string text = readFile(dir.path() / "out.obj");
  CHECK(text.find("vt") == std::string::npos);
  CHECK(text.find('/') == std::string::npos);
}

TEST_CASE("surface_mesh: texture coordinates out of range are refused with file:line, partial ones dropped",
          "[cutting]") {
  const TempDir dir;
  const std::string v = kTetVertices + "vt 0 0\nvt 1 0\nvt 0 1\n";  // vt on lines 5..7
  const std::string faces = "f 1/1 3/2 2/3\nf 1/1 2/2 4/3\nf 1/1 4/2 3/3\n";
  // A face (or one corner) without: the mesh loads without texture coordinates, as a mesh without vt.
  std::ofstream(dir.path() / "mixed.obj") << v << faces << "f 2 3 4\n";
  CHECK_FALSE(loadSurfaceMesh(dir.path() / "mixed.obj").hasTexCoords());
  std::ofstream(dir.path() / "partial.obj") << v << faces << "f 2/1 3 4/3\n";
  CHECK_FALSE(loadSurfaceMesh(dir.path() / "partial.obj").hasTexCoords());
  std::ofstream(dir.path() / "all.obj") << v << faces << "f 2/1 3/2 4/3\n";
  CHECK(loadSurfaceMesh(dir.path() / "all.obj").hasTexCoords());
  std::ofstream(dir.path() / "range.obj") << v << "f 1/1 3/2 2/9\n";
  CHECK_THAT(loadError(dir.path() / "range.obj"),
             Catch::Matchers::Contains("range.obj:8: texture coordinate index 9 out of range (3 texture coordinates)"));
  std::ofstream(dir.path() / "word.obj") << v << "f 1/x 3/2 2/3\n";
  CHECK_THAT(loadError(dir.path() / "word.obj"),
             Catch::Matchers::Contains("word.obj:8: texture coordinate index '1/x' is not an integer"));
  std::ofstream(dir.path() / "short.obj") << kTetVertices << "vt 0.5\n";
  CHECK_THAT(loadError(dir.path() / "short.obj"), Catch::Matchers::Contains("short.obj:5: expected 2 texture"));
}

TEST_CASE("surface_mesh: subdivision carries texture coordinates linearly and keeps their seams", "[cutting]") {
  const TempDir dir;
  const SurfaceMesh cube = loadText(dir, "cube.obj", texturedCubeObj());
  const SurfaceMesh fine = subdivided(cube, 2);
  REQUIRE(fine.hasTexCoords());
  REQUIRE(fine.mesh().n_faces() == 12 * 16);
  // Midpoint subdivision within each face keeps the texture area exactly, and no face turns over in it.
  CHECK(textureArea(fine) == Approx(6 * 0.25 * 0.375).epsilon(1e-12));
  for (const auto f : fine.mesh().faces()) {
    const FaceCorners c = faceCorners(fine, f);
    const Eigen::Vector2d a = c.uv[1] - c.uv[0], b = c.uv[2] - c.uv[0];
    CHECK(a.x() * b.y() - a.y() * b.x() > 0.0);
  }
  // The seams: the 8 corners keep 3 coordinates each; a vertex inside a cube edge has 2, inside a face 1.
  const auto at = coordinatesAt(fine);
  int on_corners = 0, on_edges = 0, inside = 0;
  for (size_t v = 0; v < at.size(); ++v) {
    on_corners += at[v].size() == 3;
    on_edges += at[v].size() == 2;
    inside += at[v].size() == 1;
  }
  CHECK(on_corners == 8);
  CHECK(on_edges == 12 * 3);  // three new vertices on each cube edge after two rounds
  CHECK(inside == 6 * 9);     // each quad a 5 x 5 grid: 9 vertices inside it (its diagonal's 3 among them)
}

TEST_CASE(
    "surface_mesh: an OBJ's materials come from its MTL file, stay per face and are written back with the "
    "walls'",
    "[cutting]") {
  const TempDir dir;
  fs::create_directories(dir.path() / "in");
  std::ofstream(dir.path() / "in" / "cube.mtl")
      << "# skin and nail\nnewmtl skin\nKd 0.9 0.7 0.6\nmap_Kd  textures/skin.png   # relative\n\nnewmtl nail\n"
         "Kd 1 1 1\nmap_Kd /abs/nail.png\n";
  std::ofstream(dir.path() / "in" / "cube.obj") << texturedCubeObj(true);
  const SurfaceMesh cube = loadSurfaceMesh(dir.path() / "in" / "cube.obj");
  REQUIRE(cube.hasMaterials());
  REQUIRE(cube.materials().size() == 2);
  CHECK(cube.materials()[0].name == "skin");
  CHECK(cube.materials()[0].statements ==
        std::vector<std::string>{"Kd 0.9 0.7 0.6", "map_Kd " + (dir.path() / "in" / "textures" / "skin.png").string()});
  CHECK(cube.materials()[1].statements == std::vector<std::string>{"Kd 1 1 1", "map_Kd /abs/nail.png"});
  for (const auto f : cube.mesh().faces()) CHECK(cube.material(f) == (f.idx() < 4 ? 0 : 1));  // 2 quads skin

  // A subdivided copy keeps each face's material (a fine face lies in one coarse face).
  const SurfaceMesh fine = subdivided(cube, 1);
  REQUIRE(fine.hasMaterials());
  int skin = 0;
  for (const auto f : fine.mesh().faces()) skin += fine.material(f) == 0;
  CHECK(skin == 16);

  // Written: cut.mtl beside cut.obj with both materials and the walls', usemtl before each run.
  SurfaceMesh walled = cube;
  walled.setKind(TriMesh::FaceHandle(11), FaceKind::Wall);
  saveObj(walled, dir.path() / "cut.obj");
  const std::string obj = readFile(dir.path() / "cut.obj"), mtl = readFile(dir.path() / "cut.mtl");
  CHECK(obj.find("mtllib cut.mtl\n") != std::string::npos);
  CHECK(obj.find("g tissue\nusemtl skin\nf ") != std::string::npos);
  CHECK(obj.find("usemtl nail\nf ") != std::string::npos);
  CHECK(obj.find("g wall\nusemtl incise_wall\nf ") != std::string::npos);
  CHECK(mtl.find("newmtl skin\nKd 0.9 0.7 0.6\nmap_Kd " + (dir.path() / "in" / "textures" / "skin.png").string()) !=
        std::string::npos);
  CHECK(mtl.find("newmtl nail\n") != std::string::npos);
  CHECK(mtl.find("newmtl incise_wall\n") != std::string::npos);
  // With texture coordinates, the walls' flesh image beside it (scenarios/textures/flesh.png).
  CHECK(mtl.find("\nmap_Kd incise_flesh.png\n") != std::string::npos);
  const std::string png = readFile(dir.path() / "incise_flesh.png");
  const auto flesh = detail::wallTexturePng();
  CHECK(png.size() > 1000);
  CHECK(png.rfind("\x89PNG\r\n\x1a\n", 0) == 0);
  CHECK(png == std::string(reinterpret_cast<const char*>(flesh.data()), flesh.size()));
  // Read back: the same materials per face, the walls' one added to the list once.
  const SurfaceMesh again = loadSurfaceMesh(dir.path() / "cut.obj");
  REQUIRE(again.materials().size() == 3);
  for (const auto f : cube.mesh().faces())
    CHECK(again.materials()[static_cast<size_t>(again.material(f))].name ==
          (f.idx() == 11 ? "incise_wall" : cube.materials()[static_cast<size_t>(cube.material(f))].name));
  saveObj(again, dir.path() / "again.obj");
  CHECK(readFile(dir.path() / "again.mtl").find("newmtl incise_wall") ==
        readFile(dir.path() / "again.mtl").rfind("newmtl incise_wall"));
}

TEST_CASE("surface_mesh: usemtl without its MTL file loads with the names only, and no usemtl means no materials",
          "[cutting]") {
  const TempDir dir;
  std::ofstream(dir.path() / "cube.obj") << texturedCubeObj(true);  // no cube.mtl beside it
  const SurfaceMesh cube = loadSurfaceMesh(dir.path() / "cube.obj");
  REQUIRE(cube.hasMaterials());
  CHECK(cube.materials() == std::vector<Material>{{"skin", {}}, {"nail", {}}});
  std::ofstream(dir.path() / "devices.obj") << "mtllib /dev/zero /proc\n" << kTet;  // not regular files: skipped
  CHECK_FALSE(loadSurfaceMesh(dir.path() / "devices.obj").hasMaterials());
  std::ofstream(dir.path() / "late.obj") << kTetVertices << kTetFaces[0] << "usemtl skin\n"
                                         << kTetFaces[1] << kTetFaces[2] << kTetFaces[3];
  const SurfaceMesh late = loadSurfaceMesh(dir.path() / "late.obj");
  REQUIRE(late.materials().size() == 2);
  CHECK(late.materials()[static_cast<size_t>(late.material(TriMesh::FaceHandle(0)))].name == "default");
  CHECK(late.materials()[static_cast<size_t>(late.material(TriMesh::FaceHandle(1)))].name == "skin");
  // Without texture coordinates the walls' material has no image, and none is written.
  fs::create_directories(dir.path() / "out");
  saveObj(late, dir.path() / "out" / "late.obj");
  CHECK(readFile(dir.path() / "out" / "late.mtl").find("map_Kd") == std::string::npos);
  CHECK_FALSE(fs::exists(dir.path() / "out" / "incise_flesh.png"));
}

TEST_CASE("surface_mesh: boxTexCoords maps each face on the two axes across its normal, over the tile", "[cutting]") {
  SurfaceMesh box =
      makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-0.01, -0.02, -0.03), Eigen::Vector3d(0.02, 0.01, 0.0)), 3);
  REQUIRE_THROWS_AS(boxTexCoords(box, 0.0), std::invalid_argument);
  REQUIRE_FALSE(box.hasTexCoords());
  boxTexCoords(box, 0.005);
  REQUIRE(box.hasTexCoords());
  std::array<int, 3> per_axis{0, 0, 0};
  for (const auto f : box.mesh().faces()) {
    const FaceCorners c = faceCorners(box, f);
    std::array<Eigen::Vector3d, 3> x;
    for (std::size_t i = 0; i < 3; ++i) x[i] = toEigen(box.mesh().point(c.vertex[i]));
    Eigen::Index axis = 0;
    (x[1] - x[0]).cross(x[2] - x[0]).cwiseAbs().maxCoeff(&axis);
    ++per_axis[static_cast<std::size_t>(axis)];
    const int a = axis == 0 ? 2 : 0, b = axis == 1 ? 2 : 1;
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(c.uv[i].x() == Approx(x[i][a] / 0.005).margin(1e-12));
      CHECK(c.uv[i].y() == Approx(x[i][b] / 0.005).margin(1e-12));
    }
  }
  CHECK(per_axis == std::array<int, 3>{36, 36, 36});  // 2 sides x 3 x 3 squares x 2 triangles
}
