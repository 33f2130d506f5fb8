// `incise hid decode FILE [--json] [--scenario S] [--device N]`: what a hid-recorder file's reports hold,
// like hid-tools' hid-decode — every field by usage name, logical and physical — and the pose the profile
// makes of each (with the scenario's mapping when given). A file of hex bytes (a report descriptor alone)
// prints the descriptor's reports and fields, the profile (or what it lacks, and where), its tools, and what
// the pen profile reads. With --json, one JSON object per report per line:
//   {"time_s", "line", "report_id", "fields": [{"usage_page", "usage", "name", "logical", "physical", "unit"}],
//    "pose": {"time_s", "tip_m", "orientation", "buttons", "pressure"} or null}
// and {"time_s", "line", "error"} for a report the descriptor does not allow. Bad reports are printed and
// counted; the exit code is then 2 (after every report is printed).
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hid_commands.h"
#include "hid_support.h"
#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"
#include "scenario_run.h"

namespace incise::apps::hid {
namespace {

using nlohmann::json;

// Whether the file is a recording (prefix lines "X: ...") rather than bare hex bytes.
bool looksLikeRecording(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    return line.size() >= 2 && std::isupper(static_cast<unsigned char>(line[0])) && line[1] == ':';
  }
  return false;
}

std::string flagsText(const devices::HidField& f) {
  return std::string(f.isConstant() ? "Cnst" : "Data") + (f.isVariable() ? ",Var" : ",Arr") +
         (f.isRelative() ? ",Rel" : ",Abs");
}

// The field's usage, and the other elements' usages when they differ ("Tip Switch (..), In Range, Eraser").
std::string fieldUsages(const devices::HidField& f) {
  if (f.usages.empty()) return "padding";
  std::string text = usageText(f.usageOf(0));
  for (std::uint32_t e = 1; f.isVariable() && e < f.count; ++e)
    if (f.usageOf(e) != f.usageOf(e - 1)) text += ", " + devices::hidUsageName(f.usageOf(e));
  return text;
}

void printLayout(const devices::HidDescriptor& d) {
  for (const devices::HidReportLayout& r : d.reports) {
    std::printf("%s report %u: %zu bytes\n", toString(r.type), r.id, r.wireBytes(d.uses_report_ids));
    for (const devices::HidField& f : r.fields) {
      const std::string usage = fieldUsages(f);
      std::printf("  bit %4u  %2u x %-3u %-6s %s  logical %lld..%lld  physical %g..%g %s\n", f.bit_offset, f.bit_size,
                  f.count, flagsText(f).c_str(), usage.c_str(), static_cast<long long>(f.logical_min),
                  static_cast<long long>(f.logical_max), devices::hidPhysical(f, f.logical_min),
                  devices::hidPhysical(f, f.logical_max), devices::hidUnitName(f.unit).c_str());
    }
  }
}

json fieldJson(const devices::HidValue& v, const devices::HidField& f) {
  return {{"usage_page", devices::hidUsagePage(v.usage)},
          {"usage", devices::hidUsageId(v.usage)},
          {"name", devices::hidUsageName(v.usage)},
          {"logical", v.logical},
          {"physical", v.physical},
          {"unit", devices::hidUnitName(f.unit)}};
}

json poseJson(const devices::PoseSample& p) {
  return {{"time_s", p.time_s},
          {"tip_m", {p.tip_m.x(), p.tip_m.y(), p.tip_m.z()}},
          {"orientation", {p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()}},
          {"buttons", p.buttons},
          {"pressure", p.pressure ? json(*p.pressure) : json(nullptr)}};
}

struct Decoder {
  explicit Decoder(const devices::HidDescriptor& d) : descriptor(d) {}
  const devices::HidDescriptor& descriptor;
  devices::HidReportDecoder decoder{descriptor};
  std::unique_ptr<devices::HidProfile> profile;
  std::vector<devices::HidValue> values = std::vector<devices::HidValue>(decoder.maxValues());
  bool as_json = false;
  std::size_t bad = 0, first_bad_line = 0;

  void report(const devices::HidRecordedReport& r) {
    const devices::HidDecoded decoded = decoder.decode(r.bytes, values);
    if (decoded.status != devices::HidDecodeStatus::Ok) return badReport(r, decoded.status);
    devices::PoseSample pose;
    const bool moved = profile && profile->update(r.bytes, r.time_s(), pose);
    if (as_json) {
      json fields = json::array();
      for (std::size_t i = 0; i < decoded.values; ++i)
        fields.push_back(fieldJson(values[i], decoded.layout->fields[values[i].field]));
      const json line = {{"time_s", r.time_s()},
                         {"line", r.line},
                         {"report_id", decoded.layout->id},
                         {"fields", fields},
                         {"pose", moved ? poseJson(pose) : json(nullptr)}};
      std::printf("%s\n", line.dump().c_str());
      return;
    }
    std::printf("E: %.6f report %u:", r.time_s(), decoded.layout->id);
    for (std::size_t i = 0; i < decoded.values; ++i) {
      const devices::HidField& f = decoded.layout->fields[values[i].field];
      std::printf(" %s %lld", devices::hidUsageName(values[i].usage).c_str(),
                  static_cast<long long>(values[i].logical));
      if (f.unit != 0) std::printf(" (%g %s)", values[i].physical, devices::hidUnitName(f.unit).c_str());
      std::printf(i + 1 < decoded.values ? "," : "");
    }
    std::printf("\n");
    if (moved)
      std::printf("   pose: tip %.6f %.6f %.6f m, q %.5f %.5f %.5f %.5f, buttons %u%s\n", pose.tip_m.x(),
                  pose.tip_m.y(), pose.tip_m.z(), pose.orientation.w(), pose.orientation.x(), pose.orientation.y(),
                  pose.orientation.z(), pose.buttons,
                  pose.pressure ? (", pressure " + std::to_string(*pose.pressure)).c_str() : "");
  }

  void badReport(const devices::HidRecordedReport& r, devices::HidDecodeStatus status) {
    if (bad++ == 0) first_bad_line = r.line;
    if (as_json)
      std::printf("%s\n", json({{"time_s", r.time_s()}, {"line", r.line}, {"error", toString(status)}}).dump().c_str());
    else
      std::printf("E: %.6f line %zu: bad report: %s\n", r.time_s(), r.line, toString(status));
  }
};

int decodeRecording(const HidDecodeArgs& a) {
  devices::HidRecording recording;
  devices::HidMapping mapping;
  try {
    recording = devices::readHidRecording(a.file);
    mapping = mappingOf(a.scenario);
  } catch (const std::exception& e) {
    failWith("hid decode", e.what());
  }
  if (a.device < 0 || static_cast<std::size_t>(a.device) >= recording.devices.size())
    failWith("hid decode", a.file + ": --device " + std::to_string(a.device) + ": the recording has " +
                               std::to_string(recording.devices.size()) + " device(s)");
  const devices::HidRecordedDevice& device = recording.devices[static_cast<std::size_t>(a.device)];
  devices::HidDescriptor descriptor;
  try {
    descriptor = devices::parseHidDescriptor(device.descriptor);
  } catch (const devices::HidDescriptorError& e) {
    failWith("hid decode", a.file + ": device " + std::to_string(a.device) + ": " + e.what());
  }
  Decoder decoder(descriptor);
  decoder.as_json = a.json;
  const devices::HidProfileChoice choice = devices::chooseHidProfile(descriptor, {device.vid, device.pid});
  if (choice.kind != devices::HidProfileKind::None)
    decoder.profile = devices::makeHidProfile(descriptor, {device.vid, device.pid}, mapping);
  if (!a.json)
    std::printf("# device %d: '%s' %s, descriptor %zu bytes, %s\n", a.device, device.name.c_str(),
                devices::formatVidPid(device.vid, device.pid).c_str(), device.descriptor.size(), choice.reason.c_str());
  for (const devices::HidRecordedReport& r : recording.reports)
    if (r.device == a.device) decoder.report(r);
  if (decoder.bad > 0)
    failWith("hid decode", a.file + ":" + std::to_string(decoder.first_bad_line) + ": " + std::to_string(decoder.bad) +
                               " bad report(s): not what the descriptor declares");
  return 0;
}

int decodeDescriptor(const HidDecodeArgs& a) {
  std::vector<std::uint8_t> bytes;
  try {
    bytes = devices::loadHexBytes(a.file);  // its errors name the file and line
  } catch (const std::exception& e) {
    failWith("hid decode", e.what());
  }
  try {
    const devices::HidDescriptor d = devices::parseHidDescriptor(bytes);
    printLayout(d);
    std::printf("profile: %s\n", devices::chooseHidProfile(d).reason.c_str());
    const devices::HidPenSearch search = devices::findHidPen(d);
    std::printf("tools: %s\n", devices::describeHidTools(search.tools).c_str());
    if (search.pen) {
      const devices::HidPenSummary s = devices::summarizeHidPen(*search.pen);
      std::printf("pen: %s; pressure %s; tilt %s; twist %s; buttons %s; in range %s\n", s.xy.c_str(),
                  s.pressure.c_str(), s.tilt.c_str(), s.twist.c_str(), s.buttons.c_str(), s.in_range.c_str());
    }
  } catch (const std::exception& e) {
    failWith("hid decode", a.file + ": " + e.what());
  }
  return 0;
}

}  // namespace

int runHidDecode(const HidDecodeArgs& a) {
  return looksLikeRecording(a.file) ? decodeRecording(a) : decodeDescriptor(a);
}

}  // namespace incise::apps::hid
