// Test support: a shipped scenario (scenarios/<name>.json) loaded with its tissue in a world and its poses
// (its trace's, or those of its generated strokes), as replay would run it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/stroke_poses.h"
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
  mesh::SurfaceMesh tissue = sim::loadTissue(l.scenario);
  l.poses = l.scenario.source == sim::Scenario::Source::Strokes
                ? sim::posesForStrokes(tissue, l.scenario.strokes, l.scenario.world, l.scenario.rate_hz)
                : devices::TraceReader::readAll(l.scenario.trace);
  l.world = std::make_unique<sim::World>(std::move(tissue), l.scenario.world);
  return l;
}

}  // namespace incise::test
