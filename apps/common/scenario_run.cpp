#include "scenario_run.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"

#include <cstdio>
#include <cstdlib>

#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/devices/trace_csv.h"
#include "incise/sim/stroke_poses.h"

namespace incise::apps {

namespace {

// The recording through the HID parser and profile; bad reports are skipped as a live device's would be,
// and said once on stderr.
std::vector<devices::PoseSample> hidRecordingPoses(const sim::HidRecordingSource& hid) {
  const devices::HidRecording recording = devices::readHidRecording(hid.path);
  devices::HidRecordingPoses result = devices::posesFromHidRecording(recording, hid.device, hid.mapping, hid.path);
  if (result.bad_reports > 0)
    std::fprintf(stderr, "incise: warning: %s:%zu: %zu bad report(s) skipped (undeclared ID or too short)\n",
                 hid.path.string().c_str(), result.first_bad_line, result.bad_reports);
  if (result.poses.empty())
    throw std::invalid_argument(hid.path.string() + ": device " + std::to_string(hid.device) +
                                ": no report moved the tool (" + std::to_string(result.reports) + " reports)");
  return std::move(result.poses);
}

}  // namespace

std::vector<devices::PoseSample> scenarioPoses(const sim::Scenario& scenario, const mesh::SurfaceMesh& tissue) {
  switch (scenario.source) {
    case sim::Scenario::Source::Trace:
      return devices::TraceReader::readAll(scenario.trace);
    case sim::Scenario::Source::HidRecording:
      return hidRecordingPoses(scenario.hid);
    case sim::Scenario::Source::Strokes:
      break;
  }
  return sim::posesForStrokes(tissue, scenario.strokes, scenario.world, scenario.rate_hz);
}

LoadedScenario loadScenarioRun(const std::string& path) {
  LoadedScenario run;
  run.scenario = sim::loadScenario(path);
  mesh::SurfaceMesh tissue = sim::loadTissue(run.scenario);
  if (run.scenario.plan.given)
    run.plan =
        sim::projectPlan(run.scenario.plan, tissue, run.scenario.world.cutter.incision.spacing_m, run.scenario.file);
  run.poses = scenarioPoses(run.scenario, tissue);
  run.world = std::make_unique<sim::World>(std::move(tissue), run.scenario.world);
  return run;
}

std::string tissueHashText(const mesh::SurfaceMesh& tissue) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(mesh::geometryHash(tissue)));
  return buffer;
}

std::string traceTissueHash(const std::vector<std::string>& comments) {
  const std::string prefix = kTissueComment;
  for (const std::string& c : comments)
    if (c.rfind(prefix, 0) == 0) return c.substr(prefix.size());
  return "";
}

void failWith(const char* command, const std::string& message) {
  std::fprintf(stderr, "incise %s: %s\n", command, message.c_str());
  std::exit(2);
}

}  // namespace incise::apps
