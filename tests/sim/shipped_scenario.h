// Test support: a shipped scenario (scenarios/<name>.json) loaded with its tissue in a world and its
// trace's poses, as replay would run it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "incise/devices/trace_csv.h"
#include "incise/sim/scenario.h"
#include "incise/sim/world.h"

namespace incise::test {

struct ShippedScenario {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
};

inline ShippedScenario loadShipped(const std::string& name) {
  ShippedScenario l;
  l.scenario = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  l.world = std::make_unique<sim::World>(sim::loadTissue(l.scenario), l.scenario.world);
  l.poses = devices::TraceReader::readAll(l.scenario.trace);
  return l;
}

}  // namespace incise::test
