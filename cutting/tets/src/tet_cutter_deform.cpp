// TetCutter's step 4 (tet_cutter.h): moving the nodes. setSide() gives a node its stencil (its spans and
// basis values in the incision's lattice) and lists it by its lattice column; redeform() copies the
// incision's displacement into a delayed copy (lagged_) that keeps the columns near the tets' front shut,
// and moves the nodes of the columns whose copy changed and the nodes whose stencil changed (dirty_).
// Steps 1 to 3 are in tet_cutter.cpp and tet_cutter_separate.cpp.
// Cost per call: O(columns) to compare the copy, O(l n) per column copied again, one o^3 weighted sum per
// node moved. No allocation within the headroom reserved at load. Thread: the cutter's owner (inside follow()).
#include <algorithm>
#include <array>
#include <cmath>
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
    const double v = std::clamp(std::floor(d.uvw[1]), 0.0, double(cells_.size() - 1));
    cells_[static_cast<size_t>(v)].push_back(n);
  }
  Eigen::Vector3d uvw = d.uvw;
  if (d.cut_point || d.state == NodeState::Copy) uvw[0] = 0.5;  // on the cut: the lips' parameters
  for (int axis = 0; axis < 3; ++axis) {
    const auto domain = in.rest().domain(axis);
    uvw[axis] = std::clamp(uvw[axis], domain[0], domain[1]);
  }
  const size_t s = static_cast<size_t>(d.stencil);
  stencil_count_[s] = static_cast<std::uint8_t>(
      in.stencil(uvw, side, &stencil_first_[2 * s], &stencil_basis_[2 * s * static_cast<size_t>(size)]));
}

void TetCutter::redeform(const incision::Incision& in, TetStep& step) {
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
  const int order = in.options().order;
  const int columns = static_cast<int>(opening_seen_.size());
  // Columns stay shut from `shut_from` on, where tets may not be cut yet, and open gradually over the
  // lag_columns_ before it (a step would tear the tets behind the front); all open once all is cut.
  const bool all_cut = in.finished() && !pending();
  const int shut_from = next_column_ - lag_columns_;
  const bspline::BSplineVolume& source = in.displacement();
  const std::array<int, 3> counts = source.controlCounts();
  for (int c = 0; c < columns; ++c) {
    const double scale = all_cut ? 1.0 : std::clamp(double(shut_from - c) / lag_columns_, 0.0, 1.0);
    const double opening = scale * in.columnOpening(c);
    if (opening == opening_seen_[static_cast<size_t>(c)]) continue;
    opening_seen_[static_cast<size_t>(c)] = opening;
    for (int k = 0; k < counts[2]; ++k)
      for (int i = 0; i < counts[0]; ++i) lagged_->setControl(i, c, k, scale * source.control(i, c, k));
    for (int cell = c; cell < std::min(c + order, columns); ++cell)
      for (const int n : cells_[static_cast<size_t>(cell)]) move(n);
  }
  for (const int n : dirty_) move(n);
  dirty_.clear();
}

}  // namespace incise::tets
