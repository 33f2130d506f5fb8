#include "incise/jobs/mesh_arrays.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "incise/mesh/mesh_hash.h"

namespace {

using namespace incise;

// A unit cube: 8 vertices, 12 triangles counter-clockwise from outside.
const std::vector<double> kCube = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
const std::vector<std::int64_t> kCubeFaces = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                              1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};

struct Arrays {
  std::vector<double> xyz;
  std::vector<std::int64_t> faces;
  std::vector<std::uint8_t> kinds;
};

Arrays arraysOf(const mesh::SurfaceMesh& m) {
  Arrays a;
  a.xyz.resize(3 * jobs::liveVertices(m.mesh()));
  a.faces.resize(3 * jobs::liveFaces(m.mesh()));
  a.kinds.resize(jobs::liveFaces(m.mesh()));
  jobs::copyVertices(m, a.xyz);
  jobs::copyFaces(m, a.faces, a.kinds);
  return a;
}

}  // namespace

TEST_CASE("mesh_arrays: the bunny copied out and built again from its arrays has the file's geometry hash", "[jobs]") {
  const mesh::SurfaceMesh bunny = mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01);
  const Arrays a = arraysOf(bunny);
  CHECK(a.xyz.size() == 3 * bunny.mesh().n_vertices());
  const mesh::SurfaceMesh again = jobs::meshFromArrays(a.xyz, a.faces);
  CHECK(mesh::geometryHash(again) == mesh::geometryHash(bunny));
  CHECK(jobs::verticesContiguous(again.mesh()));
}

TEST_CASE("mesh_arrays: the copies leave deleted faces out and re-index past deleted vertices", "[jobs]") {
  mesh::SurfaceMesh cube = jobs::meshFromArrays(kCube, kCubeFaces);
  mesh::TriMesh& m = cube.mesh();
  const auto isolated = m.add_vertex(mesh::TriMesh::Point(5, 5, 5));  // index 8, then deleted
  m.delete_vertex(isolated);
  const auto spare = m.add_vertex(mesh::TriMesh::Point(7, 7, 7));  // index 9: 8 once compacted
  (void)spare;
  m.delete_face(mesh::TriMesh::FaceHandle(0), false);
  cube.setKind(mesh::TriMesh::FaceHandle(11), mesh::FaceKind::Wall);
  const Arrays a = arraysOf(cube);
  REQUIRE(a.faces.size() == 3 * 11);
  CHECK(a.xyz.size() == 3 * 9);
  CHECK(a.xyz[3 * 8] == 7.0);  // the vertex after the deleted one moved up
  // Face 1 (0, 3, 2) comes first now, whichever of its corners the half-edge structure starts at.
  std::vector<std::int64_t> first(a.faces.begin(), a.faces.begin() + 3);
  std::rotate(first.begin(), std::min_element(first.begin(), first.end()), first.end());
  CHECK(first == std::vector<std::int64_t>{0, 3, 2});
  CHECK(a.kinds.back() == static_cast<std::uint8_t>(mesh::FaceKind::Wall));
  CHECK_FALSE(jobs::verticesContiguous(m));
}

TEST_CASE("mesh_arrays: bad arrays are refused naming the vertex or face at fault", "[jobs]") {
  std::vector<std::int64_t> faces = kCubeFaces;
  CHECK_THROWS_WITH(jobs::meshFromArrays(std::span(kCube.data(), 23), kCubeFaces),
                    Catch::Contains("both must be multiples of 3"));
  faces[7] = 8;
  CHECK_THROWS_WITH(jobs::meshFromArrays(kCube, faces), "face 2: vertex index 8 is out of range (8 vertices)");
  faces[7] = faces[6];
  CHECK_THROWS_WITH(jobs::meshFromArrays(kCube, faces), Catch::StartsWith("face 2: repeated vertex"));
  CHECK_THROWS_WITH(jobs::meshFromArrays(kCube, std::span(kCubeFaces.data(), 33)),
                    Catch::StartsWith("not a closed two-manifold: "));
  std::vector<double> xyz = kCube;
  xyz[4] = std::nan("");
  CHECK_THROWS_WITH(jobs::meshFromArrays(xyz, kCubeFaces), "vertex 1: coordinate 1 is not finite");
  faces = kCubeFaces;
  std::swap(faces[0], faces[1]);  // face 0 turned inside out: its edge (2, 0) runs as face 1's does
  CHECK_THROWS_WITH(jobs::meshFromArrays(kCube, faces),
                    "face 1: edge (2, 0) runs the same way in face 0 (a face turned inside out, or an edge of more "
                    "than two faces)");
  CHECK_THROWS_AS(jobs::meshFromArrays(kCube, {}), mesh::MeshError);
}
