// SurfaceRays and thicknessBelowVertices (thickness.h): CGAL's AABB tree over the faces; the thickness is one
// ray per vertex on oneTBB, a probe one segment.
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

#include "incise/mesh/surface_query.h"
#include "incise/mesh/thickness.h"

namespace incise::mesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

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

float thicknessAt(const AabbTree& tree, const Eigen::Vector3d& p, const Eigen::Vector3d& n, double max_m,
                  double skin_m) {
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

// Receives the faces whose boxes a segment meets (AABB_tree::all_intersected_primitives) and keeps the
// nearest crossing along it out of the tissue (through a face whose outward normal the segment runs along):
// no container, so a query allocates nothing.
struct NearestCrossing {
  const Eigen::Vector3d* a;
  const Eigen::Vector3d* b;
  double* t;
  NearestCrossing& operator*() { return *this; }
  NearestCrossing& operator++() { return *this; }
  NearestCrossing operator++(int) { return *this; }
  NearestCrossing& operator=(std::vector<Triangle>::const_iterator face) {
    const auto corner = [&](int i) {
      return Eigen::Vector3d(face->vertex(i).x(), face->vertex(i).y(), face->vertex(i).z());
    };
    const Eigen::Vector3d p0 = corner(0), p1 = corner(1), p2 = corner(2);
    if ((p1 - p0).cross(p2 - p0).dot(*b - *a) <= 0.0) return *this;  // entering the tissue, or along the face
    if (const auto at = segmentTriangle(*a, *b, p0, p1, p2); at && *at < *t) *t = *at;
    return *this;
  }
};

}  // namespace

struct SurfaceRays::Tree {
  std::vector<Triangle> triangles;
  AabbTree tree;
};

SurfaceRays::SurfaceRays(const TriMesh& mesh) : tree_(std::make_unique<Tree>()) {
  tree_->triangles = trianglesOf(mesh);
  if (tree_->triangles.empty()) return;
  tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
  tree_->tree.build();  // now, not lazily inside the first of the concurrent queries
}

SurfaceRays::~SurfaceRays() = default;
SurfaceRays::SurfaceRays(SurfaceRays&&) noexcept = default;
SurfaceRays& SurfaceRays::operator=(SurfaceRays&&) noexcept = default;

double SurfaceRays::firstCrossing(const Eigen::Vector3d& from_m, const Eigen::Vector3d& direction,
                                  double max_m) const noexcept {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!tree_ || tree_->triangles.empty() || !from_m.allFinite() || !direction.allFinite() || !(max_m > 0.0) ||
      !std::isfinite(max_m))
    return kNone;
  const Eigen::Vector3d to_m = from_m + max_m * direction;
  if (!to_m.allFinite() || to_m == from_m) return kNone;
  double t = kNone;
  try {
    const Kernel::Segment_3 segment(Point(from_m.x(), from_m.y(), from_m.z()), Point(to_m.x(), to_m.y(), to_m.z()));
    tree_->tree.all_intersected_primitives(segment, NearestCrossing{&from_m, &to_m, &t});
  } catch (...) {  // CGAL's exact fallback could not allocate: no crossing known
    return kNone;
  }
  return t <= 1.0 ? t * max_m : kNone;
}

std::vector<float> thicknessBelowVertices(const TriMesh& mesh, double max_m, double skin_m) {
  return thicknessBelowVertices(mesh, SurfaceRays(mesh), max_m, skin_m);
}

std::vector<float> thicknessBelowVertices(const TriMesh& mesh, const SurfaceRays& rays, double max_m, double skin_m) {
  if (!(max_m >= 0.0) || !std::isfinite(max_m) || !(skin_m >= 0.0) || !std::isfinite(skin_m))
    throw std::invalid_argument("thicknessBelowVertices: max_m = " + std::to_string(max_m) +
                                " and skin_m = " + std::to_string(skin_m) + " must be finite and >= 0");
  std::vector<float> out(mesh.n_vertices(), std::numeric_limits<float>::infinity());
  if (rays.tree_->triangles.empty()) return out;
  const AabbTree& tree = rays.tree_->tree;
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
