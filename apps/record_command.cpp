// `incise record SCENARIO --out trace.csv`: records the scenario's pose source to a CSV trace
// (devices/TRACE_FORMAT.md). With a generated source ("strokes") this is the documented generator of the
// shipped traces (scripts/make_traces.sh). The writer flushes every 50 samples, so a recording that is
// killed leaves a trace that reads back up to its last flush.
#include <cstdio>

#include "commands.h"
#include "incise/cutting/surface_mesh.h"
#include "incise/devices/trace_csv.h"
#include "scenario_run.h"

namespace incise::apps {

namespace {

struct RecordArgs {
  std::string scenario;
  std::string out;
};

int runRecord(const RecordArgs& a) {
  std::vector<devices::PoseSample> poses;
  sim::Scenario scenario;
  try {
    scenario = sim::loadScenario(a.scenario);
    poses = scenarioPoses(scenario, sim::loadTissue(scenario));
  } catch (const std::exception& e) {
    failWith("record", e.what());
  }
  try {
    devices::TraceWriterOptions options;
    options.comments = {
        "generator: incise record " + std::filesystem::path(a.scenario).filename().string(),
        "scenario: " + scenario.name,
        "source: " + std::string(scenario.source == sim::Scenario::Source::Strokes ? "generated strokes" : "trace")};
    devices::TraceWriter writer(a.out, options);
    for (const auto& pose : poses) writer.write(pose);
    writer.close();
  } catch (const std::exception& e) {
    failWith("record", e.what());
  }
  std::printf("incise record: %zu poses from %s to %s\n", poses.size(), scenario.name.c_str(), a.out.c_str());
  return 0;
}

}  // namespace

void addRecordCommand(CLI::App& app) {
  auto args = std::make_shared<RecordArgs>();
  CLI::App* cmd = app.add_subcommand("record", "Record a scenario's pose source to a CSV trace");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON)")->required();
  cmd->add_option("--out", args->out, "trace file to write")->required();
  cmd->callback([args] {
    const int code = runRecord(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps
