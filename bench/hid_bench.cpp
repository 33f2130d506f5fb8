// HID input benchmark. Prints one JSON document:
//   decode_ns          HidReportDecoder::decode of one pen report (Wacom PTH-660, XP-Pen), every field;
//                      target <= 1000 ns
//   profile_update_ns  one report -> one pose through the pen / 6-DOF profile (what the device thread does)
//   arrival_to_queue   from a report's arrival (the transport's read returning; the pose is stamped then)
//                      to its pose in Simulation's pose queue, on HidPoseSource's device thread, over a
//                      200 Hz stroke replayed in real time through the replay transport; target p99 <= 50 us.
//                      The figure starts at the arrival stamp: how late the VM woke the reading thread is
//                      before it and not counted; a preemption between stamp and push is (max_us shows it).
// Usage: incise_bench_hid [--seconds S] (default 10).
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "incise/devices/hid_pose_source.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/replay_transport.h"
#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/simulation.h"

namespace {

using namespace incise;
using Clock = std::chrono::steady_clock;

std::vector<std::uint8_t> descriptorBytes(const char* name) {
  return devices::loadHexBytes(std::string(INCISE_SCENARIOS_DIR) + "/hid/descriptors/" + name);
}

// A pen report with every field set to something non-trivial.
std::vector<std::uint8_t> penReport(const devices::HidDescriptor& d, std::uint8_t id, int k) {
  const devices::HidReportEncoder encoder(d);
  const devices::HidReportLayout& layout = *d.find(devices::HidReportType::Input, id);
  auto raw = encoder.blank(layout);
  for (const auto& f : layout.fields)
    if (!f.isConstant() && f.isVariable())
      for (std::uint32_t e = 0; e < f.count; ++e)
        encoder.setLogical(raw, layout, f.usageOf(e), (f.logical_min + f.logical_max) / 2 + k % 7);
  return raw;
}

template <typename F>
double nsPerCall(F&& f, int calls) {
  const auto start = Clock::now();
  for (int i = 0; i < calls; ++i) f(i);
  return std::chrono::duration<double, std::nano>(Clock::now() - start).count() / calls;
}

nlohmann::json decodeFigures(const char* name, std::uint8_t id) {
  const devices::HidDescriptor d = devices::parseHidDescriptor(descriptorBytes(name));
  const devices::HidReportDecoder decoder(d);
  std::vector<devices::HidValue> values(decoder.maxValues());
  std::vector<std::vector<std::uint8_t>> reports;
  for (int k = 0; k < 16; ++k) reports.push_back(penReport(d, id, k));
  volatile std::int64_t sink = 0;
  constexpr int kCalls = 2'000'000;
  const double decode_ns = nsPerCall(
      [&](int i) { sink = sink + decoder.decode(reports[static_cast<std::size_t>(i) & 15u], values).values; }, kCalls);
  const auto profile = devices::makeHidProfile(d, {}, {});
  devices::PoseSample pose;
  const double update_ns = nsPerCall(
      [&](int i) { sink = sink + profile->update(reports[static_cast<std::size_t>(i) & 15u], i * 1e-3, pose); },
      kCalls);
  const std::size_t decoded = decoder.decode(reports[0], values).values;
  return {{"descriptor", name},
          {"report_id", id},
          {"values_per_report", decoded},
          {"decode_ns", decode_ns},
          {"profile_update_ns", update_ns},
          {"decode_target_ns", 1000.0}};
}

// Records arrival -> queued for every pose, in a preallocated array (the device thread's side).
class TimingSink final : public devices::PoseSink {
 public:
  TimingSink(sim::Simulation& simulation, std::size_t capacity) : simulation_(simulation) {
    latency_us_.reserve(capacity);
  }
  bool push(const devices::PoseSample& pose) noexcept override {
    const bool queued = simulation_.push(pose);
    const double now_s = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    if (pose.buttons != 0 && latency_us_.size() < latency_us_.capacity())
      latency_us_.push_back((now_s - pose.time_s) * 1e6);
    return queued;
  }
  const std::vector<double>& latencyUs() const { return latency_us_; }

 private:
  sim::Simulation& simulation_;
  std::vector<double> latency_us_;
};

nlohmann::json arrivalFigures(double seconds) {
  const auto bytes = descriptorBytes("xppen_artist_pro16_gen2_28bd_095b.txt");
  const devices::HidDescriptor d = devices::parseHidDescriptor(bytes);
  const int count = static_cast<int>(seconds * 200.0);
  std::vector<devices::HidRecordedReport> reports;
  for (int k = 0; k < count; ++k) {
    auto raw = penReport(d, 7, k);
    raw[1] = 0x21;  // in range, tip down
    reports.push_back({0, 5000 * static_cast<std::int64_t>(k), raw, 0});
  }
  devices::ReplayTransportOptions options;
  options.device.vid = 0x28bd;
  options.device.pid = 0x095b;
  devices::ReplayTransport transport(bytes, reports, options);
  sim::World world(mesh::makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 0)), 2), {});
  sim::Simulation simulation(world, nullptr, 1000, 0.0);
  TimingSink sink(simulation, static_cast<std::size_t>(count) + 16);
  devices::HidPoseSource source(transport, devices::parseHidDeviceSelector("28bd:095b"), {}, sink);
  source.start();
  while (transport.delivered() < transport.reportCount()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  source.stop();
  const auto& l = sink.latencyUs();
  return {{"reports", count},
          {"poses_timed", l.size()},
          {"rate_hz", 200},
          {"p50_us", measure::percentile(l, 0.5)},
          {"p99_us", measure::percentile(l, 0.99)},
          {"max_us", measure::percentile(l, 1.0)},
          {"target_p99_us", 50.0},
          {"bad_reports", source.badReports()},
          {"dropped", source.posesDropped()}};
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::stod(argv[i + 1]);
  nlohmann::json report = {{"benchmark", "hid_input"}, {"machine", measure::machineInfo()}};
  report["decode"] = {decodeFigures("wacom_pth660_intuos_pro_m_056a_0357.txt", 0x10),
                      decodeFigures("xppen_artist_pro16_gen2_28bd_095b.txt", 7)};
  report["arrival_to_queue"] = arrivalFigures(seconds);
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
