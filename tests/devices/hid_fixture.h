// The descriptors shipped in scenarios/hid/descriptors/, for the HID tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "incise/devices/hid_descriptor.h"

namespace incise::test {

inline std::vector<std::uint8_t> loadShippedDescriptor(const std::string& name) {
  return devices::loadHexBytes(std::string(INCISE_SCENARIOS_DIR) + "/hid/descriptors/" + name);
}

// A descriptor written out in a test.
inline devices::HidDescriptor parseBytes(const std::vector<std::uint8_t>& bytes) {
  return devices::parseHidDescriptor(bytes);
}

inline const char* const kWacomDescriptor = "wacom_pth660_intuos_pro_m_056a_0357.txt";
inline const char* const kXpPenDescriptor = "xppen_artist_pro16_gen2_28bd_095b.txt";
inline const char* const kSpaceNavigatorDescriptor = "3dconnexion_spacenavigator_046d_c626.txt";

}  // namespace incise::test
