// `incise hid list | decode | record | synth`: HID devices and their recordings.
//   list    every HID interface the transport sees: path, VID:PID, serial, name, top-level usage, and the
//           profile incise would use (or why none).
//   decode  hid_decode.cpp.   record  hid_record.cpp.   calibrate  hid_calibrate.cpp.
//   synth   the generator of the shipped recordings: `incise hid synth SCENARIO` makes the recording a
//           hid-recording scenario names, from its "synthesis" block (the strokes of another scenario, a real
//           descriptor), written atomically (FILE.tmp, then renamed). scripts/make_hid_recordings.sh runs it.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "hid_commands.h"
#include "hid_support.h"
#include "incise/core/atomic_file.h"
#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_synth.h"
#include "incise/mesh/surface_mesh.h"
#include "json_output.h"
#include "scenario_run.h"

namespace incise::apps::hid {
namespace {

struct ListArgs {
  std::string transport = "hidapi";
};

int runList(const ListArgs& a) {
  std::unique_ptr<devices::HidTransport> transport;
  try {
    transport = makeHidTransport(a.transport);
  } catch (const std::exception& e) {
    failWith("hid list", e.what());
  }
  const auto devices = transport->enumerate();
  if (devices.empty())
    std::printf(
        "no HID devices found through %s (none plugged in, or /dev/hidraw* not readable: see README, \"HID devices\")\n",
        transport->name().c_str());
  for (const devices::HidDeviceInfo& d : devices) {
    std::string error, profile;
    const auto bytes = transport->descriptorOf(d, error);
    try {
      profile = bytes.empty() ? "no profile: cannot read the report descriptor: " + error
                              : devices::chooseHidProfile(devices::parseHidDescriptor(bytes), {d.vid, d.pid}).reason;
    } catch (const devices::HidDescriptorError& e) {
      profile = std::string("no profile: ") + e.what();
    }
    std::printf("%s  %s  serial '%s'  '%s %s'  usage %s\n  profile %s\n", d.path.c_str(),
                devices::formatVidPid(d.vid, d.pid).c_str(), d.serial.c_str(), d.manufacturer.c_str(),
                d.product.c_str(), usageText(devices::hidUsage(d.usage_page, d.usage)).c_str(), profile.c_str());
  }
  return 0;
}

// Writes `recording` through HidRecordingWriter to path.tmp, then renames it (nothing half-written).
void writeRecordingAtomically(const devices::HidRecording& recording, const std::filesystem::path& path,
                              const std::vector<std::string>& comments) {
  writeThroughTemporary(path, [&](const std::filesystem::path& tmp) {
    devices::HidRecordingWriterOptions options;
    options.flush_every = 4096;
    options.comments = comments;
    devices::HidRecordingWriter writer(tmp, recording.devices.at(0), options);
    for (const auto& r : recording.reports) writer.write(r.time_us, r.bytes);
    writer.close();
  });
}

// The '#' lines of a descriptor file without the "# " (its origin and licence).
std::vector<std::string> commentLines(const std::filesystem::path& path) {
  std::vector<std::string> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("#", 0) == 0) lines.push_back(line.substr(line.rfind("# ", 0) == 0 ? 2 : 1));
  return lines;
}

struct SynthArgs {
  std::string scenario;
  std::string out;  // default: the scenario's pose_source.path
};

int runSynth(const SynthArgs& a) {
  try {
    const sim::Scenario s = sim::loadScenario(a.scenario);
    if (s.source != sim::Scenario::Source::HidRecording || !s.hid.synthesis.given)
      throw std::invalid_argument(a.scenario + ": pose_source is not a hid-recording with a \"synthesis\" block");
    const sim::HidSynthesis& how = s.hid.synthesis;
    const sim::Scenario from = sim::loadScenario(how.from);
    const auto poses = scenarioPoses(from, sim::loadTissue(from));
    devices::HidRecordedDevice device;
    device.name = how.name;
    device.bus = 3;
    device.vid = how.vid;
    device.pid = how.pid;
    device.descriptor = devices::loadHexBytes(how.descriptor);
    const devices::HidRecording recording =
        devices::synthesizeHidRecording(device, s.hid.mapping, poses, {how.rate_hz});
    const std::filesystem::path out = a.out.empty() ? s.hid.path : std::filesystem::path(a.out);
    std::vector<std::string> comments = {
        "generator: incise hid synth " + std::filesystem::path(a.scenario).filename().string(),
        "strokes: " + std::filesystem::path(how.from).filename().string() +
            ", descriptor: " + how.descriptor.filename().string()};
    for (const std::string& line : commentLines(how.descriptor))
      comments.push_back("descriptor " + line);  // origin, licence
    writeRecordingAtomically(recording, out, comments);
    std::printf("incise hid synth: %zu reports (%zu poses) to %s\n", recording.reports.size(), poses.size(),
                out.c_str());
  } catch (const std::exception& e) {
    failWith("hid synth", e.what());
  }
  return 0;
}

template <typename Args, typename Run>
void onRun(CLI::App* cmd, std::shared_ptr<Args> args, Run run) {
  cmd->callback([args, run] {
    const int code = run(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace

void addHidCommand(CLI::App& app) {
  CLI::App* hid = app.add_subcommand(
      "hid", "HID devices: list them, decode and record their reports, calibrate a pen, synthesise recordings");
  hid->require_subcommand(1);

  auto list = std::make_shared<ListArgs>();
  CLI::App* list_cmd = hid->add_subcommand("list", "List HID devices and the profile incise would use");
  list_cmd->add_option("--transport", list->transport, "hidapi, or replay:FILE.hid (a recording as a device)");
  onRun(list_cmd, list, runList);

  auto decode = std::make_shared<HidDecodeArgs>();
  CLI::App* decode_cmd = hid->add_subcommand("decode", "Print a hid-recorder file's reports by field, and their poses");
  decode_cmd->add_option("file", decode->file, "hid-recorder file, or a report descriptor as hex bytes")->required();
  decode_cmd->add_flag("--json", decode->json, "one JSON object per report per line");
  decode_cmd->add_option("--scenario", decode->scenario, "a hid-recording scenario whose mapping makes the poses");
  decode_cmd->add_option("--device", decode->device, "device index (D:) in the recording")
      ->check(CLI::NonNegativeNumber);
  onRun(decode_cmd, decode, runHidDecode);

  auto record = std::make_shared<HidRecordArgs>();
  CLI::App* record_cmd = hid->add_subcommand("record", "Record a live device's raw reports to a hid-recorder file");
  record_cmd->add_option("--device", record->device, "VID:PID[:serial] in hex, or /dev/hidrawN")->required();
  record_cmd->add_option("--out", record->out, "hid-recorder file to write")->required();
  record_cmd->add_option("--duration", record->duration_s, "seconds (default: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  record_cmd->add_option("--transport", record->transport, "hidapi, or replay:FILE.hid (a recording as a device)");
  onRun(record_cmd, record, runHidRecord);

  auto calibrate = std::make_shared<HidCalibrateArgs>();
  CLI::App* calibrate_cmd =
      hid->add_subcommand("calibrate", "A scenario's pen block from presses at two corners and one firm press");
  calibrate_cmd->add_option("--device", calibrate->device, "VID:PID[:serial] in hex, or /dev/hidrawN")->required();
  calibrate_cmd->add_option("--transport", calibrate->transport,
                            "hidapi, or replay:FILE.hid (a recording as a device)");
  calibrate_cmd->add_option("--scenario", calibrate->scenario,
                            "hid-recording scenario: its pen rectangle over the tissue, and the keys kept");
  calibrate_cmd->add_option("--timeout", calibrate->timeout_s, "seconds to wait for the presses (default 120)")
      ->check(CLI::PositiveNumber);
  onRun(calibrate_cmd, calibrate, runHidCalibrate);

  auto synth = std::make_shared<SynthArgs>();
  CLI::App* synth_cmd =
      hid->add_subcommand("synth", "Make a hid-recording scenario's recording from its synthesis block");
  synth_cmd->add_option("scenario", synth->scenario, "hid-recording scenario with a \"synthesis\" block")->required();
  synth_cmd->add_option("--out", synth->out, "recording to write (default: the scenario's pose_source.path)");
  onRun(synth_cmd, synth, runSynth);
}

}  // namespace incise::apps::hid
