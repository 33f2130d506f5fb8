// Fold-over (self-intersection) tests of a B-spline volume F: zeros of the Jacobian det J(F) =
// <dF/du x dF/dv, dF/dw> signal that moving control points folded space onto itself (Schein & Elber,
// "Discontinuous Free Form Deformations", §3.1, Theorem 1).
//
// Two tests: checkAxisOrder (Theorem 1, for a box lattice whose controls move along one axis) and
// checkJacobianPositive (sufficient, for any lattice); and minJacobianDeterminant, a sampler for tests and
// reports.
//
// Shapes: control indices (i, j, k) as in BSplineVolume; knot cells named by their span indices.
// Units: determinants in (length unit)^3 / (parameter unit)^3.
// Threads: pure functions of a const volume, safe from any number of threads at once.
// Failure: a fold is reported in FoldReport, not thrown; std::out_of_range for an axis outside 0..2,
// std::invalid_argument for samples_per_cell < 1. Validation code, not for the sim thread (allocates
// the report message).
#pragma once

#include <string>

#include "incise/bspline/bspline_volume.h"

namespace incise::bspline {

struct FoldReport {
  bool ok;
  int i, j, k;          // first offending control (checkAxisOrder) or knot cell (checkJacobianPositive) when
                        // !ok, in i-fastest order; -1 otherwise
  std::string message;  // what failed and where, with the values; empty when ok
};

// C^-1 knots: controls i and i+1 along an axis with knots[i+1] == knots[i+o] (o = order) straddle a knot
// of full multiplicity: after inserting o copies of u0, they are the last control of the - side and the
// first of the + side (the two discontinuity planes F^-, F^+ of Definition 2). Their basis functions never
// overlap, so no derivative of F involves their difference: both checks leave their order free (the two
// sides of a cut may open apart or pass each other).
//
// Theorem 1: along every row of controls in direction `axis` (0 = u, 1 = v, 2 = w), the `axis` component
// strictly increases, P_{i+1,j,k}[axis] > P_{i,j,k}[axis] for axis 0, except across a C^-1 knot (above).
// On failure (i, j, k) is the lower control of the first offending pair. Cost O(#controls).
FoldReport checkAxisOrder(const BSplineVolume& volume, int axis = 0);

// Sufficient test for det J > 0 on the whole domain. In a non-empty knot cell (spans su, sv, sw), dF/du is
// a non-negative combination (not all zero) of the u-differences P_{i+1,j,k} - P_{i,j,k} of the cell's
// support (the o_u x o_v x o_w block starting at (su - p_u, sv - p_v, sw - p_w)), with positive factors
// (o_u - 1) / (t_{i+o_u} - t_{i+1}); likewise dF/dv and dF/dw. det is trilinear, so det(a, b, c) > 0 for
// every a, b, c from the u-, v- and w-differences gives det J > 0 in the closed cell. On failure (i, j, k)
// is the first cell's (su, sv, sw) with some det(a, b, c) <= 0. The converse does not hold: a failure
// means "not proven fold-free", not "folded"; confirm with minJacobianDeterminant.
// Cost per cell: (o_u-1) o_v o_w * o_u (o_v-1) o_w * o_u o_v (o_w-1) dot products (110592 for order 4,
// ~o^9), so O(#cells * o^9); early exit at the first failure. Allocates O(o^3) scratch once per call.
FoldReport checkJacobianPositive(const BSplineVolume& volume);

// Minimum of det J over a samples_per_cell^3 grid in every non-empty knot cell: the cell's corners, faces and
// interior for samples_per_cell >= 2 (at a cell face, the one-sided value from inside the cell), the cell
// centre for 1. Cost O(#cells * samples_per_cell^3 * o^3).
double minJacobianDeterminant(const BSplineVolume& volume, int samples_per_cell);

}  // namespace incise::bspline
