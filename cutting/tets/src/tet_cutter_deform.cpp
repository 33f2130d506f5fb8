// TetCutter's step 4 (tet_cutter.h): moving the nodes. setSide() gives a node its stencil (its spans and
// basis values in the incision's lattice) and lists it under the last lattice column the stencil reaches;
// redeform() first brings the delayed copy of the incision's displacement (lagged_) up to date, whole, then
// moves every node whose stencil reaches a column it copied again and every node whose stencil or rest
// position changed in this call (dirty_): rest + D(stencil), from the finished copy. The copy is a function of
// the incision's state and of the columns the tets have cut (next_column_), never of the calls before, so
// every node sits where that state puts it after each call, whatever the timing of the calls: the same bytes
// fast and in real time. Steps 1 to 3 are in tet_cutter.cpp and tet_cutter_separate.cpp.
// Cost per call: O(final columns) to compare the copy, O(l n) per column copied again, one o^3 weighted sum per
// node moved; a stencil that moves to another column's list costs O(that list). No allocation within the
// headroom reserved at load. Thread: the cutter's owner (inside follow()).
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "incise/tets/tet_cutter.h"

namespace incise::tets {

void TetCutter::setSide(int n, int side) {
  Node& d = nodes_[static_cast<size_t>(n)];
  d.side = static_cast<std::int8_t>(side);
  dirty_.push_back(n);
  if (side == 0) return;
  const incision::Incision& in = *incision_;
  const int size = in.stencilSize();
  if (d.stencil < 0) {
    d.stencil = static_cast<int>(stencil_count_.size());
    stencil_count_.push_back(0);
    stencil_first_.resize(stencil_first_.size() + 2);
    stencil_basis_.resize(stencil_basis_.size() + 2 * static_cast<size_t>(size));
  }
  // Its own parameters, also for a node snapped onto the cut (|u - 1/2| up to the snap tolerance): on the
  // side u lies on it moves as the tissue there; Incision::stencil clamps u to the lip (1/2 -/+) for the
  // other side's (a copy on the + side of a node with u < 1/2), and side 2 takes both lips.
  Eigen::Vector3d uvw = d.uvw;
  for (int axis = 0; axis < 3; ++axis) {
    const auto domain = in.rest().domain(axis);
    uvw[axis] = std::clamp(uvw[axis], domain[0], domain[1]);
  }
  const size_t s = static_cast<size_t>(d.stencil);
  stencil_count_[s] = static_cast<std::uint8_t>(
      in.stencil(uvw, side, &stencil_first_[2 * s], &stencil_basis_[2 * s * static_cast<size_t>(size)]));
  // The stencil reaches the `order` columns up to its corner's + order - 1 (both evaluations of side 2
  // alike): the node is listed there. New parameters (a Steiner node's, when its tet is split again) may
  // move it to another list.
  const std::array<int, 3> counts = in.displacement().controlCounts();
  const int cell = stencil_first_[2 * s] / counts[0] % counts[1] + in.options().order - 1;
  if (cell == d.cell) return;
  if (d.cell >= 0) {
    std::vector<int>& old = cells_[static_cast<size_t>(d.cell)];
    old.erase(std::find(old.begin(), old.end(), n));
  }
  d.cell = cell;
  countGrowth(cells_[static_cast<size_t>(cell)], 1);
  cells_[static_cast<size_t>(cell)].push_back(n);
}

void TetCutter::copyLagged(const incision::Incision& in) {
  // Columns stay shut from `shut_from` on, where tets may not be cut yet, and open gradually over the
  // lag_columns_ before it (a step would tear the tets behind the front); all open once all is cut. A
  // column is copied again when its scale or its opening changed, unless it holds zeros before and after
  // (scale or opening 0); the incision's column is a function of its opening (its frame is fixed once it is
  // final).
  const bool all_cut = in.finished() && !pending();
  const int shut_from = next_column_ - lag_columns_;
  const bspline::BSplineVolume& source = in.displacement();
  const std::array<int, 3> counts = source.controlCounts();
  // Only final columns open (Incision::columnOpening): those after them hold zeros here too.
  const int columns = std::min(in.finalColumns(), static_cast<int>(lagged_seen_.size()));
  lagged_changed_.clear();
  for (int c = 0; c < columns; ++c) {
    const double scale = all_cut ? 1.0 : std::clamp(double(shut_from - c) / lag_columns_, 0.0, 1.0);
    const double opening = in.columnOpening(c);
    LaggedColumn& seen = lagged_seen_[static_cast<size_t>(c)];
    const bool shut = scale == 0.0 || opening == 0.0;  // zeros
    if ((shut && (seen.scale == 0.0 || seen.opening == 0.0)) || (scale == seen.scale && opening == seen.opening))
      continue;
    seen = {scale, opening};
    for (int k = 0; k < counts[2]; ++k)
      for (int i = 0; i < counts[0]; ++i) lagged_->setControl(i, c, k, scale * source.control(i, c, k));
    lagged_changed_.push_back(c);
  }
}

void TetCutter::redeform(const incision::Incision& in, TetStep& step) {
  copyLagged(in);
  if (++stamp_ == 0) stamp_ = 1;
  const auto move = [&](int n) {
    Node& d = nodes_[static_cast<size_t>(n)];
    if (d.stamp == stamp_) return;
    d.stamp = stamp_;
    Eigen::Vector3d x = rest_m_[static_cast<size_t>(n)];
    if (d.side != 0 && d.stencil >= 0) {
      const size_t s = static_cast<size_t>(d.stencil);
      x += in.displacementFromStencil(*lagged_, stencil_count_[s], &stencil_first_[2 * s],
                                      &stencil_basis_[2 * s * static_cast<size_t>(in.stencilSize())]);
    }
    deformed_m_[static_cast<size_t>(n)] = x;
    nodeChanged(n);
    ++step.nodes_moved;
  };
  // Every node whose stencil reaches a column copied again (listed under that column .. + order - 1), once.
  const int order = in.options().order, columns = static_cast<int>(cells_.size());
  for (const int c : lagged_changed_)
    for (int cell = c; cell < std::min(c + order, columns); ++cell)
      for (const int n : cells_[static_cast<size_t>(cell)]) move(n);
  for (const int n : dirty_) move(n);
  dirty_.clear();
}

}  // namespace incise::tets
