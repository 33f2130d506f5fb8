// Re-deformation throughput of a B-spline volume, one thread (§4).
// 32,768 bound parameter points, order 4, lattices 8^3 and 20^3 with perturbed control points.
// Measures, in the same run: the bound path (VolumeBinding::deformAll: stored spans and basis, an o^3
// weighted sum per point) and a per-call evaluator (BSplineVolume::evaluateUnchecked: span search and
// basis at every call, as IRIT's TrivTVEval does). Reports the median of repeated passes.
// Target for the bound path: >= 1e8 vertices/s on one core. Where the CPU has
// AVX-512 the bound path is also timed with the AVX2 kernel forced, for comparison (same bits).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "incise/bspline/bspline_volume.h"
#include "incise/bspline/volume_binding.h"
#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"

namespace {

using incise::bspline::BSplineVolume;
using incise::bspline::VolumeBinding;
using Clock = std::chrono::steady_clock;

constexpr int kPoints = 32768;
constexpr int kOrder = 4;
constexpr double kTargetVerticesPerS = 1e8;

BSplineVolume perturbedLattice(int count, std::mt19937_64& rng) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  BSplineVolume volume = BSplineVolume::identity(box, {kOrder, kOrder, kOrder}, {count, count, count});
  std::uniform_real_distribution<double> jitter(-0.2 / count, 0.2 / count);
  for (int k = 0; k < count; ++k)
    for (int j = 0; j < count; ++j)
      for (int i = 0; i < count; ++i)
        volume.setControl(i, j, k, volume.control(i, j, k) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  return volume;
}

// Median seconds of `passes` runs of `pass`.
template <typename Pass>
double medianSeconds(int passes, Pass&& pass) {
  std::vector<double> seconds;
  for (int r = 0; r < passes; ++r) {
    const auto start = Clock::now();
    pass();
    seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::nth_element(seconds.begin(), seconds.begin() + passes / 2, seconds.end());
  return seconds[static_cast<size_t>(passes / 2)];
}

nlohmann::json runLattice(int count, std::mt19937_64& rng) {
  const BSplineVolume volume = perturbedLattice(count, rng);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> params(kPoints);
  for (auto& p : params) p = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  VolumeBinding binding(volume, params);
  std::vector<Eigen::Vector3d> bound(kPoints), per_call(kPoints);

  const int passes = 201;
  const double bound_s = medianSeconds(passes, [&] { binding.deformAll(volume, bound); });
  incise::bspline::preferAvx2BoundKernel(true);
  std::vector<Eigen::Vector3d> bound_avx2(kPoints);
  const double bound_avx2_s = medianSeconds(passes, [&] { binding.deformAll(volume, bound_avx2); });
  incise::bspline::preferAvx2BoundKernel(false);
  const double per_call_s = medianSeconds(passes, [&] {
    for (int p = 0; p < kPoints; ++p) per_call[p] = volume.evaluateUnchecked(params[p][0], params[p][1], params[p][2]);
  });
  double max_difference = 0.0;
  for (int p = 0; p < kPoints; ++p) max_difference = std::max(max_difference, (bound[p] - per_call[p]).norm());
  const bool kernels_agree = std::equal(bound.begin(), bound.end(), bound_avx2.begin());

  const double bound_rate = kPoints / bound_s;
  const double per_call_rate = kPoints / per_call_s;
  return {
      {"lattice", std::to_string(count) + "^3"},
      {"order", kOrder},
      {"points", kPoints},
      {"passes", passes},
      {"bound_kernel", incise::bspline::boundKernelName()},
      {"bound_vertices_per_s", bound_rate},
      {"bound_avx2_kernel_vertices_per_s", kPoints / bound_avx2_s},
      {"bound_kernels_bit_identical", kernels_agree},
      {"per_call_vertices_per_s", per_call_rate},
      {"ratio_bound_over_per_call", bound_rate / per_call_rate},
      {"max_difference_bound_vs_per_call", max_difference},
      {"target_vertices_per_s", kTargetVerticesPerS},
      {"meets_target", bound_rate >= kTargetVerticesPerS},
  };
}

}  // namespace

int main() {
  std::mt19937_64 rng(20261125);
  nlohmann::json report = {
      {"benchmark", "volume_redeform"},
      {"threads", 1},
      {"machine", incise::measure::machineInfo()},
      {"results", nlohmann::json::array()},
  };
  for (int count : {8, 20}) report["results"].push_back(runLattice(count, rng));
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
