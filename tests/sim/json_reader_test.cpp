// The private JSON reader (sim/src/json_reader.h), through the include path tests/sim/CMakeLists.txt adds.
#include "json_reader.h"

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

using namespace incise::sim;
using namespace incise::sim::detail;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using nlohmann::json;
namespace fs = std::filesystem;
using incise::test::readFile;
using incise::test::TempDir;

namespace {

// The message of the ScenarioError that `f` throws ("" when it throws none).
template <typename F>
std::string messageOf(F&& f) {
  try {
    f();
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

JsonReader reader(const std::string& text, const std::string& key_path = "") {
  return JsonReader("dir/scene.json", json::parse(text), key_path);
}

}  // namespace

TEST_CASE("json_reader: positionOf gives the 1-based line and column of a byte", "[sim]") {
  const std::string text = "ab\ncd\n\nef";  // bytes: a b \n c d \n \n e f
  const auto at = [&](std::size_t offset) {
    const TextPosition p = positionOf(text, offset);
    return std::to_string(p.line) + ":" + std::to_string(p.column);
  };
  CHECK(at(0) == "1:1");
  CHECK(at(1) == "1:2");
  CHECK(at(2) == "1:3");  // a newline belongs to the line it ends
  CHECK(at(3) == "2:1");
  CHECK(at(4) == "2:2");
  CHECK(at(5) == "2:3");
  CHECK(at(6) == "3:1");  // the empty line
  CHECK(at(7) == "4:1");
  CHECK(at(8) == "4:2");
  CHECK(at(9) == "4:3");    // one past the end
  CHECK(at(100) == "4:3");  // clamped to the end
  CHECK(positionOf("", 0).line == 1);
  CHECK(positionOf("", 0).column == 1);
  CHECK(positionOf("\n\n\n", 3).line == 4);
}

TEST_CASE("json_reader: parseJsonFile reads a document, reports a syntax error as file:line:column", "[sim]") {
  const TempDir dir;
  const fs::path good = dir.write("good.json", "{ \"a\": { \"b\": [1, 2.5, \"x\"] } }\n");
  const json doc = parseJsonFile(good);
  REQUIRE(doc.at("a").at("b").at(1).get<double>() == 2.5);
  REQUIRE(doc.at("a").at("b").at(2).get<std::string>() == "x");

  // A stray '@' at line 3, column 5; nlohmann stops at that byte.
  const fs::path bad = dir.write("bad.json", "{\n  \"a\": 1,\n    @ \"b\": 2\n}\n");
  REQUIRE_THROWS_AS(parseJsonFile(bad), ScenarioError);
  REQUIRE_THAT(messageOf([&] { parseJsonFile(bad); }), Equals(bad.string() + ":3:5: JSON syntax error"));

  // A missing comma before "b" (line 2, columns 3 to 5): nlohmann stops after the whole unexpected token,
  // so the position is the token's last byte, its closing quote at column 5, not its start.
  const fs::path comma = dir.write("comma.json", "{\"a\": 1\n  \"b\": 2, \"c\" 3}");
  REQUIRE_THAT(messageOf([&] { parseJsonFile(comma); }), Equals(comma.string() + ":2:5: JSON syntax error"));

  // The first byte: line 1, column 1.
  const fs::path first = dir.write("first.json", "]");
  REQUIRE_THAT(messageOf([&] { parseJsonFile(first); }), Equals(first.string() + ":1:1: JSON syntax error"));

  const fs::path missing = dir.path() / "nope.json";
  REQUIRE_THAT(messageOf([&] { parseJsonFile(missing); }), Equals(missing.string() + ": cannot open"));
}

// Found by tests/fuzz/fuzz_wrap_scenario: a number beyond double's range escaped as nlohmann's out_of_range,
// not a ScenarioError (the fuzzer's wrap scenario, cut down to the line that did it).
TEST_CASE("json_reader: a number out of double's range is a ScenarioError naming it and its position", "[sim]") {
  const TempDir dir;
  const fs::path big = dir.write(
      "big.json", "{\"model\": {\"mesh\": \"../meshes/tiny.obj\",\n  \"off0et_m\": [0.0, -1e3080.05, 1.0] }}\n");
  REQUIRE_THROWS_AS(parseJsonFile(big), ScenarioError);
  REQUIRE_THAT(messageOf([&] { parseJsonFile(big); }),
               Equals(big.string() + ":2:21: JSON number out of range '-1e3080'"));
  const fs::path huge = dir.write("huge.json", "1e400");
  REQUIRE_THAT(messageOf([&] { parseJsonFile(huge); }),
               Equals(huge.string() + ":1:1: JSON number out of range '1e400'"));
}

TEST_CASE("json_reader: numbers and integers with defaults and ranges, errors naming file and key path", "[sim]") {
  const JsonReader r = reader(R"({"b": 7, "half": 1.5, "n": 3, "s": "x", "neg": -2})", "a");
  CHECK(r.number("b", 0.0, 0.0, 10.0) == 7.0);
  CHECK(r.number("absent", 0.25, 0.0, 1.0) == 0.25);  // the fallback, not range-checked
  CHECK(r.number("half", 0.0, 1.5, 1.5) == 1.5);      // the range is closed
  CHECK_THAT(messageOf([&] { r.number("b", 0.0, 0.0, 5.0); }), Equals("dir/scene.json: a.b: 7 is outside [0, 5]"));
  CHECK_THAT(messageOf([&] { r.number("half", 0.0, 2.0, 1e9); }),
             Equals("dir/scene.json: a.half: 1.5 is outside [2, 1e+09]"));  // formatNumber's shortest form
  CHECK_THAT(messageOf([&] { r.number("s", 0.0, 0.0, 1.0); }),
             Equals("dir/scene.json: a.s: must be a number, got \"x\""));

  CHECK(r.integer("n", 0, 0, 5) == 3);
  CHECK(r.integer("absent", 42, 0, 5) == 42);
  CHECK(r.integer("neg", 0, -2, 0) == -2);
  CHECK_THAT(messageOf([&] { r.integer("half", 0, 0, 5); }),
             Equals("dir/scene.json: a.half: must be an integer, got 1.5"));
  CHECK_THAT(messageOf([&] { r.integer("neg", 0, 0, 5); }), Equals("dir/scene.json: a.neg: -2 is outside [0, 5]"));
  CHECK_THAT(messageOf([&] { r.integer("b", 0, 0, 6); }), Equals("dir/scene.json: a.b: 7 is outside [0, 6]"));

  // At the root the key stands alone.
  const JsonReader root = reader(R"({"b": 7})");
  CHECK_THAT(messageOf([&] { root.number("b", 0.0, 0.0, 5.0); }), Equals("dir/scene.json: b: 7 is outside [0, 5]"));
}

TEST_CASE("json_reader: booleans, texts and choices", "[sim]") {
  const JsonReader r = reader(R"({"on": true, "off": false, "word": "yes", "num": 3, "kind": "trace"})", "src");
  CHECK(r.boolean("on", false));
  CHECK_FALSE(r.boolean("off", true));
  CHECK(r.boolean("absent", true));
  CHECK_THAT(messageOf([&] { r.boolean("word", false); }), Equals("dir/scene.json: src.word: must be true or false"));
  CHECK_THAT(messageOf([&] { r.boolean("num", false); }), Equals("dir/scene.json: src.num: must be true or false"));

  CHECK(r.text("word", nullptr) == "yes");
  CHECK(r.text("absent", "fallback") == "fallback");
  CHECK_THAT(messageOf([&] { r.text("absent", nullptr); }), Equals("dir/scene.json: src.absent: is missing"));
  CHECK_THAT(messageOf([&] { r.text("num", nullptr); }), Equals("dir/scene.json: src.num: must be a string, got 3"));

  const std::vector<std::string> kinds = {"trace", "strokes", "device"};
  CHECK(r.choice("kind", nullptr, kinds) == "trace");
  CHECK(r.choice("absent", "strokes", kinds) == "strokes");
  CHECK_THAT(messageOf([&] { r.choice("word", nullptr, kinds); }),
             Equals("dir/scene.json: src.word: must be \"trace\", \"strokes\" or \"device\", got \"yes\""));
  CHECK_THAT(messageOf([&] {
               r.choice("word", nullptr, {"a", "b"});
             }),
             Equals("dir/scene.json: src.word: must be \"a\" or \"b\", got \"yes\""));
  CHECK_THAT(messageOf([&] { r.choice("absent", nullptr, kinds); }), Equals("dir/scene.json: src.absent: is missing"));
}

TEST_CASE("json_reader: vectors of exactly 3 numbers", "[sim]") {
  const JsonReader r = reader(R"({"v": [1, -2.5, 3e-3], "two": [1, 2], "four": [1, 2, 3, 4], "text": [1, "2", 3],
                                  "scalar": 1})");
  CHECK(r.vector("v", Eigen::Vector3d::Zero()) == Eigen::Vector3d(1, -2.5, 3e-3));
  CHECK(r.vector("absent", Eigen::Vector3d(4, 5, 6)) == Eigen::Vector3d(4, 5, 6));
  CHECK_THAT(messageOf([&] { r.vector("two", Eigen::Vector3d::Zero()); }),
             Equals("dir/scene.json: two: must be an array of 3 numbers, got [1,2]"));
  CHECK_THAT(messageOf([&] { r.vector("four", Eigen::Vector3d::Zero()); }),
             Contains("four: must be an array of 3 numbers, got [1,2,3,4]"));
  CHECK_THAT(messageOf([&] { r.vector("text", Eigen::Vector3d::Zero()); }),
             Contains("text: must be an array of 3 numbers, got [1,\"2\",3]"));
  CHECK_THAT(messageOf([&] { r.vector("scalar", Eigen::Vector3d::Zero()); }),
             Contains("scalar: must be an array of 3 numbers, got 1"));
}

TEST_CASE("json_reader: objects() gives each entry its key path list[i]", "[sim]") {
  const JsonReader r = reader(R"({"list": [{"n": 1}, {"n": "x"}], "empty": [], "notarray": {"n": 1},
                                  "mixed": [{"n": 1}, 2]})",
                              "pose_source");
  const std::vector<JsonReader> list = r.objects("list");
  REQUIRE(list.size() == 2);
  CHECK(list[0].number("n", 0.0, 0.0, 5.0) == 1.0);
  CHECK_THAT(messageOf([&] { list[1].number("n", 0.0, 0.0, 5.0); }),
             Equals("dir/scene.json: pose_source.list[1].n: must be a number, got \"x\""));
  CHECK_THAT(messageOf([&] { list[1].fail("is odd"); }), Equals("dir/scene.json: pose_source.list[1]: is odd"));
  CHECK_THAT(messageOf([&] { r.objects("empty"); }),
             Equals("dir/scene.json: pose_source.empty: must be a non-empty array"));
  CHECK_THAT(messageOf([&] { r.objects("notarray"); }),
             Equals("dir/scene.json: pose_source.notarray: must be a non-empty array"));
  CHECK_THAT(messageOf([&] { r.objects("absent"); }),
             Equals("dir/scene.json: pose_source.absent: must be a non-empty array"));
  CHECK_THAT(messageOf([&] { r.objects("mixed"); }), Equals("dir/scene.json: pose_source.mixed[1]: must be an object"));
}

TEST_CASE("json_reader: child() of an absent key gives defaults, requiredChild() says it is missing", "[sim]") {
  const JsonReader r = reader(R"({"tissue": {"scale": 0.01, "tets": {"max": -1}}, "num": 3})");
  const JsonReader absent = r.child("tool");
  CHECK(absent.raw().is_object());
  CHECK(absent.raw().empty());
  CHECK(absent.number("blade_length_m", 0.03, 0.0, 1.0) == 0.03);
  CHECK(absent.text("name", "scalpel") == "scalpel");
  CHECK_THAT(messageOf([&] { absent.text("name", nullptr); }), Equals("dir/scene.json: tool.name: is missing"));

  const JsonReader tissue = r.requiredChild("tissue");
  CHECK(tissue.number("scale", 1.0, 0.0, 1.0) == 0.01);
  CHECK_THAT(messageOf([&] { tissue.child("tets").number("max", 0.0, 0.0, 1.0); }),
             Equals("dir/scene.json: tissue.tets.max: -1 is outside [0, 1]"));
  CHECK_THAT(messageOf([&] { r.requiredChild("pose_source"); }), Equals("dir/scene.json: pose_source: is missing"));
  CHECK_THAT(messageOf([&] { tissue.requiredChild("mesh"); }), Equals("dir/scene.json: tissue.mesh: is missing"));
  // A key that is there but is not an object, and a document that is not one.
  CHECK_THAT(messageOf([&] { r.child("num"); }), Equals("dir/scene.json: num: must be an object"));
  CHECK_THAT(messageOf([&] { JsonReader("dir/scene.json", json::array(), ""); }),
             Equals("dir/scene.json: the document must be a JSON object"));
  CHECK(r.has("num"));
  CHECK_FALSE(r.has("tool"));
  CHECK(r.join("x") == "x");
  CHECK(tissue.join("x") == "tissue.x");
}

TEST_CASE("json_reader: file() is relative to the scenario's folder and must exist", "[sim]") {
  const TempDir dir;
  const fs::path scenario = dir.write("scenes/cut.json", R"({"tissue": {"mesh": "meshes/m.obj", "gone": "meshes/x.obj"},
                                                             "up": "../top.txt"})");
  dir.write("scenes/meshes/m.obj", "v 0 0 0\n");
  dir.write("top.txt", "top\n");
  const json doc = parseJsonFile(scenario);
  const JsonReader root(scenario, doc, "");
  const JsonReader tissue = root.requiredChild("tissue");
  const fs::path mesh = tissue.file("mesh");
  CHECK(mesh == scenario.parent_path() / "meshes/m.obj");
  CHECK(fs::equivalent(mesh, dir.path() / "scenes/meshes/m.obj"));
  CHECK(fs::equivalent(root.file("up"), dir.path() / "top.txt"));

  const fs::path gone = scenario.parent_path() / "meshes/x.obj";
  CHECK_THAT(messageOf([&] { tissue.file("gone"); }),
             Equals(scenario.string() + ": tissue.gone: file " + gone.string() + " does not exist"));
  CHECK_THAT(messageOf([&] { tissue.file("absent"); }), Equals(scenario.string() + ": tissue.absent: is missing"));
}

// Regression, found by fuzz_scenario's long run (tests/fuzz/corpus/fuzz_scenario/name-too-long.json): a name
// the system refuses to look up (a component over NAME_MAX, 255 bytes on Linux) made std::filesystem::exists
// throw filesystem_error out of the loader instead of a ScenarioError at the key.
TEST_CASE("json_reader: file() with a name the system cannot look up is a ScenarioError at its key", "[sim]") {
  const TempDir dir;
  const std::string name(300, 'k');
  const fs::path scenario = dir.write("cut.json", "{\"trace\": \"" + name + ".csv\"}");
  const json doc = parseJsonFile(scenario);
  const JsonReader root(scenario, doc, "");
  const std::string message = messageOf([&] { root.file("trace"); });
  CHECK_THAT(message, Contains(scenario.string() + ": trace: file "));
  CHECK_THAT(message, Contains(name + ".csv cannot be looked up: "));
}

// Regression, once a bug: integer() reads any JSON integer with get<long long>(), and nlohmann casts an unsigned value above
// LLONG_MAX without a check: 18446744073709551615 becomes -1 and passes the range [-5, 5], and
// 9223372036854775808 is reported as "-9223372036854775808 is outside ...".
TEST_CASE("json_reader: an unsigned integer beyond long long is refused, not wrapped", "[sim]") {
  const JsonReader r = reader(R"({"max": 18446744073709551615, "big": 9223372036854775808})");
  CHECK_THAT(messageOf([&] { r.integer("max", 0, -5, 5); }), Contains("max: 18446744073709551615 is outside [-5, 5]"));
  CHECK_THAT(messageOf([&] { r.integer("big", 0, -5, 5); }), Contains("big: 9223372036854775808 is outside [-5, 5]"));
}
