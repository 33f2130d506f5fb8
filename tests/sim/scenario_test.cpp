#include "incise/sim/scenario.h"

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "scenario_fixture.h"

#include <filesystem>
#include <fstream>

using namespace incise;
using Catch::Matchers::Contains;

namespace {

std::filesystem::path scenarioFile(const std::string& name, const std::string& text) {
  return incise::test::scenarioDir().scenario(name, text);
}

const char* kGood = R"({
  "name": "t",
  "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01 },
  "pose_source": { "kind": "strokes", "strokes": [ { "start_m": [0, 0, 0.01], "length_m": 0.02 } ] }
})";

}  // namespace

TEST_CASE("scenario: the shipped scenarios load", "[sim]") {
  for (const char* name : {"bunny-straight", "bunny-curved", "bunny-crossing"}) {
    INFO(name);
    const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
    REQUIRE(s.name == name);
    REQUIRE(s.source == sim::Scenario::Source::Trace);
    REQUIRE(std::filesystem::exists(s.trace));
    REQUIRE(s.periodUs() == 1000);
    REQUIRE(s.world.cutter.incision.depth_m == 0.004);
    REQUIRE(s.subdivide == 2);
    REQUIRE_FALSE(s.world.tets.enabled);
  }
  const sim::Scenario tets = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-tets.json");
  REQUIRE(tets.world.tets.enabled);
  REQUIRE(tets.world.tets.mesh.max_volume_m3 == 5e-9);
  REQUIRE(tets.world.tets.mesh.keep_surface);
}

TEST_CASE("scenario: defaults fill what a scenario leaves out", "[sim]") {
  const sim::Scenario s = sim::loadScenario(scenarioFile("good", kGood));
  REQUIRE(s.source == sim::Scenario::Source::Strokes);
  REQUIRE(s.strokes.size() == 1);
  REQUIRE(s.strokes[0].length_m == 0.02);
  REQUIRE(s.rate_hz == 1000.0);
  REQUIRE(s.world.cutter.incision.order == 4);
}

TEST_CASE("scenario: bad scenarios name the file and the key or line", "[sim]") {
  REQUIRE_THROWS_WITH(sim::loadScenario(scenarioFile("syntax", "{\n  \"name\": \"x\",\n  \"tissue\": { ]\n}")),
                      Contains("syntax.json:3:") && Contains("JSON syntax error"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile("nomesh", R"({"tissue": {}, "pose_source": {"kind": "trace", "path": "x.csv"}})")),
      Contains("nomesh.json: tissue.mesh: is missing"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "missing",
          R"({"tissue": {"mesh": "meshes/nope.obj"}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.mesh: file") && Contains("nope.obj does not exist"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "notrace",
          R"({"tissue": {"mesh": "meshes/bunny.obj"}, "pose_source": {"kind": "trace", "path": "traces/gone.csv"}})")),
      Contains("pose_source.path: file") && Contains("gone.csv does not exist"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "range",
          R"({"tissue": {"mesh": "meshes/bunny.obj", "subdivide": 9}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.subdivide: 9 is outside [0, 5]"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "type",
          R"({"tissue": {"mesh": "meshes/bunny.obj", "scale": "big"}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.scale: must be a number"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "fold",
          R"({"tissue": {"mesh": "meshes/bunny.obj"}, "incision": {"opening_m": 0.02}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("incision: ") && Contains("Theorem 1"));
  REQUIRE_THROWS_WITH(sim::loadScenario(scenarioFile(
                          "kind", R"({"tissue": {"mesh": "meshes/bunny.obj"}, "pose_source": {"kind": "hid"}})")),
                      Contains("pose_source.kind: must be \"trace\", \"strokes\" or \"hid-recording\", got \"hid\""));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "stroke",
          R"({"tissue": {"mesh": "meshes/bunny.obj"}, "pose_source": {"kind": "strokes", "strokes": [{"start_m": [0, 1]}]}})")),
      Contains("pose_source.strokes[0].start_m: must be an array of 3 numbers"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "tets",
          R"({"tissue": {"mesh": "meshes/bunny.obj", "tets": {"max_volume_m3": -1}}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.tets.max_volume_m3: ") && Contains("is outside"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "ratio",
          R"({"tissue": {"mesh": "meshes/bunny.obj", "tets": {"radius_edge_ratio": 0.5}}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.tets.radius_edge_ratio: must be 0 (no quality refinement) or >= 1"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(scenarioFile(
          "keep",
          R"({"tissue": {"mesh": "meshes/bunny.obj", "tets": {"keep_surface": 1}}, "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
      Contains("tissue.tets.keep_surface: must be true or false"));
  REQUIRE_THROWS_WITH(sim::loadScenario("/nonexistent/scenario.json"), Contains("scenario.json: cannot open"));
}

TEST_CASE("scenario: hid-recording sources, their mappings and how they were made", "[sim][hid]") {
  const sim::Scenario wacom = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-pen-wacom.json");
  REQUIRE(wacom.source == sim::Scenario::Source::HidRecording);
  CHECK(std::filesystem::exists(wacom.hid.path));
  CHECK(wacom.hid.mapping.pen.max_depth_m == 0.02);
  CHECK(wacom.hid.mapping.pen.x_edge_m.x() == 0.097384);
  CHECK(wacom.hid.synthesis.given);
  CHECK(wacom.hid.synthesis.vid == 0x056a);
  CHECK(wacom.hid.synthesis.rate_hz == 200.0);
  const sim::Scenario navigator = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-spacenavigator.json");
  CHECK(navigator.hid.mapping.six_dof.max_speed_m_per_s == 0.4);
  CHECK(navigator.hid.mapping.six_dof.start_orientation.w() == 0.769644815);

  const auto hid = [](const std::string& name, const std::string& source) {
    return scenarioFile(
        name, R"({"tissue": {"mesh": "meshes/bunny.obj"}, "pose_source": {"kind": "hid-recording", )" + source + "}}");
  };
  REQUIRE_THROWS_WITH(sim::loadScenario(hid("nofile", R"("path": "none.hid")")), Contains("pose_source.path: file"));
  REQUIRE_THROWS_WITH(
      sim::loadScenario(hid("parallel", R"("path": "x.hid", "pen": {"x_edge_m": [1, 0, 0], "y_edge_m": [2, 0, 0]},
                                                           "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "1", "pid": "2"})")),
      Contains("pose_source.pen.y_edge_m: must not be parallel to x_edge_m"));
  REQUIRE_THROWS_WITH(sim::loadScenario(hid("vid", R"("path": "x.hid",
                                                      "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "wacom", "pid": "2"})")),
                      Contains("pose_source.synthesis.vid: must be 1-4 hex digits (\"056a\"), got \"wacom\""));
  REQUIRE_THROWS_WITH(sim::loadScenario(hid("axes", R"("path": "x.hid", "six_dof": {"axes": "sideways"},
                                                       "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "1", "pid": "2"})")),
                      Contains("pose_source.six_dof.axes: must be"));
  CHECK(wacom.hid.mapping.pen.tip_depth_m == 0.004);  // the default
  const sim::Scenario tip = sim::loadScenario(hid("tip", R"("path": "x.hid", "pen": {"tip_depth_m": 0.007},
                                                   "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "1", "pid": "2"})"));
  CHECK(tip.hid.mapping.pen.tip_depth_m == 0.007);
  REQUIRE_THROWS_WITH(sim::loadScenario(hid("deep", R"("path": "x.hid", "pen": {"tip_depth_m": 2},
                                                       "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "1", "pid": "2"})")),
                      Contains("pose_source.pen.tip_depth_m"));
  REQUIRE_THROWS_WITH(sim::loadScenario(hid("quat", R"("path": "x.hid", "six_dof": {"start_orientation": [1, 1, 0, 0]},
                                                       "synthesis": {"from": "meshes/bunny.obj", "descriptor": "meshes/bunny.obj", "vid": "1", "pid": "2"})")),
                      Contains("pose_source.six_dof.start_orientation: must be a unit quaternion"));
}

TEST_CASE("scenario: local refinement's keys", "[sim]") {
  const sim::Scenario refined = sim::loadScenario(scenarioFile("refine", R"({
    "tissue": {"mesh": "meshes/bunny.obj", "scale": 0.01},
    "incision": {"refine": "pn", "refine_edge_m": 0.001},
    "pose_source": {"kind": "strokes", "strokes": [{}]}})"));
  REQUIRE(refined.world.cutter.refine == incision::CutterOptions::Refine::PnTriangles);
  REQUIRE(refined.world.cutter.refine_edge_m == 0.001);
  REQUIRE(sim::loadScenario(scenarioFile("good", kGood)).world.cutter.refine ==
          incision::CutterOptions::Refine::Linear);
  REQUIRE_THROWS_WITH(sim::loadScenario(scenarioFile("refineword", R"({
    "tissue": {"mesh": "meshes/bunny.obj"}, "incision": {"refine": "cubic"},
    "pose_source": {"kind": "strokes", "strokes": [{}]}})")),
                      Contains("incision.refine: must be \"linear\", \"pn\" or \"off\", got \"cubic\""));
}

TEST_CASE("scenario: a tissue's texture: a box map made at load, images named, bad ones refused", "[sim]") {
  const auto& dir = incise::test::scenarioDir();
  std::filesystem::create_directories(dir.path() / "textures");
  dir.write("textures/skin.png", "any bytes: the loader checks that it exists; the viewer reads it");
  const sim::Scenario s = sim::loadScenario(scenarioFile("textured", R"({
    "tissue": {"shape": "pad", "size_m": [0.02, 0.01, 0.02], "grid_m": 0.002,
               "texture": {"map": "box", "tile_m": 0.004, "skin": "textures/skin.png"}},
    "pose_source": {"kind": "strokes", "strokes": [{}]}})"));
  REQUIRE(s.texture.given);
  REQUIRE(s.texture.box_map);
  REQUIRE(s.texture.tile_m == 0.004);
  REQUIRE(s.texture.skin_image == dir.path() / "textures/skin.png");
  REQUIRE(s.texture.wall_image.empty());
  const mesh::SurfaceMesh pad = sim::loadTissue(s);
  REQUIRE(pad.hasTexCoords());
  // The pad's top (y = 0, normal +y) is mapped on x and z over the tile.
  std::size_t top = 0;
  for (const auto f : pad.mesh().faces()) {
    const mesh::FaceCorners c = mesh::faceCorners(pad, f);
    const auto p = [&](std::size_t i) { return mesh::toEigen(pad.mesh().point(c.vertex[i])); };
    if (std::abs(p(0).y()) > 1e-12 || std::abs(p(1).y()) > 1e-12 || std::abs(p(2).y()) > 1e-12) continue;
    ++top;
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(c.uv[i].x() == Approx(p(i).x() / 0.004).margin(1e-12));
      CHECK(c.uv[i].y() == Approx(p(i).z() / 0.004).margin(1e-12));
    }
  }
  CHECK(top > 100);
  REQUIRE_FALSE(sim::loadTissue(sim::loadScenario(scenarioFile("good", kGood))).hasTexCoords());

  const auto bad = [&](const char* name, const std::string& texture) {
    return sim::loadScenario(scenarioFile(name, R"({"tissue": {"mesh": "meshes/bunny.obj", "texture": )" + texture +
                                                    R"(}, "pose_source": {"kind": "strokes", "strokes": [{}]}})"));
  };
  REQUIRE_THROWS_WITH(bad("texmap", R"({"map": "sphere"})"),
                      Contains("tissue.texture.map: must be") && Contains("box"));
  REQUIRE_THROWS_WITH(bad("textile", R"({"map": "box", "tile_m": 0})"),
                      Contains("tissue.texture.tile_m: 0 is outside"));
  REQUIRE_THROWS_WITH(bad("textilealone", R"({"tile_m": 0.01})"),
                      Contains(R"(tissue.texture.tile_m: needs "map": "box")"));
  REQUIRE_THROWS_WITH(bad("texskin", R"({"map": "box", "skin": "textures/none.png"})"),
                      Contains("tissue.texture.skin: file") && Contains("none.png does not exist"));
  // No map on a mesh without coordinates: refused when the tissue is loaded, naming the scenario.
  const sim::Scenario own = bad("texown", R"({"wall": "textures/skin.png"})");
  REQUIRE_THROWS_WITH(sim::loadTissue(own),
                      Contains("texown.json: tissue.texture: ") && Contains("bunny.obj has no texture coordinates"));
}

TEST_CASE("scenario: a key nothing reads is refused, naming the nearest known key", "[sim]") {
  const auto load = [](const char* name, const std::string& text) {
    return sim::loadScenario(scenarioFile(name, text));
  };
  const std::string source = R"("pose_source": {"kind": "strokes", "strokes": [{}]})";
  // At the root, in a nested object, in an array's entry, in a mapping.
  REQUIRE_THROWS_WITH(load("budget", R"({"tissue": {"shape": "pad"}, "cut_budegt_us": 100, )" + source + "}"),
                      Contains("budget.json: cut_budegt_us: unknown key; did you mean cut_budget_us?"));
  REQUIRE_THROWS_WITH(load("depth", R"({"tissue": {"shape": "pad"}, "incision": {"dpeth_m": 0.002}, )" + source + "}"),
                      Contains("incision.dpeth_m: unknown key; did you mean incision.depth_m?"));
  REQUIRE_THROWS_WITH(
      load("stroke",
           R"({"tissue": {"shape": "pad"}, "pose_source": {"kind": "strokes", "strokes": [{}, {"lenght_m": 0.02}]}})"),
      Contains("pose_source.strokes[1].lenght_m: unknown key; did you mean pose_source.strokes[1].length_m?"));
  REQUIRE_THROWS_WITH(
      load("pen", R"({"tissue": {"shape": "pad"}, "pose_source": {"kind": "hid-recording", "path": "meshes/bunny.obj",
                      "pen": {"hover": 0.01}}})"),
      Contains("pose_source.pen.hover: unknown key; did you mean pose_source.pen.hover_m?"));
  // Far from every known key: no guess.
  REQUIRE_THROWS_WITH(load("far", R"({"tissue": {"shape": "pad", "colour": "pink"}, )" + source + "}"),
                      Contains("tissue.colour: unknown key") && !Contains("did you mean"));
  // A known key where it does nothing: a mesh tissue's grid.
  REQUIRE_THROWS_WITH(load("grid", R"({"tissue": {"mesh": "meshes/bunny.obj", "grid_m": 0.001}, )" + source + "}"),
                      Contains("tissue.grid_m: has no effect here"));
  // A misspelt key is named rather than the error it causes ("tissue: is missing").
  REQUIRE_THROWS_WITH(load("tisue", R"({"tisue": {"shape": "pad"}, )" + source + "}"),
                      Contains("tisue: unknown key; did you mean tissue?"));
  // Every shipped replay scenario, and the generators' scenarios, hold only keys that are read.
  for (const auto& folder :
       {std::filesystem::path(INCISE_SCENARIOS_DIR), std::filesystem::path(INCISE_SCENARIOS_DIR) / "generate"})
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.path().extension() == ".json") {
        INFO(entry.path());
        REQUIRE_NOTHROW(sim::loadScenario(entry.path()));
      }
}
