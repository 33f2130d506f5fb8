// Tests for sim/src/wrap_scenario.cpp: the shipped wrap scenarios load with their values (and the
// defaults); syntax errors give file:line:column, bad values the key path, a bad obstacle its name.
#include "incise/sim/wrap_scenario.h"

#include <catch2/catch.hpp>

#include "scenario_fixture.h"

#include <filesystem>
#include <fstream>
#include <string>

using namespace incise;
using Catch::Matchers::Contains;

namespace {

std::filesystem::path wrapFile(const std::string& name, const std::string& text) {
  return incise::test::scenarioDir().scenario(name, text);
}

const std::string kBar =
    R"({ "name": "bar", "shape": "cylinder", "base_m": [0, 0, -0.03], "axis_m": [0, 0, 0.06], "radius_m": 0.005 })";

// A scenario with a sphere for the model, `obstacles` and `more` keys.
std::string scene(const std::string& obstacles, const std::string& more = "") {
  return R"({ "model": { "shape": "sphere", "radius_m": 0.01 }, "obstacles": [ )" + obstacles + " ]" + more + " }";
}

}  // namespace

TEST_CASE("wrap scenario: the shipped scenarios load with their values", "[sim]") {
  const sim::WrapScenario s = sim::loadWrapScenario(INCISE_SCENARIOS_DIR "/wrap/sphere-cylinder.json");
  CHECK(s.name == "sphere-cylinder");
  CHECK(s.model.mesh().n_vertices() > 0);
  REQUIRE(s.obstacles.size() == 1);
  CHECK(s.obstacles[0].name == "cylinder");
  CHECK(s.obstacles[0].mesh.mesh().n_faces() > 0);
  CHECK(s.options.order == 4);
  CHECK(s.options.controls == std::array<int, 3>{24, 16, 8});
  CHECK(s.options.margin_m == 0.025);
  CHECK(s.options.kernel == global_dffd::DffdKernel::QuadraticBSpline);
  CHECK(s.options.kernel_width == 6.0);
  CHECK(s.options.clearance_m == 0.0005);
  CHECK(s.options.v_knots == global_dffd::VKnots::AtObstacleExtremes);
  CHECK(s.options.on_fold == global_dffd::FoldPolicy::Refuse);
  CHECK(s.treatment == global_dffd::OpeningTreatment::Open);
  CHECK(s.translate_m == Eigen::Vector3d(0.0, 0.07, 0.0));
  CHECK(s.frames == 14);
  CHECK(s.format == sim::WrapFormat::Obj);
  CHECK(s.tolerance_m == 1e-6);
  // The sphere squashed in z (stretch [1, 1, 0.5]) around its centre at y = -0.045.
  double z_max = 0.0;
  for (const auto v : s.model.mesh().vertices()) z_max = std::max(z_max, double(s.model.mesh().point(v)[2]));
  CHECK(std::abs(z_max - 0.01) < 1e-9);

  const sim::WrapScenario capped = sim::loadWrapScenario(INCISE_SCENARIOS_DIR "/wrap/part-silhouette.json");
  CHECK(capped.treatment == global_dffd::OpeningTreatment::Capped);
  CHECK(capped.options.on_fold == global_dffd::FoldPolicy::Widen);
  CHECK(capped.obstacles.at(0).name == "face");
  const sim::WrapScenario stitched = sim::loadWrapScenario(INCISE_SCENARIOS_DIR "/wrap/bunny-tool-stitched.json");
  CHECK(stitched.treatment == global_dffd::OpeningTreatment::Stitched);
  CHECK(stitched.obstacles.at(0).name == "tool");
  CHECK(sim::loadWrapScenario(INCISE_SCENARIOS_DIR "/wrap/sphere-cylinder-no-v-knots.json").options.v_knots ==
        global_dffd::VKnots::None);
}

TEST_CASE("wrap scenario: defaults fill what a scenario leaves out", "[sim]") {
  const std::string unnamed = R"({ "shape": "sphere", "centre_m": [0.05, 0, 0] })";
  const sim::WrapScenario s = sim::loadWrapScenario(wrapFile("defaults", scene(kBar + ", " + unnamed)));
  CHECK(s.name == "defaults");
  REQUIRE(s.obstacles.size() == 2);
  CHECK(s.obstacles[1].name == "obstacle 1");  // an obstacle without a name is named by its index
  const global_dffd::GlobalDffdOptions o;
  CHECK(s.options.controls == o.controls);
  CHECK(s.options.kernel_width == o.kernel_width);
  CHECK(s.treatment == global_dffd::OpeningTreatment::Open);
  CHECK(s.frames == 20);
  CHECK(s.translate_m == Eigen::Vector3d(0.0, 0.1, 0.0));
  CHECK(s.format == sim::WrapFormat::Obj);
  CHECK(sim::treatmentName(global_dffd::OpeningTreatment::Stitched) == std::string("stitched"));
  CHECK(sim::formatName(sim::WrapFormat::Ply) == std::string("ply"));
}

TEST_CASE("wrap scenario: bad scenarios name the file and the key, the line or the obstacle", "[sim]") {
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("syntax", "{\n  \"model\": { \"shape\": \"sphere\" },\n  \"obstacles\": [ ]]\n}")),
      Contains("syntax.json:3:") && Contains("JSON syntax error"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("range", scene(kBar, R"(, "motion": { "frames": 0 })"))),
                      Contains("range.json: motion.frames: 0 is outside [1, 100000]"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("type", scene(kBar, R"(, "lattice": { "kernel_width": "wide" })"))),
      Contains("type.json: lattice.kernel_width: must be a number"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("shape", R"({ "model": { "shape": "cube" }, "obstacles": [ )" + kBar + " ] }")),
      Contains("shape.json: model.shape: must be box, cylinder, sphere, prism or robot, got \"cube\""));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("obshape", scene(R"({ "name": "rod", "shape": "cone" })"))),
                      Contains("obshape.json: obstacles[0].shape: must be box"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("unknown", scene(kBar, R"(, "motion": { "frame": 3 })"))),
                      Contains("unknown.json: motion.frame: unknown key; did you mean motion.frames?"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("treat", scene(kBar, R"(, "treatment": "glued")"))),
                      Contains("treat.json: treatment: must be \"open\", \"stitched\" or \"capped\", got \"glued\""));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("kernel", scene(kBar, R"(, "lattice": { "kernel": "box" })"))),
                      Contains("kernel.json: lattice.kernel: must be \"bspline\" or \"gaussian\""));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("noname", scene(R"({ "name": 7, "shape": "sphere" })"))),
                      Contains("noname.json: obstacles[0].name: must be a string"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile(
                          "nomesh", R"({ "model": { "mesh": "meshes/gone.obj" }, "obstacles": [ )" + kBar + " ] }")),
                      Contains("nomesh.json: model.mesh: file") && Contains("gone.obj does not exist"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("obmesh", scene(R"({ "name": "lid", "mesh": "meshes/lid.obj" })"))),
      Contains("obmesh.json: obstacles[0].mesh: file") && Contains("lid.obj does not exist"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("nomodel", R"({ "obstacles": [ )" + kBar + " ] }")),
                      Contains("nomodel.json: model: must be an object"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("noobstacles", R"({ "model": { "shape": "sphere" }, "obstacles": [] })")),
      Contains("noobstacles.json: obstacles: must be a non-empty array"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("notobject", "[1, 2]")),
                      Contains("notobject.json: the document must be a JSON object"));
  REQUIRE_THROWS_AS(sim::loadWrapScenario("/nonexistent/wrap.json"), sim::ScenarioError);
  // fuzz_wrap_scenario's finding: a control count beyond int's range was cast to int (undefined behaviour).
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile(
          "controls",
          scene(
              kBar,
              R"(, "lattice": { "controls": [6666666666666666666666666666666666666666666666666666666666666666666656, 16, 16] })"))),
      Contains("controls.json: lattice.controls: [0] = ") && Contains("is not a whole number in [4, 4096]"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("controls2", scene(kBar, R"(, "lattice": { "controls": [16, 12.5, 8] })"))),
      Contains("controls2.json: lattice.controls: [1] = 12.5 is not a whole number in [4, 4096]"));
  CHECK(sim::loadWrapScenario(wrapFile("controls3", scene(kBar, R"(, "lattice": { "controls": [4, 4096, 8] })")))
            .options.controls == std::array<int, 3>{4, 4096, 8});
}

TEST_CASE("wrap scenario: a mesh that cannot be loaded names the file, and the obstacle", "[sim]") {
  std::ofstream(incise::test::scenarioDir().path() / "meshes" / "open.obj")
      << "v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nv 0 0 0.01\nf 1 3 2\nf 1 2 4\nf 2 3 4\n";
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("openob", scene(R"({ "name": "lid", "mesh": "meshes/open.obj" })"))),
      Contains("openob.json: obstacle 'lid': ") && Contains("open surface"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile(
                          "openmodel", R"({ "model": { "mesh": "meshes/open.obj" }, "obstacles": [ )" + kBar + " ] }")),
                      Contains("openmodel.json: ") && Contains("open surface"));
  CHECK_NOTHROW(sim::loadWrapScenario(
      wrapFile("bunny", R"({ "model": { "mesh": "meshes/bunny.obj", "scale": 0.01 }, "obstacles": [ )" + kBar +
                            R"( ], "treatment": "capped" })")));
}

namespace {

// The triangles of the model `shape` (a JSON object's keys after "shape") once loaded.
std::size_t modelFaces(const std::string& name, const std::string& shape) {
  return sim::loadWrapScenario(
             wrapFile(name, R"({ "model": { "shape": )" + shape + " }, \"obstacles\": [ " + kBar + " ] }"))
      .model.mesh()
      .n_faces();
}

}  // namespace

// The loader's cap, 2^18 = 262,144 triangles a model or obstacle (wrap_scenario.cpp: kMaxWrapTriangles),
// from each shape's formula before it is built: accepted at the largest size within it (the built mesh has
// the formula's count), refused one step above, at the key that makes the shape large.
TEST_CASE("wrap scenario: a shape or mesh over 262,144 triangles is refused before it is built", "[sim]") {
  const auto model = [](const std::string& shape) {
    return R"({ "model": { "shape": )" + shape + " }, \"obstacles\": [ " + kBar + " ] }";
  };
  CHECK(modelFaces("box147", R"("box", "divisions": 147)") == 12u * 147 * 147);  // 259,308
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("box148", model(R"("box", "divisions": 148)"))),
                      Contains("box148.json: model.divisions: a box of 148 divisions has 262,848 triangles; a shape "
                               "may have at most 262,144"));
  CHECK(modelFaces("sphere6", R"("sphere", "subdivisions": 6)") == 20u * 4096);  // 81,920
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("sphere7", model(R"("sphere", "subdivisions": 7)"))),
                      Contains("sphere7.json: model.subdivisions: a sphere of 7 subdivisions has 327,680 triangles"));
  // Cylinders: 2 segments (rings + 2 cap_rings - 1), exactly 262,144 three ways.
  CHECK(modelFaces("cyl", R"("cylinder", "segments": 1024, "rings": 125, "cap_rings": 2)") == 262144u);
  CHECK(modelFaces("cylr", R"("cylinder", "segments": 4, "rings": 32767, "cap_rings": 1)") == 262144u);
  CHECK(modelFaces("cylc", R"("cylinder", "segments": 4, "rings": 1, "cap_rings": 16384)") == 262144u);
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("cyl+", model(R"("cylinder", "segments": 1024, "rings": 126, "cap_rings": 2)"))),
      Contains("cyl+.json: model.segments: a cylinder of 1,024 segments, 126 rings and 2 cap rings "
               "has 264,192 triangles"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("cylr+", model(R"("cylinder", "segments": 4, "rings": 32768, "cap_rings": 1)"))),
      Contains("cylr+.json: model.rings: ") && Contains("has 262,152 triangles"));
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("cylc+", model(R"("cylinder", "segments": 4, "rings": 1, "cap_rings": 16385)"))),
      Contains("cylc+.json: model.cap_rings: ") && Contains("has 262,160 triangles"));
  // Prisms: 2 points rings + 2 (points - 2); 65,537 points in one ring is exactly the cap.
  CHECK(modelFaces("prism", R"("prism", "points": 65537, "rings": 1, "height_m": 0.5)") == 262144u);
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("prism+", model(R"("prism", "points": 65538, "rings": 1)"))),
                      Contains("prism+.json: model.points: a prism of 65,538 points and 1 ring has 262,148 triangles"));
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("prismr", model(R"("prism", "points": 25, "rings": 5500)"))),
                      Contains("prismr.json: model.rings: ") && Contains("has 275,046 triangles"));
  // The robot: 1032 d^2 - 120 d.
  CHECK(modelFaces("robot15", R"("robot", "detail": 15)") == 1032u * 225 - 120 * 15);  // 230,400
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("robot16", model(R"("robot", "detail": 16)"))),
                      Contains("robot16.json: model.detail: a robot of detail 16 has 262,272 triangles"));
  // An obstacle's key path; a mesh file's triangles times 4^subdivide (the bunny's 3,674: 3 times is 235,136).
  REQUIRE_THROWS_WITH(
      sim::loadWrapScenario(wrapFile("obstacle", scene(R"({ "name": "ball", "shape": "sphere", "subdivisions": 8 })"))),
      Contains("obstacle.json: obstacles[0].subdivisions: a sphere of 8 subdivisions has 1,310,720 triangles"));
  const std::string bunny = R"({ "model": { "mesh": "meshes/bunny.obj", "scale": 0.01, "subdivide": )";
  CHECK(sim::loadWrapScenario(wrapFile("bunny3", bunny + "3 }, \"obstacles\": [ " + kBar + " ] }"))
            .model.mesh()
            .n_faces() == 235136u);
  REQUIRE_THROWS_WITH(sim::loadWrapScenario(wrapFile("bunny4", bunny + "4 }, \"obstacles\": [ " + kBar + " ] }")),
                      Contains("bunny4.json: model.subdivide: bunny.obj (3,674 triangles) subdivided 4 times has "
                               "940,544 triangles; a mesh may have at most 262,144"));
}
