// `incise hid record --device SEL --out FILE.hid` (raw reports, hid-recorder's format) and `incise record
// --device SEL --out trace.csv [--scenario S]` (poses through the device's profile, a CSV trace), both
// until --duration, SIGINT or SIGTERM. Both writers flush as they go (the hid recorder also whenever the
// device is idle for 50 ms): a recording killed with SIGKILL reads back up to its last flush. Nothing is
// created before the device is open and has given its first report.
#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "hid_commands.h"
#include "hid_support.h"
#include "incise/devices/hid_pose_source.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/pose_queue.h"
#include "scenario_run.h"

namespace incise::apps::hid {
namespace {

using Clock = std::chrono::steady_clock;

struct Opened {
  devices::HidDeviceInfo info;
  std::unique_ptr<devices::HidConnection> connection;
};

Opened openDevice(devices::HidTransport& transport, const devices::HidDeviceSelector& selector) {
  std::string why;
  const auto devices = transport.enumerate();
  for (const devices::HidDeviceInfo& d : devices) {
    if (!selector.matches(d)) continue;
    std::string error;
    if (auto c = transport.open(d, error)) return {d, std::move(c)};
    why = "; " + d.path + ": " + error;
  }
  failWith("hid record", "no device " + selector.describe() + " could be opened on " + transport.name() + " (" +
                             std::to_string(devices.size()) + " HID interfaces found" + why + "; see incise hid list)");
}

bool timeUp(Clock::time_point start, double duration_s) {
  return duration_s > 0.0 && std::chrono::duration<double>(Clock::now() - start).count() >= duration_s;
}

}  // namespace

int runHidRecord(const HidRecordArgs& a) {
  installStopSignals();
  const LiveDevice live = liveDevice("hid record", a.transport, a.device, "");
  const devices::HidDeviceSelector& selector = live.selector;
  Opened device = openDevice(*live.transport, selector);
  devices::HidRecordedDevice recorded;
  recorded.name =
      device.info.manufacturer.empty() ? device.info.product : device.info.manufacturer + " " + device.info.product;
  recorded.phys = device.info.path;
  recorded.bus = device.info.bus;
  recorded.vid = device.info.vid;
  recorded.pid = device.info.pid;
  recorded.descriptor = device.connection->descriptor();
  std::optional<devices::HidRecordingWriter> writer;
  devices::HidRecordingWriterOptions options;
  options.flush_every = 8;
  options.comments = {"generator: incise hid record --device " + a.device, "device: " + device.info.path};
  std::array<std::uint8_t, devices::kHidMaxReportBytes> buffer{};
  const auto start = Clock::now();
  Clock::time_point first;
  const char* ended = "stopped";
  try {
    while (!stopRequested() && !timeUp(start, a.duration_s)) {
      const int n = device.connection->read(buffer, 50);
      if (n < 0) {
        ended = "the device went away";
        break;
      }
      if (n == 0) {
        if (writer) writer->flush();
        continue;
      }
      if (!writer) writer.emplace(a.out, recorded, options), first = Clock::now();
      const auto t_us = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - first).count();
      writer->write(t_us, std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)));
    }
    if (!writer) failWith("hid record", "no report from " + selector.describe() + " (" + ended + "); nothing written");
    writer->close();
  } catch (const std::exception& e) {
    failWith("hid record", e.what());
  }
  std::printf("incise hid record: %zu reports from %s '%s' to %s (%s)\n", writer->reportsWritten(),
              devices::formatVidPid(recorded.vid, recorded.pid).c_str(), recorded.name.c_str(), a.out.c_str(), ended);
  return 0;
}

int runPoseRecord(const HidRecordArgs& a) {
  installStopSignals();
  const LiveDevice live = liveDevice("record", a.transport, a.device, a.scenario);
  sim::PoseQueue<8192> queue;
  devices::HidPoseSource source(*live.transport, live.selector, live.mapping, queue,
                                [](const std::string& m) { std::fprintf(stderr, "incise record: %s\n", m.c_str()); });
  std::optional<devices::TraceWriter> writer;
  devices::TraceWriterOptions options;
  options.comments = {"generator: incise record --device " + a.device,
                      "scenario: " + (a.scenario.empty() ? "(default mapping)" : a.scenario)};
  try {  // the tissue the recording was made over, for `incise score` to check against
    if (!a.scenario.empty())
      options.comments.push_back(kTissueComment + tissueHashText(sim::loadTissue(sim::loadScenario(a.scenario))));
  } catch (const std::exception& e) {
    failWith("record", e.what());
  }
  const auto start = Clock::now();
  try {
    source.start();
    devices::PoseSample pose;
    while (!stopRequested() && !timeUp(start, a.duration_s)) {
      while (queue.pop(pose)) (writer ? *writer : writer.emplace(a.out, options)).write(pose);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    source.stop();
    while (queue.pop(pose)) (writer ? *writer : writer.emplace(a.out, options)).write(pose);
    if (!writer) failWith("record", "no pose from " + source.describe() + "; nothing written");
    writer->close();
  } catch (const std::exception& e) {
    source.stop();
    failWith("record", e.what());
  }
  std::printf("incise record: %zu poses from %s to %s (%lld reports, %lld bad)\n", writer->samplesWritten(),
              source.describe().c_str(), a.out.c_str(), static_cast<long long>(source.reports()),
              static_cast<long long>(source.badReports()));
  return 0;
}

}  // namespace incise::apps::hid
