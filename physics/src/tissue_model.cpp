// TissueModel (tissue_model.h): load, state, the tool. The step is in tissue_model_step.cpp, cuts in
// tissue_model_changes.cpp, embedding and contact in tissue_model_locate.cpp.
#include "incise/physics/tissue_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "incise/core/format.h"
#include "tissue_model_state.h"

namespace incise::physics {
namespace {

void validateOptions(const ModelOptions& o) {
  const auto refuse = [](const std::string& what) { throw std::invalid_argument("ModelOptions: " + what); };
  if (!(std::isfinite(o.cg_tolerance) && o.cg_tolerance > 0.0))
    refuse("cg_tolerance = " + core::formatNumber(o.cg_tolerance) + " must be finite and > 0");
  if (!(o.ssor_relaxation >= 0.0 && o.ssor_relaxation < 2.0))
    refuse("ssor_relaxation = " + core::formatNumber(o.ssor_relaxation) + " is outside [0, 2)");
  if (o.max_cg_iterations < 1) refuse("max_cg_iterations = " + std::to_string(o.max_cg_iterations) + " must be >= 1");
  if (!(std::isfinite(o.rotation_tolerance) && o.rotation_tolerance > 0.0))
    refuse("rotation_tolerance = " + core::formatNumber(o.rotation_tolerance) + " must be finite and > 0");
  if (o.max_rotation_iterations < 1)
    refuse("max_rotation_iterations = " + std::to_string(o.max_rotation_iterations) + " must be >= 1");
  if (o.reserve_nodes < 0 || o.reserve_elements < 0)
    refuse("reserve_nodes and reserve_elements must be >= 0 (" + std::to_string(o.reserve_nodes) + ", " +
           std::to_string(o.reserve_elements) + ")");
  if (o.coarse_aggregates < 0 || o.coarse_aggregates > 64 || o.coarse_nodes_per_aggregate < 1)
    refuse("coarse_aggregates = " + std::to_string(o.coarse_aggregates) + " must be in [0, 64] and " +
           "coarse_nodes_per_aggregate = " + std::to_string(o.coarse_nodes_per_aggregate) + " >= 1");
}

// Elements a locate() query may list (the grid's hits near one point) before its scratch list grows.
constexpr std::size_t kCandidateRoom = 4096;

// Twice the mean tet edge: a grid cell then holds a few element centroids.
double gridCell(const tets::TetMesh& mesh) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto& t : mesh.tets)
    for (const auto& pair : detail::kPairs) {
      const auto a = static_cast<std::size_t>(t[static_cast<std::size_t>(pair[0])]);
      const auto b = static_cast<std::size_t>(t[static_cast<std::size_t>(pair[1])]);
      if (a < mesh.nodes_m.size() && b < mesh.nodes_m.size())
        sum += (mesh.nodes_m[a] - mesh.nodes_m[b]).norm(), ++count;
    }
  const double cell = count > 0 ? 2.0 * sum / static_cast<double>(count) : 1.0;
  return std::isfinite(cell) && cell > 0.0 ? cell : 1.0;
}

// Per node, the number of distinct nodes above it that share a tet: its block row's entries.
std::vector<int> upperNeighbours(const tets::TetMesh& mesh) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(mesh.tets.size() * 6);
  for (const auto& t : mesh.tets)
    for (const auto& p : detail::kPairs) {
      const int a = t[static_cast<std::size_t>(p[0])], b = t[static_cast<std::size_t>(p[1])];
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<int> count(mesh.nodes_m.size(), 0);
  for (const auto& [a, b] : pairs) ++count[static_cast<std::size_t>(a)];
  return count;
}

}  // namespace

const char* toString(StepStatus status) noexcept {
  switch (status) {
    case StepStatus::Converged:
      return "converged";
    case StepStatus::IterationLimit:
      return "iteration limit";
    case StepStatus::BadTimeStep:
      return "bad time step";
    case StepStatus::NonFinite:
      return "non-finite";
  }
  return "?";
}

TissueModel::TissueModel(const tets::TetMesh& mesh, const Material& material, const Boundary& boundary,
                         const ModelOptions& options, std::span<const int> sides) {
  validate(material);
  const int n = static_cast<int>(mesh.nodes_m.size());
  validate(boundary, n);
  validateOptions(options);
  if (!sides.empty() && sides.size() != mesh.tets.size())
    throw std::invalid_argument("TissueModel: " + std::to_string(sides.size()) + " sides for " +
                                std::to_string(mesh.tets.size()) + " tets");
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (const int node : mesh.tets[t])
      if (node < 0 || node >= n)
        throw std::invalid_argument("TissueModel: tet " + std::to_string(t) + " has node " + std::to_string(node) +
                                    " outside [0, " + std::to_string(n) + ")");
  s_ = std::make_unique<State>(gridCell(mesh));
  State& s = *s_;
  s.material = material, s.lame = lame(material), s.boundary = boundary, s.options = options;
  s.inverse_prestretch = material.prestretch.cwiseInverse();
  const std::size_t nodes = static_cast<std::size_t>(n + options.reserve_nodes);
  const std::size_t tets = mesh.tets.size(), elements = tets + static_cast<std::size_t>(options.reserve_elements);
  for (auto* v : {&s.rest_m, &s.x_m, &s.v_m_per_s, &s.target_m, &s.external_N, &s.force_N, &s.rhs, &s.v_next,
                  &s.dv_last_m_per_s, &s.contact_w, &s.contact_z[0], &s.contact_z[1], &s.contact_z[2]})
    v->reserve(nodes);
  for (auto* v : {&s.active, &s.fixed_by_boundary, &s.known, &s.held_by_tool}) v->reserve(nodes);
  s.mass_kg.reserve(nodes), s.role.reserve(nodes), s.node_mark.reserve(nodes), s.touched_nodes.reserve(nodes);
  s.pcg.reserve(nodes);
  s.coarse.reserve(nodes, options.coarse_aggregates);
  s.elements.reserve(elements), s.free_elements.reserve(elements), s.element_mark.reserve(elements);
  s.touched_elements.reserve(elements);
  s.node_elements.reserve(nodes, 4 * elements + 8 * nodes);
  s.base_elements.reserve(tets + static_cast<std::size_t>(options.reserve_elements) / 4, 3 * elements);
  s.grid.reserve(elements);
  s.candidates.reserve(kCandidateRoom);
  const std::vector<int> upper = upperNeighbours(mesh);
  s.matrix.reserve(
      nodes, 2 * static_cast<std::size_t>(nodes) + 3 * tets + 40 * static_cast<std::size_t>(options.reserve_nodes));
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  for (const auto& t : mesh.tets)
    for (const int node : t) ++degree[static_cast<std::size_t>(node)];
  for (int i = 0; i < n; ++i)
    s.addNode(mesh.nodes_m[static_cast<std::size_t>(i)], upper[static_cast<std::size_t>(i)] + 2,
              degree[static_cast<std::size_t>(i)] + 4);
  for (const int node : boundary.fixed_nodes) s.fixed_by_boundary[static_cast<std::size_t>(node)] = 1;
  for (std::size_t t = 0; t < tets; ++t) {
    s.base_elements.addList(1);
    const int side = sides.empty() ? 0 : sides[t];
    if (s.addElement(static_cast<int>(t), mesh.tets[t], side, {1.0, 0.0, 0.0, 0.0}) < 0)
      throw std::invalid_argument("TissueModel: tet " + std::to_string(t) + " is flat or inverted at rest");
  }
  int held = 0;
  for (int i = 0; i < n; ++i) {
    s.recomputeMass(i);
    s.setRole(i);
    held += s.role[static_cast<std::size_t>(i)] == NodeRole::Fixed ? 1 : 0;
  }
  if (held == 0)
    throw std::invalid_argument(
        "TissueModel: no node is held (Boundary: fixed_nodes and fixed_boxes select none of "
        "the tets' nodes): a free tissue has no rest");
  s.pcg.resize(static_cast<std::size_t>(n));
}

TissueModel::~TissueModel() = default;
TissueModel::TissueModel(TissueModel&&) noexcept = default;
TissueModel& TissueModel::operator=(TissueModel&&) noexcept = default;

void TissueModel::State::addNode(const Eigen::Vector3d& rest, int matrix_room, int element_room) {
  if (x_m.size() == x_m.capacity()) ++growths;
  matrix.addRow(matrix_room);
  node_elements.addList(element_room);
  rest_m.push_back(rest), x_m.push_back(rest), target_m.push_back(rest);
  for (auto* v : {&v_m_per_s, &external_N, &force_N, &rhs, &v_next, &dv_last_m_per_s, &contact_w, &contact_z[0],
                  &contact_z[1], &contact_z[2]})
    v->push_back(Eigen::Vector3d::Zero());
  mass_kg.push_back(0.0), role.push_back(NodeRole::Unused), active.push_back(0);
  fixed_by_boundary.push_back(insideFixedBox(boundary, rest) ? 1 : 0);
  known.push_back(1), held_by_tool.push_back(0), node_mark.push_back(0);
}

void TissueModel::State::setRole(int node) noexcept {
  const auto i = static_cast<std::size_t>(node);
  NodeRole r = NodeRole::Free;
  if (!known[i] || node_elements[node].empty())
    r = NodeRole::Unused;
  else if (held_by_tool[i])
    r = NodeRole::Held;
  else if (fixed_by_boundary[i])
    r = NodeRole::Fixed;
  role[i] = r;
  const std::uint8_t free = r == NodeRole::Free ? 1 : 0;
  if (active[i] != free) ++structure;
  active[i] = free;
  if (r != NodeRole::Free) v_m_per_s[i].setZero();
}

void TissueModel::State::recomputeMass(int node) noexcept {
  double m = 0.0;
  for (const int e : node_elements[node]) m += elements[static_cast<std::size_t>(e)].volume_m3;
  mass_kg[static_cast<std::size_t>(node)] = 0.25 * material.density_kg_per_m3 * m;
}

void TissueModel::State::moveHeldNodes() noexcept {
  for (std::size_t i = 0; i < role.size(); ++i) {
    if (role[i] == NodeRole::Fixed) x_m[i] = rest_m[i];
    if (role[i] == NodeRole::Held) x_m[i] = target_m[i];
    if (role[i] != NodeRole::Free) v_m_per_s[i].setZero();
  }
}

std::int64_t TissueModel::steps() const noexcept { return s_->steps; }
int TissueModel::nodeCount() const noexcept { return static_cast<int>(s_->x_m.size()); }
std::span<const Eigen::Vector3d> TissueModel::positions_m() const noexcept { return s_->x_m; }
std::span<const Eigen::Vector3d> TissueModel::velocities_m_per_s() const noexcept { return s_->v_m_per_s; }
std::span<const Eigen::Vector3d> TissueModel::restPositions_m() const noexcept { return s_->rest_m; }
double TissueModel::mass_kg(int node) const noexcept { return s_->mass_kg[static_cast<std::size_t>(node)]; }
int TissueModel::elementCount() const noexcept { return s_->alive; }
int TissueModel::baseTetCount() const noexcept { return s_->base_elements.lists(); }
const Material& TissueModel::material() const noexcept { return s_->material; }
const Boundary& TissueModel::boundary() const noexcept { return s_->boundary; }
const ModelOptions& TissueModel::options() const noexcept { return s_->options; }
std::size_t TissueModel::matrixEntries() const noexcept { return s_->matrix.entries(); }

int TissueModel::reserveOverflows() const noexcept {
  const State& s = *s_;
  return s.node_elements.overflows() + s.base_elements.overflows() + s.matrix.overflows() + s.growths;
}

std::size_t TissueModel::copyPositions(std::span<Eigen::Vector3d> out) const noexcept {
  const std::size_t n = std::min(out.size(), s_->x_m.size());
  std::copy_n(s_->x_m.begin(), n, out.begin());
  return n;
}

double TissueModel::totalMass_kg() const noexcept {
  double m = 0.0;
  for (const double node : s_->mass_kg) m += node;
  return m;
}

double TissueModel::maxDisplacement_m() const noexcept {
  double largest_m = 0.0;
  for (std::size_t n = 0; n < s_->x_m.size() && n < s_->rest_m.size(); ++n)
    largest_m = std::max(largest_m, (s_->x_m[n] - s_->rest_m[n]).norm());
  return largest_m;
}

bool TissueModel::isHeld(int node) const noexcept {
  if (node < 0 || node >= nodeCount()) return false;
  const NodeRole r = s_->role[static_cast<std::size_t>(node)];
  return r == NodeRole::Fixed || r == NodeRole::Held;
}

void TissueModel::resetState() noexcept {
  State& s = *s_;
  s.x_m = s.rest_m;  // same size: no allocation
  for (auto& v : s.v_m_per_s) v.setZero();
  for (auto& dv : s.dv_last_m_per_s) dv.setZero();
  s.last_step_dt_s = 0.0;
  for (auto& e : s.elements) e.q = {1.0, 0.0, 0.0, 0.0};
  s.moveHeldNodes();
}

void TissueModel::clearExternalForces() noexcept {
  for (auto& f : s_->external_N) f.setZero();
}

void TissueModel::addNodeForce(int node, const Eigen::Vector3d& force_N) noexcept {
  if (node >= 0 && node < nodeCount() && force_N.allFinite()) s_->external_N[static_cast<std::size_t>(node)] += force_N;
}

void TissueModel::addPointForce(const Embedded& point, const Eigen::Vector3d& force_N) noexcept {
  for (int i = 0; i < 4; ++i)
    addNodeForce(point.nodes[static_cast<std::size_t>(i)], point.weights[static_cast<std::size_t>(i)] * force_N);
}

void TissueModel::setToolPress(const Embedded& anchor, const Eigen::Vector3d& normal, const Eigen::Vector3d& tool_m,
                               double stiffness_N_per_m) noexcept {
  State::Press& p = s_->press;
  p.on = normal.allFinite() && std::abs(normal.norm() - 1.0) < 1e-6 && tool_m.allFinite() &&
         std::isfinite(stiffness_N_per_m) && stiffness_N_per_m > 0.0;
  p.anchor = anchor, p.normal = normal, p.tool_m = tool_m, p.stiffness_N_per_m = stiffness_N_per_m;
}

void TissueModel::clearToolPress() noexcept { s_->press.on = false; }

Eigen::Vector3d TissueModel::toolPressForce_N() const noexcept { return s_->press_force_N; }

void TissueModel::holdNode(int node, const Eigen::Vector3d& x_m) noexcept {
  if (node < 0 || node >= nodeCount() || !x_m.allFinite()) return;
  const auto i = static_cast<std::size_t>(node);
  s_->held_by_tool[i] = 1, s_->target_m[i] = x_m;
  s_->setRole(node);
  if (s_->role[i] == NodeRole::Held) s_->x_m[i] = x_m;
}

void TissueModel::releaseNode(int node) noexcept {
  if (node < 0 || node >= nodeCount()) return;
  s_->held_by_tool[static_cast<std::size_t>(node)] = 0;
  s_->setRole(node);
}

void TissueModel::setPosition(int node, const Eigen::Vector3d& x_m) noexcept {
  if (node >= 0 && node < nodeCount() && x_m.allFinite()) s_->x_m[static_cast<std::size_t>(node)] = x_m;
}

}  // namespace incise::physics
