// thicknessBelowVertices (thickness.h): CGAL's AABB tree over the faces, one ray per vertex on oneTBB.
// Compiled in the mesh module's CGAL object library.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <boost/variant/get.hpp>

#include "incise/mesh/thickness.h"

namespace incise::mesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point toPoint(const TriMesh::Point& p) { return Point(p[0], p[1], p[2]); }

std::vector<Triangle> trianglesOf(const TriMesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.n_faces());
  for (const auto f : mesh.faces()) {  // skips deleted faces
    auto corner = mesh.cfv_iter(f);
    const Point a = toPoint(mesh.point(*corner++)), b = toPoint(mesh.point(*corner++));
    const Point c = toPoint(mesh.point(*corner));
    if (!Kernel::Collinear_3()(a, b, c)) out.emplace_back(a, b, c);  // a degenerate face hides nothing
  }
  return out;
}

// The vertex's outward normal: the sum of its faces' cross products (area-weighted), unit length; zero
// when there is none.
Eigen::Vector3d vertexNormal(const TriMesh& mesh, TriMesh::VertexHandle v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto f : mesh.vf_range(v)) {
    auto corner = mesh.cfv_iter(f);
    const Eigen::Vector3d a = toEigen(mesh.point(*corner++)), b = toEigen(mesh.point(*corner++));
    const Eigen::Vector3d c = toEigen(mesh.point(*corner));
    sum += (b - a).cross(c - a);
  }
  const double norm = sum.norm();
  return norm > 0.0 && std::isfinite(norm) ? Eigen::Vector3d(sum / norm) : Eigen::Vector3d::Zero();
}

float thicknessAt(const Tree& tree, const Eigen::Vector3d& p, const Eigen::Vector3d& n, double max_m, double skin_m) {
  constexpr float kNone = std::numeric_limits<float>::infinity();
  if (n.isZero()) return kNone;
  const Eigen::Vector3d start = p - skin_m * n;
  const Kernel::Ray_3 ray(Point(start.x(), start.y(), start.z()), Kernel::Vector_3(-n.x(), -n.y(), -n.z()));
  const auto hit = tree.first_intersection(ray);
  if (!hit) return kNone;
  const Point* at = boost::get<Point>(&hit->first);
  if (!at) return static_cast<float>(skin_m);  // the ray runs along a face: the far side is right there
  const double distance_m = (Eigen::Vector3d(at->x(), at->y(), at->z()) - p).norm();
  return distance_m <= max_m ? static_cast<float>(distance_m) : kNone;
}

}  // namespace

std::vector<float> thicknessBelowVertices(const TriMesh& mesh, double max_m, double skin_m) {
  if (!(max_m >= 0.0) || !std::isfinite(max_m) || !(skin_m >= 0.0) || !std::isfinite(skin_m))
    throw std::invalid_argument("thicknessBelowVertices: max_m = " + std::to_string(max_m) +
                                " and skin_m = " + std::to_string(skin_m) + " must be finite and >= 0");
  std::vector<float> out(mesh.n_vertices(), std::numeric_limits<float>::infinity());
  const std::vector<Triangle> triangles = trianglesOf(mesh);
  if (triangles.empty()) return out;
  Tree tree(triangles.begin(), triangles.end());
  tree.build();  // now, not lazily inside the first of the concurrent queries
  const auto vertex = [&](int i) {
    const TriMesh::VertexHandle v(i);
    if (!mesh.status(v).deleted())
      out[static_cast<size_t>(i)] = thicknessAt(tree, toEigen(mesh.point(v)), vertexNormal(mesh, v), max_m, skin_m);
  };
#if defined(__SANITIZE_THREAD__)
  // The thread sanitizer cannot see inside Debian's oneTBB (not built for it) and reports its scheduler's
  // own accesses: one thread there. The values are the same (each vertex is computed alone).
  for (int i = 0; i < static_cast<int>(mesh.n_vertices()); ++i) vertex(i);
#else
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(mesh.n_vertices()), 1024),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int i = range.begin(); i != range.end(); ++i) vertex(i);
                    });
#endif
  return out;
}

}  // namespace incise::mesh
