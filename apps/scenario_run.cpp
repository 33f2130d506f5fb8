#include "scenario_run.h"
#include "incise/cutting/surface_mesh.h"

#include <cstdio>
#include <cstdlib>

#include "incise/devices/trace_csv.h"
#include "incise/sim/stroke_poses.h"

namespace incise::apps {

std::vector<devices::PoseSample> scenarioPoses(const sim::Scenario& scenario, const cutting::SurfaceMesh& tissue) {
  if (scenario.source == sim::Scenario::Source::Trace) return devices::TraceReader::readAll(scenario.trace);
  return sim::posesForStrokes(tissue, scenario.strokes, scenario.world, scenario.rate_hz);
}

LoadedScenario loadScenarioRun(const std::string& path) {
  LoadedScenario run;
  run.scenario = sim::loadScenario(path);
  cutting::SurfaceMesh tissue = sim::loadTissue(run.scenario);
  run.poses = scenarioPoses(run.scenario, tissue);
  run.world = std::make_unique<sim::World>(std::move(tissue), run.scenario.world);
  return run;
}

void failWith(const char* command, const std::string& message) {
  std::fprintf(stderr, "incise %s: %s\n", command, message.c_str());
  std::exit(2);
}

}  // namespace incise::apps
