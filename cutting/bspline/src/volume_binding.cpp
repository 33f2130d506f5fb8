#include "incise/bspline/volume_binding.h"

#include "incise/core/format.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "incise/bspline/knot_vector.h"
#include "incise/bspline/tensor_kernel.h"

namespace incise::bspline {

namespace {

#if INCISE_TENSOR_AVX512
const bool kCpuHasAvx512 = detail::cpuHasAvx512();
std::atomic<bool> prefer_avx2{false};

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12's AVX-512 intrinsics (tensor_kernel.h)
// deformSlots for order 4 on every axis with AVX-512: point s's plane sums are issued before point s - 1's
// final sum, so the CPU overlaps that sum's dependency chain with independent work.
__attribute__((target("avx512f,avx512vl"))) void deformSlots444Wide(const double* xyz, const std::array<int, 3>& counts,
                                                                    const int* first_control, const double* basis,
                                                                    int stride, const int* slot_point, int begin,
                                                                    int end, Eigen::Vector3d* out) noexcept {
  if (begin == end) return;
  const double* nu = basis + static_cast<std::ptrdiff_t>(begin) * stride;
  detail::WideSums previous = detail::planeSums444Wide(xyz, counts[0], counts[1], first_control[begin], nu + 4, nu + 8);
  for (int s = begin + 1; s < end; ++s) {
    const double* next_nu = nu + stride;
    const detail::WideSums current =
        detail::planeSums444Wide(xyz, counts[0], counts[1], first_control[s], next_nu + 4, next_nu + 8);
    detail::reduceNu4Wide(previous, nu, out[slot_point[s - 1]].data());
    previous = current;
    nu = next_nu;
  }
  detail::reduceNu4Wide(previous, nu, out[slot_point[end - 1]].data());
}
#pragma GCC diagnostic pop

bool useWideKernel(const std::array<int, 3>& orders) noexcept {
  return orders == std::array{4, 4, 4} && kCpuHasAvx512 && !prefer_avx2.load(std::memory_order_relaxed);
}
#endif

// Deforms the points in slots [begin, end). Slots hold the points sorted by support cell, so consecutive
// slots read the same control points; the kernel choice is hoisted out of the loop.
void deformSlots(const double* xyz, const std::array<int, 3>& orders, const std::array<int, 3>& counts,
                 const int* first_control, const double* basis, int stride, const int* slot_point, int begin, int end,
                 Eigen::Vector3d* out) noexcept {
#if INCISE_TENSOR_AVX512
  if (useWideKernel(orders))
    return deformSlots444Wide(xyz, counts, first_control, basis, stride, slot_point, begin, end, out);
#endif
  detail::withKernel(orders, [&]<int Ou, int Ovw>() {
    for (int s = begin; s < end; ++s) {
      const double* nu = basis + static_cast<std::ptrdiff_t>(s) * stride;
      const double* nv = nu + orders[0];
      const double* nw = nv + orders[1];
      out[slot_point[s]] =
          detail::tensorKernel<Ou, Ovw>(xyz, counts[0], counts[1], first_control[s], orders, nu, nv, nw);
    }
  });
}

}  // namespace

const char* boundKernelName() noexcept {
#if INCISE_TENSOR_AVX512
  if (useWideKernel({4, 4, 4})) return "avx512";
#endif
#if INCISE_TENSOR_AVX2
  return "avx2";
#else
  return "generic";
#endif
}

void preferAvx2BoundKernel(bool prefer) noexcept {
#if INCISE_TENSOR_AVX512
  prefer_avx2.store(prefer, std::memory_order_relaxed);
#else
  (void)prefer;
#endif
}

VolumeBinding::VolumeBinding(const BSplineVolume& volume, std::span<const Eigen::Vector3d> parameters)
    : orders_(volume.orders()), counts_(volume.controlCounts()) {
  for (int a = 0; a < 3; ++a) knots_[a] = volume.knots(a);
  basis_stride_ = orders_[0] + orders_[1] + orders_[2];
  const size_t n_points = parameters.size();
  if (n_points > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("VolumeBinding: " + std::to_string(n_points) + " points is more than an int indexes");
  std::vector<int> corner_of(n_points);
  std::vector<double> basis(n_points * static_cast<size_t>(basis_stride_));
  for (size_t p = 0; p < n_points; ++p) {
    const Eigen::Vector3d& t = parameters[p];
    if (!volume.inDomain(t[0], t[1], t[2]))
      throw std::invalid_argument("VolumeBinding: parameter point " + std::to_string(p) + " (" +
                                  core::formatNumber(t[0]) + ", " + core::formatNumber(t[1]) + ", " +
                                  core::formatNumber(t[2]) + ") is NaN or outside the volume's domain");
    int corner[3];
    double* out = basis.data() + p * static_cast<size_t>(basis_stride_);
    for (int a = 0; a < 3; ++a) {
      const int span = findSpan(knots_[a], orders_[a], counts_[a], t[a]);
      basisFunctions(knots_[a], orders_[a], span, t[a], out);
      out += orders_[a];
      corner[a] = span - (orders_[a] - 1);
    }
    corner_of[p] = volume.controlIndex(corner[0], corner[1], corner[2]);
  }

  // Slots: the points sorted by corner control (a stable counting sort). A cell's points are one
  // contiguous slot range, and consecutive slots share control points (cache-friendly).
  const size_t n_controls = static_cast<size_t>(counts_[0]) * counts_[1] * counts_[2];
  cell_begin_.assign(n_controls + 1, 0);
  for (int c : corner_of) ++cell_begin_[static_cast<size_t>(c) + 1];
  for (size_t c = 0; c < n_controls; ++c) cell_begin_[c + 1] += cell_begin_[c];
  std::vector<int> fill(cell_begin_.begin(), cell_begin_.end() - 1);
  slot_point_.resize(n_points);
  first_control_.resize(n_points);
  basis_.resize(basis.size());
  for (size_t p = 0; p < n_points; ++p) {
    const size_t slot = static_cast<size_t>(fill[static_cast<size_t>(corner_of[p])]++);
    slot_point_[slot] = static_cast<int>(p);
    first_control_[slot] = corner_of[p];
    std::copy_n(basis.data() + p * static_cast<size_t>(basis_stride_), basis_stride_,
                basis_.data() + slot * static_cast<size_t>(basis_stride_));
  }
  cell_stamp_.assign(n_controls, 0);
}

bool VolumeBinding::matches(const BSplineVolume& volume) const noexcept {
  if (volume.orders() != orders_ || volume.controlCounts() != counts_) return false;
  for (int a = 0; a < 3; ++a)
    if (volume.knots(a) != knots_[a]) return false;
  return true;
}

bool VolumeBinding::deformAll(const BSplineVolume& volume, std::span<Eigen::Vector3d> out) const noexcept {
  if (out.size() != size() || !matches(volume)) return false;
  deformSlots(volume.controls().data()->data(), orders_, counts_, first_control_.data(), basis_.data(), basis_stride_,
              slot_point_.data(), 0, static_cast<int>(size()), out.data());
  return true;
}

template <typename Visit>
bool VolumeBinding::forEachAffectedCell(std::span<const int> moved_controls, Visit&& visit) noexcept {
  const int n_controls = counts_[0] * counts_[1] * counts_[2];
  for (int c : moved_controls)
    if (c < 0 || c >= n_controls) return false;
  if (++stamp_ == 0) {  // wrapped: forget every old stamp
    std::fill(cell_stamp_.begin(), cell_stamp_.end(), 0u);
    stamp_ = 1;
  }
  for (int c : moved_controls) {
    const int ci = c % counts_[0];
    const int cj = (c / counts_[0]) % counts_[1];
    const int ck = c / (counts_[0] * counts_[1]);
    // Corners whose o_u x o_v x o_w support block contains (ci, cj, ck).
    for (int k = std::max(0, ck - orders_[2] + 1); k <= ck; ++k) {
      for (int j = std::max(0, cj - orders_[1] + 1); j <= cj; ++j) {
        for (int i = std::max(0, ci - orders_[0] + 1); i <= ci; ++i) {
          const int cell = i + counts_[0] * (j + counts_[1] * k);
          if (cell_stamp_[static_cast<size_t>(cell)] == stamp_) continue;
          cell_stamp_[static_cast<size_t>(cell)] = stamp_;
          const int begin = cell_begin_[static_cast<size_t>(cell)];
          const int end = cell_begin_[static_cast<size_t>(cell) + 1];
          if (begin != end) visit(begin, end);
        }
      }
    }
  }
  return true;
}

int VolumeBinding::deformAffected(const BSplineVolume& volume, std::span<const int> moved_controls,
                                  std::span<Eigen::Vector3d> out) noexcept {
  if (out.size() != size() || !matches(volume)) return -1;
  const double* xyz = volume.controls().data()->data();
  int written = 0;
  const bool ok = forEachAffectedCell(moved_controls, [&](int begin, int end) {
    deformSlots(xyz, orders_, counts_, first_control_.data(), basis_.data(), basis_stride_, slot_point_.data(), begin,
                end, out.data());
    written += end - begin;
  });
  return ok ? written : -1;
}

void VolumeBinding::affectedPoints(std::span<const int> moved_controls, std::vector<int>& points) {
  points.clear();
  forEachAffectedCell(moved_controls, [&](int begin, int end) {
    points.insert(points.end(), slot_point_.begin() + begin, slot_point_.begin() + end);
  });
}

}  // namespace incise::bspline
