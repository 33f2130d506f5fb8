#include "incise/jobs/mesh_arrays.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace incise::jobs {

namespace {

using mesh::MeshError;
using mesh::TriMesh;

void checkArrays(std::span<const double> xyz_m, std::span<const std::int64_t> triangles) {
  if (xyz_m.size() % 3 != 0 || triangles.size() % 3 != 0)
    throw std::invalid_argument("mesh arrays: " + std::to_string(xyz_m.size()) + " coordinates and " +
                                std::to_string(triangles.size()) + " indices: both must be multiples of 3");
  if (triangles.empty()) throw MeshError("mesh arrays: no face");
  for (std::size_t i = 0; i < xyz_m.size(); ++i)
    if (!std::isfinite(xyz_m[i]))
      throw MeshError("vertex " + std::to_string(i / 3) + ": coordinate " + std::to_string(i % 3) + " is not finite");
  const std::int64_t n = static_cast<std::int64_t>(xyz_m.size() / 3);
  for (std::size_t i = 0; i < triangles.size(); ++i)
    if (triangles[i] < 0 || triangles[i] >= n)
      throw MeshError("face " + std::to_string(i / 3) + ": vertex index " + std::to_string(triangles[i]) +
                      " is out of range (" + std::to_string(n) + " vertices)");
  for (std::size_t f = 0; f < triangles.size(); f += 3) {
    const std::int64_t a = triangles[f], b = triangles[f + 1], c = triangles[f + 2];
    if (a == b || b == c || a == c)
      throw MeshError("face " + std::to_string(f / 3) + ": repeated vertex " +
                      std::to_string(a == b || a == c ? a : b));
  }
}

// Each directed edge once: a second use is a face turned the wrong way or an edge of more than two faces
// (found here, with both faces named, before OpenMesh refuses the face with a message of its own).
void checkOrientation(std::span<const std::int64_t> triangles) {
  std::unordered_map<std::uint64_t, std::size_t> directed;
  directed.reserve(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); f += 3)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto from = static_cast<std::uint64_t>(triangles[f + k]);
      const auto to = static_cast<std::uint64_t>(triangles[f + (k + 1) % 3]);
      const auto [where, fresh] = directed.emplace(from << 32 | to, f / 3);
      if (!fresh)
        throw MeshError("face " + std::to_string(f / 3) + ": edge (" + std::to_string(from) + ", " +
                        std::to_string(to) + ") runs the same way in face " + std::to_string(where->second) +
                        " (a face turned inside out, or an edge of more than two faces)");
    }
}

// The new index of every vertex past the deleted ones (-1 for a deleted one).
std::vector<std::int64_t> compactIndex(const TriMesh& mesh) {
  std::vector<std::int64_t> index(mesh.n_vertices(), -1);
  std::int64_t next = 0;
  for (const auto v : mesh.vertices()) index[static_cast<std::size_t>(v.idx())] = next++;
  return index;
}

}  // namespace

mesh::SurfaceMesh meshFromArrays(std::span<const double> xyz_m, std::span<const std::int64_t> triangles) {
  checkArrays(xyz_m, triangles);
  checkOrientation(triangles);
  mesh::SurfaceMesh surface;
  TriMesh& m = surface.mesh();
  m.reserve(xyz_m.size() / 3, triangles.size() / 2, triangles.size() / 3);
  for (std::size_t i = 0; i < xyz_m.size(); i += 3) m.add_vertex(TriMesh::Point(xyz_m[i], xyz_m[i + 1], xyz_m[i + 2]));
  for (std::size_t f = 0; f < triangles.size(); f += 3) {
    const auto vertex = [&](std::size_t k) { return TriMesh::VertexHandle(static_cast<int>(triangles[f + k])); };
    if (!m.add_face(vertex(0), vertex(1), vertex(2)).is_valid())
      throw MeshError("face " + std::to_string(f / 3) +
                      ": refused (its edges would be shared by more than two faces, or turn the wrong way)");
  }
  const mesh::ManifoldReport report = mesh::checkManifold(m);
  if (!report.closed_two_manifold) throw MeshError("not a closed two-manifold: " + report.first_problem);
  m.update_normals();
  return surface;
}

// Tight loops over the status flags and the half-edges (not OpenMesh's skipping iterators and circulators):
// these run at memory speed on meshes of millions of elements.
std::size_t liveVertices(const TriMesh& mesh) noexcept {
  std::size_t n = 0;
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    n += !mesh.status(TriMesh::VertexHandle(static_cast<int>(v))).deleted();
  return n;
}

std::size_t liveFaces(const TriMesh& mesh) noexcept {
  std::size_t n = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    n += !mesh.status(TriMesh::FaceHandle(static_cast<int>(f))).deleted();
  return n;
}

bool verticesContiguous(const TriMesh& mesh) noexcept { return liveVertices(mesh) == mesh.n_vertices(); }

void copyVertices(const mesh::SurfaceMesh& surface, std::span<double> xyz_m) {
  const TriMesh& m = surface.mesh();
  const std::size_t n = liveVertices(m);
  if (xyz_m.size() != 3 * n) throw std::invalid_argument("copyVertices: wrong output size");
  static_assert(sizeof(TriMesh::Point) == 3 * sizeof(double));
  if (n == m.n_vertices()) {
    if (n > 0) std::memcpy(xyz_m.data(), m.points(), n * sizeof(TriMesh::Point));
    return;
  }
  std::size_t i = 0;
  for (const auto v : m.vertices()) {
    const TriMesh::Point& p = m.point(v);
    xyz_m[i++] = p[0], xyz_m[i++] = p[1], xyz_m[i++] = p[2];
  }
}

void copyFaces(const mesh::SurfaceMesh& surface, std::span<std::int64_t> triangles, std::span<std::uint8_t> kinds) {
  const TriMesh& m = surface.mesh();
  const std::size_t n = liveFaces(m);
  if (triangles.size() != 3 * n || (!kinds.empty() && kinds.size() != n))
    throw std::invalid_argument("copyFaces: wrong output size");
  const bool contiguous = verticesContiguous(m);
  const std::vector<std::int64_t> index = contiguous ? std::vector<std::int64_t>{} : compactIndex(m);
  std::size_t i = 0, k = 0;
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const TriMesh::FaceHandle face(static_cast<int>(f));
    if (m.status(face).deleted()) continue;
    // A face's vertices as its circulator gives them (cfv_iter: the face's half-edge, then its next ones).
    TriMesh::HalfedgeHandle h = m.halfedge_handle(face);
    for (int corner = 0; corner < 3; ++corner, h = m.next_halfedge_handle(h)) {
      const int v = m.to_vertex_handle(h).idx();
      triangles[i++] = contiguous ? v : index[static_cast<std::size_t>(v)];
    }
    if (!kinds.empty()) kinds[k++] = static_cast<std::uint8_t>(surface.kind(face));
  }
}

void copyTexCoords(const mesh::SurfaceMesh& surface, std::span<double> uv) {
  const TriMesh& m = surface.mesh();
  if (!surface.hasTexCoords()) throw std::invalid_argument("copyTexCoords: the mesh has no texture coordinates");
  if (uv.size() != 6 * liveFaces(m)) throw std::invalid_argument("copyTexCoords: wrong output size");
  std::size_t i = 0;
  for (const TriMesh::FaceHandle face : m.faces()) {  // skips deleted faces
    TriMesh::HalfedgeHandle h = m.halfedge_handle(face);
    for (int corner = 0; corner < 3; ++corner, h = m.next_halfedge_handle(h)) {
      const Eigen::Vector2d c = surface.texCoord(h);
      uv[i++] = c.x();
      uv[i++] = c.y();
    }
  }
}

void copyFaceMaterials(const mesh::SurfaceMesh& surface, std::span<std::int32_t> materials) {
  const TriMesh& m = surface.mesh();
  if (!surface.hasMaterials()) throw std::invalid_argument("copyFaceMaterials: the mesh has no materials");
  if (materials.size() != liveFaces(m)) throw std::invalid_argument("copyFaceMaterials: wrong output size");
  std::size_t i = 0;
  for (const TriMesh::FaceHandle face : m.faces())
    materials[i++] = surface.kind(face) == mesh::FaceKind::Wall ? -1 : surface.material(face);
}

}  // namespace incise::jobs
