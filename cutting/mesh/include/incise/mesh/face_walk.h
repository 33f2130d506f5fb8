// Private: the first crossing of a segment with the faces around a set of vertices (a grid query's hits).
// Shared by intersectSegment (current positions, every face) and SurfaceCutter::intersect (rest positions,
// some faces skipped). `position(VertexHandle)` gives a vertex's position; `skip(FaceHandle)` leaves a face
// out. Of crossings at the same parameter (the segment through a shared edge or vertex), the face with the
// lowest index: the answer does not depend on the order the vertices come in. Cost O(faces around the
// vertices). No allocation.
#pragma once

#include <array>
#include <optional>
#include <span>

#include "incise/mesh/surface_query.h"

namespace incise::mesh::detail {

// As firstCrossing below, each face tested as the triangle `corners(FaceHandle)` gives (three points,
// counter-clockwise): e.g. the face a retriangulated face lies in, so that any of its pieces gives the same
// bits.
template <typename Corners, typename Skip>
std::optional<SurfacePoint> firstCrossingOfCorners(const TriMesh& mesh, std::span<const int> vertices,
                                                   const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                   Corners&& corners, Skip&& skip) {
  std::optional<SurfacePoint> best;
  double best_t = 1.0;
  for (const int id : vertices) {
    const TriMesh::VertexHandle v(id);
    if (mesh.status(v).deleted()) continue;
    for (auto f = mesh.cvf_iter(v); f.is_valid(); ++f) {
      if (skip(*f)) continue;
      const std::array<Eigen::Vector3d, 3> p = corners(*f);
      const auto t = segmentTriangle(a, b, p[0], p[1], p[2]);
      if (!t || *t > best_t || (best && *t == best_t && f->idx() > best->face.idx())) continue;
      best_t = *t;
      best = SurfacePoint{a + *t * (b - a), (p[1] - p[0]).cross(p[2] - p[0]).normalized(), *f, *t * (b - a).norm()};
    }
  }
  return best;
}

template <typename Position, typename Skip>
std::optional<SurfacePoint> firstCrossing(const TriMesh& mesh, std::span<const int> vertices, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, Position&& position, Skip&& skip) {
  const auto corners = [&](TriMesh::FaceHandle f) {
    auto corner = mesh.cfv_iter(f);
    std::array<Eigen::Vector3d, 3> p;
    for (Eigen::Vector3d& c : p) c = position(*corner++);
    return p;
  };
  return firstCrossingOfCorners(mesh, vertices, a, b, corners, skip);
}

}  // namespace incise::mesh::detail
