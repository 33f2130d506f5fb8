#include "incise/jobs/scenario_run.h"

#include <cstdio>
#include <stdexcept>

#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/devices/trace_csv.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/stroke_poses.h"

namespace incise::jobs {

namespace {

// The recording through the HID parser and profile; bad reports are skipped as a live device's would be,
// and said once.
std::vector<devices::PoseSample> hidRecordingPoses(const sim::HidRecordingSource& hid, const Warn& warn) {
  const devices::HidRecording recording = devices::readHidRecording(hid.path);
  devices::HidRecordingPoses result = devices::posesFromHidRecording(recording, hid.device, hid.mapping, hid.path);
  if (result.bad_reports > 0)
    warnWith(warn, hid.path.string() + ":" + std::to_string(result.first_bad_line) + ": " +
                       std::to_string(result.bad_reports) + " bad report(s) skipped (undeclared ID or too short)");
  if (result.poses.empty())
    throw std::invalid_argument(hid.path.string() + ": device " + std::to_string(hid.device) +
                                ": no report moved the tool (" + std::to_string(result.reports) + " reports)");
  return std::move(result.poses);
}

}  // namespace

void warnWith(const Warn& warn, const std::string& text) {
  if (warn)
    warn(text);
  else
    std::fprintf(stderr, "incise: warning: %s\n", text.c_str());
}

std::vector<devices::PoseSample> scenarioPoses(const sim::Scenario& scenario, const mesh::SurfaceMesh& tissue,
                                               const Warn& warn) {
  switch (scenario.source) {
    case sim::Scenario::Source::Trace:
      return devices::TraceReader::readAll(scenario.trace);
    case sim::Scenario::Source::HidRecording:
      return hidRecordingPoses(scenario.hid, warn);
    case sim::Scenario::Source::Strokes:
      break;
  }
  return sim::posesForStrokes(tissue, scenario.strokes, scenario.world, scenario.rate_hz);
}

ScenarioRun loadScenarioRun(const std::string& path, const Warn& warn) {
  ScenarioRun run;
  run.scenario = sim::loadScenario(path);
  mesh::SurfaceMesh tissue = sim::loadTissue(run.scenario);
  if (run.scenario.plan.given)
    run.plan =
        sim::projectPlan(run.scenario.plan, tissue, run.scenario.world.cutter.incision.spacing_m, run.scenario.file);
  run.poses = scenarioPoses(run.scenario, tissue, warn);
  run.world = std::make_unique<sim::World>(std::move(tissue), run.scenario.world);
  return run;
}

std::string hexText(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

std::string tissueHashText(const mesh::SurfaceMesh& tissue) { return hexText(mesh::geometryHash(tissue)); }

std::string traceTissueHash(const std::vector<std::string>& comments) {
  const std::string prefix = kTissueComment;
  for (const std::string& c : comments)
    if (c.rfind(prefix, 0) == 0) return c.substr(prefix.size());
  return "";
}

}  // namespace incise::jobs
