// A trivariate tensor-product B-spline volume F(u, v, w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w), the
// deformation function of the paper's Eq. (1) (Schein & Elber, "Discontinuous Free Form Deformations",
// §3.1). Inserting `order` knots at u0 gives a potential C^-1 discontinuity: two coincident control
// planes that can then be moved apart (Definition 2).
//
// Shapes: orders o_a >= 2 per axis a in {0 = u, 1 = v, 2 = w}; n_a control points per axis; knots per axis
// of size n_a + o_a; control points stored i-fastest, index = i + n_u * (j + n_v * k).
// Units: parameters and positions in whatever unit the caller uses (the identity lattice makes them
// the same, metres in incise).
// Threads: const members may be called from any number of threads at once; mutators need exclusive
// access. Failure: constructors and mutators throw std::invalid_argument (bad values, with the value in
// the message) or std::out_of_range (bad indices) and leave the object as it was.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace incise::bspline {

class BSplineVolume {
 public:
  // orders (>= 2, <= kMaxOrder) per axis; knots per axis, non-decreasing, size = count + order;
  // control points in i-fastest order: index = i + n_u * (j + n_v * k). Counts are deduced from the
  // knot vectors; `controls` must hold their product. Cost O(#controls).
  BSplineVolume(std::array<int, 3> orders, std::array<std::vector<double>, 3> knots,
                std::vector<Eigen::Vector3d> controls);

  // Clamped uniform knots over the box (the parameter domain is the box itself), control points at the
  // Greville abscissae: F is the identity on the box. Throws for an empty or non-finite box, orders
  // outside [2, kMaxOrder] or counts < order.
  static BSplineVolume identity(const Eigen::AlignedBox3d& box, std::array<int, 3> orders, std::array<int, 3> counts);

  // F(u, v, w). At a knot of full multiplicity (C^-1) the right-hand (+) side is taken, as IRIT and
  // verb do. Throws std::invalid_argument for NaN or parameters outside the domain. Cost O(o^3).
  Eigen::Vector3d evaluate(double u, double v, double w) const;
  Eigen::Vector3d evaluate(const Eigen::Vector3d& uvw) const { return evaluate(uvw[0], uvw[1], uvw[2]); }

  // Columns dF/du, dF/dv, dF/dw (right-hand derivatives at knots). Same checks as evaluate. Cost O(o^3).
  Eigen::Matrix3d jacobian(double u, double v, double w) const;
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& uvw) const { return jacobian(uvw[0], uvw[1], uvw[2]); }

  // Boehm knot insertion of t, `times` times, along `axis`: the map F is unchanged, one more control
  // plane per insertion. t must lie strictly inside the domain; the resulting multiplicity may reach
  // the order (a C^-1 plane). Cost O(times * #controls). Strong guarantee on failure.
  void insertKnot(int axis, double t, int times = 1);

  const std::vector<double>& knots(int axis) const;
  std::array<int, 3> orders() const { return orders_; }
  std::array<int, 3> controlCounts() const { return counts_; }
  // Parameter domain along `axis`: [knots[o-1], knots[n]].
  std::array<double, 2> domain(int axis) const;
  Eigen::AlignedBox3d parameterBox() const;

  int controlIndex(int i, int j, int k) const { return i + counts_[0] * (j + counts_[1] * k); }
  const Eigen::Vector3d& control(int i, int j, int k) const;
  // Throws std::invalid_argument for a non-finite point, std::out_of_range for a bad index.
  void setControl(int i, int j, int k, const Eigen::Vector3d& p);
  // Every control point set to `p` (finite: else std::invalid_argument, nothing changed). No allocation.
  void fillControls(const Eigen::Vector3d& p);
  // All control points, i-fastest. Read-only view; valid until the next insertKnot.
  std::span<const Eigen::Vector3d> controls() const { return controls_; }

  // True when (u, v, w) is finite and inside the domain.
  bool inDomain(double u, double v, double w) const noexcept;
  // F without checks, for callers that have validated (u, v, w); NaN-safe (clamps to the domain).
  // noexcept, no allocation: usable on the sim thread. Cost O(o^3).
  Eigen::Vector3d evaluateUnchecked(double u, double v, double w) const noexcept;

 private:
  BSplineVolume() = default;
  void checkParameters(double u, double v, double w, const char* who) const;
  void checkIndex(int i, int j, int k) const;

  std::array<int, 3> orders_{};
  std::array<int, 3> counts_{};
  std::array<std::vector<double>, 3> knots_;
  std::vector<Eigen::Vector3d> controls_;
};

}  // namespace incise::bspline
