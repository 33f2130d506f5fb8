// The surface cutter on thin tissue (surface_cutter.h): the groove's depth limited by the tissue's thickness
// under the stroke (limitToThickness), and cuts through it (cutThrough): where the blade's tip passed the
// tissue's far side, its path is removed down through that side once the incision has settled, so the far
// skin is split too and a piece cut free is closed on its own.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/solid.h"
#include "surface_cutter_internal.h"

namespace incise::incision {
namespace {

using detail::VH;

// The kerf: a thin box swept along `centres` (at rest, on the skin), its cross-section at each station a
// rectangle across the stroke (`side`, kerf wide) from `top_m` above the skin down to `bottom_m[i]` along
// `down`; closed by its two end rectangles, oriented outward. Appended to `solid` as a component of its own.
void appendSweptKerf(mesh::SurfaceMesh& solid, const std::vector<Eigen::Vector3d>& centres,
                     const std::vector<Eigen::Vector3d>& sides, const std::vector<double>& bottom_m,
                     const Eigen::Vector3d& down, double top_m, double kerf_m) {
  const int base = static_cast<int>(solid.mesh().n_vertices());
  const std::size_t n = centres.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d half = 0.5 * kerf_m * sides[i], top = centres[i] - top_m * down,
                          bottom = centres[i] + bottom_m[i] * down;
    for (const Eigen::Vector3d& p :
         std::array<Eigen::Vector3d, 4>{top - half, top + half, bottom + half, bottom - half})
      solid.addVertex(p);
  }
  std::vector<std::array<int, 3>> faces;
  const auto quad = [&faces, base](int a, int b, int c, int d) {
    faces.push_back({base + a, base + b, base + c});
    faces.push_back({base + a, base + c, base + d});
  };
  for (int i = 0; i + 1 < static_cast<int>(n); ++i)
    for (int k = 0; k < 4; ++k) {
      const int a = 4 * i + k, b = 4 * i + (k + 1) % 4;
      quad(a, b, b + 4, a + 4);
    }
  const int last = 4 * (static_cast<int>(n) - 1);
  quad(3, 2, 1, 0);
  quad(last, last + 1, last + 2, last + 3);
  double volume = 0.0;
  const mesh::TriMesh& m = solid.mesh();
  for (const auto& f : faces) {
    const Eigen::Vector3d a = mesh::toEigen(m.point(VH(f[0]))), b = mesh::toEigen(m.point(VH(f[1]))),
                          c = mesh::toEigen(m.point(VH(f[2])));
    volume += a.dot(b.cross(c));
  }
  for (const auto& f : faces)
    volume > 0 ? solid.addFace(VH(f[0]), VH(f[1]), VH(f[2])) : solid.addFace(VH(f[0]), VH(f[2]), VH(f[1]));
}

}  // namespace

bool SurfaceCutter::limitToThickness(StrokeSample& sample) noexcept {
  const IncisionOptions& o = options_.incision;
  if (sample.depth_m > kClampedOver * o.depth_m) ++stats_.figures.back().depth_clamped_samples;
  const double want_m = sample.depth_m >= 0.0 ? std::clamp(sample.depth_m, o.min_depth_m, o.depth_m) : o.depth_m;
  const double thickness_m = thicknessBelow(sample);
  through_last_ = false;
  if (!(want_m > kFloorOfThickness * thickness_m)) return false;
  if (want_m >= thickness_m) {
    through_last_ = sample.through = true;
    last_through_ = ThroughSample{sample.point_m, sample.normal, want_m, thickness_m};
  }
  sample.depth_m = std::max(o.min_depth_m, kFloorOfThickness * thickness_m);
  ++stats_.figures.back().thickness_limited_samples;
  return true;
}

double SurfaceCutter::RowProbe::rowDepth(const Eigen::Vector3d& point_m, const Eigen::Vector3d& inward,
                                         double want_m) const noexcept {
  if (!rays) return want_m;
  const double tissue_m = rays->firstCrossing(point_m + kSkinM * inward, inward, want_m / kFloorOfThickness);
  // A micrometre's slack: a sample limitToThickness() limited (from the thickness below the vertices, kept
  // as floats) is not limited again by its rounding.
  constexpr double kSlackM = 1e-6;
  const double allowed_m = kFloorOfThickness * (tissue_m + kSkinM);
  return want_m <= allowed_m + kSlackM ? want_m : allowed_m;
}

double SurfaceCutter::thicknessBelow(const StrokeSample& sample) noexcept {
  // The last answer holds within a lattice spacing (the stations' own resolution).
  ThicknessProbe& c = thickness_;
  if (c.valid && (sample.point_m - c.at_m).norm() < options_.incision.spacing_m) return c.thickness_m;
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const mesh::TriMesh& m = mesh_.mesh();
  for (const double radius_m : {mean_edge_m_, longest_edge_m_}) {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(radius_m);
    query_.clear();
    try {
      grid_.query(Eigen::AlignedBox3d(sample.point_m - r, sample.point_m + r), query_);
    } catch (...) {  // allocation in the grid query: leave the depth as it is
      return kNone;
    }
    bool found = false;
    double thinnest_m = kNone;
    for (const int id : query_) {
      if (static_cast<size_t>(id) >= thickness_below_m_.size() || m.status(VH(id)).deleted()) continue;
      found = true;
      thinnest_m = std::min(thinnest_m, static_cast<double>(thickness_below_m_[static_cast<size_t>(id)]));
    }
    if (found) {
      c = {true, sample.point_m, thinnest_m};
      return thinnest_m;
    }
  }
  return kNone;
}

void SurfaceCutter::noteThrough() {
  if (!through_last_) return;
  through_last_ = false;
  pushReserved(through_, last_through_);
  ++stats_.figures.back().through_samples;
}

void SurfaceCutter::cutThrough() {
  through_done_ = true;
  if (through_on_worker_ && !unlimited_) {
    through_state_.store(ThroughState::Due, std::memory_order_release);  // postThrough() hands it over
    return;
  }
  computeThroughPatch();
  applyThrough();
}

bool SurfaceCutter::postThrough() noexcept {
  ThroughState due = ThroughState::Due;
  return through_state_.compare_exchange_strong(due, ThroughState::Posted, std::memory_order_acq_rel);
}

void SurfaceCutter::computeThrough() noexcept {
  ThroughState posted = ThroughState::Posted;
  if (!through_state_.compare_exchange_strong(posted, ThroughState::Running, std::memory_order_acq_rel)) return;
  computeThroughPatch();
  through_by_worker_ = true;  // published with Ready
  through_state_.store(ThroughState::Ready, std::memory_order_release);
}

bool SurfaceCutter::throughStep(bool unlimited) noexcept {
  ThroughState state = through_state_.load(std::memory_order_acquire);
  if (state == ThroughState::None) return true;
  if (!unlimited && state != ThroughState::Ready) return false;
  // Unlimited: not yet taken by the worker, it is computed here; taken, it is waited for.
  while (state == ThroughState::Due || state == ThroughState::Posted) {
    if (through_state_.compare_exchange_weak(state, ThroughState::Running, std::memory_order_acq_rel)) {
      computeThroughPatch();
      through_state_.store(ThroughState::Ready, std::memory_order_release);
    }
    state = through_state_.load(std::memory_order_acquire);
  }
  while (through_state_.load(std::memory_order_acquire) != ThroughState::Ready) std::this_thread::yield();
  if (through_by_worker_) ++stats_.through_on_worker;
  through_by_worker_ = false;
  applyThrough();
  through_state_.store(ThroughState::None, std::memory_order_release);
  return true;
}

void SurfaceCutter::computeThroughPatch() noexcept {
  try {
    // Runs of through samples: a gap of more than twice the kerf's reach between two parts the runs; each
    // run's kerf is a component of one solid, removed by one Boolean difference.
    const double gap_m = 2.0 * kKerfReachSpacings * options_.incision.spacing_m;
    mesh::SurfaceMesh kerfs;
    for (std::size_t first = 0; first < through_.size();) {
      std::size_t last = first + 1;
      while (last < through_.size() && (through_[last].point_m - through_[last - 1].point_m).norm() <= gap_m) ++last;
      appendKerf(kerfs, first, last);
      first = last;
    }
    if (kerfs.mesh().n_faces() == 0) {  // the blade went straight down: nothing to sweep
      through_patch_ = mesh::SolidDifference{};
      through_patch_.ok = true;
      through_patch_.vertices_before = static_cast<int>(mesh_.mesh().n_vertices());
      through_patch_.faces_before = static_cast<int>(mesh_.mesh().n_faces());
      through_patch_.pieces = mesh::pieces(mesh_.mesh());
      return;
    }
    kerfs.mesh().update_normals();
    through_patch_ = mesh::differenceOf(mesh_, kerfs);
    if (!through_patch_.ok) through_patch_.pieces = mesh::pieces(mesh_.mesh());  // the tissue as it stays
  } catch (const std::exception&) {                                              // allocation failure
    through_patch_.ok = false;
  }
}

void SurfaceCutter::appendKerf(mesh::SurfaceMesh& kerfs, std::size_t first, std::size_t last) const {
  const double spacing_m = options_.incision.spacing_m;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t i = first; i < last; ++i) normal += through_[i].normal.normalized();
  const Eigen::Vector3d down = -normal.normalized();
  const auto across = [&down](const Eigen::Vector3d& v) { return Eigen::Vector3d(v - v.dot(down) * down); };
  // Stations at least half a spacing apart across `down`, each with its depth: past the far side by a
  // quarter of the thickness (the thickness is the least of the neighbourhood's) and at least the tip's.
  std::vector<Eigen::Vector3d> centres, sides;
  std::vector<double> bottom_m;
  for (std::size_t i = first; i < last; ++i) {
    const ThroughSample& s = through_[i];
    if (!centres.empty() && across(s.point_m - centres.back()).norm() < 0.5 * spacing_m) continue;
    centres.push_back(s.point_m);
    bottom_m.push_back(std::max(s.depth_m, 1.25 * s.thickness_m + 1e-4));
  }
  Eigen::Vector3d ahead =
      centres.size() > 1 ? across(centres.back() - centres.front()) : across(incision_->bladeDirection());
  if (ahead.norm() < 1e-12) return;
  ahead.normalize();
  const double reach_m = kKerfReachSpacings * spacing_m;
  centres.insert(centres.begin(), centres.front() - reach_m * ahead);
  bottom_m.insert(bottom_m.begin(), bottom_m.front());
  centres.push_back(centres.back() + reach_m * ahead);
  bottom_m.push_back(bottom_m.back());
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const Eigen::Vector3d tangent =
        across(centres[std::min(i + 1, centres.size() - 1)] - centres[i == 0 ? 0 : i - 1]).normalized();
    sides.push_back(down.cross(tangent).normalized());
  }
  const double top_m = std::max(1e-3, options_.incision.opening_m);
  appendSweptKerf(kerfs, centres, sides, bottom_m, down, top_m, kKerfM);
}

void SurfaceCutter::applyThrough() noexcept {
  IncisionFigures& figures = stats_.figures.back();
  const mesh::SolidDifference& d = through_patch_;
  const mesh::SubtractResult result = mesh::applyDifference(mesh_, d);
  figures.through = result.ok ? ThroughCut::Made : ThroughCut::Failed;
  figures.pieces = static_cast<int>(d.pieces.size());
  for (std::size_t i = 0; i < d.pieces.size() && i < figures.piece_volumes_m3.size(); ++i)
    figures.piece_volumes_m3[i] = d.pieces[i].volume_m3;
  if (!result.ok) {
    if (stats_.failure.empty()) {
      try {
        stats_.failure = "the cut through the tissue was refused: " +
                         (d.message.empty() ? std::string("the tissue changed while it was computed") : d.message);
      } catch (...) {  // no memory for the message: the figure says it failed
      }
    }
    return;
  }
  // The grid indexes the new vertices and forgets the deleted ones (a bound one at rest until
  // prepareBegin() re-indexes it).
  mesh::TriMesh& m = mesh_.mesh();
  for (const int id : d.touched_vertices) {
    const VH v(id);
    if (id >= d.vertices_before) {
      if (!m.status(v).deleted()) {
        data(v) = VertexData{};
        grid_.insert(id, mesh::toEigen(m.point(v)));
      }
    } else if (m.status(v).deleted()) {
      grid_.remove(id, bound(v) ? data(v).rest_m : mesh::toEigen(m.point(v)));
    }
    vertexChanged(v);
  }
  for (const int f : d.removed_faces) faceChanged(mesh::TriMesh::FaceHandle(f));
  for (int i = 0; i < static_cast<int>(d.added_faces.size()); ++i)
    faceChanged(mesh::TriMesh::FaceHandle(d.faces_before + i));
}

}  // namespace incise::incision
