// Private: what a TissueModel holds (tissue_model.h), shared by its source files: tissue_model.cpp (load,
// state, the tool), tissue_model_step.cpp (assembly, the implicit step, the static solve),
// tissue_model_changes.cpp (cuts), tissue_model_locate.cpp (embedding, contact).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "block_matrix.h"
#include "buckets.h"
#include "coarse_space.h"
#include "element.h"
#include "incise/mesh/vertex_grid.h"
#include "incise/physics/tissue_model.h"
#include "pcg.h"

namespace incise::physics {

enum class NodeRole : std::uint8_t {
  Free,    // in the solve
  Fixed,   // held at rest by the boundary
  Held,    // held at target_m by holdNode()
  Unused,  // no live element uses it (or its rest is not known yet)
};

struct TissueModel::State {
  explicit State(double grid_cell_m) : grid(grid_cell_m) {}

  Material material;
  Lame lame{};
  Boundary boundary;
  ModelOptions options;
  Eigen::Vector3d inverse_prestretch = Eigen::Vector3d::Ones();

  // Per node.
  std::vector<Eigen::Vector3d> rest_m, x_m, v_m_per_s, target_m, external_N, force_N, rhs, v_next;
  // The last step's change of velocity per node (zero where not Free): the next step's CG starts from
  // v + dv_last (a constant acceleration's guess) when it has the same dt.
  std::vector<Eigen::Vector3d> dv_last_m_per_s;
  std::vector<double> mass_kg;
  std::vector<NodeRole> role;
  std::vector<std::uint8_t> active;             // role == Free: the solver's projection
  std::vector<std::uint8_t> fixed_by_boundary;  // listed in Boundary::fixed_nodes or in a fixed box at rest
  std::vector<std::uint8_t> known;              // a rest position was given
  std::vector<std::uint8_t> held_by_tool;
  detail::Buckets node_elements;  // node -> live elements using it

  // Elements: pieces of base tets; slots of dead ones are reused (free_elements, last freed first).
  std::vector<detail::Element> elements;
  std::vector<int> free_elements;
  detail::Buckets base_elements;  // base tet -> its live elements
  int alive = 0;

  detail::BlockMatrix matrix;  // the last assembly: A = kM M + kK K
  detail::PcgScratch pcg;
  detail::CoarseSpace coarse;
  // Counts changes of the free nodes (setRole); the coarse space is partitioned again at the next step that
  // uses it when it differs from partitioned_structure.
  std::uint64_t structure = 0, partitioned_structure = ~std::uint64_t{0};
  bool coarse_current = false;  // `coarse` was built from `matrix` as it is (the contact model's solves use it)
  // When the coarse level is used (useCoarse): on, on for a first step whose iterations are compared with
  // the step before's (ssor_iterations, SSOR alone), or resting after one that did not pay.
  bool coarse_on = false, coarse_trial = false;
  int ssor_iterations = 0, coarse_rest_steps = 0;
  std::array<std::vector<Eigen::Vector3d>, 3> contact_z;  // contactModel's solutions (warm starts)
  std::vector<Eigen::Vector3d> contact_w;
  // The tool's press (TissueModel::setToolPress) and the force it put on the tissue at the last assembly.
  struct Press {
    bool on = false;
    Embedded anchor;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitY(), tool_m = Eigen::Vector3d::Zero();
    double stiffness_N_per_m = 0.0;
  } press;
  Eigen::Vector3d press_force_N = Eigen::Vector3d::Zero();
  double last_dt_s = 0.0;       // of the matrix in `matrix` (0: none assembled for a step)
  double last_step_dt_s = 0.0;  // of the last step, whose dv_last_m_per_s holds (0: none, or reset since)
  int last_step_cg_iterations = 0;
  std::int64_t steps = 0;

  // Elements at rest by centroid (locate(), and new nodes' starting positions).
  mesh::VertexGrid grid;
  double max_radius_m = 0.0;  // over every element ever added: the grid query's reach
  mutable std::vector<int> candidates;

  // apply()'s scratch: marks by stamp.
  std::vector<std::uint32_t> node_mark, element_mark;
  std::uint32_t mark = 0;
  std::vector<int> touched_nodes, touched_elements;

  int growths = 0;  // arrays grown past their reserve

  // --- tissue_model.cpp
  // Appends a node at rest_m (x there, velocity zero, no element yet) with its matrix row and element list.
  void addNode(const Eigen::Vector3d& rest_m, int matrix_room, int element_room);
  void setRole(int node) noexcept;  // from held_by_tool, fixed_by_boundary, uses and known
  void recomputeMass(int node) noexcept;
  // --- tissue_model_changes.cpp
  int addElement(int base_tet, const std::array<int, 4>& nodes, int side, const std::array<double, 4>& q);
  void removeElement(int element) noexcept;
  std::array<Eigen::Vector3d, 4> restOf(const detail::Element& e) const noexcept;
  // --- tissue_model_step.cpp
  // Elastic forces into force_N and A = mass_coefficient M + stiffness_coefficient K into the matrix;
  // returns the number of inverted elements.
  int assemble(double mass_coefficient, double stiffness_coefficient) noexcept;
  void moveHeldNodes() noexcept;  // x = target, v = 0 for every node not Free
  bool useCoarse() noexcept;      // whether this step's CG uses the coarse level (from the last steps)
  bool buildCoarse() noexcept;    // the coarse space for this step's matrix (after the assembly): in use?
  // The press's force into force_N and its stiffness times stiffness_coefficient into the matrix (after
  // assemble()); sets press_force_N.
  void addToolPress(double stiffness_coefficient) noexcept;
  // --- tissue_model_locate.cpp
  std::optional<Embedded> locate(const Eigen::Vector3d& p, ElementFilter filter, double max_distance_m) const;
};

}  // namespace incise::physics
