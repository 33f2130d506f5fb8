#include "hid_support.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_usages.h"
#include "incise/devices/hidapi_transport.h"
#include "incise/devices/replay_transport.h"
#include "incise/sim/scenario.h"
#include "scenario_run.h"

namespace incise::apps::hid {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void onStopSignal(int) { g_stop.store(true); }

}  // namespace

std::unique_ptr<devices::HidTransport> makeHidTransport(const std::string& spec) {
  if (spec == "hidapi") return std::make_unique<devices::HidapiTransport>();
  if (spec.rfind("replay:", 0) == 0) {
    const std::string path = spec.substr(7);
    return std::make_unique<devices::ReplayTransport>(devices::readHidRecording(path), 0,
                                                      devices::ReplayTransportOptions{});
  }
  throw std::invalid_argument("--transport '" + spec + "': must be hidapi or replay:FILE.hid");
}

void installStopSignals() {
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
}

bool stopRequested() { return g_stop.load(); }

devices::HidMapping mappingOf(const std::string& scenario) {
  if (scenario.empty()) return {};
  const sim::Scenario s = sim::loadScenario(scenario);
  if (s.source != sim::Scenario::Source::HidRecording)
    throw std::invalid_argument(scenario + ": pose_source is not a hid-recording: it has no pen or six_dof mapping");
  return s.hid.mapping;
}

LiveDevice liveDevice(const char* command, const std::string& transport, const std::string& device,
                      const std::string& scenario) {
  LiveDevice live;
  try {
    live.transport = makeHidTransport(transport);
    live.selector = devices::parseHidDeviceSelector(device);
    live.mapping = mappingOf(scenario);
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
  return live;
}

std::string usageText(std::uint32_t usage) {
  char numbers[32];
  std::snprintf(numbers, sizeof numbers, " (0x%04x:0x%04x)", devices::hidUsagePage(usage), devices::hidUsageId(usage));
  return devices::hidUsagePageName(devices::hidUsagePage(usage)) + ":" + devices::hidUsageName(usage) + numbers;
}

}  // namespace incise::apps::hid
