// Where a report descriptor's pen is, found as Linux's hid-input maps a stylus: the input fields are
// grouped by tool (HidTool), and a group that is a pen and has absolute X and Y and a contact usage is one
// (findHidPen). A pen tool's fields may come in several input reports (hid-input keeps each usage's last
// value; so does the profile).
//
// Threads: any (a pure function of an immutable descriptor). Cost: O(fields x collection depth).
// Failure: none; no pen is a HidPenSearch without `pen`, and `reason` names the tool that came closest, the
// usage it lacks, and where its other usages are (report ID, collection path, byte of the report).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "incise/devices/hid_descriptor.h"

namespace incise::devices {

// Tools. Each data field of an input report belongs to the innermost enclosing collection (application,
// physical or logical, any depth) whose usage is a tool of the Digitizers page (0x0D, or Wacom's 0xFF0D read
// through hidEquivalentUsage): Stylus 0x20 (a pen), Puck 0x21, Finger 0x22 (touch), Tablet Function Keys
// 0x39 (a pad). A field under none of them belongs to its innermost application collection, whose usage
// says the tool: Digitizer 0x01, Pen 0x02, Light Pen 0x03, Whiteboard 0x06 are pens (hid-input maps their
// In Range to BTN_TOOL_PEN); Touch Screen 0x04, Touch Pad 0x05 are touch; Generic Desktop Mouse and Pointer a
// mouse, Keyboard and Keypad a keyboard, Multi-axis Controller a 6-DOF; Device Configuration and the
// rest "other". So a Stylus application nested in a Pen application (Huion), a Stylus physical collection in
// a Touch Screen application (eGalax) or in an application whose usage is 0 (an Atmel) are all pens.
enum class HidToolKind : std::uint8_t { Pen, Touch, Puck, Pad, Mouse, Keyboard, SixDof, Other };
const char* toString(HidToolKind kind);

// One tool: the data fields of input reports that share a tool collection.
struct HidTool {
  HidToolKind kind = HidToolKind::Other;
  int collection = -1;                   // index in HidDescriptor::collections (-1: fields outside any)
  std::string path;                      // "Digitizers:Pen > Digitizers:Stylus"
  std::vector<std::uint8_t> report_ids;  // the input reports with its fields, in order
};

// One element of one field of one input report (pointers into the descriptor, which must outlive them).
struct HidElement {
  const HidReportLayout* layout = nullptr;
  const HidField* field = nullptr;
  std::uint32_t element = 0;
  explicit operator bool() const { return field != nullptr; }
  // "report 16 byte 3" or "report 16 byte 1 bit 5": where it is in the report as hid_read returns it (the
  // ID byte, when the descriptor uses IDs, is byte 0).
  std::string where(bool with_report_ids) const;
};

enum class HidPenRole : std::uint8_t {
  X,
  Y,
  TipSwitch,
  TipPressure,
  InRange,
  Barrel,
  SecondaryBarrel,
  Eraser,
  Invert,
  TiltX,
  TiltY,
  Twist
};
inline constexpr std::size_t kHidPenRoles = 12;
const char* toString(HidPenRole role);

struct HidPen {
  HidTool tool;
  std::array<HidElement, kHidPenRoles> elements;
  const HidElement& operator[](HidPenRole role) const { return elements[static_cast<std::size_t>(role)]; }
  // The input reports the pen's elements are in, in descriptor order, without repeats.
  std::vector<const HidReportLayout*> layouts() const;
};

struct HidPenSearch {
  std::optional<HidPen> pen;
  std::vector<HidTool> tools;  // every tool of the descriptor, in order of first field
  std::string reason;          // "pen: ..." (which tool, what it has) or "no pen: ..." (what is missing, where)
};
// The pen. In the tool's fields, in report order, the first element of each of: X and Y (Generic Desktop,
// absolute), Tip Switch (else Touch 0x33), Tip Pressure, In Range, Barrel Switch, Secondary Barrel Switch
// (else Tablet Pick 0x46), Eraser, Invert, X Tilt, Y Tilt, Twist. A pen needs X, Y and Tip Switch or Tip
// Pressure; when several tools qualify, the one with Tip Pressure, then tilt, then In Range wins, the first
// in descriptor order on a tie. Vendor pages other than Wacom's are not read: a tablet whose driver
// (hid-uclogic) rewrites its descriptor is read through the rewritten one, which is what Linux shows in
// sysfs and through HIDIOCGRDESC.
HidPenSearch findHidPen(const HidDescriptor& descriptor);
// "touch (Touch Screen > Finger x10, input report 12); other (Device Configuration, input report 2)": the
// tools of one kind and path counted once.
std::string describeHidTools(const std::vector<HidTool>& tools);

// What incise reads from a pen, in words (the device table of devices/README.md and `incise hid decode`):
//   xy        "X 0..44800, Y 0..29600 (224 x 148 mm)" (the size when the unit is a length)
//   pressure  "8192 levels (16-bit field)" or "none (tip switch only)"
//   tilt      "X/Y -64..63 deg", "X/Y -127..127 (no unit: read as degrees)" or "none"
//   twist     "-180..179 deg" or "none"
//   buttons   "barrel, secondary barrel, eraser, invert" or "none"
//   in_range  "yes" or "no"
struct HidPenSummary {
  std::string xy, pressure, tilt, twist, buttons, in_range;
};
HidPenSummary summarizeHidPen(const HidPen& pen);

}  // namespace incise::devices
