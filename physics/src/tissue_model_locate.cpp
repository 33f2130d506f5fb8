// Points in the tets (TissueModel::locate, embedding.h) and the contact's local model
// (TissueModel::contactModel, contact_model.h).
#include <cmath>
#include <limits>
#include <new>
#include <optional>

#include <Eigen/LU>

#include "incise/physics/embedding.h"
#include "incise/physics/rest_map.h"
#include "incise/physics/tissue_model.h"
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

namespace {

// The edges from node 0 of the tet holding `point`, at rest (dm) and now (ds): F = ds dm^-1.
void edgeMatrices(const Embedded& point, std::span<const Eigen::Vector3d> rest_m,
                  std::span<const Eigen::Vector3d> current_m, Eigen::Matrix3d& dm, Eigen::Matrix3d& ds) noexcept {
  const auto n0 = static_cast<std::size_t>(point.nodes[0]);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto n = static_cast<std::size_t>(point.nodes[i + 1]);
    dm.col(static_cast<Eigen::Index>(i)) = rest_m[n] - rest_m[n0];
    ds.col(static_cast<Eigen::Index>(i)) = current_m[n] - current_m[n0];
  }
}

}  // namespace

Eigen::Vector3d embeddedNormal(const Embedded& point, std::span<const Eigen::Vector3d> rest_m,
                               std::span<const Eigen::Vector3d> current_m,
                               const Eigen::Vector3d& rest_normal) noexcept {
  Eigen::Matrix3d dm, ds;
  edgeMatrices(point, rest_m, current_m, dm, ds);
  const double det_rest = dm.determinant(), det_now = ds.determinant();
  if (!(std::abs(det_rest) > 0.0 && det_now * det_rest > 0.0)) return rest_normal;
  // F = ds dm^-1, so F^-T = ds^-T dm^T.
  const Eigen::Vector3d n = ds.inverse().transpose() * (dm.transpose() * rest_normal);
  const double length = n.norm();
  return std::isfinite(length) && length > 0.0 ? Eigen::Vector3d(n / length) : rest_normal;
}

namespace {

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
    const double d = detail::distanceToTet(restOf(e), p);
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

namespace {

// Newton steps of restMap: inside one tet the deformation is affine, so one lands on the point; a few more
// when the point is in another tet than the guess.
constexpr int kRestMapIterations = 4;

// F^-1 = Dm Ds^-1 of the tet holding `point` (rest edges Dm, current edges Ds); false when the tet is flat
// at rest, crushed flat or inverted (then the map is a translation).
bool inverseGradient(const Embedded& point, std::span<const Eigen::Vector3d> rest_m,
                     std::span<const Eigen::Vector3d> x_m, Eigen::Matrix3d& f_inverse) noexcept {
  Eigen::Matrix3d dm, ds;
  edgeMatrices(point, rest_m, x_m, dm, ds);
  const double det_rest = dm.determinant(), det_now = ds.determinant();
  if (!(det_rest * det_now > 1e-6 * det_rest * det_rest)) return false;
  f_inverse = dm * ds.inverse();
  return f_inverse.allFinite();
}

}  // namespace

RestMap TissueModel::restMap(const Eigen::Vector3d& world_m, const Eigen::Vector3d& guess_rest_m,
                             double reach_m) const noexcept {
  const State& s = *s_;
  RestMap map;
  map.world_m = map.rest_m = world_m;
  if (!world_m.allFinite()) return map;
  Eigen::Vector3d r = guess_rest_m.allFinite() ? guess_rest_m : world_m;
  try {
    for (int i = 0; i < kRestMapIterations; ++i) {
      const std::optional<Embedded> e = s.locate(r, {}, reach_m);
      if (!e) break;  // out of reach (the first guess: no tissue near; later: keep the last tet's map)
      Eigen::Matrix3d f_inverse = Eigen::Matrix3d::Identity();
      if (!inverseGradient(*e, s.rest_m, s.x_m, f_inverse)) f_inverse.setIdentity();
      const Eigen::Vector3d at = embeddedPosition(*e, s.x_m);  // where the rest point r is now
      if (!at.allFinite()) break;
      map.world_m = at, map.rest_m = r, map.world_to_rest = f_inverse, map.located = true;
      const Eigen::Vector3d delta = f_inverse * (world_m - at);
      r += delta;
      if (delta.squaredNorm() < 1e-24) break;
    }
  } catch (const std::bad_alloc&) {  // locate's scratch list outgrew its reserve: the identity
    return {};
  }
  return map;
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
    const detail::PcgResult cg = detail::solvePcg(
        s.matrix, s.active, s.contact_w, s.contact_z[static_cast<std::size_t>(k)], s.options.cg_tolerance,
        s.options.max_cg_iterations, s.options.ssor_relaxation, {}, s.pcg, s.coarse_current ? &s.coarse : nullptr);
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
