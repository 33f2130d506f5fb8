// libFuzzer harness: the wrap scenario loader (sim/wrap_scenario.h: loadWrapScenario), which also builds
// the model and the obstacles (mesh files through loadSurfaceMesh, or shapes). The input is the scenario's
// JSON text, written to scratch/scenarios/wrap/scenario.json; the meshes it may name are tiny valid ones
// (scenario_files.h: "../meshes/tiny.obj", "../meshes/tiny.off"). ScenarioError is the documented failure;
// anything else escaping, a crash, a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "incise/sim/wrap_scenario.h"
#include "scenario_files.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  incise::fuzz::writeScenarioFiles();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = incise::fuzz::writeInput(data, size, "scenarios/wrap/scenario.json");
  try {
    const incise::sim::WrapScenario scenario = incise::sim::loadWrapScenario(path);
    (void)incise::sim::treatmentName(scenario.treatment);
  } catch (const incise::sim::ScenarioError&) {
  }
  return 0;
}
