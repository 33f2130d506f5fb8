// Private: four doubles in one register where the build has AVX, in an array where it has not: the same
// operations in the same order either way (no fused multiply-add; the targets build with -ffp-contract=off), so
// an AVX build and a portable one give the same bits. Threads: values. Cost: one instruction each with AVX.
#pragma once

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace incise::physics::detail {

#if defined(__AVX__)
struct Lanes {
  __m256d v;
  static Lanes zero() noexcept { return {_mm256_setzero_pd()}; }
  static Lanes load(const double* p) noexcept { return {_mm256_load_pd(p)}; }  // 32-byte aligned
  static Lanes load3(const double* p) noexcept {                               // p[0..2], lane 3 zero
    return {_mm256_maskload_pd(p, _mm256_set_epi64x(0, -1, -1, -1))};
  }
  static Lanes broadcast(double x) noexcept { return {_mm256_set1_pd(x)}; }
  void store(double* p) const noexcept { _mm256_store_pd(p, v); }
  Lanes operator+(Lanes o) const noexcept { return {_mm256_add_pd(v, o.v)}; }
  Lanes operator*(Lanes o) const noexcept { return {_mm256_mul_pd(v, o.v)}; }
  double sum3() const noexcept {  // (l0 + l1) + l2
    alignas(32) double out[4];
    _mm256_store_pd(out, v);
    return (out[0] + out[1]) + out[2];
  }
};
#else
struct Lanes {
  double v[4];
  static Lanes zero() noexcept { return {{0.0, 0.0, 0.0, 0.0}}; }
  static Lanes load(const double* p) noexcept { return {{p[0], p[1], p[2], p[3]}}; }
  static Lanes load3(const double* p) noexcept { return {{p[0], p[1], p[2], 0.0}}; }
  static Lanes broadcast(double x) noexcept { return {{x, x, x, x}}; }
  void store(double* p) const noexcept { p[0] = v[0], p[1] = v[1], p[2] = v[2], p[3] = v[3]; }
  Lanes operator+(Lanes o) const noexcept { return {{v[0] + o.v[0], v[1] + o.v[1], v[2] + o.v[2], v[3] + o.v[3]}}; }
  Lanes operator*(Lanes o) const noexcept { return {{v[0] * o.v[0], v[1] * o.v[1], v[2] * o.v[2], v[3] * o.v[3]}}; }
  double sum3() const noexcept { return (v[0] + v[1]) + v[2]; }
};
#endif

}  // namespace incise::physics::detail
