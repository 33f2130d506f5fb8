// Uses the public API exactly as an outside project would: exits 0 only if an o-fold insertion and
// a moved + plane give the expected discontinuity.
#include <incise/bspline/bspline_volume.h>

#include <cstdio>

int main() {
  using incise::bspline::BSplineVolume;
  BSplineVolume volume = BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
                                                 {4, 4, 4}, {6, 6, 6});
  volume.insertKnot(0, 0.5, 4);
  const auto counts = volume.controlCounts();
  // Open the cut: shift the + side's first control plane (index 5 after the insertion: knots 0,0,0,0,1/3,.5,.5,.5,.5,...) by +0.1 in x.
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      volume.setControl(5, j, k, volume.control(5, j, k) + Eigen::Vector3d(0.1, 0, 0));
  const double left = volume.evaluate(0.5 - 1e-12, 0.5, 0.5).x();
  const double right = volume.evaluate(0.5, 0.5, 0.5).x();
  std::printf("consumer: F(0.5-) = %.12f, F(0.5+) = %.12f\n", left, right);
  return (right - left > 0.099 && right - left < 0.101) ? 0 : 1;
}
