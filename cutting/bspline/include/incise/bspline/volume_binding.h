// Binding of a fixed set of parameter points (mesh vertices in the lattice's parameter space) to a
// B-spline volume's knots: the spans and basis values of each point are computed once, so re-deforming
// after control points move is an o_u * o_v * o_w weighted sum per point with no span search and no basis
// evaluation, only for points whose support holds a moved control point. This is what makes a cut cheap
// enough for a 1 kHz loop (paper §5: evaluation is linear in the number of vertices; here the constant is
// small).
//
// Shapes: `parameters` is #P points (u, v, w) inside the volume's domain; outputs are #P positions.
// Cost: construction O(#P * o^2 + #cells); deformAll O(#P * o^3); deformAffected O(affected points * o^3
// + moved controls * o^3). Memory: (o_u + o_v + o_w) doubles + 1 int per point, plus a cell index.
// Threads: construction anywhere; deformAll is const and may run concurrently; deformAffected uses the
// binding's scratch (one caller at a time). Both are noexcept and allocation-free (sim-thread safe).
// Failure: the constructor throws std::invalid_argument naming the index of a NaN or out-of-domain point;
// the deform calls return a status instead of throwing (a volume whose knots changed since binding is
// refused: re-bind after insertKnot).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "incise/bspline/bspline_volume.h"

namespace incise::bspline {

// The kernel VolumeBinding uses for order 4 on every axis, in this build on this CPU: "avx512" (AVX-512F
// and VL found at run time, in a native build), "avx2" (a native build) or "generic". Every kernel gives
// the same bits. For benchmarks' reports.
const char* boundKernelName() noexcept;

// true: VolumeBinding uses the AVX2 kernel even where AVX-512 is found (process-wide; false restores the
// automatic choice). For tests and benchmarks that compare the two.
void preferAvx2BoundKernel(bool prefer) noexcept;

class VolumeBinding {
 public:
  VolumeBinding(const BSplineVolume& volume, std::span<const Eigen::Vector3d> parameters);

  std::size_t size() const { return slot_point_.size(); }

  // True when `volume` has the orders and knot vectors this binding was made with.
  bool matches(const BSplineVolume& volume) const noexcept;

  // out[p] = F(parameters[p]) for every point; bit-identical to volume.evaluate(parameters[p]).
  // Returns false and writes nothing if !matches(volume) or out.size() != size().
  bool deformAll(const BSplineVolume& volume, std::span<Eigen::Vector3d> out) const noexcept;

  // Re-deforms only the points whose support contains one of `moved_controls` (linear control indices,
  // i + n_u * (j + n_v * k)); out[p] for other points is left as it is. Returns the number of points
  // written, or -1 (nothing written) on a mismatch as above or a control index out of range.
  int deformAffected(const BSplineVolume& volume, std::span<const int> moved_controls,
                     std::span<Eigen::Vector3d> out) noexcept;

  // The indices of the points deformAffected would write, in increasing cell order, into `points`
  // (cleared first). For tests and for callers that re-split or re-draw only those points.
  void affectedPoints(std::span<const int> moved_controls, std::vector<int>& points);

 private:
  template <typename Visit>
  bool forEachAffectedCell(std::span<const int> moved_controls, Visit&& visit) noexcept;

  std::array<int, 3> orders_{};
  std::array<int, 3> counts_{};
  std::array<std::vector<double>, 3> knots_;
  int basis_stride_ = 0;  // o_u + o_v + o_w
  // Per slot (the points sorted by the corner control of their support): the point it holds, the
  // linear index of that corner control, and Nu[o_u], Nv[o_v], Nw[o_w].
  std::vector<int> slot_point_;
  std::vector<int> first_control_;
  std::vector<double> basis_;
  std::vector<int> cell_begin_;            // slots of corner control c: [cell_begin_[c], cell_begin_[c + 1])
  std::vector<std::uint32_t> cell_stamp_;  // scratch: the call in which a cell was last visited
  std::uint32_t stamp_ = 0;
};

}  // namespace incise::bspline
