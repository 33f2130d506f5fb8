#include "pcg.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

namespace incise::physics::detail {

void PcgScratch::reserve(std::size_t nodes) {
  for (auto* v : {&r, &z, &p, &q, &t}) v->reserve(nodes);
  push.reserve(nodes);
  for (auto* m : {&inverse_diagonal, &scaled_diagonal, &correction}) m->reserve(nodes);
}

void PcgScratch::resize(std::size_t nodes) {
  for (auto* v : {&r, &z, &p, &q, &t}) v->resize(nodes, Eigen::Vector3d::Zero());
  push.resize(nodes, Quad{{0.0, 0.0, 0.0, 0.0}});
  for (auto* m : {&inverse_diagonal, &scaled_diagonal, &correction}) m->resize(nodes, Eigen::Matrix3d::Zero());
}

double dotActive(std::span<const Eigen::Vector3d> a, std::span<const Eigen::Vector3d> b,
                 std::span<const std::uint8_t> active) noexcept {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (active[i]) sum += a[i].dot(b[i]);
  return sum;
}

namespace {

// The diagonal blocks' inverses (and with SSOR, w > 0, their scaled copies) into the scratch.
void invertDiagonal(const BlockMatrix& a, std::span<const std::uint8_t> active, double omega, PcgScratch& s) noexcept {
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (!active[i]) continue;
    const Eigen::Matrix3d d = a.diagonal(static_cast<int>(i)).matrix();
    if (omega > 0.0) s.scaled_diagonal[i] = d / omega, s.correction[i] = (1.0 - 2.0 / omega) * d;
    const double det = d.determinant();
    // A singular block (a node of flat pieces only) falls back to the inverse of its mean diagonal.
    if (std::abs(det) > 1e-300 && std::isfinite(det))
      s.inverse_diagonal[i] = d.inverse();
    else
      s.inverse_diagonal[i] = Eigen::Matrix3d::Identity() * (3.0 / std::max(d.trace(), 1e-300));
  }
}

// The system CG runs on, its preconditioner and how x maps to it: with SSOR (omega > 0) the split system
// A^ = E^-1 A E^-T, E = D / w + L, preconditioned by D / w, x^ = E^T x, b^ = E^-1 b (so r^T (D / w) r on it is
// r^T M^-1 r on A); with block Jacobi A itself preconditioned by D^-1.
struct System {
  const BlockMatrix& a;
  std::span<const std::uint8_t> active;
  double omega;
  PcgScratch& s;

  // q = A^ p (Eisenstat: t = E^-T p, q = t + E^-1 (p + (D - 2 D / w) t)); returns p . q. s.z is its scratch.
  double apply(std::span<const Eigen::Vector3d> p, std::span<Eigen::Vector3d> q) const noexcept {
    if (omega <= 0.0) {
      a.multiply(p, q, active, s.push);
      return dotActive(p, q, active);
    }
    a.upperSolve(p, s.t, s.inverse_diagonal, active, omega);
    for (std::size_t i = 0; i < active.size(); ++i)
      if (active[i]) s.z[i] = p[i] + s.correction[i] * s.t[i];
    a.lowerSolve(s.z, q, s.inverse_diagonal, active, omega, s.push);
    double pq = 0.0;
    for (std::size_t i = 0; i < active.size(); ++i)
      if (active[i]) q[i] += s.t[i], pq += p[i].dot(q[i]);
    return pq;
  }
  // The preconditioner applied to one active node's residual.
  Eigen::Vector3d preconditioned(std::size_t i, const Eigen::Vector3d& r) const noexcept {
    return omega > 0.0 ? Eigen::Vector3d(s.scaled_diagonal[i] * r) : Eigen::Vector3d(s.inverse_diagonal[i] * r);
  }
  // z = the preconditioner applied to r (zero on inactive nodes); returns r . z.
  double precondition(std::span<const Eigen::Vector3d> r, std::span<Eigen::Vector3d> z) const noexcept {
    double rz = 0.0;
    for (std::size_t i = 0; i < active.size(); ++i) {
      if (!active[i]) {
        z[i].setZero();
        continue;
      }
      z[i] = preconditioned(i, r[i]);
      rz += r[i].dot(z[i]);
    }
    return rz;
  }
};

// sqrt(f^T D^-1 f) over the active nodes.
double floorNorm(std::span<const Eigen::Vector3d> f, std::span<const std::uint8_t> active, const PcgScratch& s) {
  if (f.empty()) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < active.size(); ++i)
    if (active[i]) sum += f[i].dot(s.inverse_diagonal[i] * f[i]);
  return std::sqrt(std::max(sum, 0.0));
}

// z = M^-1 r = (D / w + U)^-1 (D / w) (D / w + L)^-1 r, plus the coarse correction; returns r . z and, in
// ssor_part, r . M^-1 r.
double twoLevel(const BlockMatrix& a, std::span<const std::uint8_t> active, double omega, CoarseSpace& coarse,
                std::span<const Eigen::Vector3d> r, std::span<Eigen::Vector3d> z, PcgScratch& s,
                double& ssor_part) noexcept {
  a.lowerSolve(r, s.t, s.inverse_diagonal, active, omega, s.push);
  for (std::size_t i = 0; i < active.size(); ++i)
    if (active[i]) s.t[i] = s.scaled_diagonal[i] * s.t[i];
  a.upperSolve(s.t, z, s.inverse_diagonal, active, omega);
  ssor_part = dotActive(r, z, active);
  return ssor_part + coarse.addCorrection(r, z, active);
}

// CG on A with the two-level preconditioner (see solvePcg); the diagonal already inverted.
PcgResult solveTwoLevel(const BlockMatrix& a, std::span<const std::uint8_t> active, std::span<const Eigen::Vector3d> b,
                        std::span<Eigen::Vector3d> x, double tolerance, int max_iterations, double omega,
                        std::span<const Eigen::Vector3d> floor_vector, PcgScratch& s, CoarseSpace& coarse) noexcept {
  const std::size_t n = active.size();
  double bb = 0.0;
  twoLevel(a, active, omega, coarse, b, s.z, s, bb);
  const double scale = std::max(std::sqrt(std::max(bb, 0.0)), floorNorm(floor_vector, active, s));
  const double limit2 = tolerance * tolerance * scale * scale;
  a.multiply(x, s.q, active, s.push);
  for (std::size_t i = 0; i < n; ++i) s.r[i] = active[i] ? Eigen::Vector3d(b[i] - s.q[i]) : Eigen::Vector3d::Zero();
  PcgResult result;
  double ssor_part = 0.0;  // r^T M^-1 r: the stopping test's, as SSOR alone's
  double rz = twoLevel(a, active, omega, coarse, s.r, s.z, s, ssor_part);
  for (std::size_t i = 0; i < n; ++i) s.p[i] = s.z[i];
  while (ssor_part > limit2 && result.iterations < max_iterations) {
    a.multiply(s.p, s.q, active, s.push);
    const double pq = dotActive(s.p, s.q, active);
    if (!(pq > 0.0) || !std::isfinite(rz)) {
      result.finite = std::isfinite(pq) && std::isfinite(rz);
      break;
    }
    const double alpha = rz / pq;
    for (std::size_t i = 0; i < n; ++i)
      if (active[i]) x[i] += alpha * s.p[i], s.r[i] -= alpha * s.q[i];
    const double rz_next = twoLevel(a, active, omega, coarse, s.r, s.z, s, ssor_part);
    ++result.iterations;
    const double beta = rz_next / rz;
    rz = rz_next;
    if (ssor_part <= limit2) break;
    for (std::size_t i = 0; i < n; ++i) s.p[i] = s.z[i] + beta * s.p[i];
  }
  result.relative_residual = scale > 0.0 ? std::sqrt(std::max(ssor_part, 0.0)) / scale : 0.0;
  result.converged = ssor_part <= limit2;
  result.finite = result.finite && std::isfinite(rz) && std::isfinite(ssor_part);
  return result;
}

}  // namespace

PcgResult solvePcg(const BlockMatrix& a, std::span<const std::uint8_t> active, std::span<const Eigen::Vector3d> b,
                   std::span<Eigen::Vector3d> x, double tolerance, int max_iterations, double omega,
                   std::span<const Eigen::Vector3d> floor_vector, PcgScratch& s, CoarseSpace* coarse) noexcept {
  const std::size_t n = active.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!active[i]) x[i].setZero();
  invertDiagonal(a, active, omega, s);
  if (coarse && coarse->ready() && omega > 0.0)
    return solveTwoLevel(a, active, b, x, tolerance, max_iterations, omega, floor_vector, s, *coarse);
  const System system{a, active, omega, s};
  // r = b^ - A^ x^ (q holds x^, then b^).
  if (omega > 0.0) {
    a.upperMultiply(x, s.q, active, omega);
    for (std::size_t i = 0; i < n; ++i) x[i] = s.q[i];
    a.lowerSolve(b, s.r, s.inverse_diagonal, active, omega, s.push);
  } else {
    for (std::size_t i = 0; i < n; ++i) s.r[i] = active[i] ? b[i] : Eigen::Vector3d::Zero();
  }
  const double bb = system.precondition(s.r, s.z);
  const double scale = std::max(std::sqrt(std::max(bb, 0.0)), floorNorm(floor_vector, active, s));
  const double limit2 = tolerance * tolerance * scale * scale;
  system.apply(x, s.q);
  for (std::size_t i = 0; i < n; ++i) s.r[i] -= s.q[i];
  PcgResult result;
  double rz = system.precondition(s.r, s.z);
  for (std::size_t i = 0; i < n; ++i) s.p[i] = s.z[i];
  while (rz > limit2 && result.iterations < max_iterations) {
    const double pq = system.apply(s.p, s.q);
    if (!(pq > 0.0) || !std::isfinite(rz)) {
      result.finite = std::isfinite(pq) && std::isfinite(rz);
      break;  // breakdown: the system is not positive definite along p (or already solved)
    }
    const double alpha = rz / pq;
    // x += alpha p, r -= alpha q, z = M^-1 r and r . z in one pass (z is zero on inactive nodes from before).
    double rz_next = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!active[i]) continue;
      x[i] += alpha * s.p[i], s.r[i] -= alpha * s.q[i];
      s.z[i] = system.preconditioned(i, s.r[i]);
      rz_next += s.r[i].dot(s.z[i]);
    }
    ++result.iterations;
    const double beta = rz_next / rz;
    rz = rz_next;
    if (rz <= limit2) break;
    for (std::size_t i = 0; i < n; ++i) s.p[i] = s.z[i] + beta * s.p[i];
  }
  if (omega > 0.0) {  // x = E^-T x^
    for (std::size_t i = 0; i < n; ++i) s.q[i] = x[i];
    a.upperSolve(s.q, x, s.inverse_diagonal, active, omega);
  }
  result.relative_residual = scale > 0.0 ? std::sqrt(std::max(rz, 0.0)) / scale : 0.0;
  result.converged = rz <= limit2;
  result.finite = result.finite && std::isfinite(rz);
  return result;
}

}  // namespace incise::physics::detail
