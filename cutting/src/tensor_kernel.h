// Private: the tensor-product sum at the heart of every B-spline volume evaluation,
//   F = sum_k Nw[k] sum_j Nv[j] sum_i Nu[i] P[first + i + n_u * (j + n_v * k)],
// shared by BSplineVolume::evaluate and VolumeBinding so that both do the same arithmetic in the same
// order (bit-identical results). Control points are read as interleaved x, y, z doubles: a row of o_u
// consecutive control points is 3 * o_u contiguous doubles, which the compiler vectorises when o_u is a
// compile-time constant. Cost: o_u * o_v * o_w multiply-adds of 3-vectors. noexcept, no allocation.
#pragma once

#include <array>
#include <cmath>

#include <Eigen/Core>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define INCISE_TENSOR_AVX2 1
#endif

#include "incise/cutting/knot_vector.h"

namespace incise::cutting::detail {

// a * b + c: one fused instruction where the CPU has one, else a multiply and an add (std::fma without
// hardware support is a slow library call). Either way the same in every caller of one build.
[[gnu::always_inline]] inline double madd(double a, double b, double c) noexcept {
#if defined(FP_FAST_FMA) || defined(__FP_FAST_FMA)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "control points must be packed xyz");

// Ov, Ow: compile-time orders along v and w, or 0 to read o_v, o_w at run time.
template <int Ou, int Ov = 0, int Ow = 0>
[[gnu::always_inline]] inline Eigen::Vector3d tensorSumFixed(const double* xyz, int n_u, int n_v, int first,
                                                             int o_v_runtime, int o_w_runtime, const double* Nu,
                                                             const double* Nv, const double* Nw) noexcept {
  const int o_v = Ov > 0 ? Ov : o_v_runtime;
  const int o_w = Ow > 0 ? Ow : o_w_runtime;
  // Weighted sum of whole rows first (3 * Ou lanes), then one reduction by Nu.
  // Rows of Ou control points are 3 * Ou contiguous doubles. Explicit fused multiply-adds: the build
  // forbids the compiler from fusing on its own (-ffp-contract=off, so that every path gives the same
  // bits); madd is one vfmadd where the CPU has FMA.
  constexpr int kLanes = 3 * Ou;
  double acc[kLanes] = {};
  if constexpr (Ow > 0) {
    // One accumulator per w-plane: Ow independent chains of multiply-adds, so their latency overlaps.
    double plane_acc[Ow][kLanes] = {};
    for (int k = 0; k < Ow; ++k) {
      const double* plane = xyz + 3 * (first + n_u * n_v * k);
      for (int j = 0; j < o_v; ++j) {
        const double weight = Nw[k] * Nv[j];
        const double* row = plane + 3 * n_u * j;
        for (int m = 0; m < kLanes; ++m) plane_acc[k][m] = madd(weight, row[m], plane_acc[k][m]);
      }
    }
    for (int k = 0; k < Ow; ++k)
      for (int m = 0; m < kLanes; ++m) acc[m] += plane_acc[k][m];
  } else {
    for (int k = 0; k < o_w; ++k) {
      const double* plane = xyz + 3 * (first + n_u * n_v * k);
      for (int j = 0; j < o_v; ++j) {
        const double weight = Nw[k] * Nv[j];
        const double* row = plane + 3 * n_u * j;
        for (int m = 0; m < kLanes; ++m) acc[m] = madd(weight, row[m], acc[m]);
      }
    }
  }
  Eigen::Vector3d out(0.0, 0.0, 0.0);
  for (int i = 0; i < Ou; ++i)
    for (int c = 0; c < 3; ++c) out[c] = madd(Nu[i], acc[3 * i + c], out[c]);
  return out;
}

#if INCISE_TENSOR_AVX2
// Order 4 on every axis with AVX2: a row of 4 control points is 12 doubles, three 256-bit lanes; one set
// of lanes per w-plane keeps 4 independent multiply-add chains. Explicit FMAs (the build forbids the
// compiler from fusing on its own), so the result is the same bits wherever this is inlined.
template <>
[[gnu::always_inline]] inline Eigen::Vector3d tensorSumFixed<4, 4, 4>(const double* xyz, int n_u, int n_v, int first,
                                                                      int, int, const double* Nu, const double* Nv,
                                                                      const double* Nw) noexcept {
  __m256d lanes[4][3];
  for (int k = 0; k < 4; ++k) {
    const double* plane = xyz + 3 * (first + n_u * n_v * k);
    lanes[k][0] = lanes[k][1] = lanes[k][2] = _mm256_setzero_pd();
    for (int j = 0; j < 4; ++j) {
      const __m256d weight = _mm256_set1_pd(Nw[k] * Nv[j]);
      const double* row = plane + 3 * n_u * j;
      lanes[k][0] = _mm256_fmadd_pd(weight, _mm256_loadu_pd(row), lanes[k][0]);
      lanes[k][1] = _mm256_fmadd_pd(weight, _mm256_loadu_pd(row + 4), lanes[k][1]);
      lanes[k][2] = _mm256_fmadd_pd(weight, _mm256_loadu_pd(row + 8), lanes[k][2]);
    }
  }
  double acc[12];
  for (int l = 0; l < 3; ++l) {
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(lanes[0][l], lanes[1][l]), _mm256_add_pd(lanes[2][l], lanes[3][l]));
    _mm256_storeu_pd(acc + 4 * l, sum);
  }
  Eigen::Vector3d out(0.0, 0.0, 0.0);
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) out[c] = madd(Nu[i], acc[3 * i + c], out[c]);
  return out;
}
#endif

inline Eigen::Vector3d tensorSumAny(const double* xyz, int n_u, int n_v, int first, int o_u, int o_v, int o_w,
                                    const double* Nu, const double* Nv, const double* Nw) noexcept {
  double acc[3 * kMaxOrder] = {};
  for (int k = 0; k < o_w; ++k) {
    for (int j = 0; j < o_v; ++j) {
      const double weight = Nw[k] * Nv[j];
      const double* row = xyz + 3 * (first + n_u * (j + n_v * k));
      for (int m = 0; m < 3 * o_u; ++m) acc[m] += weight * row[m];
    }
  }
  Eigen::Vector3d out(0.0, 0.0, 0.0);
  for (int i = 0; i < o_u; ++i) {
    out[0] += Nu[i] * acc[3 * i];
    out[1] += Nu[i] * acc[3 * i + 1];
    out[2] += Nu[i] * acc[3 * i + 2];
  }
  return out;
}

// One kernel for every caller: Ou > 0 fixes the row length, Ovw > 0 fixes o_v = o_w as well, Ou = 0 is
// the any-order fallback. `first` is the linear index of the support's corner control
// (span_u - p_u, span_v - p_v, span_w - p_w).
template <int Ou, int Ovw>
[[gnu::always_inline]] inline Eigen::Vector3d tensorKernel(const double* xyz, int n_u, int n_v, int first,
                                                           const std::array<int, 3>& orders, const double* Nu,
                                                           const double* Nv, const double* Nw) noexcept {
  if constexpr (Ou == 0) {
    return tensorSumAny(xyz, n_u, n_v, first, orders[0], orders[1], orders[2], Nu, Nv, Nw);
  } else {
    return tensorSumFixed<Ou, Ovw, Ovw>(xyz, n_u, n_v, first, orders[1], orders[2], Nu, Nv, Nw);
  }
}

// Calls body.template operator()<Ou, Ovw>() with the kernel parameters that suit `orders`. Every
// evaluation path goes through this choice, so the same point gives the same bits whichever path
// computed it.
template <typename Body>
[[gnu::always_inline]] inline decltype(auto) withKernel(const std::array<int, 3>& orders, Body&& body) {
  if (orders[0] == orders[1] && orders[1] == orders[2]) {  // the common case: fully unrolled
    switch (orders[0]) {
      case 2:
        return body.template operator()<2, 2>();
      case 3:
        return body.template operator()<3, 3>();
      case 4:
        return body.template operator()<4, 4>();
      default:
        break;
    }
  }
  switch (orders[0]) {
    case 2:
      return body.template operator()<2, 0>();
    case 3:
      return body.template operator()<3, 0>();
    case 4:
      return body.template operator()<4, 0>();
    case 5:
      return body.template operator()<5, 0>();
    case 6:
      return body.template operator()<6, 0>();
    default:
      return body.template operator()<0, 0>();
  }
}

inline Eigen::Vector3d tensorSum(const double* xyz, int n_u, int n_v, int first, const std::array<int, 3>& orders,
                                 const double* Nu, const double* Nv, const double* Nw) noexcept {
  return withKernel(orders,
                    [&]<int Ou, int Ovw>() { return tensorKernel<Ou, Ovw>(xyz, n_u, n_v, first, orders, Nu, Nv, Nw); });
}

}  // namespace incise::cutting::detail
