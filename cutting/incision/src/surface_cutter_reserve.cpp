// The surface cutter's room for an incision, reserved at load (surface_cutter.h, "Allocation": the
// sim thread allocates nothing after its first frame): the arrays an incision fills, sized for
// CutterOptions::reserved_bound_vertices; the seam's chain, grown at both ends in one buffer; the bound
// vertices' lattice cells, a list per cell through one pool, with their counts (what redeform() will move,
// for the budget); the mesh's headroom, topped up between incisions; and the settled incision's vertices
// re-indexed for the next one (prepareBegin, in budgeted steps). The incision's steps are in surface_cutter.cpp.
#include <algorithm>
#include <cstddef>
#include <exception>
#include <utility>
#include <vector>

#include "incise/incision/surface_cutter.h"

namespace incise::incision {

void SurfaceCutter::reserveIncisionArrays() {
  const auto bound = static_cast<std::size_t>(options_.reserved_bound_vertices);
  const auto columns = static_cast<std::size_t>(options_.incision.max_columns);
  const auto rows = static_cast<std::size_t>(options_.wall_rows) + 1;
  // The first incision's lattice, made here: begin() restarts it at the stroke's first sample.
  spare_ = std::make_unique<Incision>(options_.incision,
                                      StrokeSample{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0},
                                      Eigen::Vector3d::UnitX());
  cell_first_.assign(columns, -1);
  cell_last_.assign(columns, -1);
  cell_count_.assign(columns, 0);
  cell_next_.reserve(bound);
  cell_vertex_.reserve(bound);
  for (auto* v : {&all_bound_, &seam_created_, &dirty_, &fresh_}) v->reserve(bound);
  for (auto* v : {&candidates_, &query_}) v->reserve(bound);
  through_.reserve(16 * columns);
  changed_columns_.reserve(columns);
  stencil_count_.reserve(bound);
  stencil_first_.reserve(2 * bound);
  stencil_basis_.reserve(2 * bound * static_cast<std::size_t>(3 * options_.incision.order));
  // The seam: at most a few seam vertices per column (a vertex per crossed edge), each with a wall column
  // and a strip to its successor.
  const std::size_t seam = 8 * columns;
  chain_.reset(seam);
  wall_columns_.resize(seam);
  for (WallColumn& c : wall_columns_) c.minus.reserve(rows), c.plus.reserve(rows);
  strips_.resize(2 * seam);
  for (Strip& strip : strips_) strip.faces.reserve(4 * rows);
  crossings_.reserve(bound);
  around_.reserve(64);
  plus_.reserve(64);
  strip_faces_.reserve(4 * rows);
  side_a_.reserve(rows);
  side_b_.reserve(rows);
}

void SurfaceCutter::Chain::reset(std::size_t room_each_end) {
  if (buffer_.size() < 2 * room_each_end) buffer_.resize(2 * room_each_end);
  head_ = tail_ = buffer_.size() / 2;
}

void SurfaceCutter::Chain::recentre(std::size_t capacity) {
  std::vector<mesh::TriMesh::VertexHandle> grown(capacity);
  const std::size_t n = size(), head = (capacity - n) / 2;
  std::copy(buffer_.begin() + static_cast<std::ptrdiff_t>(head_), buffer_.begin() + static_cast<std::ptrdiff_t>(tail_),
            grown.begin() + static_cast<std::ptrdiff_t>(head));
  buffer_ = std::move(grown);
  head_ = head;
  tail_ = head + n;
}

bool SurfaceCutter::Chain::pushBack(mesh::TriMesh::VertexHandle v) {
  const bool fits = tail_ < buffer_.size();
  if (!fits) recentre(2 * buffer_.size() + 16);
  buffer_[tail_++] = v;
  return fits;
}

bool SurfaceCutter::Chain::pushFront(mesh::TriMesh::VertexHandle v) {
  const bool fits = head_ > 0;
  if (!fits) recentre(2 * buffer_.size() + 16);
  buffer_[--head_] = v;
  return fits;
}

void SurfaceCutter::addToCell(int cell, mesh::TriMesh::VertexHandle v) {
  const int index = static_cast<int>(cell_vertex_.size());
  pushReserved(cell_vertex_, v);
  pushReserved(cell_next_, -1);
  const auto c = static_cast<std::size_t>(cell);
  if (cell_last_[c] >= 0)
    cell_next_[static_cast<std::size_t>(cell_last_[c])] = index;
  else
    cell_first_[c] = index;
  cell_last_[c] = index;
  ++cell_count_[c];
}

int SurfaceCutter::redeformMoves() const noexcept {
  // The cells redeform() visits: [column, column + order) for each changed column (ascending), each once.
  const int order = options_.incision.order;
  const int cells = static_cast<int>(cell_count_.size());
  int moves = 0, next_cell = 0;
  for (const int column : changed_columns_) {
    for (int cell = std::max(column, next_cell); cell < std::min(column + order, cells); ++cell)
      moves += cell_count_[static_cast<size_t>(cell)];
    next_cell = std::max(next_cell, column + order);
  }
  return moves;
}

void SurfaceCutter::reserveHeadroom() {
  // Growing OpenMesh's arrays mid-stroke copies every vertex and face (tens of ms on a 1M-triangle mesh):
  // keep room for a long cut's new elements, topped up between incisions, never during one.
  mesh::TriMesh& m = mesh_.mesh();
  if (m.n_vertices() + kHeadroomVertices / 2 <= reserved_vertices_) return;  // room left: no copy
  if (reserved_vertices_ > 0) ++stats_.reserve_overflows;                    // a top-up after load
  reserved_vertices_ = kHeadroomVertices + m.n_vertices();
  m.reserve(reserved_vertices_, m.n_edges() + 3 * kHeadroomVertices, m.n_faces() + 2 * kHeadroomVertices);
  // The grids likewise: the new vertices' entries, and the cells vertices move into.
  grid_.reserve(kHeadroomVertices);
  coarse_grid_.reserve(kHeadroomVertices);
  // The contact queries' per-face stamps (queryRest) for the faces reserved: else the first query of the
  // sim thread sizes them, in whichever frame the first pose arrives.
  const std::size_t faces = m.n_faces() + 2 * kHeadroomVertices;
  if (face_stamp_.size() < faces) face_stamp_.resize(faces, 0u);
}

bool SurfaceCutter::prepareBegin(bool unlimited) noexcept {
  if (!settleStep(unlimited)) return false;
  if (!incision_ || failed_) return true;
  core::WorkBudget budget =
      unlimited ? core::WorkBudget::unlimited() : core::WorkBudget(options_.max_inversions_per_call, deadline_);
  try {
    return reindexStep(budget);
  } catch (const std::exception&) {  // an entry not in the grid: a broken invariant; begin() reports it
    return true;
  }
}

// The settled incision's vertices have moved: the grid indexes them where they are now, then (with
// refinement) their and their neighbours' coarse flags follow their edges' new lengths. Resumable.
bool SurfaceCutter::reindexStep(core::WorkBudget& budget) {
  const mesh::TriMesh& m = mesh_.mesh();
  for (; reindexed_moves_ < all_bound_.size(); ++reindexed_moves_) {
    if (!budget.takeEvery(reindexed_moves_, kReindexMovesPerUnit)) return false;
    const mesh::TriMesh::VertexHandle v = all_bound_[reindexed_moves_];
    if (m.status(v).deleted()) continue;  // removed by a through-cut, and from the grid with it
    grid_.move(v.idx(), data(v).rest_m, mesh::toEigen(m.point(v)));
  }
  if (options_.refine == CutterOptions::Refine::Off) return true;
  for (; reindexed_coarse_ < all_bound_.size(); ++reindexed_coarse_) {
    if (!budget.takeEvery(reindexed_coarse_, kReindexCoarsePerUnit)) return false;
    if (!m.status(all_bound_[reindexed_coarse_]).deleted()) updateCoarseAround(all_bound_[reindexed_coarse_], true);
  }
  return true;
}

}  // namespace incise::incision
