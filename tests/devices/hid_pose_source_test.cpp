// The live HID source on the replay transport: poses pushed as reports arrive, the device unplugged and
// replugged mid-stroke (tool lifted at once, reopened by VID/PID under a new path, resumed), bad reports
// counted and skipped, a clean stop. The threaded cases also run under ThreadSanitizer (.ci/run).
#include <catch2/catch.hpp>

#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_pose_source.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hidapi_transport.h"
#include "incise/devices/replay_transport.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

class RecordingSink final : public PoseSink {
 public:
  bool push(const PoseSample& sample) noexcept override {
    std::lock_guard lock(mutex_);
    samples_.push_back(sample);
    return true;
  }
  std::vector<PoseSample> samples() const {
    std::lock_guard lock(mutex_);
    return samples_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<PoseSample> samples_;
};

// An XP-Pen stroke: `count` reports 5 ms apart, tip down, moving right across the tablet.
std::vector<HidRecordedReport> penStroke(const HidDescriptor& d, int count) {
  const HidReportEncoder encoder(d);
  const HidReportLayout& layout = *d.find(HidReportType::Input, 7);
  std::vector<HidRecordedReport> reports;
  for (int k = 0; k < count; ++k) {
    auto raw = encoder.blank(layout);
    encoder.setLogical(raw, layout, hidUsage(0x0D, 0x32), 1);
    encoder.setLogical(raw, layout, hidUsage(0x0D, 0x42), 1);
    encoder.setLogical(raw, layout, hidUsage(0x01, 0x30), 1000 + 200 * k);
    encoder.setLogical(raw, layout, hidUsage(0x01, 0x31), 16000);
    encoder.setLogical(raw, layout, hidUsage(0x0D, 0x30), 8000);
    reports.push_back({0, 5000 * k, raw, 0});
  }
  return reports;
}

ReplayTransportOptions xpPen() {
  ReplayTransportOptions options;
  options.device.vid = 0x28bd;
  options.device.pid = 0x095b;
  options.device.serial = "SN1";
  options.device.product = "Artist Pro 16 (Gen2)";
  return options;
}

bool waitFor(const std::function<bool()>& done, double timeout_s = 10.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

struct Messages {
  std::mutex mutex;
  std::vector<std::string> lines;
  HidPoseSource::MessageFn callback() {
    return [this](const std::string& line) {
      std::lock_guard lock(mutex);
      lines.push_back(line);
    };
  }
  std::vector<std::string> all() {
    std::lock_guard lock(mutex);
    return lines;
  }
};

}  // namespace

TEST_CASE("hid_pose_source: unplugged mid-stroke, lifted at once, reopened by VID/PID, resumed",
          "[devices][hid][threads]") {
  const auto descriptor_bytes = loadShippedDescriptor(kXpPenDescriptor);
  const HidDescriptor d = parseHidDescriptor(descriptor_bytes);
  auto options = xpPen();
  options.cues = {{40, 0.3}};
  ReplayTransport transport(descriptor_bytes, penStroke(d, 80), options);
  RecordingSink sink;
  Messages messages;
  HidPoseSourceOptions source_options;
  source_options.reconnect_period_s = 0.05;
  HidPoseSource source(transport, parseHidDeviceSelector("28bd:095b:SN1"), {}, sink, messages.callback(),
                       source_options);
  source.start();
  REQUIRE(waitFor([&] { return transport.unplugged(); }));
  const auto unplugged_at = std::chrono::steady_clock::now();
  REQUIRE(waitFor([&] { return source.state() == HidSourceState::Unplugged; }));
  // The lifted pose is pushed before the state says unplugged: it is already there.
  const auto at_unplug = sink.samples();
  REQUIRE(at_unplug.size() == 41);
  CHECK(at_unplug[39].buttons == 1u);
  CHECK(at_unplug[40].buttons == 0u);
  CHECK(at_unplug[40].tip_m.z() > at_unplug[39].tip_m.z());
  CHECK(at_unplug[40].time_s - at_unplug[39].time_s < 0.1);
  REQUIRE(waitFor([&] { return transport.delivered() == transport.reportCount(); }));
  CHECK(std::chrono::steady_clock::now() - unplugged_at > std::chrono::milliseconds(250));  // stayed away
  CHECK(source.state() == HidSourceState::Connected);
  CHECK(source.describe().find("replay:hidraw1") != std::string::npos);  // the new path
  source.stop();
  CHECK(source.state() == HidSourceState::Stopped);
  const auto all = sink.samples();
  REQUIRE(all.size() == 80 + 2);  // every report, the unplug's lifted pose, the stop's
  CHECK(all[41].buttons == 1u);   // resumed cutting
  CHECK(all.back().buttons == 0u);
  for (std::size_t i = 1; i < all.size(); ++i) CHECK(all[i].time_s > all[i - 1].time_s);
  CHECK(source.connects() == 2);
  CHECK(source.disconnects() == 1);
  const auto lines = messages.all();
  REQUIRE(lines.size() == 4);
  CHECK(lines[0] == "connected: 28bd:095b 'Artist Pro 16 (Gen2)' at replay:hidraw0, pen profile");
  CHECK(lines[1] ==
        "unplugged: 28bd:095b 'Artist Pro 16 (Gen2)' at replay:hidraw0, pen profile (replayed device unplugged); the "
        "tool is lifted");
  CHECK(lines[2] == "no device 28bd:095b:SN1 on replay transport");  // once, while it is away
  CHECK(lines[3] == "connected: 28bd:095b 'Artist Pro 16 (Gen2)' at replay:hidraw1, pen profile");
}

TEST_CASE("hid_pose_source: bad reports are counted and skipped, never a crash", "[devices][hid][threads]") {
  const auto descriptor_bytes = loadShippedDescriptor(kXpPenDescriptor);
  const HidDescriptor d = parseHidDescriptor(descriptor_bytes);
  auto reports = penStroke(d, 6);
  reports[2].bytes.resize(4);  // shorter than report 7's layout
  reports[3].bytes[0] = 0x55;  // an ID the descriptor does not declare
  auto options = xpPen();
  options.real_time = false;
  ReplayTransport transport(descriptor_bytes, reports, options);
  RecordingSink sink;
  HidPoseSource source(transport, parseHidDeviceSelector("28bd:095b"), {}, sink);
  source.start();
  REQUIRE(waitFor([&] { return source.reports() == 6; }));
  source.stop();
  CHECK(source.badReports() == 2);
  CHECK(sink.samples().size() == 4 + 1);
}

TEST_CASE("hid_pose_source: no matching device, or a broken descriptor: messages and retries",
          "[devices][hid][threads]") {
  auto bytes = loadShippedDescriptor(kXpPenDescriptor);
  SECTION("serial does not match") {
    ReplayTransport transport(bytes, {}, xpPen());
    RecordingSink sink;
    Messages messages;
    HidPoseSourceOptions o;
    o.reconnect_period_s = 0.01;
    HidPoseSource source(transport, parseHidDeviceSelector("28bd:095b:OTHER"), {}, sink, messages.callback(), o);
    source.start();
    REQUIRE(waitFor([&] { return !messages.all().empty(); }));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    source.stop();
    const auto lines = messages.all();
    REQUIRE(lines.size() == 1);  // said once, not at every retry
    CHECK(lines[0] == "no device 28bd:095b:OTHER on replay transport");
    CHECK(sink.samples().empty());
  }
  SECTION("a truncated descriptor") {
    bytes.resize(50);
    ReplayTransport transport(bytes, {}, xpPen());
    RecordingSink sink;
    Messages messages;
    HidPoseSource source(transport, parseHidDeviceSelector("28bd:095b"), {}, sink, messages.callback());
    source.start();
    REQUIRE(waitFor([&] { return !messages.all().empty(); }));
    source.stop();
    CHECK(messages.all()[0].find("report descriptor") != std::string::npos);
    CHECK(source.connects() == 0);
  }
}

TEST_CASE("hid_transport: device selectors", "[devices][hid]") {
  const HidDeviceSelector a = parseHidDeviceSelector("056a:0357");
  CHECK(a.vid == 0x056a);
  CHECK(a.pid == 0x0357);
  CHECK_FALSE(a.serial.has_value());
  CHECK(parseHidDeviceSelector("46d:C626:ABC").serial == "ABC");
  CHECK(parseHidDeviceSelector("/dev/hidraw3").path == "/dev/hidraw3");
  CHECK_THROWS_WITH(parseHidDeviceSelector("wacom"),
                    "--device 'wacom': expected VID:PID, VID:PID:serial (hex) or a /dev/hidraw path");
  CHECK_THROWS_WITH(parseHidDeviceSelector("056a:zz"), "--device '056a:zz': product id 'zz' is not 1-4 hex digits");
  CHECK_THROWS_WITH(parseHidDeviceSelector("12345:1"), "--device '12345:1': vendor id '12345' is not 1-4 hex digits");
  HidDeviceInfo info;
  info.vid = 0x056a;
  info.pid = 0x0357;
  info.serial = "X";
  CHECK(a.matches(info));
  CHECK_FALSE(parseHidDeviceSelector("056a:0357:Y").matches(info));
}

TEST_CASE("hidapi_transport: enumerates what the system has, refuses what is not there", "[devices][hid]") {
  HidapiTransport transport;
  const auto devices = transport.enumerate();  // none on a machine without HID devices; never a crash
  for (const auto& d : devices) CHECK_FALSE(d.path.empty());
  CHECK(transport.name().rfind("hidapi 0.13", 0) == 0);
  HidDeviceInfo missing;
  missing.path = "/dev/hidraw-none";
  std::string error;
  CHECK(transport.open(missing, error) == nullptr);
  CHECK(error.find("/dev/hidraw-none") != std::string::npos);
  CHECK(transport.descriptorOf(missing, error).empty());
  CHECK_THROWS_WITH(readHidrawDescriptor("/dev/hidraw-none"), Catch::Contains("/dev/hidraw-none: cannot open"));
}
