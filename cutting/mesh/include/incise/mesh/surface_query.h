// Closest point on a tissue surface, found locally through a VertexGrid: the scalpel's contact with the
// tissue, and the stroke generator's projection of a path onto it.
//
// Shapes: positions in metres; the normal is the unit outward face normal (counter-clockwise faces).
// Cost: O(vertices within radius_m of p + their faces). Threads: const, any thread while the mesh and grid
// are not being changed. Failure: std::nullopt when no vertex lies within radius_m (off the surface) or
// for a non-finite p; never throws.
#pragma once

#include <array>
#include <optional>

#include <Eigen/Core>

#include "incise/mesh/surface_mesh.h"
#include "incise/mesh/vertex_grid.h"

namespace incise::mesh {

struct SurfacePoint {
  Eigen::Vector3d point_m;
  Eigen::Vector3d normal;
  TriMesh::FaceHandle face;
  double distance_m;
};

// A triangle copied out of a mesh (a contact proxy's face): corners counter-clockwise, outward unit normal.
struct SkinTriangle {
  std::array<Eigen::Vector3d, 3> corners_m;
  Eigen::Vector3d normal;
};

// The closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, §5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) noexcept;

// Where the segment a + t (b - a), t in [0, 1], crosses triangle (p0, p1, p2): t, or nullopt (Moller-Trumbore).
std::optional<double> segmentTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p0,
                                      const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) noexcept;

// The closest point to p among the faces around the grid's vertices within radius_m of p. The grid must
// index the mesh's vertex handles by idx() at their current positions.
std::optional<SurfacePoint> closestSurfacePoint(const TriMesh& mesh, const VertexGrid& grid, const Eigen::Vector3d& p,
                                                double radius_m);

// The first crossing of the segment a -> b with the surface, among the faces around the grid's vertices
// within radius_m of the segment's bounding box (radius_m >= the longest edge finds every crossing).
// Moller-Trumbore ray-triangle intersection. Cost O(vertices in that box + their faces).
std::optional<SurfacePoint> intersectSegment(const TriMesh& mesh, const VertexGrid& grid, const Eigen::Vector3d& a,
                                             const Eigen::Vector3d& b, double radius_m);

}  // namespace incise::mesh
