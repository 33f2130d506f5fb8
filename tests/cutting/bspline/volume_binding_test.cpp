#include "incise/bspline/volume_binding.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>

#include "test_volumes.h"

using namespace incise;
using namespace incise::bspline;
using Catch::Matchers::Contains;
using incise::bspline::testing::randomParameter;
using incise::bspline::testing::randomVolume;

namespace {

std::vector<Eigen::Vector3d> randomParameters(std::mt19937_64& rng, const BSplineVolume& volume, int count) {
  std::vector<Eigen::Vector3d> params(static_cast<size_t>(count));
  for (auto& t : params) t = randomParameter(rng, volume);
  return params;
}

}  // namespace

// Every kernel VolumeBinding may choose on this machine (AVX-512 where the CPU has it, AVX2, generic)
// against the per-call evaluator.
TEST_CASE("volume_binding: re-deforming bound points is bit-identical to evaluating them", "[cutting]") {
  const bool prefer_avx2 = GENERATE(false, true);
  preferAvx2BoundKernel(prefer_avx2);
  INFO("kernel " << boundKernelName() << (prefer_avx2 ? " (AVX2 preferred)" : ""));
  std::mt19937_64 rng(11);
  for (const std::array<int, 3> orders :
       {std::array{4, 4, 4}, std::array{2, 3, 4}, std::array{3, 3, 3}, std::array{7, 2, 5}}) {
    BSplineVolume volume = randomVolume(rng, orders, {9, 8, 7});
    auto params = randomParameters(rng, volume, 2000);
    params[0] = Eigen::Vector3d(1.0, 1.0, 1.0);  // the domain's upper corner
    params[1] = Eigen::Vector3d(0.0, 0.0, 0.0);
    VolumeBinding binding(volume, params);
    REQUIRE(binding.size() == params.size());
    // Move every control point: the binding must follow the current controls, not the ones at binding time.
    for (int k = 0; k < 7; ++k)
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 9; ++i)
          volume.setControl(i, j, k, volume.control(i, j, k) * 1.5 + Eigen::Vector3d(0.1, 0, 0));
    std::vector<Eigen::Vector3d> out(params.size());
    REQUIRE(binding.deformAll(volume, out));
    for (size_t p = 0; p < params.size(); ++p) REQUIRE(out[p] == volume.evaluate(params[p]));
    // One point per cell, and cells of one point between cells of many: the AVX-512 loop's first and last
    // points and its overlap of neighbouring points.
    std::vector<Eigen::Vector3d> few = {params[0], params[1], params[2], params[2], params[3]};
    VolumeBinding few_binding(volume, few);
    std::vector<Eigen::Vector3d> few_out(few.size());
    REQUIRE(few_binding.deformAll(volume, few_out));
    for (size_t p = 0; p < few.size(); ++p) REQUIRE(few_out[p] == volume.evaluate(few[p]));
  }
  preferAvx2BoundKernel(false);
}

TEST_CASE("volume_binding: only points whose support holds a moved control are re-deformed", "[cutting]") {
  std::mt19937_64 rng(12);
  BSplineVolume volume = BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
                                                 {4, 4, 4}, {10, 10, 10});
  const auto params = randomParameters(rng, volume, 5000);
  VolumeBinding binding(volume, params);
  std::vector<Eigen::Vector3d> out(params.size());
  REQUIRE(binding.deformAll(volume, out));
  const std::vector<Eigen::Vector3d> before = out;

  const std::vector<int> moved{volume.controlIndex(4, 5, 6), volume.controlIndex(5, 5, 6),
                               volume.controlIndex(0, 9, 0)};
  for (int c : moved) {
    const int i = c % 10, j = (c / 10) % 10, k = c / 100;
    volume.setControl(i, j, k, volume.control(i, j, k) + Eigen::Vector3d(0.01, -0.02, 0.03));
  }
  const int written = binding.deformAffected(volume, moved, out);
  std::vector<int> affected;
  binding.affectedPoints(moved, affected);
  REQUIRE(written == static_cast<int>(affected.size()));
  const std::set<int> affected_set(affected.begin(), affected.end());
  REQUIRE(affected_set.size() == affected.size());  // each point once

  int moved_points = 0;
  for (size_t p = 0; p < params.size(); ++p) {
    const Eigen::Vector3d exact = volume.evaluate(params[p]);
    // Every point agrees with a full evaluation: the affected ones were rewritten, the others never moved.
    REQUIRE(out[p] == exact);
    if (exact != before[p]) {
      ++moved_points;
      REQUIRE(affected_set.count(static_cast<int>(p)) == 1);
    }
  }
  REQUIRE(moved_points > 0);
  // Affected is local: far fewer points than the whole set (3 controls of 1000, support 4^3 cells of 7^3).
  REQUIRE(written < static_cast<int>(params.size()) / 4);
}

TEST_CASE("volume_binding: a volume whose knots changed is refused until re-bound", "[cutting]") {
  std::mt19937_64 rng(13);
  BSplineVolume volume = randomVolume(rng, {3, 3, 3}, {6, 6, 6});
  const auto params = randomParameters(rng, volume, 100);
  VolumeBinding binding(volume, params);
  std::vector<Eigen::Vector3d> out(params.size(), Eigen::Vector3d::Constant(7.0));
  volume.insertKnot(2, 0.5, 3);
  REQUIRE_FALSE(binding.matches(volume));
  REQUIRE_FALSE(binding.deformAll(volume, out));
  const int control = 0;
  REQUIRE(binding.deformAffected(volume, std::span<const int>(&control, 1), out) == -1);
  for (const auto& p : out) REQUIRE(p == Eigen::Vector3d::Constant(7.0));  // nothing written

  VolumeBinding rebound(volume, params);
  REQUIRE(rebound.deformAll(volume, out));
  for (size_t p = 0; p < params.size(); ++p) REQUIRE(out[p] == volume.evaluate(params[p]));

  std::vector<Eigen::Vector3d> wrong_size(params.size() - 1);
  REQUIRE_FALSE(rebound.deformAll(volume, wrong_size));
  const int bad_control = 6 * 6 * 9;
  REQUIRE(rebound.deformAffected(volume, std::span<const int>(&bad_control, 1), out) == -1);
}

TEST_CASE("volume_binding: NaN or out-of-domain parameters are refused with their index", "[cutting]") {
  std::mt19937_64 rng(14);
  const BSplineVolume volume = randomVolume(rng, {3, 3, 3}, {5, 5, 5});
  std::vector<Eigen::Vector3d> params(10, Eigen::Vector3d::Constant(0.5));
  params[7] = Eigen::Vector3d(0.5, NAN, 0.5);
  REQUIRE_THROWS_WITH(VolumeBinding(volume, params), Contains("point 7") && Contains("nan"));
  params[7] = Eigen::Vector3d(0.5, 0.5, 1.5);
  REQUIRE_THROWS_WITH(VolumeBinding(volume, params), Contains("point 7") && Contains("1.5"));
}
