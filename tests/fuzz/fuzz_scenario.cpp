// libFuzzer harness: the replay scenario loader (sim/scenario.h: loadScenario). The input is the scenario's
// JSON text, written to scratch/scenarios/scenario.json; the files it may name are tiny valid ones
// (scenario_files.h). ScenarioError is the documented failure; anything else escaping, a crash, a hang or a
// sanitizer report is a finding. The tissue itself is not built (loadTissue is not the loader: its cost is
// the mesh's, chosen by the scenario's author).
#include <cstddef>
#include <cstdint>

#include "incise/sim/scenario.h"
#include "scenario_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return incise::fuzz::runScenario(data, size, "scenarios/scenario.json", [](const std::filesystem::path& path) {
    const auto s = incise::sim::loadScenario(path);
    (void)s.periodUs();
  });
}
