// The tissue's material and boundary as value types, and their validation: linear elasticity (Young's
// modulus, Poisson's ratio) in the co-rotated frame of each tet, density (lumped masses), Rayleigh damping,
// a prestretch (the natural, stress-free shape is the mesh shrunk by these factors, so a tissue held at its
// mesh positions is under tension and a cut gapes by itself), the nodes held at rest and gravity.
//
// Units: Pa, kg/m^3, 1/s and s (damping), m, m/s^2. Threads: values; any thread. Cost: O(1) (resolving
// boxes: O(nodes x boxes)). Failure: validate() throws std::invalid_argument naming the field and its value.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

namespace incise::physics {

// Rayleigh damping: D = mass_per_s * M + stiffness_s * K (M the lumped masses, K the co-rotated
// stiffness). mass_per_s damps every motion (a drag towards rest in the world frame); stiffness_s damps
// fast deformation more than slow (its damping ratio grows with frequency: zeta = stiffness_s * omega / 2).
struct Damping {
  double mass_per_s = 1.0;
  double stiffness_s = 0.01;
};

struct Material {
  double youngs_modulus_Pa = 30e3;  // E: soft tissue (skin and fat lie between 1 kPa and 1 MPa)
  double poisson_ratio = 0.45;      // nu, in [0, 0.5): 0.5 would be incompressible (locking tets)
  double density_kg_per_m3 = 1000.0;
  Damping damping;
  // (sx, sy, sz): the natural shape of every tet is its mesh shape with x divided by sx, y by sy, z by sz.
  // 1 = the mesh is stress-free; > 1 = the mesh is stretched (in tension where it is held); each > 0.
  Eigen::Vector3d prestretch = Eigen::Vector3d::Ones();
};

// An axis-aligned box in the mesh's frame (inclusive).
struct Box {
  Eigen::Vector3d min_m;
  Eigen::Vector3d max_m;
  bool contains(const Eigen::Vector3d& p) const noexcept {
    return (p.array() >= min_m.array()).all() && (p.array() <= max_m.array()).all();
  }
};

// Which nodes are held at their rest (mesh) positions, and gravity. A node is held when it is listed or its
// rest position lies in one of the boxes (nodes a cut adds too). incise's tissues have +y up.
struct Boundary {
  std::vector<int> fixed_nodes;
  std::vector<Box> fixed_boxes;
  Eigen::Vector3d gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
};

// Lame's parameters of (E, nu): lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)), in Pa.
struct Lame {
  double lambda_Pa;
  double mu_Pa;
};
Lame lame(const Material& material) noexcept;

// Refuses E <= 0, nu outside [0, 0.5), density <= 0, negative damping, a prestretch factor <= 0, and any
// non-finite value: std::invalid_argument("Material: poisson_ratio = 0.5 is outside [0, 0.5)") and so on.
void validate(const Material& material);
// Refuses a non-finite gravity, an empty or non-finite box (min > max) and a node index outside
// [0, node_count): std::invalid_argument naming the entry ("Boundary: fixed_nodes[3] = 812 ...").
void validate(const Boundary& boundary, int node_count);

// Whether `rest_m` is held by `boundary`'s boxes (the listed nodes are checked by index). O(boxes).
bool insideFixedBox(const Boundary& boundary, const Eigen::Vector3d& rest_m) noexcept;

}  // namespace incise::physics
