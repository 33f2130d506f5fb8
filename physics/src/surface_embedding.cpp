#include "incise/physics/surface_embedding.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "element.h"

namespace incise::physics {

std::optional<TetLocator::Held> TetLocator::held(std::span<const Eigen::Vector3d> rest_m, const LocatorTet& t) {
  Held h{t, Eigen::Matrix3d::Identity(), {}};
  for (std::size_t i = 0; i < 4; ++i) {
    if (t.nodes[i] < 0 || static_cast<std::size_t>(t.nodes[i]) >= rest_m.size()) return std::nullopt;
    h.x_m[i] = rest_m[static_cast<std::size_t>(t.nodes[i])];
  }
  Eigen::Matrix3d edges;
  for (int i = 0; i < 3; ++i) edges.col(i) = h.x_m[static_cast<std::size_t>(i + 1)] - h.x_m[0];
  const double scale = edges.colwise().norm().maxCoeff();
  if (!(std::abs(edges.determinant()) > 1e-12 * scale * scale * scale)) return std::nullopt;  // flat at rest
  h.inverse_edges = edges.inverse();
  return h;
}

Eigen::AlignedBox3d TetLocator::cellRange(const Held& h) const {
  const double cell_m = grid_.cellSize();
  const Eigen::AlignedBox3d box = h.box();
  return {(box.min().array() / cell_m).floor().matrix(), (box.max().array() / cell_m).floor().matrix()};
}

template <typename Visit>
void TetLocator::forCells(const Held& h, Visit&& visit) const {
  const double cell_m = grid_.cellSize();
  const Eigen::AlignedBox3d range = cellRange(h);
  const Eigen::Vector3d first = range.min(), last = range.max();
  for (double cx = first.x(); cx <= last.x(); ++cx)
    for (double cy = first.y(); cy <= last.y(); ++cy)
      for (double cz = first.z(); cz <= last.z(); ++cz) visit(Eigen::Vector3d(cx + 0.5, cy + 0.5, cz + 0.5) * cell_m);
}

void TetLocator::build(std::span<const Eigen::Vector3d> rest_m, std::span<const LocatorTet> tets,
                       std::vector<int>* slots) {
  tets_.clear();
  free_.clear();
  tets_.reserve(tets.size());
  if (slots) slots->assign(tets.size(), -1);
  double edge_sum_m = 0.0;
  for (std::size_t i = 0; i < tets.size(); ++i) {
    std::optional<Held> h = held(rest_m, tets[i]);
    if (!h) continue;
    if (h->tet.key < 0) h->tet.key = static_cast<std::int64_t>(i);
    double longest_m = 0.0;  // of the edges from its first node
    for (std::size_t k = 1; k < 4; ++k) longest_m = std::max(longest_m, (h->x_m[k] - h->x_m[0]).norm());
    edge_sum_m += longest_m;
    if (slots) (*slots)[i] = static_cast<int>(tets_.size());
    tets_.push_back(*h);
  }
  // Each tet is entered in every grid cell its bounding box overlaps (at the cell's centre), so that the
  // tets that may hold p are those entered in p's own cell.
  const double cell_m = tets_.empty() ? 1.0 : std::max(edge_sum_m / static_cast<double>(tets_.size()), 1e-9);
  grid_ = mesh::VertexGrid(cell_m);
  grid_.reserve(8 * tets_.size());
  cells_.setEmpty();
  for (std::size_t i = 0; i < tets_.size(); ++i) enter(static_cast<int>(i));
}

void TetLocator::enter(int slot) {
  const Held& h = tets_[static_cast<std::size_t>(slot)];
  cells_.extend(cellRange(h));
  forCells(h, [&](const Eigen::Vector3d& centre) { grid_.insert(slot, centre); });
}

void TetLocator::update(std::span<const Eigen::Vector3d> rest_m, std::span<const int> removed,
                        std::span<const LocatorTet> added, std::vector<int>& slots) {
  for (const int slot : removed) {
    if (slot < 0 || static_cast<std::size_t>(slot) >= tets_.size()) continue;
    Held& h = tets_[static_cast<std::size_t>(slot)];
    if (h.tet.nodes[0] < 0) continue;  // already free
    forCells(h, [&](const Eigen::Vector3d& centre) { grid_.remove(slot, centre); });
    h.tet.nodes = {-1, -1, -1, -1};
    free_.push_back(slot);
  }
  slots.assign(added.size(), -1);
  for (std::size_t i = 0; i < added.size(); ++i) {
    const std::optional<Held> h = held(rest_m, added[i]);
    if (!h) continue;
    int slot = static_cast<int>(tets_.size());
    if (free_.empty()) {
      tets_.push_back(*h);
    } else {
      slot = free_.back();
      free_.pop_back();
      tets_[static_cast<std::size_t>(slot)] = *h;
    }
    slots[i] = slot;
    enter(slot);
  }
}

void TetLocator::ringCandidates(const Eigen::Array3d& index, int ring, std::vector<int>& out) const {
  out.clear();
  // The cells at Chebyshev distance `ring` from `index`: two faces of the cube whole in x, two in y without
  // the x faces' rows, two in z without either. A box from a quarter cell before the first cell's centre
  // to a quarter after the last's holds exactly their entries (entered at cell centres).
  const double cell_m = grid_.cellSize(), r = static_cast<double>(ring);
  const auto slab = [&](Eigen::Array3d lo, Eigen::Array3d hi) {
    grid_.query(Eigen::AlignedBox3d(((lo + 0.25) * cell_m).matrix(), ((hi + 0.75) * cell_m).matrix()), out);
  };
  for (const double side : {-r, r}) {
    slab(index + Eigen::Array3d(side, -r, -r), index + Eigen::Array3d(side, r, r));
    slab(index + Eigen::Array3d(1 - r, side, -r), index + Eigen::Array3d(r - 1, side, r));
    slab(index + Eigen::Array3d(1 - r, 1 - r, side), index + Eigen::Array3d(r - 1, r - 1, side));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::optional<Embedded> TetLocator::locate(const Eigen::Vector3d& p, ElementFilter filter,
                                           double max_distance_m) const {
  if (!p.allFinite() || !(max_distance_m >= 0.0) || tets_.empty()) return std::nullopt;
  thread_local std::vector<int> candidates;
  // A tet holding p is entered in p's cell: those first; the cells within max_distance_m only when none does.
  const double cell_m = grid_.cellSize();
  const Eigen::Vector3d centre = ((p.array() / cell_m).floor() + 0.5).matrix() * cell_m;
  candidates.clear();
  grid_.query(Eigen::AlignedBox3d(centre, centre), candidates);
  const auto embedded = [&](const Held& h, double outside_m) {
    const Eigen::Vector3d l = h.inverse_edges * (p - h.x_m[0]);
    Embedded e;
    e.nodes = h.tet.nodes;
    e.weights = {1.0 - l.sum(), l.x(), l.y(), l.z()};
    e.element = h.tet.element;
    e.outside_m = outside_m;
    return e;
  };
  // Inside: the tet where p is deepest (largest smallest weight; ties to the smaller key).
  int best = -1;
  const auto keyBefore = [&](const Held& h) {  // a tie: h goes before the best so far
    return best >= 0 && h.tet.key < tets_[static_cast<std::size_t>(best)].tet.key;
  };
  double best_score = -std::numeric_limits<double>::infinity();
  for (const int c : candidates) {
    const Held& h = tets_[static_cast<std::size_t>(c)];
    if (!filter(h.tet.element)) continue;
    const Eigen::Vector3d l = h.inverse_edges * (p - h.x_m[0]);
    const double deepest = std::min({1.0 - l.sum(), l.x(), l.y(), l.z()});
    if (deepest > best_score || (deepest == best_score && keyBefore(h))) best = c, best_score = deepest;
  }
  constexpr double kInside = -1e-12;
  if (best >= 0 && best_score >= kInside) return embedded(tets_[static_cast<std::size_t>(best)], 0.0);
  // Outside every tet: the nearest one within max_distance_m, ring by ring of cells around p's cell (ring 0
  // is p's cell, already listed). A tet entered in no cell of rings 0..k has its box, and so itself, farther
  // from p than k cells plus p's margin in its own cell: the search stops once the nearest so far is nearer
  // than that, or that is beyond max_distance_m. The same answer as a search of every tet within reach.
  const Eigen::Array3d index = (p.array() / cell_m).floor();
  const Eigen::Array3d offset_m = p.array() - index * cell_m;
  const double margin_m = std::max(0.0, std::min(offset_m.minCoeff(), (cell_m - offset_m).minCoeff()));
  double best_distance = std::numeric_limits<double>::infinity();
  best = -1;
  for (int ring = 0;; ++ring) {
    if (ring > 0) ringCandidates(index, ring, candidates);
    for (const int c : candidates) {
      const Held& h = tets_[static_cast<std::size_t>(c)];
      // A tet whose box is farther than the nearest so far is farther too (a tie is measured: it may win).
      if (!filter(h.tet.element) || h.box().exteriorDistance(p) > best_distance) continue;
      const double d = detail::distanceToTet(h.x_m, p);
      if (d < best_distance || (d == best_distance && keyBefore(h))) best = c, best_distance = d;
    }
    // Unseen tets are farther than this (less a rounding allowance).
    const double cleared_m = static_cast<double>(ring) * cell_m + margin_m - 1e-9 * cell_m;
    const bool every_cell =
        (index - ring <= cells_.min().array()).all() && (index + ring >= cells_.max().array()).all();
    if (best_distance < cleared_m || cleared_m >= max_distance_m || every_cell) break;
  }
  if (best < 0 || best_distance > max_distance_m) return std::nullopt;
  return embedded(tets_[static_cast<std::size_t>(best)], best_distance);
}

Eigen::Vector3d probeBeside(const Eigen::Vector3d& x_m, std::span<const Eigen::Vector3d> neighbours_m,
                            const Eigen::Vector3d& area_normal, double area_sum) {
  if (neighbours_m.empty()) return x_m;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double spread_m = 0.0;
  for (const Eigen::Vector3d& y : neighbours_m) centroid += y, spread_m += (y - x_m).norm();
  const auto count = static_cast<double>(neighbours_m.size());
  centroid /= count, spread_m /= count;
  const double n = area_normal.norm();
  if (n > 1e-9 * area_sum) return 0.5 * (x_m + centroid) - 0.25 * spread_m * area_normal / n;
  // A fold (the faces meet at zero angle, as two walls at the floor of a groove cut with no opening): the
  // tissue lies past its tip, away from the faces (their centroid).
  const Eigen::Vector3d away = x_m - centroid;
  const double length = away.norm();
  return length > 0.0 ? Eigen::Vector3d(x_m + 0.25 * spread_m * away / length) : x_m;
}

namespace {

// Among the tets `filter` admits, the one holding the point kEmbedNudgeM from x towards `beside_m` (the
// vertex's own side), with x's weights in it, when x is on it. nullopt when the nudged point is in no
// admitted tet (a wall vertex a little across the tets' own cut face) or x is not on that tet.
std::optional<Embedded> ownTet(const PointLocator& tets, const Eigen::Vector3d& x, const Eigen::Vector3d& beside_m,
                               ElementFilter filter, int& near_base) {
  const Eigen::Vector3d towards = beside_m - x;
  if (!(towards.norm() > kEmbedNudgeM)) return std::nullopt;
  const std::optional<Embedded> near = tets.locate(x + kEmbedNudgeM * towards.normalized(), filter, 0.0);
  if (!near) return std::nullopt;
  const ElementInfo own = near->element;
  near_base = own.base_tet;
  return tets.locate(
      x, [&](const ElementInfo& t) { return t.base_tet == own.base_tet && t.side == own.side; }, kEmbedOnFaceM);
}

}  // namespace

std::optional<Embedded> embedSurfaceVertex(const PointLocator& tets, const Eigen::Vector3d& x_m,
                                           const Eigen::Vector3d& beside_m, EmbedBases* bases) {
  const std::optional<Embedded> probe = tets.locate(beside_m, {}, kEmbedReachM);
  const int side = probe ? probe->element.side : 0;
  const OnSide on_side{side};
  const ElementFilter filter = side != 0 ? ElementFilter(on_side) : ElementFilter();
  int near_base = -1;
  std::optional<Embedded> e = ownTet(tets, x_m, beside_m, filter, near_base);
  if (!e && side != 0) e = tets.locate(x_m, on_side, kEmbedReachM);
  if (!e) e = tets.locate(x_m, {}, kEmbedReachM);
  if (bases) *bases = {probe ? probe->element.base_tet : -1, near_base, e ? e->element.base_tet : -1};
  return e;
}

}  // namespace incise::physics
