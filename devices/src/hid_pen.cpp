#include "incise/devices/hid_pen.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "hid_pen_units.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace {

constexpr std::uint16_t kDigitizers = hid_pages::kDigitizers, kDesktop = hid_pages::kGenericDesktop;

// The usage each role reads, and the one hid-input maps the same way when the first is absent (0: none).
struct RoleUsages {
  std::uint32_t usage, fallback;
};
constexpr std::array<RoleUsages, kHidPenRoles> kRoleUsages = {{
    {hidUsage(kDesktop, 0x30), 0},                               // X
    {hidUsage(kDesktop, 0x31), 0},                               // Y
    {hidUsage(kDigitizers, 0x42), hidUsage(kDigitizers, 0x33)},  // Tip Switch, else Touch
    {hidUsage(kDigitizers, 0x30), 0},                            // Tip Pressure
    {hidUsage(kDigitizers, 0x32), 0},                            // In Range
    {hidUsage(kDigitizers, 0x44), 0},                            // Barrel Switch
    {hidUsage(kDigitizers, 0x5A), hidUsage(kDigitizers, 0x46)},  // Secondary Barrel Switch, else Tablet Pick
    {hidUsage(kDigitizers, 0x45), 0},                            // Eraser
    {hidUsage(kDigitizers, 0x3C), 0},                            // Invert
    {hidUsage(kDigitizers, 0x3D), 0},                            // X Tilt
    {hidUsage(kDigitizers, 0x3E), 0},                            // Y Tilt
    {hidUsage(kDigitizers, 0x41), 0},                            // Twist
}};

HidToolKind applicationKind(std::uint32_t usage) {
  const std::uint16_t page = hidUsagePage(usage), id = hidUsageId(usage);
  if (page == kDigitizers) {
    if (id == 0x01 || id == 0x02 || id == 0x03 || id == 0x06) return HidToolKind::Pen;
    if (id == 0x04 || id == 0x05) return HidToolKind::Touch;
  } else if (page == kDesktop) {
    if (id == 0x01 || id == 0x02) return HidToolKind::Mouse;
    if (id == 0x06 || id == 0x07) return HidToolKind::Keyboard;
    if (id == 0x08) return HidToolKind::SixDof;
  }
  return HidToolKind::Other;
}

// The tool collection of a field whose innermost collection is `c` (see the header), and its kind.
std::pair<int, HidToolKind> toolOf(const HidDescriptor& d, int c) {
  for (int i = c; i >= 0; i = d.collections[static_cast<std::size_t>(i)].parent) {
    const std::uint32_t u = hidEquivalentUsage(d.collections[static_cast<std::size_t>(i)].usage);
    if (hidUsagePage(u) != kDigitizers) continue;
    switch (hidUsageId(u)) {
      case 0x20:
        return {i, HidToolKind::Pen};
      case 0x21:
        return {i, HidToolKind::Puck};
      case 0x22:
        return {i, HidToolKind::Touch};
      case 0x39:
        return {i, HidToolKind::Pad};
      default:
        break;
    }
  }
  for (int i = c; i >= 0; i = d.collections[static_cast<std::size_t>(i)].parent)
    if (d.collections[static_cast<std::size_t>(i)].kind == 1)
      return {i, applicationKind(hidEquivalentUsage(d.collections[static_cast<std::size_t>(i)].usage))};
  return {-1, HidToolKind::Other};
}

std::string pathOf(const HidDescriptor& d, int c) {
  std::string path;
  for (int i = c; i >= 0; i = d.collections[static_cast<std::size_t>(i)].parent) {
    const std::uint32_t u = d.collections[static_cast<std::size_t>(i)].usage;
    path = hidUsageName(u) + (path.empty() ? "" : " > ") + path;
  }
  return path.empty() ? "(no collection)" : path;
}

// A tool and the fields it owns, while the descriptor is walked.
struct ToolFields {
  HidTool tool;
  std::vector<std::pair<const HidReportLayout*, const HidField*>> fields;
};

std::vector<ToolFields> groupTools(const HidDescriptor& d) {
  std::vector<ToolFields> tools;
  for (const HidReportLayout& r : d.reports) {
    if (r.type != HidReportType::Input) continue;
    for (const HidField& f : r.fields) {
      if (f.isConstant()) continue;
      const std::pair<int, HidToolKind> tool = toolOf(d, f.collection);
      const int collection = tool.first;
      auto it = std::find_if(tools.begin(), tools.end(),
                             [&](const ToolFields& t) { return t.tool.collection == collection; });
      if (it == tools.end()) {
        it = tools.insert(tools.end(), ToolFields{});
        it->tool.kind = tool.second;
        it->tool.collection = collection;
        it->tool.path = pathOf(d, collection);
      }
      if (it->tool.report_ids.empty() || it->tool.report_ids.back() != r.id) it->tool.report_ids.push_back(r.id);
      it->fields.emplace_back(&r, &f);
    }
  }
  return tools;
}

// The first variable element with `usage` (through hidEquivalentUsage); relative ones only when asked.
HidElement findElement(const ToolFields& t, std::uint32_t usage, bool relative) {
  if (usage == 0) return {};
  for (const auto& [layout, field] : t.fields) {
    if (!field->isVariable() || field->isRelative() != relative) continue;
    for (std::uint32_t e = 0; e < field->count; ++e)
      if (hidEquivalentUsage(field->usageOf(e)) == usage) return {layout, field, e};
  }
  return {};
}

HidPen bindPen(const ToolFields& t) {
  HidPen pen;
  pen.tool = t.tool;
  for (std::size_t r = 0; r < kHidPenRoles; ++r) {
    pen.elements[r] = findElement(t, kRoleUsages[r].usage, false);
    if (!pen.elements[r]) pen.elements[r] = findElement(t, kRoleUsages[r].fallback, false);
  }
  return pen;
}

bool complete(const HidPen& p) {
  return p[HidPenRole::X] && p[HidPenRole::Y] && (p[HidPenRole::TipSwitch] || p[HidPenRole::TipPressure]);
}

// Which of two complete pens is read: pressure, then tilt, then In Range, then more pressure levels.
bool better(const HidPen& a, const HidPen& b) {
  const auto score = [](const HidPen& p) {
    const HidElement& pressure = p[HidPenRole::TipPressure];
    const std::int64_t levels = pressure ? pressure.field->logical_max - pressure.field->logical_min : 0;
    return std::pair(
        (pressure ? 4 : 0) + (p[HidPenRole::TiltX] && p[HidPenRole::TiltY] ? 2 : 0) + (p[HidPenRole::InRange] ? 1 : 0),
        levels);
  };
  return score(a) > score(b);
}

int required(const HidPen& p) {
  return (p[HidPenRole::X] ? 1 : 0) + (p[HidPenRole::Y] ? 1 : 0) +
         (p[HidPenRole::TipSwitch] || p[HidPenRole::TipPressure] ? 1 : 0);
}

std::string reportsText(const std::vector<std::uint8_t>& ids) {
  std::string text = ids.size() == 1 ? "input report " : "input reports ";
  for (std::size_t i = 0; i < ids.size(); ++i) text += (i ? ", " : "") + std::to_string(ids[i]);
  return text;
}

std::string toolText(const HidDescriptor& d, const HidTool& t, const std::vector<std::uint8_t>& ids) {
  std::string text = reportsText(ids) + " (" + t.path;
  if (t.collection >= 0)
    text += ", collection at descriptor byte " +
            std::to_string(d.collections[static_cast<std::size_t>(t.collection)].offset);
  return text + ")";
}

std::string penReason(const HidDescriptor& d, const HidPen& pen) {
  std::vector<std::uint8_t> ids;
  for (const HidReportLayout* layout : pen.layouts()) ids.push_back(layout->id);
  std::string text = "pen: " + toolText(d, pen.tool, ids) + ":";
  for (std::size_t r = 0; r < kHidPenRoles; ++r)
    if (pen.elements[r]) text += std::string(r ? ", " : " ") + toString(static_cast<HidPenRole>(r));
  return text;
}

std::string missingReason(const HidDescriptor& d, const ToolFields& t, const HidPen& pen) {
  std::string have, lacks;
  for (std::size_t r = 0; r < kHidPenRoles; ++r)
    if (pen.elements[r])
      have += (have.empty() ? "" : ", ") + std::string(toString(static_cast<HidPenRole>(r))) + " at " +
              pen.elements[r].where(d.uses_report_ids);
  const auto lack = [&](const std::string& what) { lacks += (lacks.empty() ? "" : " and ") + what; };
  for (const HidPenRole axis : {HidPenRole::X, HidPenRole::Y}) {
    if (pen[axis]) continue;
    const HidElement relative = findElement(t, kRoleUsages[static_cast<std::size_t>(axis)].usage, true);
    lack(relative ? std::string("an absolute ") + toString(axis) + " (" + toString(axis) + " at " +
                        relative.where(d.uses_report_ids) + " is relative)"
                  : std::string(toString(axis)));
  }
  if (!pen[HidPenRole::TipSwitch] && !pen[HidPenRole::TipPressure]) lack("Tip Switch, Touch or Tip Pressure");
  return "no pen: the pen of " + toolText(d, t.tool, t.tool.report_ids) +
         (have.empty() ? " has none of its usages" : " has " + have) + " but no " + lacks;
}

std::string toolsReason(const std::vector<HidTool>& tools) {
  if (tools.empty()) return "no pen: the descriptor has no input fields";
  return "no pen: no Stylus, Pen, Digitizer or Light Pen collection; its input is " + describeHidTools(tools);
}

std::string rangeText(const HidField& f) {
  return std::to_string(f.logical_min) + ".." + std::to_string(f.logical_max);
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

std::string xyText(const HidElement& x, const HidElement& y) {
  std::string text = "X " + rangeText(*x.field) + ", Y " + rangeText(*y.field);
  const auto mm = [](const HidField& f) {
    return (hidPhysical(f, f.logical_max) - hidPhysical(f, f.logical_min)) * hidUnitToSi(f.unit) * 1000.0;
  };
  const bool lengths = isLengthUnit(x.field->unit) && isLengthUnit(y.field->unit);
  if (lengths) return text + " (" + number(mm(*x.field)) + " x " + number(mm(*y.field)) + " mm)";
  if (x.field->unit == 0) return text + " (no unit)";
  return text + " (unit " + hidUnitName(x.field->unit) + ": not a length)";
}

std::string angleText(const HidField& f) {
  if (!isAngleUnit(f.unit)) return rangeText(f) + " (no angle unit: read as degrees)";
  return number(hidPenDegrees(f, f.logical_min)) + ".." + number(hidPenDegrees(f, f.logical_max)) + " deg";
}

}  // namespace

const char* toString(HidToolKind kind) {
  switch (kind) {
    case HidToolKind::Pen:
      return "pen";
    case HidToolKind::Touch:
      return "touch";
    case HidToolKind::Puck:
      return "puck";
    case HidToolKind::Pad:
      return "pad";
    case HidToolKind::Mouse:
      return "mouse";
    case HidToolKind::Keyboard:
      return "keyboard";
    case HidToolKind::SixDof:
      return "6-dof";
    case HidToolKind::Other:
      return "other";
  }
  return "?";
}

const char* toString(HidPenRole role) {
  static constexpr std::array<const char*, kHidPenRoles> kNames = {
      "X",      "Y",      "Tip Switch", "Tip Pressure", "In Range", "Barrel Switch", "Secondary Barrel Switch",
      "Eraser", "Invert", "X Tilt",     "Y Tilt",       "Twist"};
  const auto i = static_cast<std::size_t>(role);
  return i < kNames.size() ? kNames[i] : "?";
}

std::string HidElement::where(bool with_report_ids) const {
  if (field == nullptr) return "nowhere";
  const std::uint64_t bit = std::uint64_t{field->bit_offset} + std::uint64_t{element} * field->bit_size;
  std::string text =
      "report " + std::to_string(layout->id) + " byte " + std::to_string(bit / 8 + (with_report_ids ? 1 : 0));
  if (bit % 8 != 0 || field->bit_size < 8) text += " bit " + std::to_string(bit % 8);
  return text;
}

std::vector<const HidReportLayout*> HidPen::layouts() const {
  std::vector<const HidReportLayout*> out;
  for (const HidElement& e : elements)
    if (e && std::find(out.begin(), out.end(), e.layout) == out.end()) out.push_back(e.layout);
  std::sort(out.begin(), out.end());  // one vector in the descriptor: address order is descriptor order
  return out;
}

HidPenSearch findHidPen(const HidDescriptor& d) {
  const std::vector<ToolFields> tools = groupTools(d);
  HidPenSearch search;
  for (const ToolFields& t : tools) search.tools.push_back(t.tool);
  const ToolFields* closest = nullptr;
  int closest_required = -1;
  for (const ToolFields& t : tools) {
    if (t.tool.kind != HidToolKind::Pen) continue;
    HidPen pen = bindPen(t);
    if (complete(pen)) {
      if (!search.pen || better(pen, *search.pen)) search.pen = std::move(pen);
    } else if (required(pen) > closest_required) {
      closest = &t;
      closest_required = required(pen);
    }
  }
  if (search.pen)
    search.reason = penReason(d, *search.pen);
  else
    search.reason = closest != nullptr ? missingReason(d, *closest, bindPen(*closest)) : toolsReason(search.tools);
  return search;
}

std::string describeHidTools(const std::vector<HidTool>& tools) {
  struct Same {
    const HidTool* first;
    std::vector<std::uint8_t> ids;
    int count;
  };
  std::vector<Same> groups;  // tools of one kind and path (a touch screen's ten Finger collections) as one
  for (const HidTool& t : tools) {
    auto it = std::find_if(groups.begin(), groups.end(),
                           [&](const Same& g) { return g.first->kind == t.kind && g.first->path == t.path; });
    if (it == groups.end()) it = groups.insert(groups.end(), Same{&t, {}, 0});
    ++it->count;
    for (const std::uint8_t id : t.report_ids)
      if (std::find(it->ids.begin(), it->ids.end(), id) == it->ids.end()) it->ids.push_back(id);
  }
  std::string text;
  for (const Same& g : groups) {
    text += (text.empty() ? "" : "; ") + std::string(toString(g.first->kind)) + " (" + g.first->path;
    if (g.count > 1) text += " x" + std::to_string(g.count);
    text += ", " + reportsText(g.ids) + ")";
  }
  return text;
}

HidPenSummary summarizeHidPen(const HidPen& pen) {
  HidPenSummary s;
  s.xy = xyText(pen[HidPenRole::X], pen[HidPenRole::Y]);
  if (const HidElement& p = pen[HidPenRole::TipPressure])
    s.pressure = std::to_string(p.field->logical_max - p.field->logical_min + 1) + " levels (" +
                 std::to_string(p.field->bit_size) + "-bit field)";
  else
    s.pressure = "none (tip switch only)";
  const HidElement &tx = pen[HidPenRole::TiltX], &ty = pen[HidPenRole::TiltY];
  s.tilt = tx && ty ? "X/Y " + angleText(*tx.field) : "none";
  s.twist = pen[HidPenRole::Twist] ? angleText(*pen[HidPenRole::Twist].field) : "none";
  for (const HidPenRole b : {HidPenRole::Barrel, HidPenRole::SecondaryBarrel, HidPenRole::Eraser, HidPenRole::Invert})
    if (pen[b]) s.buttons += (s.buttons.empty() ? "" : ", ") + std::string(toString(b));
  if (s.buttons.empty()) s.buttons = "none";
  s.in_range = pen[HidPenRole::InRange] ? "yes" : "no";
  return s;
}

}  // namespace incise::devices

namespace incise::devices {

bool isLengthUnit(std::uint32_t unit) {
  const std::uint32_t system = unit & 0xFu;
  return (system == 1 || system == 3) && hidUnitToSi(unit) > 0.0;
}

bool isAngleUnit(std::uint32_t unit) {
  const std::uint32_t system = unit & 0xFu;
  return (system == 2 || system == 4) && hidUnitToSi(unit) > 0.0;
}

double hidPenDegrees(const HidField& f, std::int64_t logical) {
  if (!isAngleUnit(f.unit)) return static_cast<double>(logical);
  return hidPhysical(f, logical) * hidUnitToSi(f.unit) * (180.0 / std::numbers::pi);
}

std::int64_t hidPenLogicalDegrees(const HidField& f, double degrees) {
  if (isAngleUnit(f.unit)) return hidLogical(f, degrees * (std::numbers::pi / 180.0) / hidUnitToSi(f.unit));
  const std::int64_t lo = std::min(f.logical_min, f.logical_max), hi = std::max(f.logical_min, f.logical_max);
  const double clamped =
      std::isfinite(degrees) ? std::clamp(degrees, static_cast<double>(lo), static_cast<double>(hi)) : 0.0;
  return std::clamp<std::int64_t>(std::llround(clamped), lo, hi);
}

}  // namespace incise::devices
