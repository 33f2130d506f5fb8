#include "incise/devices/hid_descriptor.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

namespace incise::devices {
namespace {

constexpr std::size_t kMaxReportBytes = 4096;
constexpr std::size_t kMaxPushDepth = 16;
constexpr std::uint32_t kMaxReportSize = 256;  // bits per element, Linux hid-core's limit
constexpr std::int64_t kMaxUsageRange = 65536;

enum ItemType : std::uint8_t { kMain = 0, kGlobal = 1, kLocal = 2, kReserved = 3 };

// Main item tags (6.2.2.4).
enum MainTag : std::uint8_t { kInput = 0x8, kOutput = 0x9, kCollection = 0xA, kFeature = 0xB, kEndCollection = 0xC };

// One short item as read from the bytes.
struct Item {
  std::size_t offset = 0;
  std::uint8_t prefix = 0, type = 0, tag = 0, size = 0;
  std::uint32_t data = 0;  // little-endian, zero-extended

  std::int64_t signedData() const {
    if (size == 1) return static_cast<std::int8_t>(data);
    if (size == 2) return static_cast<std::int16_t>(data);
    return static_cast<std::int32_t>(data);
  }
};

// A Logical or Physical Minimum/Maximum pair as declared. The maximum is kept raw: it is read signed only
// when the minimum is negative (hid-core does the same), whichever item came first.
struct RangeItems {
  std::int64_t min = 0;
  std::uint32_t max_raw = 0;
  std::uint8_t max_size = 0;

  void setMin(const Item& item);
  void setMax(const Item& item) { max_raw = item.data, max_size = item.size; }
  std::int64_t max() const;
};

// The global state (6.2.2.7): what Push saves and Pop restores.
struct Globals {
  std::uint16_t usage_page = 0;
  RangeItems logical, physical;
  int unit_exponent = 0;
  std::uint32_t unit = 0;
  std::uint32_t report_size = 0, report_count = 0;
  std::uint8_t report_id = 0;
  bool has_report_size = false, has_report_count = false;
};

// The local state (6.2.2.8), cleared after every main item.
struct Locals {
  struct Usage {
    std::uint32_t value;
    bool has_page;  // a 4-byte usage: the page is its own
  };
  std::vector<Usage> usages;
  std::optional<Usage> usage_min, usage_max;
  int delimiter_depth = 0;
  int delimiter_sets = 0;  // usage sets opened inside the current delimiter
};

void RangeItems::setMin(const Item& item) { min = item.signedData(); }

std::int64_t RangeItems::max() const {
  if (min >= 0) return max_raw;
  Item item;
  item.size = max_size;
  item.data = max_raw;
  return item.signedData();
}

std::string hex2(unsigned value) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%02x", value & 0xffu);
  return text;
}

class Parser {
 public:
  explicit Parser(std::span<const std::uint8_t> bytes) : bytes_(bytes) {
    result_.bytes.assign(bytes.begin(), bytes.end());
  }

  HidDescriptor run() {
    std::size_t offset = 0;
    while (offset < bytes_.size()) offset = readItem(offset);
    if (!open_.empty()) {
      const HidCollection& c = result_.collections[static_cast<std::size_t>(open_.back())];
      throw HidDescriptorError("report descriptor: the collection opened at byte " + std::to_string(c.offset) +
                                   " is never closed (an End Collection is missing)",
                               c.offset);
    }
    if (result_.reports.empty()) throw HidDescriptorError("report descriptor: declares no report fields", 0);
    return std::move(result_);
  }

 private:
  [[noreturn]] void fail(const Item& item, const std::string& what) const {
    throw HidDescriptorError(
        "report descriptor byte " + std::to_string(item.offset) + " (item " + hex2(item.prefix) + "): " + what,
        item.offset);
  }

  std::size_t readItem(std::size_t offset) {
    Item item;
    item.offset = offset;
    item.prefix = bytes_[offset];
    if (item.prefix == 0xFE) return skipLongItem(item);
    static constexpr std::array<std::uint8_t, 4> kSizes = {0, 1, 2, 4};
    item.size = kSizes[item.prefix & 3u];
    item.type = (item.prefix >> 2) & 3u;
    item.tag = item.prefix >> 4;
    if (offset + 1 + item.size > bytes_.size())
      fail(item, "truncated: the item needs " + std::to_string(item.size) + " data bytes, " +
                     std::to_string(bytes_.size() - offset - 1) + " left");
    for (std::uint8_t i = 0; i < item.size; ++i)
      item.data |= static_cast<std::uint32_t>(bytes_[offset + 1 + i]) << (8 * i);
    switch (item.type) {
      case kMain:
        mainItem(item);
        break;
      case kGlobal:
        globalItem(item);
        break;
      case kLocal:
        localItem(item);
        break;
      default:
        fail(item, "reserved item type 3 (not defined by HID 1.11)");
    }
    return offset + 1 + item.size;
  }

  std::size_t skipLongItem(Item& item) {
    if (item.offset + 3 > bytes_.size()) fail(item, "truncated long item header");
    const std::size_t size = bytes_[item.offset + 1];
    if (item.offset + 3 + size > bytes_.size()) fail(item, "truncated long item data");
    return item.offset + 3 + size;
  }

  void mainItem(const Item& item) {
    switch (item.tag) {
      case kInput:
        addField(item, HidReportType::Input);
        break;
      case kOutput:
        addField(item, HidReportType::Output);
        break;
      case kFeature:
        addField(item, HidReportType::Feature);
        break;
      case kCollection:
        openCollection(item);
        break;
      case kEndCollection:
        if (open_.empty()) fail(item, "End Collection without an open collection");
        open_.pop_back();
        break;
      default:
        fail(item, "unknown main item tag " + hex2(item.tag));
    }
    locals_ = Locals{};
  }

  void globalItem(const Item& item) {
    Globals& g = globals_;
    switch (item.tag) {
      case 0x0:
        g.usage_page = static_cast<std::uint16_t>(item.data);
        break;
      case 0x1:
        g.logical.setMin(item);
        break;
      case 0x2:
        g.logical.setMax(item);
        break;
      case 0x3:
        g.physical.setMin(item);
        break;
      case 0x4:
        g.physical.setMax(item);
        break;
      case 0x5:
        g.unit_exponent =
            (item.data & ~0xFu) == 0 ? static_cast<int>((item.data ^ 8u) - 8u) : static_cast<int>(item.signedData());
        break;
      case 0x6:
        g.unit = item.data;
        break;
      case 0x7:
        reportSize(item);
        break;
      case 0x8:
        reportId(item);
        break;
      case 0x9:
        g.report_count = item.data, g.has_report_count = true;
        break;
      case 0xA:
        if (stack_.size() >= kMaxPushDepth) fail(item, "Push nested over " + std::to_string(kMaxPushDepth) + " deep");
        stack_.push_back(g);
        break;
      case 0xB:
        if (stack_.empty()) fail(item, "Pop without a Push");
        g = stack_.back();
        stack_.pop_back();
        break;
      default:
        fail(item, "unknown global item tag " + hex2(item.tag));
    }
  }

  void reportSize(const Item& item) {
    if (item.data == 0 || item.data > kMaxReportSize)
      fail(item, "Report Size " + std::to_string(item.data) + " bits: must be 1.." + std::to_string(kMaxReportSize));
    globals_.report_size = item.data;
    globals_.has_report_size = true;
  }

  void reportId(const Item& item) {
    if (item.data == 0 || item.data > 255) fail(item, "Report ID " + std::to_string(item.data) + ": must be 1..255");
    if (!result_.uses_report_ids && fields_without_id_)
      fail(item, "Report ID after fields without one: a descriptor declares IDs for all its reports or none");
    result_.uses_report_ids = true;
    globals_.report_id = static_cast<std::uint8_t>(item.data);
  }

  void localItem(const Item& item) {
    const Locals::Usage usage{item.data, item.size == 4};
    switch (item.tag) {
      case 0x0:
        if (keepUsage()) locals_.usages.push_back(usage);
        break;
      case 0x1:
        if (keepUsage()) locals_.usage_min = usage;
        break;
      case 0x2:
        if (keepUsage()) locals_.usage_max = usage;
        break;
      case 0x3:
      case 0x4:
      case 0x5:
      case 0x7:
      case 0x8:
      case 0x9:
        break;  // designators, strings: not kept
      case 0xA:
        delimiter(item);
        break;
      default:
        fail(item, "unknown local item tag " + hex2(item.tag));
    }
  }

  // Inside a delimiter only the first usage set counts (the alternatives are dropped, as hid-core does).
  bool keepUsage() const { return locals_.delimiter_depth == 0 || locals_.delimiter_sets <= 1; }

  void delimiter(const Item& item) {
    if (item.data == 1) {
      if (locals_.delimiter_depth > 0) fail(item, "nested Delimiter");
      locals_.delimiter_depth = 1;
      locals_.delimiter_sets = 1;
    } else if (item.data == 0) {
      if (locals_.delimiter_depth == 0) fail(item, "Delimiter close without an open");
      locals_.delimiter_depth = 0;
    } else {
      fail(item, "Delimiter " + std::to_string(item.data) + ": must be 0 (close) or 1 (open)");
    }
  }

  std::uint32_t fullUsage(const Locals::Usage& usage) const {
    return usage.has_page ? usage.value : hidUsage(globals_.usage_page, static_cast<std::uint16_t>(usage.value));
  }

  std::vector<std::uint32_t> declaredUsages(const Item& item) const {
    std::vector<std::uint32_t> usages;
    for (const auto& u : locals_.usages) usages.push_back(fullUsage(u));
    if (locals_.usage_min || locals_.usage_max) {
      if (!locals_.usage_min || !locals_.usage_max) fail(item, "Usage Minimum without Usage Maximum, or the reverse");
      const std::int64_t lo = fullUsage(*locals_.usage_min), hi = fullUsage(*locals_.usage_max);
      if (lo > hi) fail(item, "Usage Minimum above Usage Maximum");
      if (hi - lo + 1 > kMaxUsageRange) fail(item, "a usage range of " + std::to_string(hi - lo + 1) + " usages");
      for (std::int64_t u = lo; u <= hi; ++u) usages.push_back(static_cast<std::uint32_t>(u));
    }
    return usages;
  }

  void openCollection(const Item& item) {
    HidCollection c;
    c.kind = static_cast<std::uint8_t>(item.data);
    const auto usages = declaredUsages(item);
    c.usage = usages.empty() ? 0 : usages.front();
    c.parent = open_.empty() ? -1 : open_.back();
    c.offset = item.offset;
    open_.push_back(static_cast<int>(result_.collections.size()));
    result_.collections.push_back(c);
  }

  std::uint32_t application() const {
    for (auto it = open_.rbegin(); it != open_.rend(); ++it) {
      const HidCollection& c = result_.collections[static_cast<std::size_t>(*it)];
      if (c.kind == 1) return c.usage;
    }
    return 0;
  }

  HidReportLayout& layout(HidReportType type, std::uint8_t id) {
    for (auto& r : result_.reports)
      if (r.type == type && r.id == id) return r;
    HidReportLayout& r = result_.reports.emplace_back();
    r.type = type;
    r.id = id;
    return r;
  }

  HidField makeField(const Item& item, HidReportType type) const {
    const Globals& g = globals_;
    HidField f;
    f.type = type;
    f.report_id = g.report_id;
    f.bit_size = g.report_size;
    f.count = g.report_count;
    f.flags = item.data;
    f.logical_min = g.logical.min;
    f.logical_max = g.logical.max();
    f.physical_min = g.physical.min;
    f.physical_max = g.physical.max();
    if (f.physical_min == 0 && f.physical_max == 0) f.physical_min = f.logical_min, f.physical_max = f.logical_max;
    f.unit = g.unit;
    f.unit_exponent = g.unit_exponent;
    f.application = application();
    f.collection = open_.empty() ? -1 : open_.back();
    return f;
  }

  void addField(const Item& item, HidReportType type) {
    if (!globals_.has_report_size || !globals_.has_report_count)
      fail(item, std::string(toString(type)) + " item before any Report Size and Report Count");
    HidField field = makeField(item, type);
    HidReportLayout& report = layout(type, field.report_id);
    // The size first: a huge Report Count must not allocate its usages before it is refused.
    const std::uint64_t bits = std::uint64_t{report.bits} + std::uint64_t{field.bit_size} * field.count;
    if (bits > kMaxReportBytes * 8)
      fail(item, std::string(toString(type)) + " report " + std::to_string(field.report_id) + " grows over " +
                     std::to_string(kMaxReportBytes) + " bytes");
    field.usages = declaredUsages(item);
    if (field.isVariable() && !field.usages.empty()) field.usages.resize(field.count, field.usages.back());
    if (!result_.uses_report_ids) fields_without_id_ = true;
    field.bit_offset = report.bits;
    report.bits = static_cast<std::uint32_t>(bits);
    if (field.count > 0) report.fields.push_back(std::move(field));
  }

  std::span<const std::uint8_t> bytes_;
  HidDescriptor result_;
  Globals globals_;
  std::vector<Globals> stack_;
  Locals locals_;
  std::vector<int> open_;
  bool fields_without_id_ = false;
};

}  // namespace

const char* toString(HidReportType type) {
  switch (type) {
    case HidReportType::Input:
      return "Input";
    case HidReportType::Output:
      return "Output";
    case HidReportType::Feature:
      return "Feature";
  }
  return "?";
}

std::uint32_t HidField::usageOf(std::uint32_t element) const {
  if (usages.empty()) return 0;
  return usages[std::min<std::size_t>(element, usages.size() - 1)];
}

const HidReportLayout* HidDescriptor::find(HidReportType type, std::uint8_t id) const {
  for (const auto& r : reports)
    if (r.type == type && r.id == id) return &r;
  return nullptr;
}

std::vector<std::uint32_t> HidDescriptor::applications() const {
  std::vector<std::uint32_t> usages;
  for (const auto& c : collections)
    if (c.kind == 1) usages.push_back(c.usage);
  return usages;
}

HidDescriptor parseHidDescriptor(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) throw HidDescriptorError("report descriptor: empty", 0);
  return Parser(bytes).run();
}

std::vector<std::uint8_t> parseHexBytes(const std::string& text) {
  std::vector<std::uint8_t> bytes;
  std::size_t line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') {
      ++line, ++i;
    } else if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else {
      std::size_t end = i;
      while (end < text.size() && std::isxdigit(static_cast<unsigned char>(text[end]))) ++end;
      const bool word_ends = end == text.size() || std::isspace(static_cast<unsigned char>(text[end]));
      if (end - i != 2 || !word_ends) {
        std::size_t word_end = i;
        while (word_end < text.size() && !std::isspace(static_cast<unsigned char>(text[word_end]))) ++word_end;
        throw std::invalid_argument("line " + std::to_string(line) + ": '" + text.substr(i, word_end - i) +
                                    "' is not a two-digit hex byte");
      }
      bytes.push_back(static_cast<std::uint8_t>(std::stoul(text.substr(i, 2), nullptr, 16)));
      i = end;
    }
  }
  return bytes;
}

}  // namespace incise::devices

namespace incise::devices {

std::vector<std::uint8_t> loadHexBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (!in || !(text << in.rdbuf())) throw std::runtime_error(path.string() + ": cannot read");
  try {
    return parseHexBytes(text.str());
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();  // "line L: ..."
    throw std::runtime_error(path.string() + ":" + what.substr(5));
  }
}

}  // namespace incise::devices
