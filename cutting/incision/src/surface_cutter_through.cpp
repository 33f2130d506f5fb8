// The surface cutter on thin tissue (surface_cutter.h): the groove's depth limited by the tissue's thickness
// under the stroke (limitToThickness), and cuts through it (cutThrough): where the blade's tip passed the
// tissue's far side, its path is removed down through that side once the incision has settled, so the far
// skin is split too and a piece cut free is closed on its own.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/solid.h"
#include "surface_cutter_internal.h"

namespace incise::incision {
namespace {

using detail::VH;

// The kerf: a thin box swept along `centres` (at rest, on the skin), its cross-section at each station a
// rectangle across the stroke (`side`, kerf wide) from `top_m` above the skin down to `bottom_m[i]` along
// `down`; closed by its two end rectangles, oriented outward.
mesh::SurfaceMesh sweptKerf(const std::vector<Eigen::Vector3d>& centres, const std::vector<Eigen::Vector3d>& sides,
                            const std::vector<double>& bottom_m, const Eigen::Vector3d& down, double top_m,
                            double kerf_m) {
  mesh::SurfaceMesh kerf;
  const std::size_t n = centres.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d half = 0.5 * kerf_m * sides[i], top = centres[i] - top_m * down,
                          bottom = centres[i] + bottom_m[i] * down;
    for (const Eigen::Vector3d& p :
         std::array<Eigen::Vector3d, 4>{top - half, top + half, bottom + half, bottom - half})
      kerf.addVertex(p);
  }
  std::vector<std::array<int, 3>> faces;
  const auto quad = [&faces](int a, int b, int c, int d) {
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
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
  const mesh::TriMesh& m = kerf.mesh();
  for (const auto& f : faces) {
    const Eigen::Vector3d a = mesh::toEigen(m.point(VH(f[0]))), b = mesh::toEigen(m.point(VH(f[1]))),
                          c = mesh::toEigen(m.point(VH(f[2])));
    volume += a.dot(b.cross(c));
  }
  for (const auto& f : faces)
    volume > 0 ? kerf.addFace(VH(f[0]), VH(f[1]), VH(f[2])) : kerf.addFace(VH(f[0]), VH(f[2]), VH(f[1]));
  kerf.mesh().update_normals();
  return kerf;
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
  IncisionFigures& figures = stats_.figures.back();
  // Runs of through samples: a gap of more than twice the kerf's reach between two parts the runs.
  const double gap_m = 2.0 * kKerfReachSpacings * options_.incision.spacing_m;
  bool made = true;
  for (std::size_t first = 0; first < through_.size();) {
    std::size_t last = first + 1;
    while (last < through_.size() && (through_[last].point_m - through_[last - 1].point_m).norm() <= gap_m) ++last;
    made = subtractKerf(first, last) && made;
    first = last;
  }
  figures.through = made ? ThroughCut::Made : ThroughCut::Failed;
  const std::vector<mesh::Piece> parts = mesh::pieces(mesh_.mesh());
  figures.pieces = static_cast<int>(parts.size());
  for (std::size_t i = 0; i < parts.size() && i < figures.piece_volumes_m3.size(); ++i)
    figures.piece_volumes_m3[i] = parts[i].volume_m3;
}

bool SurfaceCutter::subtractKerf(std::size_t first, std::size_t last) {
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
  if (ahead.norm() < 1e-12) return true;  // the blade went straight down: nothing to sweep
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
  const mesh::SurfaceMesh kerf = sweptKerf(centres, sides, bottom_m, down, top_m, kKerfM);
  std::vector<int> vertices, faces;
  const int old_vertices = static_cast<int>(mesh_.mesh().n_vertices());
  // Where the grid holds each vertex: a bound one at rest until prepareBegin() re-indexes it.
  std::vector<Eigen::Vector3d> held(static_cast<std::size_t>(old_vertices));
  for (const auto v : mesh_.mesh().vertices())
    held[static_cast<std::size_t>(v.idx())] = bound(v) ? data(v).rest_m : mesh::toEigen(mesh_.mesh().point(v));
  const mesh::SubtractResult result = mesh::subtractSolid(mesh_, kerf, &vertices, &faces);
  if (!result.ok) {
    if (stats_.failure.empty()) stats_.failure = "the cut through the tissue was refused: " + result.message;
    return false;
  }
  mesh::TriMesh& m = mesh_.mesh();
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  for (const int id : vertices) {
    const VH v(id);
    if (id >= old_vertices) {
      if (!m.status(v).deleted()) {
        data(v) = VertexData{};
        grid_.insert(id, mesh::toEigen(m.point(v)));
      }
    } else if (m.status(v).deleted()) {
      grid_.remove(id, held[static_cast<std::size_t>(id)]);
    }
    vertexChanged(v);
  }
  for (const int id : faces) faceChanged(mesh::TriMesh::FaceHandle(id));
  return true;
}

}  // namespace incise::incision
