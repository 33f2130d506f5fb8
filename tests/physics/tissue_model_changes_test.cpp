// Tests for physics/src/tissue_model_changes.cpp, cut_changes.cpp and tet_cutter_journal.cpp: a grid cut by
// the real tet cutter (a stroke along its top, the surface cutter's incision), the journal applied to the
// model after every sample, gives the model a model built from the cut mesh would have: the same pieces,
// masses, matrix pattern and motion; with nothing allocated past the reserve (no rebuild); so does a model
// that takes many samples' journals at once. Cut pieces keep their side, and a cut through a tissue held in
// tension (a prestretch) gapes by itself.
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/shapes.h"
#include "incise/physics/tet_cutter_journal.h"
#include "incise/tets/tet_cutter.h"
#include "physics_fixture.h"

namespace incise::physics {
namespace {

// A 10 x 10 x 14 mm block of 2 mm cubes (1,050 tets), top at y = 0, held on its z = 0 face.
struct Block {
  Eigen::AlignedBox3d box{Eigen::Vector3d(-0.005, -0.01, 0.0), Eigen::Vector3d(0.005, 0.0, 0.014)};
  Eigen::Vector3i cells{5, 5, 7};
  tets::TetMesh tets = gridTets(box, cells);
  mesh::SurfaceMesh surface = mesh::makeBox(box, cells);
  Boundary boundary;
  Block() { boundary.fixed_boxes = {testing::plane(2, 0.0)}; }
};

// Cuts `block` along +z over its top's middle, the tet cutter following the surface cutter's incision (block.surface
// is cut too). After every sample the cutter's journal is collected, and every `batch` samples (and at the end)
// what was collected goes to `model`, as a physics thread that takes the cuts at its own rate. Returns the
// cutter and the summed change counts.
struct Cut {
  tets::TetCutter cutter;
  ChangeStats total;
};

Cut cutAlongTop(Block& block, TissueModel& model, int batch = 1) {
  incision::StrokePathOptions path;
  path.start_m = Eigen::Vector3d(0.0003, 0.05, 0.003);
  path.direction = Eigen::Vector3d::UnitZ();
  path.length_m = 0.008;
  const incision::Stroke stroke = incision::strokeAlongPath(block.surface, path);
  incision::CutterOptions options;
  options.refine = incision::CutterOptions::Refine::Off;
  // A wound barely open at rest (0.1 mm; the kernel's default is wider): the model's tension, not the
  // kernel, is what opens it here, and a point on the cut plane is within reach of both lips' tets.
  options.incision.opening_m = 1e-4;
  incision::SurfaceCutter surface(block.surface, options);
  Cut cut{tets::TetCutter(block.tets), {}};
  cut.cutter.recordChanges(true);
  CutChanges scratch;
  scratch.reserve(1 << 12, 1 << 12, 1 << 14);
  const auto count = [&](const ChangeStats& c) {
    cut.total.nodes_added += c.nodes_added, cut.total.nodes_moved += c.nodes_moved;
    cut.total.elements_added += c.elements_added, cut.total.elements_removed += c.elements_removed;
    cut.total.pieces_refused += c.pieces_refused;
  };
  int collected = 0;
  const auto follow = [&](tets::TetBudget budget) {
    cut.cutter.follow(*surface.incision(), surface.stats().incisions, budget);
    if (batch == 1) return count(applyTetCutterJournal(model, cut.cutter, scratch));
    collectCutChanges(cut.cutter, cut.cutter.changes(), scratch);
    cut.cutter.clearChanges();
    if (++collected % batch == 0) count(model.apply(scratch)), scratch.clear();
  };
  surface.begin(stroke.first, stroke.blade_direction);
  follow(tets::TetBudget::PerCall);
  for (const incision::StrokeSample& s : stroke.samples) {
    surface.extend(s);
    follow(tets::TetBudget::PerCall);
  }
  surface.finish();
  surface.advance(1e9);
  while (surface.pending()) surface.advance(1e9);
  follow(tets::TetBudget::All);
  if (!scratch.empty()) count(model.apply(scratch));
  return cut;
}

// The cutter's working mesh as it is (uncompacted: the model's indices), at its current positions.
tets::TetMesh workingMesh(const tets::TetCutter& cutter, std::vector<int>& sides) {
  tets::TetMesh mesh;
  for (int n = 0; n < cutter.nodeCount(); ++n) mesh.nodes_m.push_back(cutter.nodePosition(n));
  sides.clear();
  for (int b = 0; b < cutter.baseTetCount(); ++b)
    for (const tets::TetChild& c : cutter.children(b)) mesh.tets.push_back(c.nodes), sides.push_back(c.side);
  return mesh;
}

TEST_CASE("tissue_model: a cut enters the model as it is made, as if the model were built from the cut mesh",
          "[physics]") {
  Block block;
  ModelOptions o;
  o.cg_tolerance = 1e-10, o.max_cg_iterations = 2000;
  o.reserve_nodes = 2000, o.reserve_elements = 8000;
  TissueModel model(block.tets, Material{}, block.boundary, o);
  const std::size_t entries_before = model.matrixEntries();
  const Cut cut = cutAlongTop(block, model);
  INFO("tets cut " << cut.cutter.stats().tets_cut << ", nodes added " << cut.total.nodes_added << ", pieces added "
                   << cut.total.elements_added << ", removed " << cut.total.elements_removed);
  REQUIRE(cut.cutter.stats().failure.empty());
  REQUIRE(cut.cutter.stats().tets_cut > 10);
  CHECK(cut.total.nodes_added > 0);
  CHECK(cut.total.pieces_refused == 0);
  CHECK(model.elementCount() == cut.cutter.tetCount());
  CHECK(model.nodeCount() == cut.cutter.nodeCount());
  CHECK(model.reserveOverflows() == 0);  // every change within the reserve: nothing rebuilt or reallocated
  CHECK(model.matrixEntries() > entries_before);

  std::vector<int> sides;
  const tets::TetMesh cut_mesh = workingMesh(cut.cutter, sides);
  TissueModel fresh(cut_mesh, Material{}, block.boundary, o, sides);
  CHECK(model.matrixEntries() == fresh.matrixEntries());
  CHECK(model.totalMass_kg() == Approx(fresh.totalMass_kg()).epsilon(1e-12));
  for (int n = 0; n < model.nodeCount(); ++n) {
    INFO("node " << n);
    REQUIRE(model.restPositions_m()[static_cast<std::size_t>(n)] ==
            fresh.restPositions_m()[static_cast<std::size_t>(n)]);
    REQUIRE(model.mass_kg(n) == Approx(fresh.mass_kg(n)).epsilon(1e-12).margin(1e-18));
    REQUIRE(model.isHeld(n) == fresh.isHeld(n));
  }
  // Released from rest, both swing the same way (to CG's tolerance: their sums run in other orders).
  model.resetState();
  double sag_m = 0.0, difference_m = 0.0;
  for (int i = 0; i < 20; ++i) {
    REQUIRE(model.step(0.005).status == StepStatus::Converged);
    REQUIRE(fresh.step(0.005).status == StepStatus::Converged);
    for (int n = 0; n < model.nodeCount(); ++n) {
      const auto k = static_cast<std::size_t>(n);
      sag_m = std::max(sag_m, (model.positions_m()[k] - model.restPositions_m()[k]).norm());
      difference_m = std::max(difference_m, (model.positions_m()[k] - fresh.positions_m()[k]).norm());
    }
  }
  INFO("largest displacement " << sag_m << " m, largest difference " << difference_m << " m");
  CHECK(sag_m > 1e-4);
  CHECK(difference_m < 1e-8 * sag_m);
}

TEST_CASE("tissue_model: cut pieces keep their side, and a point is embedded on its own side of the cut", "[physics]") {
  Block block;
  TissueModel model(block.tets, Material{}, block.boundary);
  const Cut cut = cutAlongTop(block, model);
  REQUIRE(cut.cutter.stats().failure.empty());
  // A point on the cut plane (x = 0.3 mm) inside the cut's length, just under the top.
  const Eigen::Vector3d on_cut(0.0003, -0.0005, 0.007);
  for (const int side : {-1, 1}) {
    const std::optional<Embedded> e = model.locate(on_cut, OnSide{side}, 1e-4);
    REQUIRE(e);
    CHECK(e->element.side == side);
  }
  // The two lips' embeddings move with their own pieces: pulled apart, they part.
  const std::optional<Embedded> minus = model.locate(on_cut, OnSide{-1}, 1e-4),
                                plus = model.locate(on_cut, OnSide{1}, 1e-4);
  REQUIRE(minus);
  REQUIRE(plus);
  model.addPointForce(*minus, Eigen::Vector3d(-0.01, 0, 0));
  model.addPointForce(*plus, Eigen::Vector3d(0.01, 0, 0));
  for (int i = 0; i < 20; ++i) REQUIRE(model.step(0.005).status != StepStatus::NonFinite);
  const double gap_m =
      embeddedPosition(*plus, model.positions_m()).x() - embeddedPosition(*minus, model.positions_m()).x();
  const double rest_gap_m =
      embeddedPosition(*plus, model.restPositions_m()).x() - embeddedPosition(*minus, model.restPositions_m()).x();
  INFO("gap at rest " << rest_gap_m << " m, pulled " << gap_m << " m");
  CHECK(gap_m > rest_gap_m + 1e-4);
}

TEST_CASE("tissue_model: the cut's changes collected over many samples and applied at once give the same model",
          "[physics]") {
  // A physics thread slower than the cut takes several samples' journals in one apply(): a node or a base tet
  // named by several journals is applied once, in its latest state.
  ModelOptions o;
  o.cg_tolerance = 1e-10, o.max_cg_iterations = 2000;
  const auto cutModel = [&](int batch) {
    Block block;
    TissueModel model(block.tets, Material{}, block.boundary, o);
    const Cut cut = cutAlongTop(block, model, batch);
    REQUIRE(cut.cutter.stats().failure.empty());
    CHECK(cut.total.pieces_refused == 0);
    CHECK(model.elementCount() == cut.cutter.tetCount());
    return model;
  };
  TissueModel each = cutModel(1);
  for (const int batch : {7, 100000}) {
    INFO("journals applied every " << batch << " samples");
    TissueModel batched = cutModel(batch);
    REQUIRE(batched.nodeCount() == each.nodeCount());
    CHECK(batched.elementCount() == each.elementCount());
    CHECK(batched.matrixEntries() == each.matrixEntries());
    for (int n = 0; n < each.nodeCount(); ++n) {
      INFO("node " << n);
      REQUIRE(batched.restPositions_m()[static_cast<std::size_t>(n)] ==
              each.restPositions_m()[static_cast<std::size_t>(n)]);
      REQUIRE(batched.mass_kg(n) == Approx(each.mass_kg(n)).epsilon(1e-12).margin(1e-18));
    }
    each.resetState(), batched.resetState();
    double difference_m = 0.0;
    for (int i = 0; i < 10; ++i) {
      each.step(0.005), batched.step(0.005);
      for (int n = 0; n < each.nodeCount(); ++n)
        difference_m = std::max(difference_m, (each.positions_m()[static_cast<std::size_t>(n)] -
                                               batched.positions_m()[static_cast<std::size_t>(n)])
                                                  .norm());
    }
    CHECK(difference_m < 1e-12);
  }
}

TEST_CASE("tissue_model: a cut through a tissue held in tension gapes by itself", "[physics]") {
  // The block held on its x = -5 mm and x = +5 mm faces, its natural shape 1 / 1.25 of the mesh along x: in
  // tension across the cut. Cut fully through, each half would shrink to its natural length towards its held
  // face, opening the top by 10 mm x (1 - 1 / 1.25) = 2 mm; the cut (8 mm of 14, part of the depth) opens less.
  Block block;
  block.boundary.fixed_boxes = {testing::plane(0, -0.005), testing::plane(0, 0.005)};
  block.boundary.gravity_m_per_s2.setZero();
  Material m;
  m.prestretch = Eigen::Vector3d(1.25, 1.0, 1.0);
  ModelOptions o;
  o.max_cg_iterations = 300;
  TissueModel model(block.tets, m, block.boundary, o);
  const auto settle = [&] {
    for (int i = 0; i < 300; ++i) REQUIRE(model.step(0.005).status != StepStatus::NonFinite);
  };
  // Two points of the top 2 mm apart across the cut's plane (x = 0.3 mm), half-way along it.
  const Eigen::Vector3d a(-0.0007, -0.0002, 0.007), b(0.0013, -0.0002, 0.007);
  const auto apart = [&](int side_a, int side_b) {
    const std::optional<Embedded> ea = model.locate(a, OnSide{side_a}, 1e-4),
                                  eb = model.locate(b, OnSide{side_b}, 1e-4);
    REQUIRE(ea);
    REQUIRE(eb);
    return embeddedPosition(*eb, model.positions_m()).x() - embeddedPosition(*ea, model.positions_m()).x();
  };
  settle();
  const double uncut_m = apart(0, 0);
  const Cut cut = cutAlongTop(block, model);
  REQUIRE(cut.cutter.stats().failure.empty());
  const double just_cut_m = apart(-1, 1);
  settle();
  const double cut_m = apart(-1, 1);
  INFO("apart along x: uncut, held " << uncut_m << " m; just cut " << just_cut_m << " m; 1.5 s later " << cut_m
                                     << " m");
  CHECK(std::abs(uncut_m - 0.002) < 2e-4);       // held at its mesh length, it does not open
  CHECK(std::abs(just_cut_m - uncut_m) < 1e-4);  // the cut itself moves them little (its rest changes only)
  CHECK(cut_m > uncut_m + 1e-3);                 // the lips part by themselves
  CHECK(cut_m < uncut_m + 2e-3);                 // but less than a cut through everything would
}

}  // namespace
}  // namespace incise::physics
