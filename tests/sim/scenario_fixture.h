// Test support for scenario loaders: a temporary folder holding the shipped bunny under meshes/, so that
// a test's scenario text can say "mesh": "meshes/bunny.obj". One folder per test binary (a function-local
// static), removed at exit.
#pragma once

#include <filesystem>
#include <string>

#include "support/temp_dir.h"

namespace incise::test {

class ScenarioDir : public TempDir {
 public:
  ScenarioDir() {
    std::filesystem::create_directories(path() / "meshes");
    std::filesystem::copy_file(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", path() / "meshes" / "bunny.obj");
  }
  // Writes `text` as <folder>/<name>.json.
  std::filesystem::path scenario(const std::string& name, const std::string& text) const {
    return write(name + ".json", text);
  }
};

inline const ScenarioDir& scenarioDir() {
  static const ScenarioDir dir;
  return dir;
}

}  // namespace incise::test
