#include "incise/devices/hid_recording.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <system_error>

#include "message_text.h"
#include "record_stream.h"

namespace incise::devices {
namespace {

using detail::quoteField;

constexpr std::string_view kFieldBlank = " \t";
constexpr std::int64_t kMicrosecondsPerSecond = 1000000;

std::string_view trimRight(std::string_view text) {
  const std::size_t end = text.find_last_not_of(kFieldBlank);
  return end == std::string_view::npos ? std::string_view() : text.substr(0, end + 1);
}

// Fields separated by runs of spaces and tabs.
std::vector<std::string_view> splitBlankFields(std::string_view text) {
  std::vector<std::string_view> fields;
  std::size_t start = text.find_first_not_of(kFieldBlank);
  while (start != std::string_view::npos) {
    const std::size_t end = text.find_first_of(kFieldBlank, start);
    fields.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    start = end == std::string_view::npos ? end : text.find_first_not_of(kFieldBlank, end);
  }
  return fields;
}

// The whole field as an unsigned number in `base`; nullopt when it is not one (or is out of range).
std::optional<std::uint64_t> parseUnsigned(std::string_view field, int base) {
  std::uint64_t value = 0;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value, base);
  if (field.empty() || result.ec != std::errc() || result.ptr != field.data() + field.size()) return std::nullopt;
  return value;
}

bool allDigits(std::string_view text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
}

// "%06lld.%06lld": the file's own spelling of a time.
std::string formatTime(std::int64_t time_us) {
  char text[48];
  const int n =
      std::snprintf(text, sizeof text, "%06lld.%06lld", static_cast<long long>(time_us / kMicrosecondsPerSecond),
                    static_cast<long long>(time_us % kMicrosecondsPerSecond));
  return std::string(text, static_cast<std::size_t>(n));
}

// What the reader knows of each device besides its fields: where its lines were.
struct DeviceLines {
  std::size_t first = 0;       // the line that started it (its D:, or the first line of device 0)
  std::size_t descriptor = 0;  // its R:
  std::size_t name = 0, phys = 0, info = 0;
  std::size_t last_report = 0;    // its last E:
  std::int64_t last_time_us = 0;  // that report's time
};

class RecordingParser {
 public:
  explicit RecordingParser(std::filesystem::path path) : path_(std::move(path)) {}
  HidRecording read();

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw HidRecordingError(path_.string() + ":" + std::to_string(line_) + ": " + what, path_, line_);
  }
  void parseLine(std::string_view line);
  void parseDeviceSwitch(std::string_view rest);
  void parseDescriptor(std::string_view rest);
  void parseInfo(std::string_view rest);
  void parseReport(std::string_view rest);
  void checkEnd(bool truncated_tail) const;
  // The device the current line belongs to: device 0 when no D: line came yet.
  int currentDevice();
  // Marks field `slot` as seen on this line, failing when it was seen before.
  void once(std::size_t& slot, const char* prefix);
  // fields[0] is a length, the rest its bytes (hex): the bytes, checked.
  std::vector<std::uint8_t> parseBytes(const char* prefix, std::span<const std::string_view> fields,
                                       std::size_t max_bytes) const;
  std::int64_t parseTime(std::string_view field) const;

  std::filesystem::path path_;
  HidRecording recording_;
  std::vector<DeviceLines> lines_;  // per device
  int current_ = -1;                // -1: before the first D: line
  std::size_t line_ = 0;
  bool leading_comments_ = true;
};

HidRecording RecordingParser::read() {
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    const int error = errno;
    throw HidRecordingError(path_.string() + ": cannot open (" + std::generic_category().message(error) + ")", path_,
                            0);
  }
  std::ostringstream whole;
  whole << in.rdbuf();
  if (in.bad()) throw HidRecordingError(path_.string() + ": read error", path_, 0);
  std::string_view text = whole.view();
  if (text.empty()) {
    line_ = 1;
    fail("empty file; expected a hid-recorder recording (R:, N:, I: lines, then E: lines)");
  }
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    if (end == std::string_view::npos) {
      // The tail a killed writer leaves: not part of the recording.
      recording_.truncated_tail = true;
      break;
    }
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end + 1);
    ++line_;
    if (line.ends_with('\r')) line.remove_suffix(1);
    parseLine(line);
  }
  checkEnd(recording_.truncated_tail);
  return std::move(recording_);
}

void RecordingParser::parseLine(std::string_view line) {
  if (line.starts_with('#')) {
    if (leading_comments_) {
      std::string_view comment = line.substr(1);
      if (comment.starts_with(' ')) comment.remove_prefix(1);
      recording_.comments.emplace_back(comment);
    }
    return;
  }
  leading_comments_ = false;
  if (line.find_first_not_of(kFieldBlank) == std::string_view::npos) return;  // empty line
  const char prefix = line.size() >= 2 && line[1] == ':' ? line[0] : '\0';
  std::string_view rest = line.substr(prefix == '\0' ? 0 : 2);
  switch (prefix) {
    case 'D':
      return parseDeviceSwitch(rest);
    case 'R':
      return parseDescriptor(rest);
    case 'I':
      return parseInfo(rest);
    case 'E':
      return parseReport(rest);
    case 'N':
    case 'P': {
      // Verbatim after "N: " (a name may end in spaces).
      if (rest.starts_with(' ')) rest.remove_prefix(1);
      const int device = currentDevice();
      DeviceLines& lines = lines_[static_cast<std::size_t>(device)];
      HidRecordedDevice& d = recording_.devices[static_cast<std::size_t>(device)];
      once(prefix == 'N' ? lines.name : lines.phys, prefix == 'N' ? "N:" : "P:");
      (prefix == 'N' ? d.name : d.phys) = std::string(rest);
      return;
    }
    default:
      fail("unknown line " + quoteField(line) + "; a hid-recorder line starts with '#', 'D:', 'R:', 'N:', 'P:', " +
           "'I:' or 'E:'");
  }
}

int RecordingParser::currentDevice() {
  if (current_ < 0) {
    current_ = 0;
    recording_.devices.emplace_back();
    lines_.push_back(DeviceLines{line_});
  }
  return current_;
}

void RecordingParser::once(std::size_t& slot, const char* prefix) {
  if (slot != 0)
    fail(std::string("a second ") + prefix + " line for device " + std::to_string(current_) +
         " (the first is on line " + std::to_string(slot) + ")");
  slot = line_;
}

void RecordingParser::parseDeviceSwitch(std::string_view rest) {
  const std::vector<std::string_view> fields = splitBlankFields(rest);
  if (fields.size() != 1) fail("D: expects one device number, got " + quoteField(trimRight(rest)));
  const auto index = parseUnsigned(fields[0], 10);
  if (!index || *index > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
    fail("D: " + quoteField(fields[0]) + " is not a device number");
  const std::size_t count = recording_.devices.size();
  if (*index > count)
    fail("D: " + std::to_string(*index) + " skips a device: devices are numbered 0, 1, 2, ... in order, and the next " +
         "new one is " + std::to_string(count));
  current_ = static_cast<int>(*index);
  if (*index == count) {
    recording_.devices.emplace_back().index = current_;
    lines_.push_back(DeviceLines{line_});
  }
}

std::vector<std::uint8_t> RecordingParser::parseBytes(const char* prefix, std::span<const std::string_view> fields,
                                                      std::size_t max_bytes) const {
  if (!allDigits(fields[0]))
    fail(std::string(prefix) + " length " + quoteField(fields[0]) + " is not a number of bytes");
  const auto length = parseUnsigned(fields[0], 10);  // nullopt: too many digits for 64 bits
  if (!length || *length == 0 || *length > max_bytes)
    fail(std::string(prefix) + " length " + quoteField(fields[0]) + " is outside 1.." + std::to_string(max_bytes));
  const std::size_t count = fields.size() - 1;
  if (count == 0) fail(std::string(prefix) + " length " + std::to_string(*length) + " but no bytes follow");
  if (count != *length)
    fail(std::string(prefix) + " length " + std::to_string(*length) + " but " + std::to_string(count) + " byte" +
         (count == 1 ? "" : "s") + " follow" + (count == 1 ? "s" : ""));
  std::vector<std::uint8_t> bytes;
  bytes.reserve(count);
  for (std::size_t i = 1; i <= count; ++i) {
    const std::string_view field = fields[i];
    const auto value = parseUnsigned(field, 16);
    if (value && *value <= 0xff && field.size() <= 2) {
      bytes.push_back(static_cast<std::uint8_t>(*value));
      continue;
    }
    const std::string which = std::string(prefix) + " byte " + std::to_string(i) + " " + quoteField(field);
    if (!value) fail(which + " is not hex");
    if (*value > 0xff) fail(which + " is over 0xff");
    fail(which + " is not a byte (one or two hex digits)");
  }
  return bytes;
}

void RecordingParser::parseDescriptor(std::string_view rest) {
  const std::vector<std::string_view> fields = splitBlankFields(rest);
  if (fields.empty()) fail("R: missing the descriptor's length and bytes");
  const int device = currentDevice();
  once(lines_[static_cast<std::size_t>(device)].descriptor, "R:");
  recording_.devices[static_cast<std::size_t>(device)].descriptor = parseBytes("R:", fields, kHidMaxDescriptorBytes);
}

void RecordingParser::parseInfo(std::string_view rest) {
  const std::vector<std::string_view> fields = splitBlankFields(rest);
  if (fields.size() != 3)
    fail("I: expects bus, vendor and product in hex (e.g. 'I: 3 046d c24e'), got " + quoteField(trimRight(rest)));
  const int device = currentDevice();
  once(lines_[static_cast<std::size_t>(device)].info, "I:");
  constexpr const char* kNames[3] = {"bus", "vendor", "product"};
  constexpr std::uint64_t kMax[3] = {0xffffffffu, 0xffffu, 0xffffu};
  std::uint64_t values[3] = {};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto value = parseUnsigned(fields[i], 16);
    const std::string which = std::string("I: ") + kNames[i] + " " + quoteField(fields[i]);
    if (!value) fail(which + " is not hex");
    if (*value > kMax[i]) fail(which + " is over " + (i == 0 ? "ffffffff" : "ffff"));
    values[i] = *value;
  }
  HidRecordedDevice& d = recording_.devices[static_cast<std::size_t>(device)];
  d.bus = static_cast<std::uint32_t>(values[0]);
  d.vid = static_cast<std::uint16_t>(values[1]);
  d.pid = static_cast<std::uint16_t>(values[2]);
}

std::int64_t RecordingParser::parseTime(std::string_view field) const {
  const std::size_t dot = field.find('.');
  const std::string_view seconds = field.substr(0, dot);
  const std::string_view micros = dot == std::string_view::npos ? std::string_view() : field.substr(dot + 1);
  if (dot == std::string_view::npos || !allDigits(seconds) || !allDigits(micros) || micros.size() != 6)
    fail("E: time " + quoteField(field) +
         " is not seconds.microseconds (six digits after the '.', e.g. 000001.250000)");
  constexpr std::uint64_t kMaxSeconds = (std::numeric_limits<std::int64_t>::max() - 999999) / 1000000;
  const auto s = parseUnsigned(seconds, 10);
  if (!s || *s > kMaxSeconds) fail("E: time " + quoteField(field) + " is too large");
  return static_cast<std::int64_t>(*s) * kMicrosecondsPerSecond + static_cast<std::int64_t>(*parseUnsigned(micros, 10));
}

void RecordingParser::parseReport(std::string_view rest) {
  const int device = currentDevice();
  DeviceLines& lines = lines_[static_cast<std::size_t>(device)];
  if (lines.descriptor == 0)
    fail("E: line for device " + std::to_string(device) + " before its report descriptor (R: line)");
  const std::vector<std::string_view> fields = splitBlankFields(rest);
  if (fields.size() < 2) fail("E: missing the " + std::string(fields.empty() ? "time, " : "") + "length and bytes");
  HidRecordedReport report;
  report.device = device;
  report.line = line_;
  report.time_us = parseTime(fields[0]);
  report.bytes = parseBytes("E:", std::span(fields).subspan(1), kHidMaxReportBytes);
  if (lines.last_report != 0 && report.time_us < lines.last_time_us)
    fail("E: time goes back on device " + std::to_string(device) + ": " + formatTime(report.time_us) + " s after " +
         formatTime(lines.last_time_us) + " s on line " + std::to_string(lines.last_report));
  lines.last_report = line_;
  lines.last_time_us = report.time_us;
  recording_.reports.push_back(std::move(report));
}

void RecordingParser::checkEnd(bool truncated_tail) const {
  const std::string dropped = truncated_tail ? " (the last line, without an end of line, was dropped)" : "";
  if (recording_.devices.empty()) {
    const std::size_t last = std::max<std::size_t>(line_, 1);
    throw HidRecordingError(
        path_.string() + ":" + std::to_string(last) + ": end of file without a report descriptor (R: line)" + dropped,
        path_, last);
  }
  for (std::size_t d = 0; d < lines_.size(); ++d)
    if (lines_[d].descriptor == 0)
      throw HidRecordingError(path_.string() + ":" + std::to_string(lines_[d].first) + ": device " + std::to_string(d) +
                                  " has no report descriptor (R: line)" + dropped,
                              path_, lines_[d].first);
}

}  // namespace

HidRecording readHidRecording(const std::filesystem::path& path) { return RecordingParser(path).read(); }

// ---------------------------------------------------------------------------------------------------
// HidRecordingWriter

namespace {

void appendHexBytes(std::string& out, std::span<const std::uint8_t> bytes) {
  constexpr char kHex[] = "0123456789abcdef";
  for (const std::uint8_t b : bytes) {
    out.push_back(' ');
    out.push_back(kHex[b >> 4]);
    out.push_back(kHex[b & 0xf]);
  }
}

void requireOneLine(const std::string& text, const char* what) {
  if (text.find_first_of("\r\n") != std::string::npos)
    throw std::invalid_argument(std::string("HidRecordingWriter: ") + what +
                                " contains a newline: " + quoteField(text));
}

// The comments and the device's lines: everything before the first report.
std::string headerText(const HidRecordedDevice& device, const HidRecordingWriterOptions& options) {
  for (const std::string& comment : options.comments) requireOneLine(comment, "a comment line");
  requireOneLine(device.name, "the device name");
  requireOneLine(device.phys, "the device's phys");
  if (device.descriptor.empty() || device.descriptor.size() > kHidMaxDescriptorBytes)
    throw std::invalid_argument("HidRecordingWriter: the report descriptor has " +
                                std::to_string(device.descriptor.size()) + " bytes, not 1.." +
                                std::to_string(kHidMaxDescriptorBytes));
  std::string text;
  for (const std::string& comment : options.comments) text.append(comment.empty() ? "#" : "# ").append(comment) += '\n';
  text.append("D: 0\nR: ").append(std::to_string(device.descriptor.size()));
  appendHexBytes(text, device.descriptor);
  text.append("\nN: ").append(device.name).append("\nP: ").append(device.phys) += '\n';
  char info[48];
  const int n = std::snprintf(info, sizeof info, "I: %x %04x %04x\n", static_cast<unsigned>(device.bus),
                              static_cast<unsigned>(device.vid), static_cast<unsigned>(device.pid));
  return text.append(info, static_cast<std::size_t>(n));
}

}  // namespace

HidRecordingWriter::HidRecordingWriter(std::filesystem::path path, const HidRecordedDevice& device,
                                       HidRecordingWriterOptions options)
    : path_(std::move(path)) {
  if (options.flush_every == 0) throw std::invalid_argument("HidRecordingWriter: flush_every must be >= 1");
  const std::string header = headerText(device, options);
  // "E: 000000.000000 N" and three characters a byte; a typical report is a few dozen bytes.
  stream_ = std::make_unique<detail::RecordStream>(path_, "HidRecordingWriter", options.flush_every,
                                                   options.fsync_on_close, options.flush_every * 128 + 256);
  stream_->writeHeader(header);
}

HidRecordingWriter::~HidRecordingWriter() = default;  // the stream flushes and closes, swallowing errors
HidRecordingWriter::HidRecordingWriter(HidRecordingWriter&& other) noexcept = default;
HidRecordingWriter& HidRecordingWriter::operator=(HidRecordingWriter&& other) noexcept = default;

std::size_t HidRecordingWriter::reportsWritten() const { return stream_ ? stream_->recordsWritten() : 0; }
std::size_t HidRecordingWriter::reportsFlushed() const { return stream_ ? stream_->recordsFlushed() : 0; }

void HidRecordingWriter::write(std::int64_t time_us, std::span<const std::uint8_t> report) {
  if (!stream_ || !stream_->isOpen())
    throw std::logic_error("HidRecordingWriter '" + path_.string() + "': write() after close()");
  const std::string which =
      "HidRecordingWriter '" + path_.string() + "': report " + std::to_string(stream_->recordsWritten() + 1) + ": ";
  if (report.empty() || report.size() > kHidMaxReportBytes)
    throw std::invalid_argument(which + std::to_string(report.size()) + " bytes, not 1.." +
                                std::to_string(kHidMaxReportBytes));
  if (time_us < 0) throw std::invalid_argument(which + "time " + std::to_string(time_us) + " us is negative");
  if (previous_time_us_ && time_us < *previous_time_us_)
    throw std::invalid_argument(which + "time goes back (" + formatTime(time_us) + " s after " +
                                formatTime(*previous_time_us_) + " s)");

  std::string& out = stream_->buffer();
  out.append("E: ").append(formatTime(time_us)).append(" ").append(std::to_string(report.size()));
  appendHexBytes(out, report);
  out.push_back('\n');
  previous_time_us_ = time_us;
  stream_->recordAdded();
}

void HidRecordingWriter::flush() {
  if (stream_) stream_->flush();
}

void HidRecordingWriter::sync() {
  if (stream_) stream_->sync();
}

void HidRecordingWriter::close() {
  if (stream_) stream_->close();
}

}  // namespace incise::devices
