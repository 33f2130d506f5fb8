// What the `incise hid ...` commands and `incise record --device` share: the transport they use, the stop
// signal, the mapping a scenario gives, and the text of a usage.
#pragma once

#include <memory>
#include <string>

#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_transport.h"

namespace incise::apps::hid {

// "hidapi" (the default: real devices through hidraw) or "replay:FILE.hid" (device 0 of a hid-recorder file,
// played in real time as if it were plugged in: for trying the live commands without hardware, and for
// their tests). Throws std::invalid_argument "--transport 'x': ..." for anything else.
std::unique_ptr<devices::HidTransport> makeHidTransport(const std::string& spec);

// SIGINT and SIGTERM end a recording cleanly (its file closed, everything flushed): the handler sets a flag.
void installStopSignals();
bool stopRequested();

// The pen / 6-DOF mapping of a scenario whose pose source is a hid-recording, or the defaults when `scenario`
// is empty. Throws sim::ScenarioError.
devices::HidMapping mappingOf(const std::string& scenario);

// What a live command starts from: its transport, the device selector and the scenario's mapping. Bad
// input (a transport, selector or scenario refused) exits 2 with "incise COMMAND: what" (failWith).
struct LiveDevice {
  std::unique_ptr<devices::HidTransport> transport;
  devices::HidDeviceSelector selector;
  devices::HidMapping mapping;
};
LiveDevice liveDevice(const char* command, const std::string& transport, const std::string& device,
                      const std::string& scenario);

// "Digitizers:Pen (0x000d:0x0002)"
std::string usageText(std::uint32_t usage);

}  // namespace incise::apps::hid
