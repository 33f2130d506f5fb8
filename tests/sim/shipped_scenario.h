// Test support: a shipped scenario (scenarios/<name>.json) loaded with its tissue in a world and its poses
// (its trace's, or those of its generated strokes), as replay would run it; a press on the pad before them.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/stroke_poses.h"
#include "incise/sim/world.h"

namespace incise::test {

struct ShippedScenario {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
};

inline ShippedScenario loadShipped(const std::string& name) {
  ShippedScenario l;
  l.scenario = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  mesh::SurfaceMesh tissue = sim::loadTissue(l.scenario);
  l.poses = l.scenario.source == sim::Scenario::Source::Strokes
                ? sim::posesForStrokes(tissue, l.scenario.strokes, l.scenario.world, l.scenario.rate_hz)
                : devices::TraceReader::readAll(l.scenario.trace);
  l.world = std::make_unique<sim::World>(std::move(tissue), l.scenario.world);
  return l;
}

// A press on the pad, its cut button up, at 1 kHz from time 0: the blade upright (local -z along -y) at
// (x, above_y_m, z) for settle_s, down to low_y_m in down_s, held hold_s, back up in up_s, above for after_s.
struct PadPress {
  double x_m = 0.005, z_m = 0.004, above_y_m = 0.004, low_y_m = -0.0051;
  double settle_s = 0.6, down_s = 0.5, hold_s = 1.0, up_s = 0.3, after_s = 0.8;
  double heldUntilS() const { return settle_s + down_s + hold_s; }
  double endS() const { return heldUntilS() + up_s + after_s; }
};

inline std::vector<devices::PoseSample> padPressPoses(const PadPress& p) {
  Eigen::Matrix3d r;
  r << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY();
  const Eigen::Quaterniond down(r);
  std::vector<devices::PoseSample> poses;
  for (int k = 0; k * 0.001 <= p.endS() + 1e-9; ++k) {
    const double t = k * 0.001, held_from = p.settle_s + p.down_s, up_from = p.heldUntilS();
    double y = p.above_y_m;
    if (t > p.settle_s && t <= held_from) y = p.above_y_m + (p.low_y_m - p.above_y_m) * (t - p.settle_s) / p.down_s;
    if (t > held_from) y = p.low_y_m;
    if (t > up_from) y = p.low_y_m + (p.above_y_m - p.low_y_m) * std::min(1.0, (t - up_from) / p.up_s);
    devices::PoseSample pose;
    pose.time_s = t, pose.tip_m = Eigen::Vector3d(p.x_m, y, p.z_m), pose.orientation = down, pose.buttons = 0;
    poses.push_back(pose);
  }
  return poses;
}

// `first`, then `then` shifted to start a millisecond after first's last pose.
inline std::vector<devices::PoseSample> followedBy(std::vector<devices::PoseSample> first,
                                                   const std::vector<devices::PoseSample>& then) {
  const double shift_s = first.back().time_s + 0.001 - then.front().time_s;
  for (devices::PoseSample p : then) {
    p.time_s += shift_s;
    first.push_back(p);
  }
  return first;
}

}  // namespace incise::test
