// TissueModel::apply (tissue_model.h): a cut's changes in O(changed). Steps, in order:
//  1. nodes: a new node (or one whose rest was not known) gets its rest position, and starts where the
//     tissue around it is: its rest position located among the current (not yet replaced) pieces, its position
//     and velocity the same barycentric sum of theirs; a known node whose rest moved gets the new rest;
//  2. base tets: each one's pieces are removed (matrix entries released, node and grid entries dropped) and
//     the new pieces added, warm-started with the rotation of the base tet's first old piece;
//  3. pieces around a node whose rest moved get their rest shape again;
//  4. the masses (a quarter of each live piece's mass) and roles (free, held, unused) of every node of a piece
//     added, removed or reshaped.
#include <algorithm>
#include <cmath>

#include "incise/physics/tissue_model.h"
#include "tissue_model_state.h"

namespace incise::physics {
namespace {

constexpr int kNewNodeMatrixRoom = 16;   // block entries above the diagonal a cut node starts with
constexpr int kNewNodeElementRoom = 24;  // pieces around a cut node it starts with

}  // namespace

std::array<Eigen::Vector3d, 4> TissueModel::State::restOf(const detail::Element& e) const noexcept {
  return {rest_m[static_cast<std::size_t>(e.nodes[0])], rest_m[static_cast<std::size_t>(e.nodes[1])],
          rest_m[static_cast<std::size_t>(e.nodes[2])], rest_m[static_cast<std::size_t>(e.nodes[3])]};
}

int TissueModel::State::addElement(int base_tet, const std::array<int, 4>& nodes, int side,
                                   const std::array<double, 4>& q) {
  detail::Element e;
  e.nodes = nodes, e.base_tet = base_tet, e.side = static_cast<std::int8_t>(side), e.q = q;
  if (!detail::setRest(e, restOf(e), inverse_prestretch)) return -1;
  int slot;
  if (!free_elements.empty()) {
    slot = free_elements.back();
    free_elements.pop_back();
  } else {
    if (elements.size() == elements.capacity()) ++growths;
    slot = static_cast<int>(elements.size());
    elements.emplace_back();
    element_mark.push_back(0);
  }
  for (int p = 0; p < 6; ++p) {
    const int a = nodes[static_cast<std::size_t>(detail::kPairs[p][0])];
    const int b = nodes[static_cast<std::size_t>(detail::kPairs[p][1])];
    e.pair[static_cast<std::size_t>(p)] = static_cast<std::uint16_t>(matrix.acquire(std::min(a, b), std::max(a, b)));
  }
  for (const int node : nodes) node_elements.add(node, slot);
  base_elements.add(base_tet, slot);
  grid.insert(slot, e.centroid_m);
  max_radius_m = std::max(max_radius_m, e.radius_m);
  e.alive = true;
  elements[static_cast<std::size_t>(slot)] = e;
  ++alive;
  return slot;
}

void TissueModel::State::removeElement(int slot) noexcept {
  detail::Element& e = elements[static_cast<std::size_t>(slot)];
  if (!e.alive) return;
  for (int p = 0; p < 6; ++p) {
    const int a = e.nodes[static_cast<std::size_t>(detail::kPairs[p][0])];
    const int b = e.nodes[static_cast<std::size_t>(detail::kPairs[p][1])];
    matrix.release(std::min(a, b), e.pair[static_cast<std::size_t>(p)]);
  }
  for (const int node : e.nodes) node_elements.remove(node, slot);
  base_elements.remove(e.base_tet, slot);
  try {
    grid.remove(slot, e.centroid_m);
  } catch (...) {  // cannot happen: the entry was inserted at this centroid
  }
  e.alive = false;
  --alive;
  free_elements.push_back(slot);  // within the reserve: every slot fits back
}

namespace {

using State = TissueModel::State;

void touchNode(State& s, int node) {
  if (s.node_mark[static_cast<std::size_t>(node)] == s.mark) return;
  s.node_mark[static_cast<std::size_t>(node)] = s.mark;
  s.touched_nodes.push_back(node);
}

// Where a new node starts: its rest position carried by the piece that holds it now (looked for among the
// pieces whose centroid is within the largest radius first: a piece that contains it is; only a node outside
// every piece needs the wider search).
void placeNewNode(State& s, int node) {
  const auto i = static_cast<std::size_t>(node);
  const Eigen::Vector3d rest = s.rest_m[i];
  s.x_m[i] = rest, s.v_m_per_s[i].setZero();
  std::optional<Embedded> at = s.locate(rest, {}, 0.0);
  if (!at) at = s.locate(rest, {}, 2.0 * s.max_radius_m);
  if (!at) return;
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    const auto n = static_cast<std::size_t>(at->nodes[static_cast<std::size_t>(k)]);
    x += at->weights[static_cast<std::size_t>(k)] * s.x_m[n];
    v += at->weights[static_cast<std::size_t>(k)] * s.v_m_per_s[n];
  }
  s.x_m[i] = x, s.v_m_per_s[i] = v;
}

void applyNode(State& s, const NodeRest& nr, ChangeStats& stats, std::vector<int>& moved) {
  if (nr.node < 0 || !nr.rest_m.allFinite()) return;
  const auto i = static_cast<std::size_t>(nr.node);
  while (s.x_m.size() <= i) {  // new nodes; those between are unknown until given
    s.addNode(nr.rest_m, kNewNodeMatrixRoom, kNewNodeElementRoom);
    s.known.back() = 0;
  }
  if (!s.known[i]) {
    s.known[i] = 1;
    s.rest_m[i] = s.target_m[i] = nr.rest_m;
    s.fixed_by_boundary[i] = insideFixedBox(s.boundary, nr.rest_m) ? 1 : 0;
    placeNewNode(s, nr.node);
    ++stats.nodes_added;
  } else if (s.rest_m[i] != nr.rest_m) {
    s.rest_m[i] = nr.rest_m;
    if (!s.held_by_tool[i]) s.target_m[i] = nr.rest_m;
    moved.push_back(nr.node);
    ++stats.nodes_moved;
  } else {
    return;
  }
  touchNode(s, nr.node);
}

void applyBaseTet(State& s, const CutChanges& changes, const BaseTetPieces& b, ChangeStats& stats) {
  if (b.base_tet < 0) return;
  while (s.base_elements.lists() <= b.base_tet) s.base_elements.addList(b.count);
  std::array<double, 4> q{1.0, 0.0, 0.0, 0.0};
  const std::span<const int> old = s.base_elements[b.base_tet];
  if (!old.empty()) q = s.elements[static_cast<std::size_t>(old.front())].q;
  while (!s.base_elements[b.base_tet].empty()) {
    const int e = s.base_elements[b.base_tet].front();
    for (const int node : s.elements[static_cast<std::size_t>(e)].nodes) touchNode(s, node);
    s.removeElement(e);
    ++stats.elements_removed;
  }
  for (int k = 0; k < b.count; ++k) {
    const Piece& piece = changes.pieces[static_cast<std::size_t>(b.first + k)];
    const bool known = std::all_of(piece.nodes.begin(), piece.nodes.end(), [&](int n) {
      return n >= 0 && static_cast<std::size_t>(n) < s.x_m.size() && s.known[static_cast<std::size_t>(n)];
    });
    if (!known || s.addElement(b.base_tet, piece.nodes, piece.side, q) < 0) {
      ++stats.pieces_refused;
      continue;
    }
    for (const int node : piece.nodes) touchNode(s, node);
    ++stats.elements_added;
  }
}

// Pieces around the moved nodes get their rest shape again (a piece that went flat is dropped).
void reshape(State& s, std::span<const int> moved, ChangeStats& stats) {
  for (const int node : moved) {
    for (std::size_t k = 0; k < s.node_elements[node].size(); ++k) {
      const int e = s.node_elements[node][k];
      detail::Element& el = s.elements[static_cast<std::size_t>(e)];
      if (s.element_mark[static_cast<std::size_t>(e)] == s.mark) continue;
      s.element_mark[static_cast<std::size_t>(e)] = s.mark;
      const Eigen::Vector3d centroid = el.centroid_m;
      if (!detail::setRest(el, s.restOf(el), s.inverse_prestretch)) {
        for (const int n : el.nodes) touchNode(s, n);
        s.removeElement(e);
        --k;  // the list lost this entry
        ++stats.pieces_refused;
        continue;
      }
      if (centroid != el.centroid_m) s.grid.move(e, centroid, el.centroid_m);
      s.max_radius_m = std::max(s.max_radius_m, el.radius_m);
      for (const int n : el.nodes) touchNode(s, n);  // its volume changed: so did its nodes' masses
      ++stats.elements_updated;
    }
  }
}

}  // namespace

ChangeStats TissueModel::apply(const CutChanges& changes) {
  State& s = *s_;
  ChangeStats stats;
  if (++s.mark == 0) {  // the stamps wrapped: start them over
    std::fill(s.node_mark.begin(), s.node_mark.end(), 0u);
    std::fill(s.element_mark.begin(), s.element_mark.end(), 0u);
    s.mark = 1;
  }
  s.touched_nodes.clear();
  std::vector<int>& moved = s.touched_elements;  // reused as the list of moved nodes
  moved.clear();
  for (const NodeRest& nr : changes.nodes) applyNode(s, nr, stats, moved);
  for (const BaseTetPieces& b : changes.base_tets) applyBaseTet(s, changes, b, stats);
  reshape(s, moved, stats);
  for (const int node : s.touched_nodes) {
    s.recomputeMass(node);
    s.setRole(node);
  }
  s.pcg.resize(s.x_m.size());
  s.last_dt_s = 0.0;  // the assembled matrix no longer matches: contactModel waits for the next step
  return stats;
}

}  // namespace incise::physics
