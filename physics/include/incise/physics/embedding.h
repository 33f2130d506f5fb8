// Points embedded in the tets (the skin's vertices, a contact point): the four nodes of the tet a point lies
// in at rest and its barycentric weights there, so that its deformed position is the same weighted sum of
// the nodes' current positions. TissueModel::locate finds them (tissue_model.h); these evaluate them on
// any copy of the node positions (the viewer's, the sim thread's).
//
// Shapes: node positions are #nodes Eigen::Vector3d in metres, indexed as the model's (the tet cutter's)
// nodes. Weights sum to 1; a point just outside its tet has one or more negative weights (it follows the
// tet's deformation affinely). Threads: pure functions, any thread. Cost O(1) a point. No allocation.
// Failure: node indices are not checked (they come from locate()).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <Eigen/Core>

namespace incise::physics {

// What locate()'s filter sees of a tet: the tet cutter's base tet it is a piece of, and its side of the cut
// (-1 / +1: a piece of a cut tet on that side; 0: not cut).
struct ElementInfo {
  int base_tet = -1;
  int side = 0;
};

struct Embedded {
  std::array<int, 4> nodes{-1, -1, -1, -1};
  std::array<double, 4> weights{0.0, 0.0, 0.0, 0.0};
  ElementInfo element;
  double outside_m = 0.0;  // distance from the point to the tet at rest (0: inside)
};

// A non-owning reference to a predicate bool(const ElementInfo&) for locate(): which tets a point may be
// embedded in. Empty, it accepts every tet. Pass it as an argument only (it must not outlive the callable).
class ElementFilter {
 public:
  ElementFilter() = default;
  template <class F>
  ElementFilter(const F& f)  // NOLINT: implicit, so that a lambda can be passed directly
      : object_(&f), call_([](const void* o, const ElementInfo& e) { return (*static_cast<const F*>(o))(e); }) {}
  bool operator()(const ElementInfo& e) const { return call_ == nullptr || call_(object_, e); }

 private:
  const void* object_ = nullptr;
  bool (*call_)(const void*, const ElementInfo&) = nullptr;
};

// Tets on one side of a cut, or not cut: a lip's vertex on side +1 is never embedded in a -1 piece.
struct OnSide {
  int side = 0;
  bool operator()(const ElementInfo& e) const noexcept { return e.side == 0 || e.side == side; }
};

// sum_i weights[i] * node_positions_m[nodes[i]].
Eigen::Vector3d embeddedPosition(const Embedded& point, std::span<const Eigen::Vector3d> node_positions_m) noexcept;

// Every point's position into out_m (out_m.size() >= points.size()).
void embeddedPositions(std::span<const Embedded> points, std::span<const Eigen::Vector3d> node_positions_m,
                       std::span<Eigen::Vector3d> out_m) noexcept;

// The deformed direction of a rest normal at the point: F^-T n, normalised, with F the tet's deformation
// gradient from `rest_m` to `current_m` (Nanson's formula). `rest_normal` if the tet is flat at rest or
// crushed flat.
Eigen::Vector3d embeddedNormal(const Embedded& point, std::span<const Eigen::Vector3d> rest_m,
                               std::span<const Eigen::Vector3d> current_m, const Eigen::Vector3d& rest_normal) noexcept;

}  // namespace incise::physics
