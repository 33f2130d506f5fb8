#include "incise/incision/surface_cutter.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "incise/bspline/volume_inversion.h"
#include "incise/mesh/thickness.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

namespace {

using detail::FH;
using detail::VH;

}  // namespace

SurfaceCutter::SurfaceCutter(mesh::SurfaceMesh& mesh, const CutterOptions& options)
    : mesh_(mesh), options_(options), grid_(1.0), coarse_grid_(1.0) {
  textured_ = mesh.hasTexCoords();
  if (options.max_inversions_per_call < 0)
    throw std::invalid_argument("SurfaceCutter: max_inversions_per_call = " +
                                std::to_string(options.max_inversions_per_call) + " must be >= 0");
  if (options.wall_rows < 1 || options.wall_rows > 64)
    throw std::invalid_argument("SurfaceCutter: wall_rows = " + std::to_string(options.wall_rows) +
                                " is outside [1, 64]");
  if (!(options.snap_fraction >= 0.0 && options.snap_fraction < 0.5))
    throw std::invalid_argument("SurfaceCutter: snap_fraction = " + std::to_string(options.snap_fraction) +
                                " is outside [0, 0.5)");
  if (!(options.contact_tolerance_m >= 0.0))
    throw std::invalid_argument("SurfaceCutter: contact_tolerance_m must be >= 0");
  if (!(options.refine_edge_m >= 0.0 && std::isfinite(options.refine_edge_m)))
    throw std::invalid_argument("SurfaceCutter: refine_edge_m must be finite and >= 0 (0: the default)");
  if (options.max_refine_splits_per_column < 0)
    throw std::invalid_argument("SurfaceCutter: max_refine_splits_per_column = " +
                                std::to_string(options.max_refine_splits_per_column) + " must be >= 0");
  if (options.reserved_bound_vertices < 64)
    throw std::invalid_argument("SurfaceCutter: reserved_bound_vertices = " +
                                std::to_string(options.reserved_bound_vertices) + " must be >= 64");
  Incision::validateOptions(options.incision);
  const mesh::ManifoldReport report = mesh::checkManifold(mesh.mesh());
  if (!report.closed_two_manifold)
    throw mesh::MeshError("SurfaceCutter: the tissue surface is not a closed two-manifold: " + report.first_problem);
  mesh::TriMesh& m = mesh_.mesh();
  m.add_property(vertex_data_, "incise:cutter");
  m.add_property(rest_parent_, "incise:rest_parent");
  stats_.figures.reserve(CutStats::kReservedIncisions);
  const mesh::EdgeLengths edges = mesh::edgeLengths(m);
  const double edge_m = edges.mean_m;
  mean_edge_m_ = edge_m;
  contact_tolerance_m_ = options.contact_tolerance_m > 0.0 ? options.contact_tolerance_m : 3.0 * edge_m;
  longest_edge_m_ = edges.longest_m;
  refine_edge_m_ = refineEdgeLength(options);
  refine_query_.reserve(1 << 14);
  refine_faces_.reserve(1 << 15);
  // Cells about a lattice column wide: a column step's query box spans a few cells per axis whatever the
  // mesh's resolution (tiny cells would make the query probe thousands of empty cells on a 1M mesh). With
  // refinement, the mesh along the cut becomes as fine as refine_edge_m whatever it was: cells for that.
  const IncisionOptions& io = options.incision;
  const bool refine = options.refine != CutterOptions::Refine::Off;
  const double cell_edge_m = refine ? std::min(edge_m, refine_edge_m_) : edge_m;
  grid_ = mesh::VertexGrid(std::max({2.0 * cell_edge_m, 0.5 * io.order * io.spacing_m, 1e-9}));
  for (const auto v : m.vertices()) grid_.insert(v.idx(), mesh::toEigen(m.point(v)));
  row_probe_.rays = std::make_unique<mesh::SurfaceRays>(m);
  thickness_below_m_ = mesh::thicknessBelowVertices(m, *row_probe_.rays, io.depth_m / kFloorOfThickness, kSkinM);
  coarse_grid_ = mesh::VertexGrid(std::max({2.0 * edge_m, 0.5 * io.order * io.spacing_m, 1e-9}));
  if (refine) initCoarse();
  reserveHeadroom();  // after every property is added: OpenMesh reserves the properties there are
  reserveIncisionArrays();
}

void SurfaceCutter::recordChanges(bool on) {
  record_changes_ = on;
  changes_.clear();
  if (on) {
    changes_.vertices.reserve(kReservedChanges);
    changes_.faces.reserve(kReservedChanges);
  }
}

bool SurfaceCutter::onSurface(const Eigen::Vector3d& p) const {
  // Near vertices first: on a mesh refined along the cut, a box of the whole tolerance (3 coarse edges)
  // holds hundreds of refined vertices; where one is within a refined edge, that settles it.
  const double near_m = std::min(contact_tolerance_m_, 2.0 * refine_edge_m_);
  for (const double radius_m : {near_m, contact_tolerance_m_}) {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(radius_m);
    query_.clear();
    grid_.query(Eigen::AlignedBox3d(p - r, p + r), query_);
    for (int id : query_)  // rest positions, as intersect(): independent of the cut's progress
      if ((restPosition(VH(id)) - p).norm() <= contact_tolerance_m_) return true;
  }
  return false;
}

bool SurfaceCutter::inWound(const Eigen::Vector3d& p) const {
  const double reach_m = 1.5 * options_.incision.spacing_m;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(reach_m);
  query_.clear();
  grid_.query(Eigen::AlignedBox3d(p - r, p + r), query_);
  for (int id : query_)
    if (mesh_.kind(VH(id)) != mesh::VertexKind::Original && (restPosition(VH(id)) - p).norm() <= reach_m) return true;
  return false;
}

void SurfaceCutter::settle() noexcept { settleStep(true); }

bool SurfaceCutter::settleStep(bool unlimited) noexcept {
  if (active()) finish(FinishWork::Later);
  if (!incision_) return true;
  // The incision's carried work is done (within this call's budget unless unlimited), and its wound set to
  // its final, settled opening: a state that depends on the samples alone, not on how far frames had
  // advanced its time response when the next stroke began, nor on how many calls the work took (the work's
  // order does not depend on the budget).
  time_s_ = std::numeric_limits<double>::max();
  unlimited_ = unlimited;
  process(CutStep{});
  unlimited_ = false;
  return !pending();
}

CutStep SurfaceCutter::begin(const StrokeSample& first, const Eigen::Vector3d& blade_direction) noexcept {
  settle();  // a new lattice replaces the previous incision's
  CutStep refused;
  if (!first.point_m.allFinite() || !first.normal.allFinite() || !std::isfinite(first.time_s) ||
      !blade_direction.allFinite()) {
    refused.sample = SampleStatus::RefusedNaN;
    return refused;
  }
  if (first.normal.norm() < 1e-12 || blade_direction.cross(first.normal).norm() < 1e-12 * blade_direction.norm()) {
    refused.sample = SampleStatus::RefusedNormal;
    return refused;
  }
  // The lattice: the previous incision's, settled above, or the one made at construction, started over.
  const bool had_previous = incision_ != nullptr;
  std::unique_ptr<Incision> incision = had_previous ? std::move(incision_) : std::move(spare_);
  try {
    if (!incision) incision = std::make_unique<Incision>(options_.incision, first, blade_direction);
    incision->limitRows(&row_probe_);  // before its first station
    incision->restart(first, blade_direction);
  } catch (const std::exception& e) {                   // the sample was checked above: only allocation is left
    if (had_previous) incision_ = std::move(incision);  // a throwing restart changed nothing
    fail(std::string("SurfaceCutter::begin: ") + e.what());
    refused.failed = true;
    return refused;
  }
  reserveHeadroom();
  if (had_previous) {  // what prepareBegin() has not done of the previous incision's re-indexing
    core::WorkBudget all = core::WorkBudget::unlimited();
    try {
      reindexStep(all);
    } catch (const std::exception& e) {  // an entry not in the grid: a broken invariant
      fail(std::string("SurfaceCutter::begin: ") + e.what());
    }
  }
  incision_ = std::move(incision);
  ++incision_index_;
  ++stats_.incisions;
  stats_.figures.push_back({});
  next_column_ = options_.incision.order - 1;  // the first slab of the v domain
  column_started_ = false;
  last_query_units_ = 0;
  refining_ = false;
  seam_capped_ = false;
  time_s_ = first.time_s;
  std::fill(cell_first_.begin(), cell_first_.end(), -1);
  std::fill(cell_last_.begin(), cell_last_.end(), -1);
  std::fill(cell_count_.begin(), cell_count_.end(), 0);
  cell_next_.clear();
  cell_vertex_.clear();
  all_bound_.clear();
  reindexed_moves_ = reindexed_coarse_ = 0;
  seam_created_.clear();
  column_seam_begin_ = previous_seam_begin_ = 0;
  chain_.reset(4 * static_cast<std::size_t>(options_.incision.max_columns));
  wall_columns_used_ = 0;
  strips_used_ = 0;
  dirty_.clear();
  stencil_count_.clear();
  stencil_first_.clear();
  stencil_basis_.clear();
  stats_.seam_vertices = 0;
  failed_ = false;
  jumped_ = false;
  thickness_ = {};
  through_.clear();
  through_last_ = through_done_ = false;
  CutStep step;
  no_contact_ = !onSurface(first.point_m);
  if (no_contact_) {
    step.left_surface = true;
    incision_->finish();
  } else if (StrokeSample limited = first; limitToThickness(limited)) {
    incision_->restart(limited, blade_direction);  // checked above: cannot throw
    noteThrough();
  }
  return process(step);
}

CutStep SurfaceCutter::extend(const StrokeSample& sample) noexcept { return extend(std::span(&sample, 1)); }

CutStep SurfaceCutter::extend(std::span<const StrokeSample> samples) noexcept { return process(add(samples)); }

CutStep SurfaceCutter::addSample(const StrokeSample& sample, SampleOrigin origin) noexcept {
  return add(std::span(&sample, 1), origin);
}

CutStep SurfaceCutter::add(std::span<const StrokeSample> samples, SampleOrigin origin) noexcept {
  CutStep step;
  if (!active()) {
    step.sample = SampleStatus::Ended;
    return step;
  }
  for (const StrokeSample& sample : samples) {
    if (!sample.point_m.allFinite()) {
      step.sample = SampleStatus::RefusedNaN;
      continue;
    }
    if (origin == SampleOrigin::Unchecked && !onSurface(sample.point_m)) {
      step.left_surface = true;
      incision_->finish();
      break;
    }
    StrokeSample limited = sample;
    limitToThickness(limited);
    limited.in_wound = inWound(limited.point_m);
    step.sample = incision_->extend(limited);
    if (step.sample == SampleStatus::Accepted) {
      noteThrough();
      time_s_ = std::max(time_s_, sample.time_s);
      stats_.figures.back().stroke_length_m = incision_->pathLength();
    }
    // One sample far from the stroke is a glitch, skipped; two in a row, the blade is elsewhere: the
    // incision ends (the caller may begin another there).
    if (step.sample == SampleStatus::SkippedJump && std::exchange(jumped_, true)) {
      step.left_surface = true;
      incision_->finish();
      break;
    }
    if (step.sample == SampleStatus::Accepted) jumped_ = false;
    if (step.sample == SampleStatus::Ended || step.sample == SampleStatus::EndedAtCorner) break;
  }
  return step;
}

CutStep SurfaceCutter::advance(double t_s) noexcept {
  CutStep step;
  if (!incision_ || failed_ || !std::isfinite(t_s)) return step;
  time_s_ = std::max(time_s_, t_s);
  return process(step);
}

CutStep SurfaceCutter::finish(FinishWork work) noexcept {
  CutStep step;
  if (!incision_) return step;
  incision_->finish();
  return work == FinishWork::Now ? process(step) : step;
}

CutStep SurfaceCutter::process(CutStep step) noexcept {
  if (!incision_ || failed_) {
    step.failed = failed_;
    return step;
  }
  // A through-cut outstanding: nothing else is done until it is applied (the worker reads the tissue).
  if (!throughStep(unlimited_)) return step;
  try {
    // Column steps in order, each resumable: a call stops when its inversion budget is spent and the next
    // call carries on where it stopped, so the work done (and so the mesh) does not depend on the budget.
    core::WorkBudget budget =
        unlimited_ ? core::WorkBudget::unlimited() : core::WorkBudget(options_.max_inversions_per_call, deadline_);
    // The wound's opening at this call's time first (it depends on the samples and the time only): the
    // vertices it moves are known before the columns' work, and charged (redeform() moves them at the end).
    changed_columns_.clear();
    incision_->updateOpening(time_s_, changed_columns_);
    if (!unlimited_ && options_.max_inversions_per_call > 0) {
      const int units = std::min(redeformMoves() / kMovesPerUnit, options_.max_inversions_per_call / 2);
      if (units > 0) budget.take(units);
    }
    while (next_column_ < incision_->finalColumns() && !failed_ && !budget.spent()) {
      if (!processColumn(next_column_, budget, step)) break;
      ++next_column_;
      walkChain();
      promoteInterior(step);
    }
    step.deadline_hit = budget.deadlineHit();
    // A seam vertex whose faces waited for a later column's vertices (sidesKnown) is opened at the end,
    // once the seam reaches the cut's ends.
    if (allColumnsDone()) {
      capSeamEnds(step);
      promoteInterior(step);
    }
    redeform(step);
    // The wound at its final opening: where the blade went through, its path is cut through now (at the
    // same simulated time whatever the frames' timing: the first call after the last station settles).
    if (allColumnsDone() && incision_->woundSettled() && !through_done_ && !through_.empty()) cutThrough();
  } catch (const std::exception& e) {  // allocation failure or a broken invariant: stop, never throw
    fail(std::string("SurfaceCutter: ") + e.what());
  }
  stats_.seam_vertices = static_cast<int>(chain_.size());
  if (step.vertices_duplicated > 0) stats_.figures.back().groove_length_m = grooveLength();
  const bool through_waits = through_state_.load(std::memory_order_acquire) != ThroughState::None;
  if ((failed_ || allColumnsDone()) && !stats_.figures.back().done && !through_waits) diagnose();
  step.failed = failed_;
  return step;
}

void SurfaceCutter::fail(const std::string& message) {
  failed_ = true;
  if (stats_.failure.empty()) stats_.failure = message;
  if (incision_) incision_->finish();
}

bool SurfaceCutter::bindVertex(VH v, int column, core::WorkBudget& budget) {
  const Eigen::Vector3d x = mesh::toEigen(mesh_.mesh().point(v));
  const Eigen::Vector3d guess = incision_->inversionGuess(x, column);
  // Eq. (2) read backwards is close to F0's inverse: points clearly across or beyond the lattice, or in
  // a later slab, are not worth a Newton solve now.
  if (guess[0] <= 0.0 || guess[0] >= 1.0 || guess[2] <= 0.0 || guess[2] >= 1.0 || guess[1] >= column + 1.5)
    return false;
  budget.take();
  // Search only where F0 is final (v < column + 1), so the result cannot depend on columns that are still
  // extrapolated, i.e. on when this step runs.
  const Eigen::AlignedBox3d final_part(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(1.0, column + 1.0, 1.0));
  // A point beyond the final part cannot converge: few halvings end that search early.
  const bspline::InversionResult r =
      bspline::invertPoint(incision_->rest(), x, guess, final_part, bspline::InversionOptions{12, 1e-10, 6});
  // Only the slab whose lattice is final is bound here; a vertex further on waits for its own column.
  if (!r.converged && guess[1] >= column && guess[1] < column + 1.0) ++stats_.figures.back().inversions_failed;
  if (!r.converged || r.uvw[1] >= column + 1.0) return false;
  VertexData& d = data(v);
  d = VertexData{};
  d.uvw = r.uvw;
  d.rest_m = x;
  d.incision = incision_index_;
  d.side = r.uvw[0] < 0.5 ? -1 : 1;
  setStencil(v);
  if (options_.snap_fraction > 0.0 && insideCut(r.uvw) && nearCut(v, r.uvw)) snapOntoCut(v);  // no sliver
  addToCell(static_cast<int>(std::floor(r.uvw[1])), v);
  pushReserved(all_bound_, v);
  pushReserved(dirty_, v);
  return true;
}

bool SurfaceCutter::processColumn(int column, core::WorkBudget& budget, CutStep& step) {
  if (!column_started_) {
    // The column's query costs about what the previous column's did: it waits for a call with that much
    // budget left, unless this call has done nothing yet (a query larger than a whole budget still runs).
    if (!budget.affords(last_query_units_)) return false;
    column_started_ = true;
    ++step.columns;
    previous_seam_begin_ = std::exchange(column_seam_begin_, seam_created_.size());
    candidates_.clear();
    fresh_.clear();
    next_candidate_ = 0;
    // Before any of the column's vertices is bound, the faces it will cut are made fine enough.
    refining_ = options_.refine != CutterOptions::Refine::Off && beginRefine(column);
    if (!refining_) queryColumn(column, budget);
  }
  if (refining_) {
    // Paused and resumed in the same order whatever the budget (nothing else changes the mesh meanwhile).
    if (!continueRefine(budget, step)) return false;
    refining_ = false;
    queryColumn(column, budget);
  }
  for (; next_candidate_ < candidates_.size(); ++next_candidate_) {
    const VH v(candidates_[next_candidate_]);
    if (mesh_.mesh().status(v).deleted() || bound(v)) continue;
    if (budget.spent()) return false;  // resume here next call
    if (bindVertex(v, column, budget)) pushReserved(fresh_, v), ++step.vertices_bound;
  }
  // The crossings' split and the seam's walk after it grow with the vertices bound in the column: charged
  // too, they wait for a call with that much budget left (unless this call has done nothing yet).
  const int finish_units = 1 + static_cast<int>(fresh_.size() / kFreshPerUnit);
  if (!budget.affords(finish_units)) return false;
  budget.take(finish_units);
  splitCrossings(fresh_, step);
  relieveSlivers(previous_seam_begin_);
  column_started_ = false;
  return true;
}

void SurfaceCutter::queryColumn(int column, core::WorkBudget& budget) {
  grid_.query(incision_->columnBox(column), candidates_);  // ascending ids
  last_query_units_ = 1 + static_cast<int>(candidates_.size() / kCandidatesPerUnit);
  budget.take(last_query_units_);
}

void SurfaceCutter::snapNearEnd(mesh::TriMesh::EdgeHandle e) {
  const mesh::TriMesh& m = mesh_.mesh();
  const auto h = m.halfedge_handle(e, 0);
  const VH a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
  const VertexData& da = data(a);
  const VertexData& db = data(b);
  if (da.side == 0 || db.side == 0) return;  // an end point is on the cut already
  const double lambda = (0.5 - da.uvw[0]) / (db.uvw[0] - da.uvw[0]);
  Eigen::Vector3d uvw = (1.0 - lambda) * da.uvw + lambda * db.uvw;
  uvw[0] = 0.5;
  if (!insideCut(uvw)) return;
  const double ab_m = (db.rest_m - da.rest_m).norm();
  if (lambda * ab_m < snapDistance(a)) {
    snapOntoCut(a);
  } else if ((1.0 - lambda) * ab_m < snapDistance(b)) {
    snapOntoCut(b);
  }
}

bool SurfaceCutter::insideCut(const Eigen::Vector3d& uvw) const noexcept {
  const double w_limit = incision_->bottomW() - 0.05 * (incision_->bottomW() - incision_->surfaceW());
  return uvw[1] >= incision_->startV() && uvw[2] <= w_limit &&
         (!incision_->finished() || uvw[1] <= incision_->lastStationV());
}

double SurfaceCutter::snapDistance(VH v) const {
  const mesh::TriMesh& m = mesh_.mesh();
  double shortest_m = std::numeric_limits<double>::infinity();
  // At rest for this incision (as intersect()): not where the opening has moved the neighbours so far.
  const Eigen::Vector3d x = restPosition(v);
  for (auto n = m.cvv_iter(v); n.is_valid(); ++n) shortest_m = std::min(shortest_m, (restPosition(*n) - x).norm());
  return std::isfinite(shortest_m) ? options_.snap_fraction * shortest_m : 0.0;
}

bool SurfaceCutter::nearCut(VH v, const Eigen::Vector3d& uvw) const {
  // As TetCutter: the distance to the cut is about |u - 1/2| / |grad u|, grad u the first row of F0's
  // inverse Jacobian, computed only near the cut (Eq. (2) spaces the u-planes over (l - 1) alpha).
  // Most bound vertices are far from the cut: ruled out against the largest snap distance (a tenth of the
  // longest edge) before their own edges are measured.
  const double phi = std::abs(uvw[0] - 0.5);
  const IncisionOptions& o = options_.incision;
  const double across_m = phi * (o.across_controls - 1) * o.alpha_m;
  if (across_m >= 4.0 * options_.snap_fraction * longest_edge_m_) return false;
  const double snap_m = snapDistance(v);
  if (across_m >= 4.0 * snap_m) return false;
  const double grad_u = incision_->rest().jacobian(uvw).inverse().row(0).norm();
  return std::isfinite(grad_u) && grad_u > 0.0 && phi / grad_u < snap_m;
}

void SurfaceCutter::snapOntoCut(VH v) {
  VertexData& d = data(v);
  d.uvw[0] = 0.5;
  d.side = 0;
  d.seam = true;
  pushReserved(seam_created_, v);
  ++stats_.vertices_snapped;
  ++stats_.figures.back().seam_vertices;
  if (mesh_.kind(v) == mesh::VertexKind::Original) mesh_.setKind(v, mesh::VertexKind::Seam);
  setStencil(v);
  pushReserved(dirty_, v);  // an end point snapped after its bind: moved (and journalled) with its new stencil
}

VH SurfaceCutter::addBoundVertex(const Eigen::Vector3d& rest_m, const Eigen::Vector3d& uvw, int side,
                                 mesh::VertexKind kind) {
  const VH v = mesh_.addVertex(rest_m, kind);
  VertexData& d = data(v);
  d = VertexData{};
  d.uvw = uvw;
  d.rest_m = rest_m;
  d.incision = incision_index_;
  d.side = static_cast<std::int8_t>(side);
  setStencil(v);
  addToCell(static_cast<int>(std::clamp(std::floor(uvw[1]), 0.0, double(cell_first_.size() - 1))), v);
  pushReserved(all_bound_, v);
  pushReserved(dirty_, v);
  grid_.insert(v.idx(), rest_m);
  vertexChanged(v);
  return v;
}

void SurfaceCutter::splitCrossings(const std::vector<VH>& fresh, CutStep& step) {
  mesh::TriMesh& m = mesh_.mesh();
  std::vector<Crossing>& crossings = crossings_;
  crossings.clear();
  for (const VH a : fresh) {
    for (auto h = m.voh_iter(a); h.is_valid(); ++h) {
      const VH b = m.to_vertex_handle(*h);
      if (!bound(b)) continue;
      const int sa = data(a).side, sb = data(b).side;
      if (!((sa == -1 && sb == 1) || (sa == 1 && sb == -1))) continue;
      pushReserved(crossings, Crossing{std::max(data(a).uvw[1], data(b).uvw[1]), m.edge_handle(*h).idx()});
    }
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& x, const Crossing& y) { return x.key != y.key ? x.key < y.key : x.edge < y.edge; });
  crossings.erase(std::unique(crossings.begin(), crossings.end(),
                              [](const Crossing& x, const Crossing& y) { return x.edge == y.edge; }),
                  crossings.end());
  // A crossing within the snap distance of an end point puts that end point on the cut instead (one the
  // bind left off it: just outside the cut's window, or found near only along this edge); its edges then
  // cross no more. Done for all the column's crossings before any split, so the order does not matter.
  if (options_.snap_fraction > 0.0)
    for (const Crossing& c : crossings) snapNearEnd(mesh::TriMesh::EdgeHandle(c.edge));
  for (const Crossing& c : crossings) {
    const mesh::TriMesh::EdgeHandle e(c.edge);
    const auto h = m.halfedge_handle(e, 0);
    const VH a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
    const VertexData& da = data(a);
    const VertexData& db = data(b);
    if (da.side == 0 || db.side == 0) {
      ++stats_.splits_avoided;
      continue;
    }
    const double lambda = (0.5 - da.uvw[0]) / (db.uvw[0] - da.uvw[0]);
    Eigen::Vector3d uvw = (1.0 - lambda) * da.uvw + lambda * db.uvw;
    uvw[0] = 0.5;
    if (!insideCut(uvw)) {
      ++stats_.skipped_crossings;
      ++stats_.figures.back().crossings_outside;
      continue;
    }
    pushReserved(seam_created_, splitAtCut(e));
    ++step.edges_split;
  }
}

void SurfaceCutter::setStencil(VH v) {
  VertexData& d = data(v);
  const int size = incision_->stencilSize();
  if (d.stencil < 0) {
    d.stencil = static_cast<int>(stencil_count_.size());
    pushReserved(stencil_count_, std::uint8_t{0});
    if (stencil_first_.size() + 2 > stencil_first_.capacity()) ++stats_.reserve_overflows;
    stencil_first_.resize(stencil_first_.size() + 2);
    if (stencil_basis_.size() + 2 * static_cast<size_t>(size) > stencil_basis_.capacity()) ++stats_.reserve_overflows;
    stencil_basis_.resize(stencil_basis_.size() + 2 * static_cast<size_t>(size));
  }
  const size_t s = static_cast<size_t>(d.stencil);
  // A seam vertex not (yet) duplicated lies on the cut between its two sides: it moves with their mean, as
  // the bottom of the walls and the tets' crack front do.
  const int side = d.side == 0 ? 2 : d.side;
  stencil_count_[s] = static_cast<std::uint8_t>(
      incision_->stencil(d.uvw, side, &stencil_first_[2 * s], &stencil_basis_[2 * s * static_cast<size_t>(size)]));
}

// Moves the vertices of the columns process() found changed (updateOpening) and those bound in this call.
void SurfaceCutter::redeform(CutStep& step) {
  if (++stamp_ == 0) stamp_ = 1;
  mesh::TriMesh& m = mesh_.mesh();
  const auto move = [&](VH v) {
    VertexData& d = data(v);
    if (d.stamp == stamp_ || m.status(v).deleted()) return;
    d.stamp = stamp_;
    const size_t s = static_cast<size_t>(d.stencil);
    const Eigen::Vector3d x = d.rest_m + incision_->displacementFromStencil(
                                             stencil_count_[s], &stencil_first_[2 * s],
                                             &stencil_basis_[2 * s * static_cast<size_t>(incision_->stencilSize())]);
    m.set_point(v, mesh::toOpenMesh(x));
    vertexChanged(v);
    ++step.vertices_moved;
  };
  const int order = options_.incision.order;
  const int cells = static_cast<int>(cell_first_.size());
  for (const int column : changed_columns_)
    for (int cell = column; cell < std::min(column + order, cells); ++cell)
      for (int i = cell_first_[static_cast<size_t>(cell)]; i >= 0; i = cell_next_[static_cast<size_t>(i)])
        move(cell_vertex_[static_cast<size_t>(i)]);
  for (const VH v : dirty_) move(v);
  dirty_.clear();
}

Eigen::Vector3d SurfaceCutter::restPosition(VH v) const {
  return bound(v) ? data(v).rest_m : mesh::toEigen(mesh_.mesh().point(v));
}

std::optional<SurfaceCutter::Binding> SurfaceCutter::binding(mesh::TriMesh::VertexHandle v) const {
  if (!v.is_valid() || v.idx() >= static_cast<int>(mesh_.mesh().n_vertices()) || !bound(v)) return std::nullopt;
  const VertexData& d = data(v);
  return Binding{d.uvw, d.rest_m, d.side};
}

}  // namespace incise::incision
