// Private: one linear tet of the co-rotational model. Its natural (stress-free) shape is its rest shape with
// the prestretch divided out; bm is the inverse of the natural edge matrix Dm = S^-1 [X1 - X0, X2 - X0,
// X3 - X0], so that F = Ds bm and the gradients of its shape functions are beta_1..3 = the rows of bm,
// beta_0 = -(beta_1 + beta_2 + beta_3).
//
// Co-rotational linear elasticity: R = the proper rotation nearest F; strain eps = sym(R^T F) - I; stress
// sigma = lambda tr(eps) I + 2 mu eps; force on node a: f_a = -V R sigma beta_a; stiffness (dR ignored, so
// symmetric positive semi-definite): K_ab = V (lambda c_a c_b^T + mu c_b c_a^T + mu (beta_a . beta_b) I),
// c_a = R beta_a. Units: SI. Threads: pure functions. Cost O(1) each; rotation() O(iterations).
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

namespace incise::physics::detail {

// The six node pairs (a, b), a < b, in the order Element::pair holds their matrix entries.
inline constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

struct Element {
  std::array<int, 4> nodes{-1, -1, -1, -1};
  // Pair p's matrix entry: its index in the block row of min(nodes[a], nodes[b]).
  std::array<std::uint16_t, 6> pair{};
  Eigen::Matrix3d bm = Eigen::Matrix3d::Identity();
  // beta_a . beta_b for (0,0), (1,1), (2,2), (3,3), then the pairs in kPairs order.
  std::array<double, 10> dots{};
  double volume_m3 = 0.0;                                // natural
  std::array<double, 4> q{1.0, 0.0, 0.0, 0.0};           // the rotation, (w, x, y, z), warm start of the next step
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();  // of the rest positions: the element grid's key
  double radius_m = 0.0;                                 // largest distance from it to a node, at rest
  int base_tet = -1;
  std::int8_t side = 0;
  bool alive = false;
};

// Sets e's natural shape from its rest node positions (the mesh's, `rest[i]` for e.nodes[i]) and the
// inverse prestretch; false (e unchanged) if the natural volume is not positive (relative to its edges).
bool setRest(Element& e, const std::array<Eigen::Vector3d, 4>& rest_m, const Eigen::Vector3d& inverse_prestretch);

// The proper rotation R maximising tr(R^T F) (the polar rotation of F, and for an inverted F the rotation of
// Irving et al. 2004's diagonalisation), iterated from q (updated in place) as Mueller et al. 2016 do,
// q <- normalise((1, theta / 2) q), with Newton's step theta = (tr(A) I - sym(A))^-1 omega (A = F R^T,
// omega = axial(A - A^T)) where that matrix is positive definite, else their omega / |tr A|; until
// |theta| < tolerance or max_iterations. Returns R; `iterations` gets how many corrections were made.
Eigen::Matrix3d rotation(const Eigen::Matrix3d& f, std::array<double, 4>& q, double tolerance, int max_iterations,
                         int& iterations) noexcept;
Eigen::Matrix3d rotationMatrix(const std::array<double, 4>& q) noexcept;

// Barycentric coordinates of p (rest frame) in e at rest: (1 - l1 - l2 - l3, l1, l2, l3).
Eigen::Vector4d barycentric(const Element& e, const Eigen::Vector3d& rest0_m, const Eigen::Vector3d& p_m,
                            const Eigen::Vector3d& inverse_prestretch) noexcept;

// Distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) noexcept;
// Distance from p, outside the tet x, to it (the nearest of its four faces).
double distanceToTet(const std::array<Eigen::Vector3d, 4>& x, const Eigen::Vector3d& p) noexcept;

}  // namespace incise::physics::detail
