// The cut against the plan (score.h, "the cut against the plan"): the groove's wall vertices binned along
// the plan, lateral deviation and depth per bin, and the figures over the plan's length.
#include <algorithm>
#include <cmath>
#include <optional>

#include "incise/mesh/surface_mesh.h"
#include "incise/sim/score.h"

namespace incise::sim {

namespace {

struct BinSums {
  int count = 0;
  double lateral_sum_m = 0.0;
  double deepest_m = 0.0;
};

// Each wall face of the groove (both walls, from the lip to the bottom, between consecutive wall columns)
// covers the bins whose centres lie within its vertices' span along the plan (at least the bin of its
// centroid): the walls tile the groove, so a bin is cut when a face covers it, whatever the mesh's
// resolution. Lateral: the covering faces' centroids (the two walls are symmetric about the groove's centre
// line); depth: their deepest vertex (the V's bottom).
std::vector<BinSums> binWallFaces(const Plan& plan, const mesh::SurfaceMesh& cut, double bin_m, double capture_m) {
  std::vector<BinSums> sums(static_cast<std::size_t>(std::ceil(plan.length_m / bin_m - 1e-9)));
  const mesh::TriMesh& mesh = cut.mesh();
  std::vector<std::optional<PlanLocation>> located(mesh.n_vertices());
  const auto at = [&](mesh::TriMesh::VertexHandle v) -> const PlanLocation& {
    auto& slot = located[static_cast<std::size_t>(v.idx())];
    if (!slot) slot = locate(plan, mesh::toEigen(mesh.point(v)));
    return *slot;
  };
  for (const auto f : mesh.faces()) {
    if (cut.kind(f) != mesh::FaceKind::Wall) continue;
    double s_lo = plan.length_m, s_hi = 0.0, s_sum = 0.0, lateral_sum = 0.0, deepest = 0.0;
    bool inside = true;
    for (const auto v : mesh.fv_range(f)) {
      const PlanLocation& p = at(v);
      inside = inside && p.beyond_m <= 0.5 * bin_m && std::abs(p.lateral_m) <= capture_m;
      s_lo = std::min(s_lo, p.s_m), s_hi = std::max(s_hi, p.s_m), s_sum += p.s_m;
      lateral_sum += p.lateral_m;
      deepest = std::max(deepest, -p.height_m);
    }
    if (!inside) continue;
    const auto binOf = [&](double s_m) {
      return std::min(sums.size() - 1, static_cast<std::size_t>(std::max(0.0, s_m / bin_m)));
    };
    std::size_t first = static_cast<std::size_t>(std::max(0.0, std::ceil(s_lo / bin_m - 0.5)));
    std::size_t last = binOf(s_hi - 0.5 * bin_m);
    if (s_hi - 0.5 * bin_m < 0.0 || first > last) first = last = binOf(s_sum / 3.0);
    for (std::size_t i = first; i <= last && i < sums.size(); ++i) {
      ++sums[i].count;
      sums[i].lateral_sum_m += lateral_sum / 3.0;
      sums[i].deepest_m = std::max(sums[i].deepest_m, deepest);
    }
  }
  return sums;
}

double captureOf(const Plan& plan, const ScoreOptions& options) {
  return options.capture_m > 0.0 ? options.capture_m : 5.0 * plan.lateral_tolerance_m;
}

// The bins' length: the plan cut into equal bins of at most one station spacing.
double binLength(const Plan& plan) {
  const std::size_t count = static_cast<std::size_t>(std::ceil(plan.length_m / plan.station_m - 1e-9));
  return plan.length_m / static_cast<double>(std::max<std::size_t>(1, count));
}

}  // namespace

void scoreBladeDepth(const Plan& plan, const std::vector<ScoreFrame>& frames, const ScoreOptions& options,
                     PlanScore& score) {
  const double bin_m = binLength(plan), capture_m = captureOf(plan, options);
  for (const ScoreFrame& f : frames) {
    if (!f.cutting || !f.new_pose || score.bins.empty()) continue;
    const PlanLocation at = locate(plan, f.contact_m);
    if (at.beyond_m > 0.5 * bin_m || std::abs(at.lateral_m) > capture_m) continue;
    PlanBin& bin = score.bins[std::min(score.bins.size() - 1, static_cast<std::size_t>(std::max(0.0, at.s_m / bin_m)))];
    bin.blade_depth_m = bin.blade_seen ? std::max(bin.blade_depth_m, f.penetration_m) : f.penetration_m;
    bin.blade_seen = true;
  }
  int seen = 0;
  double error_sum = 0.0;
  for (const PlanBin& bin : score.bins) {
    if (!bin.blade_seen) continue;
    ++seen;
    error_sum += std::abs(bin.blade_depth_m - plan.depth_m);
    score.blade_depth_max_overshoot_m = std::max(score.blade_depth_max_overshoot_m, bin.blade_depth_m - plan.depth_m);
  }
  if (seen > 0) score.blade_depth_mean_abs_error_m = error_sum / seen;
}

PlanScore scoreCut(const Plan& plan, const mesh::SurfaceMesh& cut, double groove_length_m,
                   const ScoreOptions& options) {
  PlanScore s;
  s.length_m = plan.length_m;
  s.target_depth_m = plan.depth_m;
  s.lateral_tolerance_m = plan.lateral_tolerance_m;
  s.depth_tolerance_m = plan.depth_tolerance_m;
  const double capture_m = captureOf(plan, options);
  const double bin_m = binLength(plan);
  const std::vector<BinSums> sums = binWallFaces(plan, cut, bin_m, capture_m);
  int cut_bins = 0, lateral_ok = 0, depth_ok = 0;
  double lateral_abs = 0.0, lateral_sq = 0.0, depth_abs = 0.0;
  for (std::size_t i = 0; i < sums.size(); ++i) {
    PlanBin bin;
    bin.s_m = (static_cast<double>(i) + 0.5) * bin_m;
    bin.cut = sums[i].count > 0;
    if (bin.cut) {
      bin.lateral_m = sums[i].lateral_sum_m / sums[i].count;
      bin.depth_m = sums[i].deepest_m;
      const double error_m = bin.depth_m - plan.depth_m;
      ++cut_bins;
      lateral_abs += std::abs(bin.lateral_m);
      lateral_sq += bin.lateral_m * bin.lateral_m;
      s.lateral_max_m = std::max(s.lateral_max_m, std::abs(bin.lateral_m));
      depth_abs += std::abs(error_m);
      s.depth_max_overshoot_m = std::max(s.depth_max_overshoot_m, error_m);
      lateral_ok += std::abs(bin.lateral_m) <= plan.lateral_tolerance_m ? 1 : 0;
      depth_ok += std::abs(error_m) <= plan.depth_tolerance_m ? 1 : 0;
    }
    s.bins.push_back(bin);
  }
  const double bins = static_cast<double>(std::max<std::size_t>(1, sums.size()));
  if (cut_bins > 0) {
    s.lateral_mean_abs_m = lateral_abs / cut_bins;
    s.lateral_rms_m = std::sqrt(lateral_sq / cut_bins);
    s.depth_mean_abs_error_m = depth_abs / cut_bins;
  }
  s.share_uncut = 1.0 - cut_bins / bins;
  s.share_within_lateral_tolerance = lateral_ok / bins;
  s.share_within_depth_tolerance = depth_ok / bins;
  s.length_cut_outside_band_m = std::max(0.0, groove_length_m - lateral_ok * bin_m);
  return s;
}

}  // namespace incise::sim
