#include "incise/jobs/cut_job.h"

#include <catch2/catch.hpp>

#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/self_intersection.h"

namespace {

incise::jobs::CutJobOptions bunnyCut() {
  incise::jobs::CutJobOptions o;
  o.mesh = INCISE_SCENARIOS_DIR "/meshes/bunny.obj";
  o.subdivide = 1;
  o.length_m = 0.03;
  return o;
}

}  // namespace

TEST_CASE("cut_job: a stroke across the bunny opens a groove and keeps a closed mesh and its Euler characteristic",
          "[jobs]") {
  using namespace incise;
  jobs::CutJob job(bunnyCut());
  std::size_t reported = 0;
  job.run([&](std::size_t done, std::size_t total) {
    reported = done;
    CHECK(total == job.samples() - 1);
  });
  CHECK(reported == job.samples() - 1);
  const mesh::MeshSummary cut = mesh::summarize(job.mesh());
  CHECK(job.ok(cut));
  CHECK(job.failure().empty());
  CHECK(cut.wall_faces > 0);
  CHECK(job.eulerBefore() == 2);
  CHECK(job.sampleUs().size() == job.samples());
  const nlohmann::json summary = job.summary(cut);
  CHECK(summary["options"]["length_m"] == 0.03);
  CHECK(summary["options"]["refine"] == "linear");
  CHECK(summary["mesh"]["wall_faces"] == cut.wall_faces);
  CHECK(summary["incision_figures"].size() == 1);
  CHECK(summary["incision_figures"][0]["groove_length_m"].get<double>() > 0.02);
  CHECK(summary["per_sample"]["count"] == job.samples());
  CHECK(summary["failure"] == "");
}

TEST_CASE("cut_job: the same options cut the same mesh", "[jobs]") {
  incise::jobs::CutJob a(bunnyCut()), b(bunnyCut());
  a.run();
  b.run();
  CHECK(incise::mesh::geometryHash(a.mesh()) == incise::mesh::geometryHash(b.mesh()));
}

TEST_CASE("cut_job: bad options and a path off the tissue are refused before any cut", "[jobs]") {
  incise::jobs::CutJobOptions o = bunnyCut();
  o.subdivide = 6;
  CHECK_THROWS_WITH(incise::jobs::CutJob(o), "subdivide 6 is outside [0, 5]");
  o = bunnyCut();
  o.start_m = Eigen::Vector3d(5.0, 0.0, 5.0);
  CHECK_THROWS_WITH(incise::jobs::CutJob(o), Catch::Contains("the first ray misses the surface"));
  o = bunnyCut();
  o.mesh = INCISE_SCENARIOS_DIR "/meshes/no-such.obj";
  CHECK_THROWS_AS(incise::jobs::CutJob(o), incise::mesh::MeshError);
}

TEST_CASE(
    "cut_job: a stroke down the bunny's flank into a crease goes on as a new incision from the corner, no "
    "faces crossing",
    "[jobs]") {
  // Drawn by scripts/random_cuts.py (the bunny at 0.6 scale, unsubdivided): the ray's point runs down a steep
  // flank into a crease and up the next one, a 94-degree turn of the path between two stations. As one
  // incision its lattice folded at the turn and 186 pairs of faces (mostly walls) crossed.
  incise::jobs::CutJobOptions o;
  o.mesh = INCISE_SCENARIOS_DIR "/meshes/bunny.obj";
  o.scale = 0.006;
  o.subdivide = 0;
  o.start_m = Eigen::Vector3d(-0.00837261993619708, 0.06, -0.007777047409646843);
  o.direction = Eigen::Vector3d(0.8047474499560493, 0.0, -0.5936173361596139);
  o.length_m = 0.011915508633078218;
  o.cutter.incision.depth_m = 0.0038270701993262917;
  incise::jobs::CutJob job(o);
  job.run();
  const incise::mesh::MeshSummary cut = incise::mesh::summarize(job.mesh());
  CHECK(job.ok(cut));
  CHECK(incise::mesh::findSelfIntersections(job.mesh().mesh()).empty());
  const nlohmann::json summary = job.summary(cut);
  REQUIRE(summary["incision_figures"].size() == 2);
  for (const auto& figures : summary["incision_figures"]) {
    CHECK(figures["shortfall"] == "none");
    CHECK(figures["groove_length_m"].get<double>() > 0.005);
  }
  CHECK(job.sampleUs().size() == job.samples());
}
