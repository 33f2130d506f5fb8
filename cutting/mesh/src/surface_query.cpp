#include "incise/mesh/surface_query.h"

#include "incise/mesh/face_walk.h"

#include <cmath>
#include <vector>

namespace incise::mesh {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) noexcept {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

std::optional<SurfacePoint> closestSurfacePoint(const TriMesh& mesh, const VertexGrid& grid, const Eigen::Vector3d& p,
                                                double radius_m) {
  if (!p.allFinite() || !(radius_m > 0.0)) return std::nullopt;
  std::vector<int> near;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(radius_m);
  grid.query(Eigen::AlignedBox3d(p - r, p + r), near);
  std::optional<SurfacePoint> best;
  for (const int id : near) {
    const TriMesh::VertexHandle v(id);
    if (mesh.status(v).deleted()) continue;
    for (auto f = mesh.cvf_iter(v); f.is_valid(); ++f) {
      auto corner = mesh.cfv_iter(*f);
      const Eigen::Vector3d a = toEigen(mesh.point(*corner++));
      const Eigen::Vector3d b = toEigen(mesh.point(*corner++));
      const Eigen::Vector3d c = toEigen(mesh.point(*corner));
      const Eigen::Vector3d q = closestPointOnTriangle(p, a, b, c);
      const double d = (q - p).norm();
      if (best && d >= best->distance_m) continue;
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      if (normal.norm() == 0.0) continue;
      best = SurfacePoint{q, normal.normalized(), *f, d};
    }
  }
  return best;
}

std::optional<double> segmentTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p0,
                                      const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) noexcept {
  const Eigen::Vector3d d = b - a, e1 = p1 - p0, e2 = p2 - p0;
  const Eigen::Vector3d q = d.cross(e2);
  const double det = e1.dot(q);
  if (std::abs(det) < 1e-300) return std::nullopt;
  const Eigen::Vector3d s = a - p0;
  const double u = s.dot(q) / det;
  const Eigen::Vector3d r = s.cross(e1);
  const double w = d.dot(r) / det;
  const double t = e2.dot(r) / det;
  if (u < 0.0 || w < 0.0 || u + w > 1.0 || t < 0.0 || t > 1.0) return std::nullopt;
  return t;
}

std::optional<SurfacePoint> intersectSegment(const TriMesh& mesh, const VertexGrid& grid, const Eigen::Vector3d& a,
                                             const Eigen::Vector3d& b, double radius_m) {
  if (!a.allFinite() || !b.allFinite() || !(radius_m >= 0.0)) return std::nullopt;
  Eigen::AlignedBox3d box(a.cwiseMin(b), a.cwiseMax(b));
  box.min().array() -= radius_m;
  box.max().array() += radius_m;
  std::vector<int> near;
  grid.query(box, near);
  return detail::firstCrossing(
      mesh, near, a, b, [&](TriMesh::VertexHandle v) { return toEigen(mesh.point(v)); },
      [](TriMesh::FaceHandle) { return false; });
}

}  // namespace incise::mesh
