// libFuzzer harness: the wrap scenario loader (sim/wrap_scenario.h: loadWrapScenario), which also builds
// the model and the obstacles (mesh files through loadSurfaceMesh, or shapes). The input is the scenario's
// JSON text, written to scratch/scenarios/wrap/scenario.json; the meshes it may name are tiny valid ones
// (scenario_files.h: "../meshes/tiny.obj", "../meshes/tiny.off"). ScenarioError is the documented failure;
// anything else escaping, a crash, a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include "incise/sim/wrap_scenario.h"
#include "scenario_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return incise::fuzz::runScenario(data, size, "scenarios/wrap/scenario.json", [](const std::filesystem::path& path) {
    const auto s = incise::sim::loadWrapScenario(path);
    (void)incise::sim::treatmentName(s.treatment);
  });
}
