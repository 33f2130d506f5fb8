// The descriptors shipped in scenarios/hid/descriptors/, for the HID tests, and the stroke and tablet
// mapping the generator's tests synthesise recordings with.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/pose_sample.h"

namespace incise::test {

inline std::vector<std::uint8_t> loadShippedDescriptor(const std::string& name) {
  return devices::loadHexBytes(std::string(INCISE_SCENARIOS_DIR) + "/hid/descriptors/" + name);
}

// A descriptor written out in a test.
inline devices::HidDescriptor parseBytes(const std::vector<std::uint8_t>& bytes) {
  return devices::parseHidDescriptor(bytes);
}

// 1 s at 1 kHz: 0.1 s hovering, then cutting along +x at 5 cm/s, 4-8 mm below the area, the blade's axis
// tilted up to 20 degrees and turning about it; the last 0.1 s lifted out.
inline std::vector<devices::PoseSample> stroke() {
  std::vector<devices::PoseSample> poses;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * 1e-3;
    devices::PoseSample p;
    p.time_s = t;
    const bool cutting = t >= 0.1 && t <= 0.9;
    p.tip_m = {0.15 + 0.05 * t, 0.15, cutting ? 0.05 - 0.004 - 0.004 * std::sin(3 * t) : 0.06};
    p.orientation =
        Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.35 * t, Eigen::Vector3d::UnitY());
    p.buttons = cutting ? 1u : 0u;
    poses.push_back(p);
  }
  return poses;
}

// A 20 x 12 cm tablet laid over z = 0.05, X along +x, Y along -y: up is +z.
inline devices::HidMapping tabletOverArea() {
  devices::HidMapping m;
  m.pen.origin_m = {0.1, 0.2, 0.05};
  m.pen.x_edge_m = {0.2, 0.0, 0.0};
  m.pen.y_edge_m = {0.0, -0.12, 0.0};
  m.pen.max_depth_m = 0.02;
  m.pen.dead_band = 0.01;
  return m;
}

// A recorded device with a shipped descriptor.
inline devices::HidRecordedDevice shippedDevice(const std::string& descriptor, std::uint16_t vid, std::uint16_t pid) {
  devices::HidRecordedDevice d;
  d.name = "synthetic";
  d.bus = 3;
  d.vid = vid;
  d.pid = pid;
  d.descriptor = loadShippedDescriptor(descriptor);
  return d;
}

inline const char* const kWacomDescriptor = "wacom_pth660_intuos_pro_m_056a_0357.txt";
inline const char* const kXpPenDescriptor = "xppen_artist_pro16_gen2_28bd_095b.txt";
inline const char* const kSpaceNavigatorDescriptor = "3dconnexion_spacenavigator_046d_c626.txt";

}  // namespace incise::test
