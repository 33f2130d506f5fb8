#include "incise/mesh/mesh_hash.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "incise/mesh/shapes.h"

using namespace incise;
using namespace incise::mesh;

namespace {

SurfaceMesh unitBox() { return makeBox(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), 2); }

// The same box rebuilt vertex by vertex and face by face, after a lone triangle that comes first in handle
// order (its three vertices take indices 0..2, so the box's vertices are shifted by 3).
SurfaceMesh boxAfterTriangle(const SurfaceMesh& box, TriMesh::FaceHandle& triangle) {
  SurfaceMesh out;
  const auto a = out.addVertex(Eigen::Vector3d(5, 5, 5));
  const auto b = out.addVertex(Eigen::Vector3d(6, 5, 5));
  const auto c = out.addVertex(Eigen::Vector3d(5, 6, 5));
  triangle = out.addFace(a, b, c);
  std::vector<TriMesh::VertexHandle> map;
  for (const auto v : box.mesh().vertices()) map.push_back(out.addVertex(toEigen(box.mesh().point(v))));
  for (const auto f : box.mesh().faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v = box.mesh().cfv_iter(f); v.is_valid(); ++v) corners.push_back(map[static_cast<std::size_t>(v->idx())]);
    out.addFace(corners[0], corners[1], corners[2], box.kind(f));
  }
  return out;
}

}  // namespace

TEST_CASE("mesh_hash: the same mesh gives the same hash, one changed coordinate bit another", "[cutting]") {
  const SurfaceMesh box = unitBox();
  const std::uint64_t h = geometryHash(box);
  SurfaceMesh copy = box;
  REQUIRE(geometryHash(copy) == h);
  REQUIRE(geometryHash(unitBox()) == h);  // the same call builds the same mesh

  // Every coordinate of a few vertices, one ulp up: each changes the hash; moving back restores it.
  for (const int id : {0, 7, static_cast<int>(box.mesh().n_vertices()) - 1}) {
    for (int axis = 0; axis < 3; ++axis) {
      const TriMesh::VertexHandle v(id);
      const double x = copy.mesh().point(v)[axis];
      copy.mesh().point(v)[axis] = std::nextafter(x, std::numeric_limits<double>::infinity());
      REQUIRE(copy.mesh().point(v)[axis] != x);
      CHECK(geometryHash(copy) != h);
      copy.mesh().point(v)[axis] = x;
      REQUIRE(geometryHash(copy) == h);
    }
  }
  // -0.0 and 0.0 compare equal but have different bytes: the hash is over the bytes.
  const TriMesh::VertexHandle origin(0);
  REQUIRE(copy.mesh().point(origin)[0] == 0.0);
  copy.mesh().point(origin)[0] = -0.0;
  CHECK(geometryHash(copy) != h);
}

TEST_CASE("mesh_hash: a face's kind is part of the hash, a vertex's kind is not", "[cutting]") {
  const SurfaceMesh box = unitBox();
  const std::uint64_t h = geometryHash(box);
  SurfaceMesh copy = box;
  const TriMesh::FaceHandle f(3);
  copy.setKind(f, FaceKind::Split);
  const std::uint64_t split = geometryHash(copy);
  REQUIRE(split != h);
  copy.setKind(f, FaceKind::Wall);
  REQUIRE(geometryHash(copy) != h);
  REQUIRE(geometryHash(copy) != split);
  copy.setKind(f, FaceKind::Original);
  REQUIRE(geometryHash(copy) == h);

  // The header lists positions, face indices and face kinds only.
  copy.setKind(TriMesh::VertexHandle(2), VertexKind::Seam);
  REQUIRE(geometryHash(copy) == h);
}

TEST_CASE("mesh_hash: the order of the vertices counts, and an empty mesh hashes to the FNV-1a basis", "[cutting]") {
  const SurfaceMesh box = unitBox();
  // The same set of positions, two of them swapped between handles: the faces now join other points.
  SurfaceMesh swapped = box;
  const TriMesh::VertexHandle a(0), b(1);
  const auto pa = swapped.mesh().point(a);
  swapped.mesh().point(a) = swapped.mesh().point(b);
  swapped.mesh().point(b) = pa;
  REQUIRE(geometryHash(swapped) != geometryHash(box));
  // Another box with as many vertices and faces.
  REQUIRE(geometryHash(makeBox(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 2)), 2)) !=
          geometryHash(box));
  // Nothing added: FNV-1a's 64-bit offset basis.
  REQUIRE(geometryHash(SurfaceMesh()) == 1469598103934665603ull);
}

TEST_CASE("mesh_hash: deleted elements are skipped and the faces re-indexed past deleted vertices", "[cutting]") {
  const SurfaceMesh box = unitBox();
  TriMesh::FaceHandle triangle;
  SurfaceMesh mesh = boxAfterTriangle(box, triangle);
  REQUIRE(mesh.mesh().n_vertices() == box.mesh().n_vertices() + 3);
  REQUIRE(geometryHash(mesh) != geometryHash(box));

  // Deleting the lone triangle (and its now isolated vertices) without garbage collection: the box's
  // vertices keep their handles 3.., but the hash re-indexes them from 0, as if the triangle never was.
  mesh.mesh().delete_face(triangle, true);
  REQUIRE(mesh.mesh().status(TriMesh::VertexHandle(0)).deleted());
  REQUIRE(mesh.mesh().n_vertices() == box.mesh().n_vertices() + 3);  // still there, marked deleted
  REQUIRE(geometryHash(mesh) == geometryHash(box));

  // A deleted vertex's position does not count.
  mesh.mesh().point(TriMesh::VertexHandle(1))[0] = 123.0;
  REQUIRE(geometryHash(mesh) == geometryHash(box));
}
