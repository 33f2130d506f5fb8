// The surface cutter's per-incision figures once its work is done (surface_cutter.h, IncisionFigures): where
// the groove runs along the stroke, how many lattice columns held no vertex, and why a groove is much
// shorter than its stroke (Shortfall), with the sentence a user reads. The incision's steps are in
// surface_cutter.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "incise/incision/surface_cutter.h"

namespace incise::incision {

namespace {

// Millimetres with one decimal, for sentences ("35.0 mm").
std::string mm(double length_m) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f mm", 1e3 * length_m);
  return text;
}

Shortfall classify(const IncisionFigures& f, bool failed, bool no_contact) {
  if (failed) return Shortfall::Failed;
  if (no_contact) return Shortfall::NoContact;
  // Shorter than the lattice needs, the wound never opens (a groove, if cut, is a slit whose walls lie on
  // each other).
  if (f.stroke_length_m > 0.0 && f.stroke_length_m < f.min_stroke_m) return Shortfall::TooShort;
  const double tolerance_m = std::max(f.min_stroke_m, 0.2 * f.stroke_length_m);
  const bool short_groove =
      f.groove_length_m + tolerance_m < f.stroke_length_m || (f.groove_length_m == 0.0 && f.stroke_length_m > 0.0);
  if (!short_groove) return Shortfall::None;
  if (f.columns > 0 && 4 * f.empty_columns >= f.columns) return Shortfall::CoarseMesh;
  if (f.inversions_failed > 0) return Shortfall::InversionFailed;
  if (f.seam_vertices == 0) return Shortfall::NoCrossing;
  if (2 * f.seam_vertices_chained < f.seam_vertices) return Shortfall::SeamBroken;
  return Shortfall::Unexplained;
}

std::string reason(const IncisionFigures& f) {
  switch (f.shortfall) {
    case Shortfall::None:
      return "";
    case Shortfall::Failed:
      return "an internal failure stopped the incision (see the cut's failure)";
    case Shortfall::NoContact:
      return "no contact: the blade's first point is not on the surface";
    case Shortfall::TooShort:
      return "the stroke is shorter than the " + mm(f.min_stroke_m) + " the lattice needs to open a groove";
    case Shortfall::CoarseMesh:
      return "the mesh is coarse next to the lattice: " + std::to_string(f.empty_columns) + " of " +
             std::to_string(f.columns) + " lattice columns along the stroke held no vertex (the first at " +
             mm(f.first_empty_at_m) + " along the stroke); its mean edge is " + mm(f.mean_edge_m) + ", the lattice " +
             mm(f.lattice_width_m) + " across: subdivide the mesh or refine it along the stroke";
    case Shortfall::InversionFailed:
      return "inversion failed on " + std::to_string(f.inversions_failed) +
             " vertices inside the lattice (their parameters were not found)";
    case Shortfall::NoCrossing:
      return "no edge crossed the cut inside the blade's window (" + std::to_string(f.crossings_outside) +
             " crossings lay outside it: below the blade's depth or beyond the stroke's ends)";
    case Shortfall::SeamBroken:
      return "the seam broke: " + std::to_string(f.seam_vertices - f.seam_vertices_chained) + " of " +
             std::to_string(f.seam_vertices) + " seam vertices are not joined to the groove by mesh edges";
    case Shortfall::Unexplained:
      return "no cause found";
  }
  return "";
}

}  // namespace

const char* toString(ThroughCut through) noexcept {
  switch (through) {
    case ThroughCut::None:
      return "none";
    case ThroughCut::Made:
      return "made";
    case ThroughCut::Failed:
      return "failed";
  }
  return "unknown";
}

const char* toString(Shortfall shortfall) noexcept {
  switch (shortfall) {
    case Shortfall::None:
      return "none";
    case Shortfall::Failed:
      return "failed";
    case Shortfall::NoContact:
      return "no_contact";
    case Shortfall::TooShort:
      return "too_short";
    case Shortfall::CoarseMesh:
      return "coarse_mesh";
    case Shortfall::InversionFailed:
      return "inversion_failed";
    case Shortfall::NoCrossing:
      return "no_crossing";
    case Shortfall::SeamBroken:
      return "seam_broken";
    case Shortfall::Unexplained:
      return "unexplained";
  }
  return "unknown";
}

std::string describeShortfall(const IncisionFigures& f) {
  if (f.shortfall == Shortfall::None) return "";
  std::string where = f.seam_vertices_chained > 0
                          ? "; it runs from " + mm(f.groove_start_m) + " to " + mm(f.groove_end_m) + " along the stroke"
                          : "";
  return "a groove of " + mm(f.groove_length_m) + " along " + mm(f.stroke_length_m) +
         " of stroke in contact: " + reason(f) + where;
}

void SurfaceCutter::diagnose() noexcept {
  IncisionFigures& f = stats_.figures.back();
  f.done = true;
  f.row_limited_stations = incision_->rowLimitedStations();
  f.stroke_length_m = incision_->pathLength();
  const double spacing_m = options_.incision.spacing_m;
  const double start_v = incision_->startV(), end_v = incision_->lastStationV();
  const int last = std::min(static_cast<int>(std::ceil(end_v)), static_cast<int>(cell_first_.size()));
  for (int c = static_cast<int>(std::floor(start_v)); c < last; ++c) {
    ++f.columns;
    if (!cellEmpty(c)) continue;
    if (f.empty_columns++ == 0) f.first_empty_at_m = std::max(0.0, (c - start_v) * spacing_m);
  }
  double v0 = INFINITY, v1 = -INFINITY;
  for (std::size_t i = 0; i < chain_.size(); ++i) {
    v0 = std::min(v0, data(chain_[i]).uvw[1]);
    v1 = std::max(v1, data(chain_[i]).uvw[1]);
  }
  if (!chain_.empty()) {
    f.groove_start_m = std::max(0.0, (v0 - start_v) * spacing_m);
    f.groove_end_m = std::max(0.0, (v1 - start_v) * spacing_m);
  }
  f.seam_vertices_chained = static_cast<int>(chain_.size());
  f.mean_edge_m = mean_edge_m_;
  const IncisionOptions& o = options_.incision;
  f.lattice_width_m = (o.across_controls - 1) * o.alpha_m;
  f.min_stroke_m = (incision_->minOpeningStations() - 1) * spacing_m;
  f.shortfall = classify(f, failed_, no_contact_);
}

}  // namespace incise::incision
