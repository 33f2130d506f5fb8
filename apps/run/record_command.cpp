// `incise record SCENARIO --out trace.csv`: records the scenario's pose source to a CSV trace; with
// `--device VID:PID` a live HID device's poses instead (hid_record.cpp), mapped as SCENARIO's hid-recording
// source says (the defaults without one)
// (devices/TRACE_FORMAT.md). With a generated source ("strokes") this is the documented generator of the
// shipped traces (scripts/make_traces.sh). The writer flushes every 50 samples, so a recording that is
// killed leaves a trace that reads back up to its last flush.
#include <cstdio>

#include "hid_commands.h"
#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "run_commands.h"
#include "scenario_run.h"

namespace incise::apps::run {

namespace {

struct RecordArgs {
  std::string scenario;
  std::string out;
  hid::HidRecordArgs live;  // --device given: a live HID device instead of the scenario's pose source
};

std::string sourceName(sim::Scenario::Source source) {
  switch (source) {
    case sim::Scenario::Source::Strokes:
      return "generated strokes";
    case sim::Scenario::Source::HidRecording:
      return "hid-recording";
    case sim::Scenario::Source::Trace:
      break;
  }
  return "trace";
}

int runRecord(const RecordArgs& a) {
  std::vector<devices::PoseSample> poses;
  sim::Scenario scenario;
  std::string tissue_hash;
  try {
    scenario = sim::loadScenario(a.scenario);
    const mesh::SurfaceMesh tissue = sim::loadTissue(scenario);
    tissue_hash = tissueHashText(tissue);
    poses = scenarioPoses(scenario, tissue);
  } catch (const std::exception& e) {
    failWith("record", e.what());
  }
  try {
    devices::TraceWriterOptions options;
    options.comments = {"generator: incise record " + std::filesystem::path(a.scenario).filename().string(),
                        "scenario: " + scenario.name, "source: " + sourceName(scenario.source),
                        kTissueComment + tissue_hash};
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
  cmd->add_option("scenario", args->scenario,
                  "scenario file (JSON); with --device, the hid-recording scenario whose mapping to use");
  cmd->add_option("--out", args->out, "trace file to write")->required();
  cmd->add_option("--device", args->live.device, "record a live HID device (VID:PID[:serial] or /dev/hidrawN) instead");
  cmd->add_option("--duration", args->live.duration_s, "with --device: seconds (default: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--transport", args->live.transport,
                  "with --device: hidapi, or replay:FILE.hid (a recording as a device)");
  cmd->callback([args] {
    int code = 0;
    if (!args->live.device.empty()) {
      args->live.out = args->out;
      args->live.scenario = args->scenario;
      code = hid::runPoseRecord(args->live);
    } else if (args->scenario.empty()) {
      failWith("record", "give a scenario, or --device for a live HID device");
    } else {
      code = runRecord(*args);
    }
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::run
