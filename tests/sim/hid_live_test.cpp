// A live HID source feeding the simulation at 1 kHz: an XP-Pen stroke replayed through the replay
// transport into Simulation's pose queue while FixedRateLoop runs the frames, the pen unplugged mid-stroke
// and replugged. The tool must be lifted (no contact, no force, no cutting) within one frame of the
// unplug, the incision in progress must end cleanly, cutting must resume after the replug, and everything
// must stop cleanly. Runs under ThreadSanitizer too ([threads]).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "incise/devices/hid_pose_source.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/replay_transport.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/simulation.h"

using namespace incise;
using Eigen::Vector3d;

namespace {

std::vector<std::uint8_t> xpPenDescriptor() {
  return devices::loadHexBytes(std::string(INCISE_SCENARIOS_DIR) +
                               "/hid/descriptors/xppen_artist_pro16_gen2_28bd_095b.txt");
}

// 100 reports 5 ms apart: tip down at half pressure, moving 3.7 cm right over the slab.
std::vector<devices::HidRecordedReport> stroke(const devices::HidDescriptor& d) {
  const devices::HidReportEncoder encoder(d);
  const devices::HidReportLayout& layout = *d.find(devices::HidReportType::Input, 7);
  std::vector<devices::HidRecordedReport> reports;
  for (int k = 0; k < 100; ++k) {
    auto raw = encoder.blank(layout);
    encoder.setLogical(raw, layout, devices::hidUsage(0x0D, 0x32), 1);
    encoder.setLogical(raw, layout, devices::hidUsage(0x0D, 0x42), 1);
    encoder.setLogical(raw, layout, devices::hidUsage(0x01, 0x30), 6000 + 150 * k);
    encoder.setLogical(raw, layout, devices::hidUsage(0x01, 0x31), 16000);
    encoder.setLogical(raw, layout, devices::hidUsage(0x0D, 0x30), 8000);
    reports.push_back({0, 5000 * k, raw, 0});
  }
  return reports;
}

double steadyNowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The poses on their way into the simulation, kept (preallocated) with the steady-clock time each was in
// the queue, to find the lifted one afterwards.
class TeeSink final : public devices::PoseSink {
 public:
  explicit TeeSink(sim::Simulation& simulation) : simulation_(simulation) {
    poses_.reserve(1024);
    queued_s_.reserve(1024);
  }
  bool push(const devices::PoseSample& pose) noexcept override {
    const bool queued = simulation_.push(pose);
    if (poses_.size() < poses_.capacity()) poses_.push_back(pose), queued_s_.push_back(steadyNowS());
    return queued;
  }
  const std::vector<devices::PoseSample>& poses() const { return poses_; }
  const std::vector<double>& queuedS() const { return queued_s_; }

 private:
  sim::Simulation& simulation_;
  std::vector<devices::PoseSample> poses_;
  std::vector<double> queued_s_;
};

}  // namespace

TEST_CASE("hid_live: unplugged mid-stroke, the simulation sees the tool lifted within one frame",
          "[sim][hid][threads]") {
  const auto bytes = xpPenDescriptor();
  const devices::HidDescriptor descriptor = devices::parseHidDescriptor(bytes);
  sim::WorldOptions world_options;
  world_options.tool.cut_button = 0;
  // The slab (5 mm cells) is coarse next to the lattice; this test times the device's unplug, not the cut:
  // without refinement its frames stay as light as they were (under TSan a refined cut's frames lag the
  // clock, and the test reads frames by their simulated time; it failed so once in a fresh-clone CI run).
  world_options.cutter.refine = incision::CutterOptions::Refine::Off;
  sim::World world(mesh::makeBox(Eigen::AlignedBox3d(Vector3d(-0.05, -0.05, -0.04), Vector3d(0.05, 0.05, 0.0)), 20),
                   world_options);
  devices::ReplayTransportOptions transport_options;
  transport_options.device.vid = 0x28bd;
  transport_options.device.pid = 0x095b;
  transport_options.cues = {{50, 0.2}};
  devices::ReplayTransport transport(bytes, stroke(descriptor), transport_options);
  devices::HidMapping mapping;
  mapping.pen.origin_m = {-0.04, 0.04, 0.0};  // the tablet over the slab's top, z = 0
  mapping.pen.x_edge_m = {0.08, 0.0, 0.0};
  mapping.pen.y_edge_m = {0.0, -0.08, 0.0};

  constexpr std::int64_t kFrames = 1500;
  const double t0_s = steadyNowS();
  sim::Simulation simulation(world, nullptr, 1000, t0_s);
  std::vector<sim::Snapshot> frames(kFrames);  // written by the loop thread, read after stop()
  TeeSink sink(simulation);
  devices::HidPoseSourceOptions source_options;
  source_options.reconnect_period_s = 0.05;
  devices::HidPoseSource source(transport, devices::parseHidDeviceSelector("28bd:095b"), mapping, sink, {},
                                source_options);
  sim::FixedRateLoop loop;
  loop.start([&](const sim::FrameInfo& info) {
    simulation.frame(info);
    if (info.frame < kFrames) simulation.takeSnapshot(frames[static_cast<std::size_t>(info.frame)]);
    if (info.frame + 1 >= kFrames) loop.requestStop();
  });
  source.start();
  while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  loop.stop();
  source.stop();

  const auto& poses = sink.poses();
  const auto lifted = std::find_if(poses.begin(), poses.end(), [](const auto& p) { return p.buttons == 0; });
  REQUIRE(lifted != poses.end());
  REQUIRE(lifted - poses.begin() == 50);
  // Frame k's time is t0 + k ms and it never starts before that (FixedRateLoop waits for its deadline): the
  // first frame whose time is at or after the lifted pose's arrival in the queue has taken it.
  const double queued_s = sink.queuedS()[static_cast<std::size_t>(lifted - poses.begin())];
  std::int64_t cut_before = -1, first_lifted = -1, cut_after = -1;
  for (std::int64_t k = 0; k < kFrames; ++k) {
    const sim::Snapshot& s = frames[static_cast<std::size_t>(k)];
    if (s.t_s < lifted->time_s && s.haptic.cutting) cut_before = k;
    if (s.t_s >= queued_s && first_lifted < 0) first_lifted = k;
    if (first_lifted >= 0 && s.haptic.cutting) {
      cut_after = k;
      break;
    }
  }
  REQUIRE(cut_before >= 0);
  REQUIRE(first_lifted >= 0);
  const sim::Snapshot& lifted_frame = frames[static_cast<std::size_t>(first_lifted)];
  CHECK(lifted_frame.t_s - queued_s <= 0.001 + 1e-9);  // within one frame of the pose's arrival
  CHECK_FALSE(lifted_frame.haptic.contact);            // ... and that frame has the tool lifted
  CHECK_FALSE(lifted_frame.haptic.cutting);
  CHECK(lifted_frame.haptic.force_N.norm() == 0.0);
  CHECK(queued_s - lifted->time_s < 0.001);  // stamped at the failed read, queued right after
  const double lifted_frame_t_s = lifted_frame.t_s;
  REQUIRE(cut_after > first_lifted);  // resumed after the replug
  // Not before the replug: the first cutting pose after the lifted one arrived when the device was back (its
  // stamp, not a frame's simulated time, which falls behind the clock when a loaded machine skips deadlines).
  const auto resumed = std::find_if(lifted, poses.end(), [](const auto& p) { return p.buttons == 1u; });
  REQUIRE(resumed != poses.end());
  CHECK(resumed->time_s - lifted->time_s >= 0.15);
  CHECK(lifted_frame_t_s > 0.0);
  CHECK(source.connects() == 2);
  CHECK(world.incisions() == 2);
  CHECK(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
}
