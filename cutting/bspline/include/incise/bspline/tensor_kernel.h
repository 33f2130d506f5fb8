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

#include "incise/bspline/knot_vector.h"

namespace incise::bspline::detail {

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
// The order-4 kernels below do the operations of tensorSumFixed<4, 4, 4>, in its order, so they give its
// bits; only the grouping into vector instructions differs. Their loops are unrolled by hand-placed
// pragmas: left to itself, GCC 12 at -O2 unrolls them in some callers and not in others (2x slower).

// The weights Nw[k] * Nv[j] of plane k (j = 0..3), each broadcast to 4 lanes: one vector product.
[[gnu::always_inline]] inline void planeWeights4(const double* Nv, const double* Nw, int k, __m256d w[4]) noexcept {
  const __m256d products = _mm256_mul_pd(_mm256_broadcast_sd(Nw + k), _mm256_loadu_pd(Nv));
  w[0] = _mm256_permute4x64_pd(products, 0x00);
  w[1] = _mm256_permute4x64_pd(products, 0x55);
  w[2] = _mm256_permute4x64_pd(products, 0xAA);
  w[3] = _mm256_permute4x64_pd(products, 0xFF);
}

// sum_i Nu[i] * (acc[3i], acc[3i + 1], acc[3i + 2]) in the order i = 0..3, as tensorSumFixed's final
// loop, on x, y and z at once: the 12 lanes of acc (acc[0..3], acc[4..7], acc[8..11] in the three
// vectors) are regrouped into four (x, y, z, -) slices, one per control point i.
[[gnu::always_inline]] inline __m256d reduceNu4(const __m256d acc[3], const double* Nu) noexcept {
  const __m256d slice1 = _mm256_permute4x64_pd(_mm256_blend_pd(acc[0], acc[1], 0b0011), 0b00'01'00'11);
  const __m256d slice2 = _mm256_permute4x64_pd(_mm256_blend_pd(acc[1], acc[2], 0b0001), 0b00'00'11'10);
  const __m256d slice3 = _mm256_permute4x64_pd(acc[2], 0b00'11'10'01);
  __m256d out = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu), acc[0], _mm256_setzero_pd());
  out = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 1), slice1, out);
  out = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 2), slice2, out);
  return _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 3), slice3, out);
}

[[gnu::always_inline]] inline Eigen::Vector3d lowXyz(__m256d v) noexcept {
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, v);
  return Eigen::Vector3d(lanes[0], lanes[1], lanes[2]);
}

// Order 4 on every axis with AVX2: a row of 4 control points is 12 doubles, three 256-bit lanes; one set
// of lanes per w-plane keeps 4 independent multiply-add chains. Per point: 52 vector multiply-adds,
// 4 products, 9 adds, 21 shuffles. Explicit FMAs (the build forbids the compiler from fusing on its own).
template <>
[[gnu::always_inline]] inline Eigen::Vector3d tensorSumFixed<4, 4, 4>(const double* xyz, int n_u, int n_v, int first,
                                                                      int, int, const double* Nu, const double* Nv,
                                                                      const double* Nw) noexcept {
  __m256d lanes[4][3];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    const double* plane = xyz + 3 * (first + n_u * n_v * k);
    __m256d w[4];
    planeWeights4(Nv, Nw, k, w);
    lanes[k][0] = lanes[k][1] = lanes[k][2] = _mm256_setzero_pd();
#pragma GCC unroll 4
    for (int j = 0; j < 4; ++j) {
      const double* row = plane + 3 * n_u * j;
      lanes[k][0] = _mm256_fmadd_pd(w[j], _mm256_loadu_pd(row), lanes[k][0]);
      lanes[k][1] = _mm256_fmadd_pd(w[j], _mm256_loadu_pd(row + 4), lanes[k][1]);
      lanes[k][2] = _mm256_fmadd_pd(w[j], _mm256_loadu_pd(row + 8), lanes[k][2]);
    }
  }
  __m256d acc[3];
#pragma GCC unroll 3
  for (int l = 0; l < 3; ++l)
    acc[l] = _mm256_add_pd(_mm256_add_pd(lanes[0][l], lanes[1][l]), _mm256_add_pd(lanes[2][l], lanes[3][l]));
  return lowXyz(reduceNu4(acc, Nu));
}

// basisFunctions (knot_vector.cpp, The NURBS Book A2.2) for order 4 on three axes at once, one axis a
// lane: each lane does that function's operations in its order (no fused multiply-add there either), so
// the same bits as three calls, with 6 vector divisions instead of 18 scalar ones. The fourth lane
// computes a harmless dummy (t = 0.5 between knots 0 and 1). out[a][0..3]: axis a's basis values.
[[gnu::always_inline]] inline void basisFunctions4x3(const double* const knots[3], const int spans[3],
                                                     const double t[3], double out[3][kMaxOrder]) noexcept {
  const __m256d tv = _mm256_set_pd(0.5, t[2], t[1], t[0]);
  const auto knotAt = [&](int offset) {
    return _mm256_set_pd(offset > 0 ? 1.0 : 0.0, knots[2][spans[2] + offset], knots[1][spans[1] + offset],
                         knots[0][spans[0] + offset]);
  };
  __m256d N[4], left[4], right[4];
  N[0] = _mm256_set1_pd(1.0);
#pragma GCC unroll 3
  for (int j = 1; j < 4; ++j) {
    left[j] = _mm256_sub_pd(tv, knotAt(1 - j));
    right[j] = _mm256_sub_pd(knotAt(j), tv);
    __m256d saved = _mm256_setzero_pd();
#pragma GCC unroll 3
    for (int r = 0; r < j; ++r) {
      const __m256d temp = _mm256_div_pd(N[r], _mm256_add_pd(right[r + 1], left[j - r]));
      N[r] = _mm256_add_pd(saved, _mm256_mul_pd(right[r + 1], temp));
      saved = _mm256_mul_pd(left[j - r], temp);
    }
    N[j] = saved;
  }
  alignas(32) double lanes[4][4];
#pragma GCC unroll 4
  for (int r = 0; r < 4; ++r) _mm256_store_pd(lanes[r], N[r]);
#pragma GCC unroll 3
  for (int a = 0; a < 3; ++a)
#pragma GCC unroll 4
    for (int r = 0; r < 4; ++r) out[a][r] = lanes[r][a];
}

// AVX-512 (F and VL), for VolumeBinding on CPUs that have it (chosen at run time; the build itself stays
// at AVX2, see cmake/InciseOptions.cmake). A row's 12 doubles are one 512-bit and one 256-bit vector: 32
// multiply-adds a point instead of 48. Split in two so that a loop can overlap one point's plane sums with
// the previous point's final sum (its dependency chain is long: 4 multiply-adds in a row).
#define INCISE_TENSOR_AVX512 1
#define INCISE_AVX512_INLINE __attribute__((target("avx512f,avx512vl"), always_inline)) inline
// GCC 12's own AVX-512 intrinsics trip -Wmaybe-uninitialized (their "undefined" source operands); the
// callers of these functions wrap them in the same push / ignore / pop.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

struct WideSums {
  __m512d low;   // acc[0..7]
  __m256d high;  // acc[8..11]
};

INCISE_AVX512_INLINE WideSums planeSums444Wide(const double* xyz, int n_u, int n_v, int first, const double* Nv,
                                               const double* Nw) noexcept {
  const __m512d nv = _mm512_broadcast_f64x4(_mm256_loadu_pd(Nv));  // Nv twice
  __m512d low[4];
  __m256d high[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    const double* plane = xyz + 3 * (first + n_u * n_v * k);
    const __m512d products = _mm512_mul_pd(_mm512_set1_pd(Nw[k]), nv);
    const __m512d w[4] = {_mm512_permutex_pd(products, 0x00), _mm512_permutex_pd(products, 0x55),
                          _mm512_permutex_pd(products, 0xAA), _mm512_permutex_pd(products, 0xFF)};
    low[k] = _mm512_setzero_pd();
    high[k] = _mm256_setzero_pd();
#pragma GCC unroll 4
    for (int j = 0; j < 4; ++j) {
      const double* row = plane + 3 * n_u * j;
      low[k] = _mm512_fmadd_pd(w[j], _mm512_loadu_pd(row), low[k]);
      high[k] = _mm256_fmadd_pd(_mm512_castpd512_pd256(w[j]), _mm256_loadu_pd(row + 8), high[k]);
    }
  }
  return {_mm512_add_pd(_mm512_add_pd(low[0], low[1]), _mm512_add_pd(low[2], low[3])),
          _mm256_add_pd(_mm256_add_pd(high[0], high[1]), _mm256_add_pd(high[2], high[3]))};
}

// reduceNu4 of WideSums, written to out[0..2].
INCISE_AVX512_INLINE void reduceNu4Wide(const WideSums& sums, const double* Nu, double* out) noexcept {
  // acc[3..5], acc[6..8] (index 8 is the high vector's lane 0) in one vector's halves
  const __m512d slices12 =
      _mm512_permutex2var_pd(sums.low, _mm512_set_epi64(8, 8, 7, 6, 5, 5, 4, 3), _mm512_castpd256_pd512(sums.high));
  const __m256d slice3 = _mm256_permute4x64_pd(sums.high, 0b00'11'10'01);
  __m256d sum = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu), _mm512_castpd512_pd256(sums.low), _mm256_setzero_pd());
  sum = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 1), _mm512_castpd512_pd256(slices12), sum);
  sum = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 2), _mm512_extractf64x4_pd(slices12, 1), sum);
  sum = _mm256_fmadd_pd(_mm256_broadcast_sd(Nu + 3), slice3, sum);
  _mm_storeu_pd(out, _mm256_castpd256_pd128(sum));
  _mm_store_sd(out + 2, _mm256_extractf128_pd(sum, 1));
}

#pragma GCC diagnostic pop

// Whether this CPU runs the AVX-512 kernels (checked once, at load).
inline bool cpuHasAvx512() noexcept {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
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

}  // namespace incise::bspline::detail
