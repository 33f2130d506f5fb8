#include "incise/bspline/volume_inversion.h"

#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "incise/bspline/knot_vector.h"

namespace incise::bspline {

namespace {

void checkFinite(const Eigen::Vector3d& x, const char* who, const char* what) {
  if (!x.allFinite())
    throw std::invalid_argument(std::string(who) + ": " + what + " " + core::formatPoint(x) + " is not finite");
}

// Greville parameter of control i along one axis, kept on the control's own side of a C^-1 knot.
double startParameter(std::span<const double> knots, int order, int count, int i) {
  // The mean of knots[i+1 .. i+o-1] may round just outside them (3 * 0.4 / 3 != 0.4); keep it inside.
  const double g = std::clamp(grevilleAbscissa(knots, order, i), knots[static_cast<size_t>(i + 1)],
                              knots[static_cast<size_t>(i + order - 1)]);
  const size_t last = static_cast<size_t>(i + order);
  // knots[i+1] == knots[i+o]: a full-multiplicity knot ends this control's support at g, where F already
  // takes the + side; one ulp to the left is on the - side. Not at the upper domain end (no + side there).
  if (knots[static_cast<size_t>(i + 1)] == knots[last] && g < knots[static_cast<size_t>(count)])
    return std::nextafter(g, -std::numeric_limits<double>::infinity());
  return g;
}

Eigen::Vector3d clampTo(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& x) {
  return x.cwiseMax(box.min()).cwiseMin(box.max());
}

}  // namespace

Eigen::Vector3d inversionStart(const BSplineVolume& volume, const Eigen::Vector3d& p) {
  checkFinite(p, "inversionStart", "point p =");
  const auto controls = volume.controls();
  size_t nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t index = 0; index < controls.size(); ++index) {
    const double d = (controls[index] - p).squaredNorm();
    if (d < best) {  // strict: ties keep the lower index, the - side of coincident cut planes
      best = d;
      nearest = index;
    }
  }
  const auto counts = volume.controlCounts();
  const auto orders = volume.orders();
  const size_t nu = static_cast<size_t>(counts[0]);
  const size_t nv = static_cast<size_t>(counts[1]);
  const int ijk[3] = {static_cast<int>(nearest % nu), static_cast<int>((nearest / nu) % nv),
                      static_cast<int>(nearest / (nu * nv))};
  Eigen::Vector3d start;
  for (int a = 0; a < 3; ++a) start[a] = startParameter(volume.knots(a), orders[a], counts[a], ijk[a]);
  return start;
}

InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p, const Eigen::Vector3d& start,
                            const InversionOptions& options) {
  return invertPoint(volume, p, start, volume.parameterBox(), options);
}

InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p, const Eigen::Vector3d& start,
                            const Eigen::AlignedBox3d& search_box, const InversionOptions& options) {
  checkFinite(p, "invertPoint", "point p =");
  checkFinite(start, "invertPoint", "start =");
  const Eigen::AlignedBox3d box = search_box.intersection(volume.parameterBox());
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    throw std::invalid_argument("invertPoint: the search box does not meet the parameter domain");
  Eigen::Vector3d x = clampTo(box, start);
  Eigen::Vector3d r = p - volume.evaluateUnchecked(x[0], x[1], x[2]);
  double residual = r.norm();
  int iterations = 0;
  while (residual > options.tolerance && iterations < options.max_iterations) {
    // x is finite and inside the box, so jacobian() cannot throw.
    const Eigen::Matrix3d jac = volume.jacobian(x);
    // A 3x3 partial-pivot LU costs a third of a pivoting QR; a singular J gives a non-finite step (stop).
    const Eigen::Vector3d dx = jac.partialPivLu().solve(r);
    if (!dx.allFinite()) break;
    ++iterations;
    // Backtracking: a full step may jump over a C^-1 cut or out of the region where F is near-linear.
    bool improved = false;
    double scale = 1.0;
    for (int h = 0; h <= options.max_halvings && !improved; ++h, scale *= 0.5) {
      const Eigen::Vector3d trial = clampTo(box, x + scale * dx);
      const Eigen::Vector3d trial_r = p - volume.evaluateUnchecked(trial[0], trial[1], trial[2]);
      const double trial_residual = trial_r.norm();
      if (trial_residual < residual) {
        x = trial;
        r = trial_r;
        residual = trial_residual;
        improved = true;
      }
    }
    // No step along the Newton direction helps: a local minimum of |F - p| (outside the range, at the box
    // boundary or in a cut's gap). x is the best point found.
    if (!improved) break;
  }
  return InversionResult{x, residual <= options.tolerance, iterations, residual};
}

InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p, const InversionOptions& options) {
  return invertPoint(volume, p, inversionStart(volume, p), options);
}

}  // namespace incise::bspline
