// Private: the first crossing of a segment with the faces around a set of vertices (a grid query's hits).
// Shared by intersectSegment (current positions, every face) and SurfaceCutter::intersect (rest positions,
// some faces skipped). `position(VertexHandle)` gives a vertex's position; `skip(FaceHandle)` leaves a face
// out. Of crossings at the same parameter (the segment through a shared edge or vertex), the face with the
// lowest index: the answer does not depend on the order the vertices come in. Cost O(faces around the
// vertices). No allocation.
#pragma once

#include <optional>
#include <span>

#include "incise/mesh/surface_query.h"

namespace incise::mesh::detail {

template <typename Position, typename Skip>
std::optional<SurfacePoint> firstCrossing(const TriMesh& mesh, std::span<const int> vertices, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, Position&& position, Skip&& skip) {
  std::optional<SurfacePoint> best;
  double best_t = 1.0;
  for (const int id : vertices) {
    const TriMesh::VertexHandle v(id);
    if (mesh.status(v).deleted()) continue;
    for (auto f = mesh.cvf_iter(v); f.is_valid(); ++f) {
      if (skip(*f)) continue;
      auto corner = mesh.cfv_iter(*f);
      const Eigen::Vector3d p0 = position(*corner++);
      const Eigen::Vector3d p1 = position(*corner++);
      const Eigen::Vector3d p2 = position(*corner);
      const auto t = segmentTriangle(a, b, p0, p1, p2);
      if (!t || *t > best_t || (best && *t == best_t && f->idx() > best->face.idx())) continue;
      best_t = *t;
      best = SurfacePoint{a + *t * (b - a), (p1 - p0).cross(p2 - p0).normalized(), *f, *t * (b - a).norm()};
    }
  }
  return best;
}

}  // namespace incise::mesh::detail
