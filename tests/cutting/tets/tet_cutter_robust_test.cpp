// The tet cutter on tissues and strokes nobody tuned it for: a tetrahedralised skin pad cut
// exactly along its top's grid lines, along the diagonals, within rounding of a grid line and along random
// strokes (seeded). After every cut: conforming at rest and deformed, every tet positive, no sliver among
// the split tets (smallest dihedral angle above half a degree), the volume kept at rest, no failure.
#include "incise/tets/tet_cutter.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <sstream>

#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/shapes.h"
#include "incise/tets/tetrahedralize.h"

using namespace incise;
using namespace incise::tets;

namespace {

struct PadTissue {
  mesh::SurfaceMesh surface = mesh::makeSkinPad(Eigen::Vector3d(0.04, 0.012, 0.04), 0.001);
  TetMesh tets;
  PadTissue() {
    TetrahedralizeOptions o;
    o.max_volume_m3 = 1e-9;
    tets = tetrahedralize(surface, o);
  }
};

const PadTissue& pad() {
  static const PadTissue t;
  return t;
}

void cutPad(const incision::StrokePathOptions& path, const std::string& what) {
  INFO(what);
  const PadTissue& tissue = pad();
  mesh::SurfaceMesh surface = tissue.surface;
  incision::SurfaceCutter cutter(surface, incision::CutterOptions{});
  TetCutter tets(tissue.tets, TetCutterOptions{});
  const incision::Stroke stroke = incision::strokeAlongPath(surface, path);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const incision::StrokeSample& s : stroke.samples) {
    cutter.extend(s);
    tets.follow(*cutter.incision(), cutter.stats().incisions);
  }
  cutter.finish();
  cutter.advance(1e9);
  while (cutter.pending()) cutter.advance(1e9);
  tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  REQUIRE_FALSE(tets.pending());
  REQUIRE(cutter.stats().figures.back().shortfall == incision::Shortfall::None);
  const TetCutStats& stats = tets.stats();
  INFO(stats.failure);
  REQUIRE(stats.failure.empty());
  REQUIRE(stats.tets_cut > 20);
  const double original = volume(tissue.tets);
  for (const TetShape shape : {TetShape::Rest, TetShape::Deformed}) {
    const TetView v = tets.view(shape);
    const TetCheck check = checkConforming(v.mesh);
    INFO(check.first_problem);
    REQUIRE(check.conforming);
    REQUIRE(v.inverted_tets == 0);
    if (shape == TetShape::Rest) {
      REQUIRE(std::abs(volume(v.mesh) - original) <= 1e-9 * original);
      REQUIRE(v.min_split_volume_m3 > 0);
      REQUIRE(v.min_split_dihedral_deg > 0.5);
    }
  }
}

incision::StrokePathOptions padPath(Eigen::Vector3d start_m, Eigen::Vector3d direction, double length_m) {
  incision::StrokePathOptions path;
  path.start_m = start_m;
  path.direction = direction.normalized();
  path.length_m = length_m;
  return path;
}

}  // namespace

TEST_CASE("tet_cutter: a tet pad cut along its grid lines, diagonals and within rounding stays conforming",
          "[cutting]") {
  cutPad(padPath({-0.012, 0.05, 0.0}, Eigen::Vector3d::UnitX(), 0.024), "along a grid line");
  cutPad(padPath({-0.012, 0.05, 1e-12}, Eigen::Vector3d::UnitX(), 0.024), "within rounding of a grid line");
  cutPad(padPath({-0.01, 0.05, -0.01}, Eigen::Vector3d(1, 0, 1), 0.024), "along the diagonals");
  cutPad(padPath({-0.012, 0.05, 0.00025}, Eigen::Vector3d::UnitX(), 0.024), "0.25 mm beside a grid line");
}

TEST_CASE("tet_cutter: property: random strokes over a tet pad stay conforming, every tet positive", "[cutting]") {
  std::mt19937 rng(1414);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    const double angle = 2.0 * M_PI * unit(rng), length_m = 0.008 + 0.012 * unit(rng);
    const Eigen::Vector3d direction(std::cos(angle), 0.0, std::sin(angle));
    const Eigen::Vector3d start(-0.5 * length_m * direction.x() + 0.004 * (unit(rng) - 0.5), 0.05,
                                -0.5 * length_m * direction.z() + 0.004 * (unit(rng) - 0.5));
    std::ostringstream what;
    what << "case " << i << ": start " << start.transpose() << ", direction " << direction.transpose() << ", length "
         << length_m;
    cutPad(padPath(start, direction, length_m), what.str());
  }
}
