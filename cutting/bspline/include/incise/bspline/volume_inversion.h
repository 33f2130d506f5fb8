// Point inversion of a B-spline volume: the parameters x = (u, v, w) with F(x) = p, found by damped Newton
// iteration. Used to embed a point of the deformed (world) space back into the DFFD's parameter domain, the
// inverse of the mapping of Eq. (1) (Schein & Elber, "Discontinuous Free Form Deformations", §3.1).
//
// Shapes: p, start and uvw are 3-vectors; uvw lies in volume.parameterBox().
// Units: p and the tolerance in the caller's length unit (metres in incise), uvw in parameter units.
// C^-1 knots: F is evaluated on the right-hand (+) side at a knot of full multiplicity, as in
// BSplineVolume::evaluate; each side of such a cut inverts to its own side of the knot, and a point that
// falls in the gap opened between the two discontinuity planes F^- and F^+ (Definition 2) is reported as
// not converged.
// Threads: pure functions of const arguments, safe from any number of threads at once.
// Failure: never throws for a point the map cannot reach (converged = false, best x found); throws
// std::invalid_argument only for a non-finite p or start, naming the value.
#pragma once

#include <Eigen/Core>

#include "incise/bspline/bspline_volume.h"

namespace incise::bspline {

struct InversionOptions {
  int max_iterations = 30;   // Newton steps, each with at most max_halvings step halvings
  double tolerance = 1e-10;  // on |F(x) - p|, in the caller's length unit; keep it above the rounding of p
  int max_halvings = 30;     // a step halved this often without lowering the residual ends the search
};

struct InversionResult {
  Eigen::Vector3d uvw;  // the best parameters found (smallest residual), inside the parameter box
  bool converged;       // residual <= options.tolerance
  int iterations;       // Newton steps taken
  double residual;      // |F(uvw) - p|
};

// A starting guess: the Greville parameters (grevilleAbscissa per axis) of the control point nearest to p.
// The last control before a C^-1 knot has its Greville abscissa on that knot, where F takes the + side; its
// parameter is moved one ulp to the left so the start lies on the control's own (-) side.
// Cost O(#controls) (a linear scan). No allocation. Throws std::invalid_argument for a non-finite p.
Eigen::Vector3d inversionStart(const BSplineVolume& volume, const Eigen::Vector3d& p);

// Damped Newton on F(x) = p from `start` (clamped into the parameter box): dx = J^-1 (p - F(x)) by a
// partial-pivot LU solve (a singular J gives a non-finite step: stop); the step is halved until the residual decreases
// (at most 30 times) and x is clamped to the parameter box after every step. Stops when the residual is
// <= options.tolerance, after options.max_iterations steps, or when no halving decreases the residual
// (a point outside F's range, or in the gap of an opened cut).
// Cost O(max_iterations * (1 + halvings) * o^3); no allocation.
InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p, const Eigen::Vector3d& start,
                            const InversionOptions& options = {});

// As above, searching only `search_box` (intersected with the parameter box): the result then depends only
// on F inside it, e.g. on the final columns of a lattice that is still growing. Throws std::invalid_argument
// also for a search box that misses the domain.
InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p, const Eigen::Vector3d& start,
                            const Eigen::AlignedBox3d& search_box, const InversionOptions& options = {});

// As above from inversionStart(volume, p): adds O(#controls) for the start.
InversionResult invertPoint(const BSplineVolume& volume, const Eigen::Vector3d& p,
                            const InversionOptions& options = {});

}  // namespace incise::bspline
