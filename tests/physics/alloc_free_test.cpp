// The physics thread's work allocates nothing in steady state: TissueModel::step, contactModel, locate and restMap,
// and apply() of a cut within the model's reserve. Every heap allocation on this thread is counted
// (alloc_counter.h: operator new and the malloc family replaced in this test executable only) while a step,
// a contact model or an apply() runs; the tet cutter and the journal's collection (the sim thread's work)
// are not counted.
#include <catch2/catch.hpp>

#include <cstdint>

#include "alloc_counter.h"
#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/shapes.h"
#include "incise/physics/cut_changes.h"
#include "incise/physics/grid_tets.h"
#include "incise/physics/tissue_model.h"
#include "incise/tets/tet_cutter.h"

namespace incise::physics {
namespace {

using test::allocationsOnThisThread;
using test::CountAllocations;

TEST_CASE("alloc_free: a tissue's steps, contact models and cuts allocate nothing on the physics thread", "[physics]") {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.005, -0.01, 0.0), Eigen::Vector3d(0.005, 0.0, 0.014));
  const Eigen::Vector3i cells(5, 5, 7);
  const tets::TetMesh tissue = gridTets(box, cells);
  mesh::SurfaceMesh surface = mesh::makeBox(box, cells);
  Boundary boundary;
  boundary.fixed_boxes = {{Eigen::Vector3d(-1, -1, -1e-9), Eigen::Vector3d(1, 1, 1e-9)}};
  TissueModel model(tissue, Material{}, boundary);
  const std::optional<Embedded> point = model.locate(Eigen::Vector3d(0.002, -0.0005, 0.01));
  REQUIRE(point);

  incision::StrokePathOptions path;
  path.start_m = Eigen::Vector3d(0.0003, 0.05, 0.003);
  path.direction = Eigen::Vector3d::UnitZ();
  path.length_m = 0.008;
  const incision::Stroke stroke = incision::strokeAlongPath(surface, path);
  incision::CutterOptions options;
  options.refine = incision::CutterOptions::Refine::Off;
  incision::SurfaceCutter cutter(surface, options);
  tets::TetCutter tets(tissue);
  tets.recordChanges(true);
  CutChanges changes;
  changes.reserve(1 << 12, 1 << 12, 1 << 14);

  std::int64_t allocations = 0;
  int steps = 0, applied = 0, added = 0;
  // One physics frame: the cut's changes so far, a press, a step, the contact model; only the model's work counted.
  const auto frame = [&](bool count) {
    changes.clear();
    collectCutChanges(tets, tets.changes(), changes);
    tets.clearChanges();
    test::resetAllocationCount();
    StepStatus status;
    {
      CountAllocations counting(count);
      if (!changes.empty()) added += model.apply(changes).elements_added, ++applied;
      if (const std::optional<Embedded> at = model.locate(Eigen::Vector3d(0.004, 0.0, 0.004)))  // a press
        model.setToolPress(*at, Eigen::Vector3d::UnitY(), Eigen::Vector3d(0.004, -0.001, 0.004), 400.0);
      status = model.step(0.005).status;
      model.contactModel(*point, Eigen::Vector3d::UnitY());
      model.locate(Eigen::Vector3d(-0.001, -0.003, 0.005));
      model.restMap(Eigen::Vector3d(0.002, -0.001, 0.01), Eigen::Vector3d(0.002, -0.0012, 0.01));
    }
    allocations += allocationsOnThisThread().calls;
    REQUIRE(status != StepStatus::NonFinite);
    CHECK(model.toolPressForce_N().y() < 0.0);  // the press pushed
    ++steps;
  };
  frame(false);  // warm-up
  for (int i = 0; i < 20; ++i) frame(true);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const incision::StrokeSample& s : stroke.samples) {
    cutter.extend(s);
    tets.follow(*cutter.incision(), cutter.stats().incisions);
    frame(true);
  }
  cutter.finish();
  cutter.advance(1e9);
  while (cutter.pending()) cutter.advance(1e9);
  tets.follow(*cutter.incision(), cutter.stats().incisions, tets::TetBudget::All);
  for (int i = 0; i < 20; ++i) frame(true);
  INFO(steps << " frames, " << applied << " with cut changes (" << added << " pieces added), " << tets.stats().tets_cut
             << " tets cut; malloc counted: " << test::countsMalloc());
  REQUIRE(tets.stats().failure.empty());
  CHECK(added > 100);
  CHECK(model.reserveOverflows() == 0);
  CHECK(allocations == 0);
}

}  // namespace
}  // namespace incise::physics
