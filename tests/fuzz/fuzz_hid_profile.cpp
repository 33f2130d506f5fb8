// libFuzzer harness: the pen finder and the profiles on what a device thread may meet (devices/hid_pen.h,
// hid_profile.h). The input is a descriptor and a stream of reports: bytes 0 and 1 give the descriptor's
// length n (little-endian, taken modulo what is left), the next n bytes are the descriptor, then each report
// is one length byte and that many bytes (the last one cut short at the end). A descriptor the parser refuses
// ends the run. The pen is looked for and described, the profile chosen; when there is one, every report goes
// through update() (noexcept: the device thread's call), with lifted() and reset() on the way. A pen's pose
// must be finite. A crash, a hang, an exception out of update or a sanitizer report is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_profile.h"

namespace {

using namespace incise::devices;

bool finite(const PoseSample& p) {
  return p.tip_m.allFinite() && p.orientation.coeffs().allFinite() && (!p.pressure || std::isfinite(*p.pressure));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t left = size - 2;
  const std::size_t n = (static_cast<std::size_t>(data[0]) | static_cast<std::size_t>(data[1]) << 8) % (left + 1);
  HidDescriptor descriptor;
  try {
    descriptor = parseHidDescriptor(std::span<const std::uint8_t>(data + 2, n));
  } catch (const HidDescriptorError&) {
    return 0;
  }
  const HidPenSearch search = findHidPen(descriptor);
  (void)describeHidTools(search.tools);
  if (search.pen) (void)summarizeHidPen(*search.pen);
  const HidProfileChoice choice = chooseHidProfile(descriptor, {data[0], data[1]});
  if ((choice.kind == HidProfileKind::Pen) != search.pen.has_value()) __builtin_trap();
  if (choice.kind == HidProfileKind::None) return 0;
  const auto profile = makeHidProfile(descriptor, {data[0], data[1]}, HidMapping{});
  std::span<const std::uint8_t> rest(data + 2 + n, left - n);
  double t_s = 0.0;
  while (!rest.empty()) {
    const std::size_t length = std::min<std::size_t>(rest[0], rest.size() - 1);
    PoseSample pose;
    if (profile->update(rest.subspan(1, length), t_s += 0.001, pose) && choice.kind == HidProfileKind::Pen &&
        !finite(pose))
      __builtin_trap();
    if (rest[0] == 0xff) profile->reset();
    if (!finite(profile->lifted(t_s)) && choice.kind == HidProfileKind::Pen) __builtin_trap();
    rest = rest.subspan(1 + length);
  }
  return 0;
}
