#include "element.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "incise/tets/tet_mesh.h"

namespace incise::physics::detail {

bool setRest(Element& e, const std::array<Eigen::Vector3d, 4>& rest_m, const Eigen::Vector3d& inverse_prestretch) {
  Eigen::Matrix3d dm;
  double longest = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d edge = rest_m[static_cast<std::size_t>(i + 1)] - rest_m[0];
    dm.col(i) = inverse_prestretch.asDiagonal() * edge;
    longest = std::max(longest, dm.col(i).norm());
  }
  const double det = dm.determinant();
  // A tet whose volume is below 1e-12 of its edge cube is flat: its inverse would be noise.
  if (!(std::isfinite(det) && det > 1e-12 * longest * longest * longest)) return false;
  e.bm = dm.inverse();
  e.volume_m3 = det / 6.0;
  std::array<Eigen::Vector3d, 4> beta;
  for (int a = 1; a < 4; ++a) beta[static_cast<std::size_t>(a)] = e.bm.row(a - 1).transpose();
  beta[0] = -(beta[1] + beta[2] + beta[3]);
  for (int a = 0; a < 4; ++a) e.dots[static_cast<std::size_t>(a)] = beta[static_cast<std::size_t>(a)].squaredNorm();
  for (int p = 0; p < 6; ++p)
    e.dots[static_cast<std::size_t>(4 + p)] =
        beta[static_cast<std::size_t>(kPairs[p][0])].dot(beta[static_cast<std::size_t>(kPairs[p][1])]);
  e.centroid_m = 0.25 * (rest_m[0] + rest_m[1] + rest_m[2] + rest_m[3]);
  e.radius_m = 0.0;
  for (const Eigen::Vector3d& x : rest_m) e.radius_m = std::max(e.radius_m, (x - e.centroid_m).norm());
  return true;
}

Eigen::Matrix3d rotationMatrix(const std::array<double, 4>& q) noexcept {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return r;
}

namespace {

// Whether |theta| < tolerance for either step rotation() would take, known without solving it: by
// Gershgorin, h's eigenvalues are at least g = min_i (h_ii - sum_j!=i |h_ij|); where g > 0, Newton's step
// has |h^-1 omega| <= |omega| / g, and the other step |omega| / (|tr A| + 1e-9) is smaller still (g <=
// tr h / 3 = 2 tr A / 3). The margin keeps the answer the one the solved step would give, rounding and all
// (so the same bits as solving it); false when unsure, and the step is solved.
bool converged(const Eigen::Matrix3d& h, const Eigen::Vector3d& omega, double tolerance) noexcept {
  double g = h(0, 0) - std::abs(h(0, 1)) - std::abs(h(0, 2));
  g = std::min(g, h(1, 1) - std::abs(h(1, 0)) - std::abs(h(1, 2)));
  g = std::min(g, h(2, 2) - std::abs(h(2, 0)) - std::abs(h(2, 1)));
  return g > 0.0 && omega.squaredNorm() < 0.998 * (tolerance * g) * (tolerance * g);
}

}  // namespace

Eigen::Matrix3d rotation(const Eigen::Matrix3d& f, std::array<double, 4>& q, double tolerance, int max_iterations,
                         int& iterations) noexcept {
  iterations = 0;
  for (;;) {
    const Eigen::Matrix3d r = rotationMatrix(q);
    if (iterations >= max_iterations) return r;
    // g(theta) = tr((exp([theta]x) R)^T F): gradient omega = axial(A - A^T), Hessian sym(A) - tr(A) I, A = F R^T.
    const Eigen::Matrix3d a = f * r.transpose();
    const Eigen::Vector3d omega(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1));
    const double trace = a.trace();
    Eigen::Matrix3d h = -0.5 * (a + a.transpose());
    h.diagonal().array() += trace;
    if (converged(h, omega, tolerance)) return r;
    // Newton's step where -Hessian is positive definite (near the maximum); else Mueller et al.'s
    // omega / |tr A| (a gradient step scaled by a bound on the curvature), which moves towards it.
    const double m1 = h(0, 0), m2 = h(0, 0) * h(1, 1) - h(0, 1) * h(1, 0), det = h.determinant();
    Eigen::Vector3d theta;
    if (m1 > 0.0 && m2 > 0.0 && det > 1e-6 * std::abs(trace * trace * trace))
      theta = h.inverse() * omega;
    else
      theta = omega / (std::abs(trace) + 1e-9);
    if (!(theta.squaredNorm() >= tolerance * tolerance)) return r;  // converged (or NaN: keep q)
    // q <- (1, theta / 2) q, normalised: a rotation by 2 atan(|theta| / 2) about theta (|theta| when small).
    const Eigen::Vector3d half = 0.5 * theta, v(q[1], q[2], q[3]);
    const double w = q[0] - half.dot(v);
    const Eigen::Vector3d u = q[0] * half + v + half.cross(v);
    const double norm = std::sqrt(w * w + u.squaredNorm());
    q = {w / norm, u.x() / norm, u.y() / norm, u.z() / norm};
    ++iterations;
  }
}

Eigen::Vector4d barycentric(const Element& e, const Eigen::Vector3d& rest0_m, const Eigen::Vector3d& p_m,
                            const Eigen::Vector3d& inverse_prestretch) noexcept {
  // The rest edge matrix is S Dm, so its inverse is bm S^-1.
  const Eigen::Vector3d l = e.bm * (inverse_prestretch.asDiagonal() * (p_m - rest0_m));
  return {1.0 - l.sum(), l.x(), l.y(), l.z()};
}

double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) noexcept {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

double distanceToTet(const std::array<Eigen::Vector3d, 4>& x, const Eigen::Vector3d& p) noexcept {
  const std::array<int, 4> local = {0, 1, 2, 3};
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {  // each face with its corners in tets::faceOpposite's order
    const std::array<int, 3> f = tets::faceOpposite(local, i);
    d = std::min(d, pointTriangleDistance(p, x[static_cast<std::size_t>(f[0])], x[static_cast<std::size_t>(f[1])],
                                          x[static_cast<std::size_t>(f[2])]));
  }
  return d;
}

}  // namespace incise::physics::detail
