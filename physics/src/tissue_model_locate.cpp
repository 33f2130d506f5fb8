// Points in the tets (TissueModel::locate, embedding.h) and the contact's local model
// (TissueModel::contactModel, contact_model.h).
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "incise/physics/embedding.h"
#include "incise/physics/tissue_model.h"
#include "incise/tets/tet_mesh.h"
#include "tissue_model_state.h"

namespace incise::physics {

Eigen::Vector3d embeddedPosition(const Embedded& point, std::span<const Eigen::Vector3d> x_m) noexcept {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < 4; ++k) p += point.weights[k] * x_m[static_cast<std::size_t>(point.nodes[k])];
  return p;
}

void embeddedPositions(std::span<const Embedded> points, std::span<const Eigen::Vector3d> x_m,
                       std::span<Eigen::Vector3d> out_m) noexcept {
  for (std::size_t i = 0; i < points.size(); ++i) out_m[i] = embeddedPosition(points[i], x_m);
}

Eigen::Vector3d embeddedNormal(const Embedded& point, std::span<const Eigen::Vector3d> rest_m,
                               std::span<const Eigen::Vector3d> current_m,
                               const Eigen::Vector3d& rest_normal) noexcept {
  Eigen::Matrix3d dm, ds;
  const auto n0 = static_cast<std::size_t>(point.nodes[0]);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto n = static_cast<std::size_t>(point.nodes[i + 1]);
    dm.col(static_cast<Eigen::Index>(i)) = rest_m[n] - rest_m[n0];
    ds.col(static_cast<Eigen::Index>(i)) = current_m[n] - current_m[n0];
  }
  const double det_rest = dm.determinant(), det_now = ds.determinant();
  if (!(std::abs(det_rest) > 0.0 && det_now * det_rest > 0.0)) return rest_normal;
  // F = ds dm^-1, so F^-T = ds^-T dm^T.
  const Eigen::Vector3d n = ds.inverse().transpose() * (dm.transpose() * rest_normal);
  const double length = n.norm();
  return std::isfinite(length) && length > 0.0 ? Eigen::Vector3d(n / length) : rest_normal;
}

namespace {

double distanceToTet(const std::array<Eigen::Vector3d, 4>& x, const Eigen::Vector3d& p) noexcept {
  const std::array<int, 4> local = {0, 1, 2, 3};
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const std::array<int, 3> f = tets::faceOpposite(local, i);
    d = std::min(d,
                 detail::pointTriangleDistance(p, x[static_cast<std::size_t>(f[0])], x[static_cast<std::size_t>(f[1])],
                                               x[static_cast<std::size_t>(f[2])]));
  }
  return d;
}

Embedded embeddedIn(const detail::Element& e, const Eigen::Vector4d& w, double outside_m) {
  Embedded out;
  out.nodes = e.nodes;
  out.weights = {w[0], w[1], w[2], w[3]};
  out.element = {e.base_tet, e.side};
  out.outside_m = outside_m;
  return out;
}

}  // namespace

std::optional<Embedded> TissueModel::State::locate(const Eigen::Vector3d& p, ElementFilter filter,
                                                   double max_distance_m) const {
  if (!p.allFinite() || !(max_distance_m >= 0.0)) return std::nullopt;
  const double reach = max_radius_m + max_distance_m;
  candidates.clear();
  grid.query(Eigen::AlignedBox3d(p.array() - reach, p.array() + reach), candidates);
  int best = -1;
  double best_score = -std::numeric_limits<double>::infinity();
  Eigen::Vector4d best_w = Eigen::Vector4d::Zero();
  // Inside: the tet where p is deepest (largest smallest weight; ties to the lower index, as queried).
  for (const int c : candidates) {
    const detail::Element& e = elements[static_cast<std::size_t>(c)];
    if (!e.alive || !filter(ElementInfo{e.base_tet, e.side})) continue;
    const Eigen::Vector4d w =
        detail::barycentric(e, rest_m[static_cast<std::size_t>(e.nodes[0])], p, inverse_prestretch);
    if (w.minCoeff() > best_score) best = c, best_score = w.minCoeff(), best_w = w;
  }
  constexpr double kInside = -1e-12;
  if (best >= 0 && best_score >= kInside) return embeddedIn(elements[static_cast<std::size_t>(best)], best_w, 0.0);
  // Outside every tet: the nearest one within max_distance_m.
  double best_distance = std::numeric_limits<double>::infinity();
  best = -1;
  for (const int c : candidates) {
    const detail::Element& e = elements[static_cast<std::size_t>(c)];
    if (!e.alive || !filter(ElementInfo{e.base_tet, e.side})) continue;
    const double d = distanceToTet(restOf(e), p);
    if (d < best_distance) best = c, best_distance = d;
  }
  if (best < 0 || best_distance > max_distance_m) return std::nullopt;
  const detail::Element& e = elements[static_cast<std::size_t>(best)];
  return embeddedIn(e, detail::barycentric(e, rest_m[static_cast<std::size_t>(e.nodes[0])], p, inverse_prestretch),
                    best_distance);
}

std::optional<Embedded> TissueModel::locate(const Eigen::Vector3d& rest_m, ElementFilter filter,
                                            double max_distance_m) const {
  return s_->locate(rest_m, filter, max_distance_m);
}

ContactModel TissueModel::contactModel(const Embedded& point, const Eigen::Vector3d& rest_normal) noexcept {
  State& s = *s_;
  ContactModel out;
  out.step = s.steps;
  const int n = nodeCount();
  for (const int node : point.nodes)
    if (node < 0 || node >= n) return out;
  out.point_m = embeddedPosition(point, s.x_m);
  out.normal = embeddedNormal(point, s.rest_m, s.x_m, rest_normal);
  const double h = s.last_dt_s;
  bool any_free = false;
  for (const int node : point.nodes) any_free = any_free || s.active[static_cast<std::size_t>(node)];
  if (!(h > 0.0) || !any_free) return out;
  // Column k of W: the unit force along axis k at the point, spread by the weights.
  Eigen::Matrix3d compliance;
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < 4; ++i) s.contact_w[static_cast<std::size_t>(point.nodes[i])][k] += point.weights[i];
    const detail::PcgResult cg =
        detail::solvePcg(s.matrix, s.active, s.contact_w, s.contact_z[static_cast<std::size_t>(k)],
                         s.options.cg_tolerance, s.options.max_cg_iterations, s.options.ssor_relaxation, {}, s.pcg);
    out.cg_iterations += cg.iterations;
    for (const int node : point.nodes) s.contact_w[static_cast<std::size_t>(node)].setZero();
    if (!cg.finite) return out;
    Eigen::Vector3d column = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 4; ++i)
      column += point.weights[i] * s.contact_z[static_cast<std::size_t>(k)][static_cast<std::size_t>(point.nodes[i])];
    compliance.col(k) = h * h * column;
  }
  compliance = 0.5 * (compliance + compliance.transpose()).eval();
  const double det = compliance.determinant();
  if (!(std::isfinite(det) && det > 0.0)) return out;
  out.stiffness_N_per_m = compliance.inverse();
  out.valid = out.stiffness_N_per_m.allFinite();
  return out;
}

}  // namespace incise::physics
