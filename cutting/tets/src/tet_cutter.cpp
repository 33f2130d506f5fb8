#include "incise/tets/tet_cutter.h"

#include "incise/incision/surface_cutter.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include <Eigen/LU>

#include "incise/bspline/volume_inversion.h"
#include "incise/mesh/surface_mesh.h"
#include "tet_split.h"

namespace incise::tets {
namespace {

double medianEdgeLength(const TetMesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.tets.size() * 6);
  for (const auto& t : mesh.tets)
    for (const auto& e : detail::kTetEdges)
      lengths.push_back(
          (mesh.nodes_m[static_cast<size_t>(t[e[0]])] - mesh.nodes_m[static_cast<size_t>(t[e[1]])]).norm());
  if (lengths.empty()) return 0.0;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

}  // namespace

TetCutter::TetCutter(TetMesh tissue, const TetCutterOptions& options) : options_(options), node_grid_(1.0) {
  if (!(options.snap_tolerance_m >= 0.0) || !std::isfinite(options.snap_tolerance_m))
    throw std::invalid_argument("TetCutter: snap_tolerance_m = " + std::to_string(options.snap_tolerance_m) +
                                " must be finite and >= 0");
  if (options.max_inversions_per_call < 0)
    throw std::invalid_argument(
        "TetCutter: max_inversions_per_call = " + std::to_string(options.max_inversions_per_call) + " must be >= 0");
  if (tissue.tets.empty()) throw mesh::MeshError("TetCutter: the tissue has no tets");
  const TetCheck check = checkConforming(tissue);
  if (!check.conforming) throw mesh::MeshError("TetCutter: the tissue is not conforming: " + check.first_problem);
  const double median = medianEdgeLength(tissue);
  snap_m_ = options.snap_tolerance_m > 0.0 ? options.snap_tolerance_m : 0.2 * median;
  build(std::move(tissue));
}

void TetCutter::build(TetMesh mesh) {
  const size_t n_nodes = mesh.nodes_m.size(), n_tets = mesh.tets.size();
  const double median = medianEdgeLength(mesh);
  median_edge_m_ = median;
  base_tets_ = mesh.tets;
  rest_m_ = mesh.nodes_m;
  deformed_m_ = mesh.nodes_m;
  nodes_.assign(n_nodes, Node{});
  for (size_t i = 0; i < n_nodes; ++i) nodes_[i].origin = static_cast<int>(i);
  // Edges: the six of every tet, numbered by sorting (node, node, tet, local).
  struct EdgeRef {
    int a, b, tet, local;
  };
  std::vector<EdgeRef> refs;
  refs.reserve(n_tets * 6);
  for (size_t t = 0; t < n_tets; ++t)
    for (int e = 0; e < 6; ++e) {
      const int a = base_tets_[t][detail::kTetEdges[e][0]], b = base_tets_[t][detail::kTetEdges[e][1]];
      refs.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), e});
    }
  std::sort(refs.begin(), refs.end(), [](const EdgeRef& x, const EdgeRef& y) {
    return std::tie(x.a, x.b, x.tet, x.local) < std::tie(y.a, y.b, y.tet, y.local);
  });
  edges_.clear();
  tet_edges_.assign(n_tets, {});
  for (size_t i = 0; i < refs.size(); ++i) {
    if (i == 0 || refs[i].a != refs[i - 1].a || refs[i].b != refs[i - 1].b) edges_.push_back({refs[i].a, refs[i].b});
    tet_edges_[static_cast<size_t>(refs[i].tet)][static_cast<size_t>(refs[i].local)] =
        static_cast<int>(edges_.size()) - 1;
  }
  edge_point_.assign(edges_.size(), -1);
  // Node -> tets (ascending), each list with room for kSlack more (a rebase adds the pieces around a node).
  constexpr int kSlack = 8;
  node_tets_count_.assign(n_nodes, 0);
  for (const auto& t : base_tets_)
    for (int n : t) ++node_tets_count_[static_cast<size_t>(n)];
  node_tets_cap_.resize(n_nodes);
  node_tets_first_.resize(n_nodes);
  int offset = 0;
  for (size_t n = 0; n < n_nodes; ++n) {
    node_tets_cap_[n] = node_tets_count_[n] + kSlack;
    node_tets_first_[n] = offset;
    offset += node_tets_cap_[n];
  }
  node_tets_.assign(static_cast<size_t>(offset), -1);
  std::vector<int> fill(node_tets_first_);
  for (size_t t = 0; t < n_tets; ++t)
    for (int n : base_tets_[t]) node_tets_[static_cast<size_t>(fill[static_cast<size_t>(n)]++)] = static_cast<int>(t);
  tet_state_.assign(n_tets, 0);
  tet_touched_.assign(n_tets, 0);
  touched_tets_.clear();
  touched_nodes_.clear();
  nodes_at_start_ = n_nodes;
  in_grid_.assign(n_nodes, 1);
  children_.resize(n_tets);
  for (size_t t = 0; t < n_tets; ++t) children_[t] = Child{base_tets_[t], 0, 0};
  child_first_.resize(n_tets);
  std::iota(child_first_.begin(), child_first_.end(), 0);
  child_count_.assign(n_tets, 1);
  steiner_.assign(n_tets, {-1, -1, -1});
  tet_count_ = static_cast<int>(n_tets);
  node_grid_ = mesh::VertexGrid(std::max(2.0 * median, 1e-9));
  node_grid_.reserve(n_nodes + kHeadroomNodes);
  for (size_t n = 0; n < n_nodes; ++n) node_grid_.insert(static_cast<int>(n), rest_m_[n]);
  decided_.assign(n_tets, 0);
  stencil_count_.clear();
  stencil_first_.clear();
  stencil_basis_.clear();
  dirty_.clear();
  reserveHeadroom();
  changes_.clear();
}

void TetCutter::recordChanges(bool on) {
  record_changes_ = on;
  changes_.clear();
  if (on) changes_.nodes.reserve(kReservedChanges), changes_.base_tets.reserve(kReservedChanges);
}

void TetCutter::reserveHeadroom() {
  // Room for the new nodes of the cutter's incisions and their children, base tets (a rebase appends a
  // split tet's pieces), edges and incidence lists, so that the sim thread does not reallocate (and copy)
  // these arrays; beyond it they still grow (amortised), counted in stats_.reserve_overflows.
  const size_t nodes = rest_m_.size() + kHeadroomNodes, children = children_.size() + 8 * kHeadroomNodes;
  for (auto* v : {&rest_m_, &deformed_m_}) v->reserve(nodes);
  nodes_.reserve(nodes);
  for (auto* v : {&node_tets_first_, &node_tets_count_, &node_tets_cap_}) v->reserve(nodes);
  in_grid_.reserve(nodes);
  node_tets_.reserve(node_tets_.size() + 64 * kHeadroomNodes);
  const size_t bases = base_tets_.size() + 4 * kHeadroomNodes;
  base_tets_.reserve(bases);
  tet_edges_.reserve(bases);
  for (auto* v : {&tet_state_, &tet_touched_, &child_count_}) v->reserve(bases);
  for (auto* v : {&decided_, &child_first_}) v->reserve(bases);
  steiner_.reserve(bases);
  edges_.reserve(edges_.size() + 8 * kHeadroomNodes);
  edge_point_.reserve(edges_.size() + 8 * kHeadroomNodes);
  touched_tets_.reserve(4 * kHeadroomNodes);
  touched_nodes_.reserve(kHeadroomNodes);
  children_.reserve(children);
  stencil_count_.reserve(kHeadroomNodes);
  stencil_first_.reserve(kHeadroomNodes * 2);
  dirty_.reserve(kHeadroomNodes);
  for (auto* v : {&candidates_, &affected_, &cut_points_, &scratch_, &scratch2_, &parent_}) v->reserve(4096);
  fresh_.reserve(kHeadroomNodes);
  waiting_.reserve(kHeadroomNodes);
  faces_.reserve(4096);
  group_seen_.reserve(4096);
}

void TetCutter::startIncision(int incision_number) {
  if (incision_number_ >= 0) {  // the previous wound, settled, is the new rest: the rebase, before any column
    std::sort(touched_tets_.begin(), touched_tets_.end());
    rebase_phase_ = Rebase::Tets;
    rebase_next_ = 0;
    bases_at_start_ = static_cast<int>(base_tets_.size());
  }
  stencil_count_.clear();
  stencil_first_.clear();
  stencil_basis_.clear();
  incision_number_ = incision_number;
  const incision::IncisionOptions& o = incision_->options();
  next_column_ = o.order - 1;
  column_started_ = false;
  last_final_columns_ = 0;
  // The tets' cut trails the lattice's final columns by the tets ahead that are not decided yet (their
  // nodes wait for a later column): about two tet edges, plus a B-spline support for the opening to fall
  // to 0 there, so that no tet at the cut's leading edge is torn open before it is cut.
  lag_columns_ = static_cast<int>(std::ceil(2.0 * median_edge_m_ / o.spacing_m)) + o.order;
  if (lagged_)
    *lagged_ = incision_->displacement();  // the same shape as prepare()'s: copied into its storage
  else
    lagged_.emplace(incision_->displacement());
  lagged_seen_.resize(static_cast<size_t>(o.max_columns));
  for (int c = 0; c < o.max_columns; ++c) lagged_seen_[static_cast<size_t>(c)] = {1.0, incision_->columnOpening(c)};
  lagged_changed_.reserve(static_cast<size_t>(o.max_columns));
  if (cells_.size() != static_cast<size_t>(o.max_columns)) cells_.resize(static_cast<size_t>(o.max_columns));
  for (auto& cell : cells_) {
    cell.clear();  // keeps its capacity
    cell.reserve(kReservedCellNodes);
  }
  stencil_basis_.reserve(kHeadroomNodes * 2 * static_cast<size_t>(incision_->stencilSize()));
  waiting_.clear();
  ++stats_.incisions;
}

void TetCutter::prepare(const incision::IncisionOptions& options) {
  const incision::Incision shape(options,
                                 incision::StrokeSample{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0},
                                 Eigen::Vector3d::UnitX());
  lagged_.emplace(shape.displacement());
  lagged_seen_.assign(static_cast<size_t>(options.max_columns), LaggedColumn{});
  lagged_changed_.reserve(static_cast<size_t>(options.max_columns));
  cells_.resize(static_cast<size_t>(options.max_columns));
  for (auto& cell : cells_) cell.reserve(kReservedCellNodes);
  stencil_basis_.reserve(kHeadroomNodes * 2 * static_cast<size_t>(shape.stencilSize()));
}

TetStep TetCutter::follow(const incision::Incision& incision, int incision_number, TetBudget budget_kind) noexcept {
  TetStep step;
  if (failed_) {
    step.failed = true;
    return step;
  }
  try {
    incision_ = &incision;
    if (incision_number != incision_number_) startIncision(incision_number);
    core::WorkBudget budget = budget_kind == TetBudget::PerCall ? core::WorkBudget(options_.max_inversions_per_call)
                                                                : core::WorkBudget::unlimited();
    last_final_columns_ = incision.finalColumns();
    if (rebase_phase_ != Rebase::None && !rebase(budget)) {
      incision_ = nullptr;
      return step;
    }
    while (next_column_ < last_final_columns_ && !budget.spent() && !failed_) {
      if (!processColumn(incision, next_column_, budget, step)) break;
      ++next_column_;
    }
    redeform(incision, step);
  } catch (const std::exception& e) {  // allocation failure or a broken invariant: stop, never throw
    fail(std::string("TetCutter: ") + e.what());
  }
  incision_ = nullptr;
  step.failed = failed_;
  return step;
}

bool TetCutter::pending() const noexcept {
  return !failed_ && (rebase_phase_ != Rebase::None || next_column_ < last_final_columns_);
}

void TetCutter::fail(const std::string& message) {
  failed_ = true;
  if (stats_.failure.empty()) stats_.failure = message;
}

bool TetCutter::processColumn(const incision::Incision& in, int column, core::WorkBudget& budget, TetStep& step) {
  if (!column_started_) {
    column_started_ = true;
    candidates_.clear();
    affected_.clear();
    fresh_.clear();
    next_candidate_ = next_fresh_ = 0;
    next_fresh_tet_ = -1;
    node_grid_.query(in.columnBox(column), candidates_);  // the nodes under this column
    retryWaiting();
  }
  // Nodes first: each one bound here becomes "fresh".
  for (; next_candidate_ < candidates_.size(); ++next_candidate_)
    if (resolveNode(in, candidates_[next_candidate_], column, budget, step) == Resolve::OutOfBudget) return false;
  // Then the tets around each fresh node: a tet is decided once, when its last node is known (its other
  // nodes are tried here too; those bound here become fresh in turn).
  for (; next_fresh_ < fresh_.size(); ++next_fresh_, next_fresh_tet_ = -1) {
    const std::span<const int> around = tetsAround(fresh_[next_fresh_]);
    if (next_fresh_tet_ < 0) next_fresh_tet_ = 0;
    for (; next_fresh_tet_ < static_cast<int>(around.size()); ++next_fresh_tet_) {
      const int t = around[static_cast<size_t>(next_fresh_tet_)];
      if (decided_[static_cast<size_t>(t)] == stats_.incisions) continue;
      bool resolved = true;
      for (const int m : base_tets_[static_cast<size_t>(t)]) {
        const Resolve r = resolveNode(in, m, column, budget, step);
        if (r == Resolve::OutOfBudget) return false;  // resume at this tet next call
        resolved = resolved && r == Resolve::Done;
      }
      if (!resolved) continue;
      decided_[static_cast<size_t>(t)] = stats_.incisions;
      if (decideCut(in, t)) ++step.tets_cut, ++stats_.tets_cut;
    }
  }
  // The column's decisions are made: subdivide what they touched, then separate the cut's nodes.
  std::sort(affected_.begin(), affected_.end());
  affected_.erase(std::unique(affected_.begin(), affected_.end()), affected_.end());
  cut_points_.clear();
  for (const int t : affected_) subdivide(t, step);
  std::sort(cut_points_.begin(), cut_points_.end());
  cut_points_.erase(std::unique(cut_points_.begin(), cut_points_.end()), cut_points_.end());
  for (const int x : cut_points_) separate(x);
  column_started_ = false;
  return true;
}

void TetCutter::retryWaiting() {
  // A node that waits is tried at every column until it is bound or known to lie beyond the lattice, also
  // once no later column's box holds it (else its tets would never be decided: a bridge at the cut's rim).
  std::erase_if(waiting_, [this](int n) { return nodes_[static_cast<size_t>(n)].state != NodeState::Waiting; });
  candidates_.insert(candidates_.end(), waiting_.begin(), waiting_.end());
}

bspline::InversionResult TetCutter::canonicalInversion(const incision::Incision& in, const Eigen::Vector3d& x,
                                                       int column, const bspline::InversionResult& found) const {
  // Newton's last bits depend on its start, and the start on the column the node was resolved at (which
  // depends on how the calls grouped the samples): solved again from the start of the slab the node lies in,
  // a function of the node alone, so fast and real-time runs bind it to the same bits.
  const int own = static_cast<int>(std::floor(found.uvw[1]));
  if (own == column) return found;  // solved from that start already
  const Eigen::AlignedBox3d final_part(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(1.0, own + 1.0, 1.0));
  const bspline::InversionResult again = bspline::invertPoint(in.rest(), x, in.inversionGuess(x, own), final_part,
                                                              bspline::InversionOptions{12, 1e-10, 6});
  return again.converged && std::floor(again.uvw[1]) == own ? again : found;
}

TetCutter::Resolve TetCutter::resolveNode(const incision::Incision& in, int n, int column, core::WorkBudget& budget,
                                          TetStep& step) {
  Node& d = nodes_[static_cast<size_t>(n)];
  if (d.state != NodeState::Unknown && d.state != NodeState::Waiting) return Resolve::Done;
  if (d.state == NodeState::Waiting && column < d.retry) return Resolve::Later;
  const Eigen::Vector3d& x = rest_m_[static_cast<size_t>(n)];
  const Eigen::Vector3d guess = in.inversionGuess(x, column);
  const bool waited = d.state == NodeState::Waiting;
  const auto outside = [&] {
    touchNode(n);  // beyond the lattice: the guess tells the side; the node never moves
    d.state = NodeState::Outside;
    d.uvw = guess;
    // Distance to the cut from Eq. (2): u spans (l - 1) alpha across the lattice.
    const incision::IncisionOptions& o = in.options();
    const double distance_m = std::abs(guess[0] - 0.5) * (o.across_controls - 1) * o.alpha_m;
    d.sign = distance_m < snap_m_ ? 0 : guess[0] < 0.5 ? -1 : 1;
    if (d.sign == 0) ++stats_.snapped_nodes;
    // A node that kept tets waiting is fresh too: the tets around it are decided now that it is known.
    if (waited) fresh_.push_back(n);
    return Resolve::Done;
  };
  if (guess[0] <= 0.0 || guess[0] >= 1.0 || guess[2] <= 0.0 || guess[2] >= 1.0) return outside();
  // The last column of a finished incision: a node no inversion reached lies beyond the lattice.
  const bool last_column = in.finished() && column + 1 >= in.finalColumns();
  if (guess[1] >= column + 1.5 && !last_column) {  // a later slab's node: not before that slab's column
    touchNode(n);
    wait(n);
    d.retry = std::max(column + 1, static_cast<int>(std::floor(guess[1] - 1.5)) + 1);
    return Resolve::Later;
  }
  if (budget.spent()) return Resolve::OutOfBudget;
  budget.take();
  touchNode(n);
  // As SurfaceCutter::bindVertex: search only where F0 is final, so the result cannot depend on when.
  const Eigen::AlignedBox3d final_part(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(1.0, column + 1.0, 1.0));
  bspline::InversionResult r =
      bspline::invertPoint(in.rest(), x, guess, final_part, bspline::InversionOptions{12, 1e-10, 6});
  if (r.converged && r.uvw[1] < column + 1.0) r = canonicalInversion(in, x, column, r);
  if (r.converged && r.uvw[1] < column + 1.0) {
    d.state = NodeState::Bound;
    d.uvw = r.uvw;
    const double phi = r.uvw[0] - 0.5;
    // Distance to the cut ~ |phi| / |grad u|; grad u is the first row of the inverse Jacobian (computed
    // only near the cut: Eq. (2) spaces the u-planes about alpha apart, over (l - 1) alpha).
    const incision::IncisionOptions& o = in.options();
    bool snapped = false;
    if (std::abs(phi) * (o.across_controls - 1) * o.alpha_m < 4.0 * snap_m_) {
      const double grad_u = in.rest().jacobian(r.uvw).inverse().row(0).norm();
      snapped = std::isfinite(grad_u) && grad_u > 0.0 && std::abs(phi) / grad_u < snap_m_;
    }
    d.sign = snapped ? 0 : (phi < 0.0 ? -1 : 1);
    if (snapped) ++stats_.snapped_nodes;
    setSide(n, phi < 0.0 ? -1 : 1);
    ++step.nodes_bound;
    fresh_.push_back(n);
    return Resolve::Done;
  }
  // Still no convergence `order` columns after the slab the guess points to: beyond the lattice.
  if (column >= guess[1] + in.options().order || last_column) return outside();
  wait(n);
  d.retry = column + 1;
  return Resolve::Later;
}

void TetCutter::wait(int n) {
  Node& d = nodes_[static_cast<size_t>(n)];
  if (d.state != NodeState::Waiting) waiting_.push_back(n);
  d.state = NodeState::Waiting;
}

bool TetCutter::insideCut(const incision::Incision& in, const Eigen::Vector3d& uvw) const {
  // As SurfaceCutter::splitCrossings: after the stroke's start, above the blade's depth, up to the last
  // station once finished. Where the blade went through the tissue (the surface's groove stops short of
  // the far side and the surface cutter cuts through it), down the whole lattice (its rows scale with the
  // floor's depth, 0.8 of the thickness, so it reaches the far side where the thickness is the least of the
  // neighbourhood's, not where a rim thins it: there a bridge of tets can stay), and as far beyond a through
  // end as the surface's kerf reaches.
  const double v = uvw[1];
  const double reach = incision::SurfaceCutter::kKerfReachSpacings;  // in spacings: v's units
  const double first_v = in.startV() - (in.throughAt(in.startV()) ? reach : 0.0);
  const double last_v = in.lastStationV() + (in.throughAt(in.lastStationV()) ? reach : 0.0);
  const double w_limit = in.throughAt(v) ? 1.0 : in.bottomW() - 0.05 * (in.bottomW() - in.surfaceW());
  return v >= first_v && uvw[2] <= w_limit && (!in.finished() || v <= last_v);
}

Eigen::Vector3d TetCutter::crossingUvw(int a, int b, double& lambda) const {
  const Eigen::Vector3d& ua = nodes_[static_cast<size_t>(a)].uvw;
  const Eigen::Vector3d& ub = nodes_[static_cast<size_t>(b)].uvw;
  lambda = (0.5 - ua[0]) / (ub[0] - ua[0]);
  Eigen::Vector3d uvw = (1.0 - lambda) * ua + lambda * ub;
  uvw[0] = 0.5;
  return uvw;
}

bool TetCutter::decideCut(const incision::Incision& in, int t) {
  const auto& tet = base_tets_[static_cast<size_t>(t)];
  int plus = 0, minus = 0, zero = 0;
  for (const int n : tet) {
    const int s = nodes_[static_cast<size_t>(n)].sign;
    s > 0 ? ++plus : s < 0 ? ++minus : ++zero;
  }
  if (!((plus > 0 && minus > 0) || (zero == 3))) return false;
  // The tet is cut when its cut polygon reaches into the cut (one vertex inside is enough): the tet is cut
  // whole, so the tissue separates over the whole cut whatever the tets' size. The cut's rim then lies
  // just beyond it — below the blade, before the start, after the end — where the opening is 0.
  bool reaches = false;
  for (const int n : tet) {
    const Node& d = nodes_[static_cast<size_t>(n)];
    if (d.sign == 0) reaches = reaches || insideCut(in, d.uvw);
  }
  for (const auto& e : detail::kTetEdges) {
    const int a = std::min(tet[e[0]], tet[e[1]]), b = std::max(tet[e[0]], tet[e[1]]);
    if (nodes_[static_cast<size_t>(a)].sign * nodes_[static_cast<size_t>(b)].sign >= 0) continue;
    double lambda = 0.0;
    reaches = reaches || insideCut(in, crossingUvw(a, b, lambda));
  }
  if (!reaches) return false;
  tet_state_[static_cast<size_t>(t)] = 2;
  affected_.push_back(t);
  for (const int n : tet)
    if (nodes_[static_cast<size_t>(n)].sign == 0) nodes_[static_cast<size_t>(n)].cut_point = true;
  for (int e = 0; e < 6; ++e) {
    const int a = tet[detail::kTetEdges[e][0]], b = tet[detail::kTetEdges[e][1]];
    if (nodes_[static_cast<size_t>(a)].sign * nodes_[static_cast<size_t>(b)].sign >= 0) continue;
    const int edge = tet_edges_[static_cast<size_t>(t)][static_cast<size_t>(e)];
    if (edge_point_[static_cast<size_t>(edge)] >= 0) continue;
    edgePoint(edge);
    // Every tet around the edge now has a point on it: it must be subdivided to stay conforming.
    const std::span<const int> lo = tetsAround(edges_[static_cast<size_t>(edge)][0]),
                               hi = tetsAround(edges_[static_cast<size_t>(edge)][1]);
    std::set_intersection(lo.begin(), lo.end(), hi.begin(), hi.end(), std::back_inserter(affected_));
  }
  return true;
}

int TetCutter::edgePoint(int edge) {
  const int a = edges_[static_cast<size_t>(edge)][0], b = edges_[static_cast<size_t>(edge)][1];
  double lambda = 0.0;
  const Eigen::Vector3d uvw = crossingUvw(a, b, lambda);
  const Eigen::Vector3d rest =
      (1.0 - lambda) * rest_m_[static_cast<size_t>(a)] + lambda * rest_m_[static_cast<size_t>(b)];
  const int id = addNode(rest, uvw, NodeState::EdgePoint, 2);
  nodes_[static_cast<size_t>(id)].cut_point = true;
  nodes_[static_cast<size_t>(id)].support = edge;
  edge_point_[static_cast<size_t>(edge)] = id;
  ++stats_.edge_points;
  return id;
}

int TetCutter::addNode(const Eigen::Vector3d& rest_m, const Eigen::Vector3d& uvw, NodeState state, int side) {
  const int id = static_cast<int>(nodes_.size());
  countGrowth(nodes_, 1);
  node_tets_first_.push_back(0);  // no tets yet: a rebase gives it its own list
  node_tets_count_.push_back(0);
  node_tets_cap_.push_back(0);
  in_grid_.push_back(0);
  rest_m_.push_back(rest_m);
  deformed_m_.push_back(rest_m);
  Node d;
  d.uvw = uvw;
  d.state = state;
  d.origin = id;
  nodes_.push_back(d);
  setSide(id, side);
  nodeChanged(id);
  return id;
}

// Steiner points of one base tet: one per piece side, reused when the tet is subdivided again.
struct TetCutter::SteinerNodes final : detail::SteinerSink {
  SteinerNodes(TetCutter& cutter, int tet) : cutter_(cutter), tet_(tet) {}
  int add(const Eigen::Vector3d& x_m, int side) override { return cutter_.steinerNode(tet_, x_m, side); }
  TetCutter& cutter_;
  int tet_;
};

int TetCutter::steinerNode(int t, const Eigen::Vector3d& x_m, int side) {
  const auto& tet = base_tets_[static_cast<size_t>(t)];
  int& slot = steiner_[static_cast<size_t>(t)][static_cast<size_t>(side + 1)];
  // Parameters by barycentric interpolation of the tet's nodes.
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    m.col(i) = rest_m_[static_cast<size_t>(tet[static_cast<size_t>(i + 1)])] - rest_m_[static_cast<size_t>(tet[0])];
  const Eigen::Vector3d b = m.partialPivLu().solve(x_m - rest_m_[static_cast<size_t>(tet[0])]);
  Eigen::Vector3d uvw = (1.0 - b.sum()) * nodes_[static_cast<size_t>(tet[0])].uvw;
  for (int i = 0; i < 3; ++i) uvw += b[i] * nodes_[static_cast<size_t>(tet[static_cast<size_t>(i + 1)])].uvw;
  const int move_side = side != 0 ? side : (uvw[0] < 0.5 ? -1 : 1);
  if (slot < 0) {
    slot = addNode(x_m, uvw, NodeState::Steiner, move_side);
    ++stats_.steiner_nodes;
  } else {
    rest_m_[static_cast<size_t>(slot)] = x_m;
    nodes_[static_cast<size_t>(slot)].uvw = uvw;
    setSide(slot, move_side);
  }
  return slot;
}

void TetCutter::subdivide(int t, TetStep& step) {
  const auto& tet = base_tets_[static_cast<size_t>(t)];
  detail::SplitInput input;
  input.cut = tet_state_[static_cast<size_t>(t)] == 2;
  for (int i = 0; i < 4; ++i) {
    const int n = tet[static_cast<size_t>(i)];
    input.nodes[static_cast<size_t>(i)] = {n, rest_m_[static_cast<size_t>(n)], nodes_[static_cast<size_t>(n)].sign};
  }
  for (int e = 0; e < 6; ++e) {
    const int p = edge_point_[static_cast<size_t>(tet_edges_[static_cast<size_t>(t)][static_cast<size_t>(e)])];
    if (p >= 0) input.edge_points[static_cast<size_t>(e)] = {p, rest_m_[static_cast<size_t>(p)], 0};
  }
  SteinerNodes sink(*this, t);
  detail::SubTet out[detail::kMaxChildren];
  const detail::SplitResult r = detail::splitTet(input, sink, out);
  if (r.degenerate)
    fail("TetCutter: splitting tet " + std::to_string(t) + " leaves a flat tet (volume " +
         std::to_string(r.min_volume_m3) + " m^3); the cutter stops");
  int& first = child_first_[static_cast<size_t>(t)];
  const int old_count = child_count_[static_cast<size_t>(t)];
  if (r.count > old_count) {
    countGrowth(children_, static_cast<size_t>(r.count));
    first = static_cast<int>(children_.size()), children_.resize(children_.size() + static_cast<size_t>(r.count));
  }
  for (int c = 0; c < r.count; ++c) {
    children_[static_cast<size_t>(first + c)] = Child{out[c].nodes, out[c].side, out[c].cut_faces};
    for (const int n : out[c].nodes)
      if (nodes_[static_cast<size_t>(n)].cut_point) cut_points_.push_back(n);
  }
  child_count_[static_cast<size_t>(t)] = static_cast<std::uint8_t>(r.count);
  tet_count_ += r.count - old_count;
  baseTetChanged(t);
  if (tet_state_[static_cast<size_t>(t)] == 0) tet_state_[static_cast<size_t>(t)] = 1;
  ++step.tets_subdivided;
}

TetView TetCutter::view(TetShape shape) const {
  const bool deformed = shape == TetShape::Deformed;
  TetView v;
  std::vector<int> remap(nodes_.size(), -1);
  for (size_t t = 0; t < base_tets_.size(); ++t)
    for (int c = child_first_[t]; c < child_first_[t] + child_count_[t]; ++c)
      for (const int n : children_[static_cast<size_t>(c)].nodes) remap[static_cast<size_t>(n)] = 0;
  const std::vector<Eigen::Vector3d>& x = deformed ? deformed_m_ : rest_m_;
  for (size_t n = 0; n < nodes_.size(); ++n) {
    if (remap[n] != 0) continue;
    remap[n] = static_cast<int>(v.mesh.nodes_m.size());
    v.mesh.nodes_m.push_back(x[n]);
    const Node& d = nodes_[n];
    v.node_cut.push_back(d.state == NodeState::Copy ? 2 : !d.cut_point ? 0 : d.side == -1 ? 1 : 3);
  }
  v.mesh.tets.reserve(static_cast<size_t>(tet_count_));
  for (size_t t = 0; t < base_tets_.size(); ++t)
    for (int c = child_first_[t]; c < child_first_[t] + child_count_[t]; ++c) {
      const Child& ch = children_[static_cast<size_t>(c)];
      v.mesh.tets.push_back({remap[static_cast<size_t>(ch.nodes[0])], remap[static_cast<size_t>(ch.nodes[1])],
                             remap[static_cast<size_t>(ch.nodes[2])], remap[static_cast<size_t>(ch.nodes[3])]});
      v.side.push_back(ch.side);
      v.split.push_back(tet_state_[t] == 0 ? 0 : tet_state_[t] == 2 ? 1 : 2);
    }
  TetMesh rest;  // quality of the split tets is judged at rest
  if (deformed) rest = view(TetShape::Rest).mesh;
  const TetMesh& at_rest = deformed ? rest : v.mesh;
  for (size_t t = 0; t < v.mesh.tets.size(); ++t) {
    if (tetVolume(v.mesh, static_cast<int>(t)) <= 0.0) ++v.inverted_tets;
    if (v.split[t] == 0) continue;
    v.min_split_dihedral_deg = std::min(v.min_split_dihedral_deg, tetMinDihedralAngleDeg(at_rest, static_cast<int>(t)));
    v.min_split_volume_m3 = std::min(v.min_split_volume_m3, tetVolume(at_rest, static_cast<int>(t)));
  }
  buildAdjacency(v.mesh);
  return v;
}

}  // namespace incise::tets
