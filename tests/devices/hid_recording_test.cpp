#include "incise/devices/hid_recording.h"

#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <catch2/catch.hpp>

#include "crash_fixture.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using incise::devices::HidRecordedDevice;
using incise::devices::HidRecordedReport;
using incise::devices::HidRecording;
using incise::devices::HidRecordingError;
using incise::devices::HidRecordingWriter;
using incise::devices::HidRecordingWriterOptions;
using incise::devices::kHidMaxReportBytes;
using incise::devices::readHidRecording;
using incise::devices::testing::Child;
using incise::devices::testing::Pipe;
using incise::devices::testing::receive;
using incise::devices::testing::report;
using incise::test::readFile;
using incise::test::TempDir;

namespace {

using Bytes = std::vector<std::uint8_t>;

// hid-recorder's output, made by hid-tools 0.12's own printing code (hidtools/hidraw.py HidrawDevice.dump
// and the D: logic of hidtools/cli/record.py) for fake hidraw nodes: a Logitech G500s mouse (the report
// descriptor of hid-tools' own tests) and a Logitech receiver's keyboard, then five reports as they arrived.
// The comments are the decoded descriptors and reports; the "# " lines end in a space, as printed.
const std::filesystem::path kTwoDevices =
    std::filesystem::path(INCISE_DEVICES_TEST_DATA) / "hid-recorder-two-devices.hid";
// The same mouse recorded alone: no D: lines, the name and the decoded descriptor as the leading comments.
const std::filesystem::path kOneDevice =
    std::filesystem::path(INCISE_DEVICES_TEST_DATA) / "hid-recorder-one-device.hid";

HidRecordedDevice stylus() {
  HidRecordedDevice d;
  d.name = "Wacom Intuos Pro M Pen";
  d.phys = "usb-0000:00:14.0-2/input0";
  d.bus = 3;
  d.vid = 0x056a;
  d.pid = 0x0357;
  d.descriptor = {0x05, 0x0d, 0x09, 0x02, 0xa1, 0x01, 0x85, 0x10, 0xc0};
  return d;
}

HidRecordingWriterOptions flushEveryReports(std::size_t reports) {
  HidRecordingWriterOptions options;
  options.flush_every = reports;
  return options;
}

struct TimedReport {
  std::int64_t time_us;
  Bytes bytes;
};

// `count` reports with times that never go back (some equal), lengths 1..64 and now and then the largest.
std::vector<TimedReport> randomReports(std::uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255), length(1, 64), step_us(0, 20000);
  std::vector<TimedReport> reports;
  std::int64_t t = 0;
  for (int i = 0; i < count; ++i) {
    if (i % 3 != 0) t += step_us(rng);   // every third report at the same time as the one before
    if (i == 7) t += 86400LL * 1000000;  // past a day: more than six digits of seconds later on
    TimedReport r{t, Bytes(static_cast<std::size_t>(i % 97 == 5 ? kHidMaxReportBytes : length(rng)))};
    for (auto& b : r.bytes) b = static_cast<std::uint8_t>(byte(rng));
    reports.push_back(std::move(r));
  }
  return reports;
}

void requireReports(const HidRecording& got, const std::vector<TimedReport>& expected, std::size_t first_line) {
  REQUIRE(got.reports.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    INFO("report " << i);
    REQUIRE(got.reports[i].device == 0);
    REQUIRE(got.reports[i].time_us == expected[i].time_us);
    REQUIRE(got.reports[i].bytes == expected[i].bytes);
    REQUIRE(got.reports[i].line == first_line + i);
  }
}

// The HidRecordingError that reading `text` raises.
HidRecordingError errorFor(const std::string& text) {
  TempDir dir;
  const auto path = dir.write("bad.hid", text);
  try {
    readHidRecording(path);
  } catch (const HidRecordingError& error) {
    return error;
  }
  FAIL("no HidRecordingError for:\n" << text);
  throw std::logic_error("unreachable");
}

// Checks that `text` is refused on `line` with a message "path:line: ..." containing `what`.
void requireError(const std::string& text, std::size_t line, const std::string& what) {
  const HidRecordingError error = errorFor(text);
  INFO(error.what());
  CHECK(error.line() == line);
  CHECK_THAT(error.what(), Contains("bad.hid:" + std::to_string(line) + ": "));
  CHECK_THAT(error.what(), Contains(what));
}

const std::string kHeader = "R: 2 05 01\nN: pen\nI: 3 056a 0357\n";  // lines 1-3

}  // namespace

TEST_CASE("hid_recording: what the writer writes reads back bit-exactly, in hid-recorder's layout", "[devices]") {
  TempDir dir;
  const auto path = dir.path() / "pen.hid";
  const std::vector<TimedReport> reports = randomReports(1, 500);
  HidRecordingWriterOptions options = flushEveryReports(7);
  options.comments = {"generator: incise test", "", " indented"};
  {
    HidRecordingWriter writer(path, stylus(), options);
    for (const TimedReport& r : reports) writer.write(r.time_us, r.bytes);
    CHECK(writer.reportsWritten() == 500);
  }
  const HidRecording got = readHidRecording(path);
  REQUIRE(got.devices.size() == 1);
  const HidRecordedDevice& d = got.devices[0];
  const HidRecordedDevice expected = stylus();
  CHECK(d.index == 0);
  CHECK(d.name == expected.name);
  CHECK(d.phys == expected.phys);
  CHECK(d.bus == 3);
  CHECK(d.vid == 0x056a);
  CHECK(d.pid == 0x0357);
  CHECK(d.descriptor == expected.descriptor);
  CHECK(got.comments == options.comments);
  CHECK_FALSE(got.truncated_tail);
  requireReports(got, reports, 9);  // 3 comments, D:, R:, N:, P:, I:, then the reports
  CHECK(got.reports[1].time_s() == static_cast<double>(reports[1].time_us) / 1e6);

  // The exact text: what hid-replay parses.
  const std::string text = readFile(path);
  CHECK_THAT(text, StartsWith("# generator: incise test\n#\n#  indented\nD: 0\nR: 9 05 0d 09 02 a1 01 85 10 c0\n"
                              "N: Wacom Intuos Pro M Pen\nP: usb-0000:00:14.0-2/input0\nI: 3 056a 0357\nE: 000000."));
  char first[64];
  std::snprintf(first, sizeof first, "E: %06lld.%06lld %zu ", static_cast<long long>(reports[0].time_us / 1000000),
                static_cast<long long>(reports[0].time_us % 1000000), reports[0].bytes.size());
  CHECK_THAT(text, Contains(std::string("\n") + first));
}

TEST_CASE("hid_recording: a hid-recorder file of two devices, with its comments, reads as recorded", "[devices]") {
  const HidRecording got = readHidRecording(kTwoDevices);
  REQUIRE(got.devices.size() == 2);
  CHECK(got.comments.empty());  // it starts with "D: 0"
  CHECK_FALSE(got.truncated_tail);
  const HidRecordedDevice& mouse = got.devices[0];
  CHECK(mouse.index == 0);
  CHECK(mouse.name == "Logitech G500s Laser Gaming Mouse");
  CHECK(mouse.phys.empty());  // hid-tools' recorder prints no P: line
  CHECK(mouse.bus == 3);
  CHECK(mouse.vid == 0x046d);
  CHECK(mouse.pid == 0xc24e);
  REQUIRE(mouse.descriptor.size() == 67);
  CHECK(mouse.descriptor.front() == 0x05);
  CHECK(mouse.descriptor[34] == 0x75);
  CHECK(mouse.descriptor.back() == 0xc0);
  const HidRecordedDevice& keyboard = got.devices[1];
  CHECK(keyboard.index == 1);
  CHECK(keyboard.name == "Logitech USB Receiver");
  CHECK(keyboard.pid == 0xc52b);
  REQUIRE(keyboard.descriptor.size() == 122);
  CHECK(keyboard.descriptor[6] == 0x85);  // Report ID (1)

  REQUIRE(got.reports.size() == 5);
  const std::vector<int> devices = {0, 0, 1, 1, 0};
  const std::vector<std::int64_t> times_us = {0, 7982, 7982, 95103, 1000004};
  const std::vector<std::size_t> lines = {107, 109, 112, 114, 117};
  for (std::size_t i = 0; i < 5; ++i) {
    INFO("report " << i);
    CHECK(got.reports[i].device == devices[i]);
    CHECK(got.reports[i].time_us == times_us[i]);
    CHECK(got.reports[i].line == lines[i]);
  }
  CHECK(got.reports[0].bytes == Bytes{0x01, 0x00, 0xff, 0xff, 0x02, 0x00, 0x00, 0x00});
  CHECK(got.reports[2].bytes == Bytes{0x01, 0x02, 0x00, 0x04, 0x00, 0x00, 0x00});
  CHECK(got.reports[4].bytes == Bytes{0x00, 0x00, 0x10, 0x00, 0xf0, 0xff, 0x01, 0x00});
  CHECK(got.reports[4].time_s() == 1.000004);
}

TEST_CASE("hid_recording: a one-device hid-recorder file: no D: lines, the decoded descriptor as comments",
          "[devices]") {
  const HidRecording got = readHidRecording(kOneDevice);
  REQUIRE(got.devices.size() == 1);
  CHECK(got.devices[0].descriptor.size() == 67);
  REQUIRE(got.comments.size() == 35);  // the name, 33 descriptor items, and the empty "# " after them
  CHECK(got.comments.front() == "Logitech G500s Laser Gaming Mouse");
  CHECK(got.comments[1] == "0x05, 0x01,                    // Usage Page (Generic Desktop)        0");
  CHECK(got.comments.back().empty());
  REQUIRE(got.reports.size() == 3);
  CHECK(got.reports[1].time_us == got.reports[2].time_us);  // one read(2), one time: equal times are fine
  CHECK(got.reports[2].bytes[6] == 0xff);
}

TEST_CASE("hid_recording: the older C hid-recorder's layout, CRLF, blanks and upper-case hex read too", "[devices]") {
  TempDir dir;
  const auto path =
      dir.write("c.hid",
                "D: 0\r\nR: 3 05 0D c0\r\nN: Name ends in a space \r\nP: usb-1/input0\r\n"
                "I: 18 04F3 2a3d  \r\n\r\n   \r\nD: 0\r\nE: 1.000004 2 0a FF\r\nE: 12.000000  1\t07 \r\n");
  const HidRecording got = readHidRecording(path);
  REQUIRE(got.devices.size() == 1);
  CHECK(got.devices[0].descriptor == Bytes{0x05, 0x0d, 0xc0});
  CHECK(got.devices[0].name == "Name ends in a space ");
  CHECK(got.devices[0].phys == "usb-1/input0");
  CHECK(got.devices[0].bus == 0x18);
  CHECK(got.devices[0].vid == 0x04f3);
  CHECK(got.devices[0].pid == 0x2a3d);
  REQUIRE(got.reports.size() == 2);
  CHECK(got.reports[0].time_us == 1000004);
  CHECK(got.reports[0].bytes == Bytes{0x0a, 0xff});
  CHECK(got.reports[1].time_us == 12000000);
  CHECK(got.reports[1].line == 10);
}

TEST_CASE("hid_recording: a final line without its newline is dropped and reported", "[devices]") {
  TempDir dir;
  const auto path = dir.write("cut.hid", kHeader + "E: 000000.000000 2 01 02\nE: 000000.000100 3 01 02");
  const HidRecording got = readHidRecording(path);
  CHECK(got.truncated_tail);
  REQUIRE(got.reports.size() == 1);
  CHECK(got.reports[0].bytes == Bytes{0x01, 0x02});
}

TEST_CASE("hid_recording: bad lines are refused with path:line and what is wrong", "[devices]") {
  SECTION("an unknown prefix") { requireError(kHeader + "X: 1 2\n", 4, "unknown line 'X: 1 2'"); }
  SECTION("a line with no prefix") { requireError(kHeader + "000000.000000 1 01\n", 4, "unknown line"); }
  SECTION("a bad hex byte") { requireError(kHeader + "E: 000000.000000 3 01 zz 03\n", 4, "E: byte 2 'zz' is not hex"); }
  SECTION("a bad hex byte in the descriptor") { requireError("R: 2 05 0g\n", 1, "R: byte 2 '0g' is not hex"); }
  SECTION("a byte over 0xff") {
    requireError(kHeader + "E: 000000.000000 2 01 100\n", 4, "E: byte 2 '100' is over 0xff");
  }
  SECTION("a byte of three digits") { requireError(kHeader + "E: 000000.000000 1 0ff\n", 4, "not a byte"); }
  SECTION("more bytes than the length") {
    requireError(kHeader + "E: 000000.000000 3 01 02 03 04\n", 4, "E: length 3 but 4 bytes follow");
  }
  SECTION("fewer bytes than the length") {
    requireError(kHeader + "E: 000000.000000 3 01 02\n", 4, "E: length 3 but 2 bytes follow");
  }
  SECTION("a descriptor shorter than its length") { requireError("R: 3 05 01\n", 1, "R: length 3 but 2 bytes follow"); }
  SECTION("no bytes after the length") { requireError(kHeader + "E: 000000.000000 3\n", 4, "but no bytes follow"); }
  SECTION("no length") { requireError(kHeader + "E: 000000.000000\n", 4, "E: missing the length and bytes"); }
  SECTION("nothing after E:") { requireError(kHeader + "E:\n", 4, "E: missing the time, length and bytes"); }
  SECTION("a length of 0 or over the maximum") {
    requireError(kHeader + "E: 000000.000000 0\n", 4, "E: length '0' is outside 1..4096");
    requireError(kHeader + "E: 000000.000000 4097 01\n", 4, "E: length '4097' is outside 1..4096");
  }
  SECTION("a length that is not a number") { requireError("R: x 05\n", 1, "R: length 'x' is not a number"); }
  SECTION("a time without microseconds") {
    requireError(kHeader + "E: 0.5 1 01\n", 4, "E: time '0.5' is not seconds.microseconds");
  }
  SECTION("a time that is too large") {
    requireError(kHeader + "E: 99999999999999999999.000000 1 01\n", 4, "is too large");
  }
  SECTION("I: fields") {
    requireError("R: 1 05\nI: 3 046d\n", 2, "I: expects bus, vendor and product");
    requireError("R: 1 05\nI: 3 046g c24e\n", 2, "I: vendor '046g' is not hex");
    requireError("R: 1 05\nI: 3 046d 1c24e\n", 2, "I: product '1c24e' is over ffff");
  }
  SECTION("D: not a number") { requireError("D: one\n", 1, "D: 'one' is not a device number"); }
}

TEST_CASE("hid_recording: time going back names both times and the earlier line", "[devices]") {
  requireError(kHeader + "E: 000001.000000 1 01\n# a decode\nE: 000000.500000 1 02\n", 6,
               "E: time goes back on device 0: 000000.500000 s after 000001.000000 s on line 4");
  // Per device: another device's earlier time is not going back.
  TempDir dir;
  const auto path =
      dir.write("two.hid", "D: 0\n" + kHeader + "D: 1\n" + kHeader + "D: 0\nE: 000002.000000 1 01\nD: 1\n" +
                               "E: 000001.000000 1 02\nE: 000001.000000 1 03\n");
  CHECK(readHidRecording(path).reports.size() == 3);
}

TEST_CASE("hid_recording: device structure: R: before E:, D: in order, one R: per device", "[devices]") {
  SECTION("an E: line before any R:") {
    requireError("N: pen\nE: 000000.000000 1 01\nR: 1 05\n", 2,
                 "E: line for device 0 before its report descriptor (R: line)");
  }
  SECTION("an E: line before its own device's R:") {
    requireError(kHeader + "D: 1\nE: 000000.000000 1 01\n", 5, "for device 1 before its report descriptor");
  }
  SECTION("a D: index that skips a device") {
    requireError("D: 1\n" + kHeader, 1, "D: 1 skips a device");
    requireError("D: 0\n" + kHeader + "D: 2\n", 5, "D: 2 skips a device");
  }
  SECTION("a second R: line for one device") {
    requireError(kHeader + "R: 1 05\n", 4, "a second R: line for device 0 (the first is on line 1)");
  }
  SECTION("a second N: line") { requireError(kHeader + "N: again\n", 4, "a second N: line for device 0"); }
  SECTION("a device without a descriptor, named by its D: line") {
    requireError(kHeader + "D: 1\nN: other\n", 4, "device 1 has no report descriptor (R: line)");
  }
  SECTION("an empty file") { requireError("", 1, "empty file"); }
  SECTION("a file without a descriptor") {
    requireError("# only\n# comments\n", 2, "end of file without a report descriptor (R: line)");
    requireError("N: pen\nI: 3 1 2\n", 1, "device 0 has no report descriptor");
  }
  SECTION("a descriptor on a cut last line") {
    requireError("N: pen\nR: 1 05", 1, "the last line, without an end of line, was dropped");
  }
}

TEST_CASE("hid_recording: a missing file is a HidRecordingError naming it", "[devices]") {
  TempDir dir;
  CHECK_THROWS_WITH(readHidRecording(dir.path() / "none.hid"), Contains("none.hid: cannot open"));
}

TEST_CASE("hid_recording: the writer refuses what the reader would, writing nothing", "[devices]") {
  TempDir dir;
  const auto path = dir.path() / "refuse.hid";
  HidRecordingWriter writer(path, stylus(), flushEveryReports(1));
  const std::string header = readFile(path);
  writer.write(1000, Bytes{0x10});
  const std::string one = readFile(path);
  CHECK_THROWS_AS(writer.write(2000, Bytes{}), std::invalid_argument);
  CHECK_THROWS_AS(writer.write(2000, Bytes(kHidMaxReportBytes + 1)), std::invalid_argument);
  CHECK_THROWS_WITH(writer.write(999, Bytes{0x10}), Contains("time goes back (000000.000999 s after 000000.001000 s)"));
  CHECK(writer.reportsWritten() == 1);
  writer.flush();
  CHECK(readFile(path) == one);
  writer.write(1000, Bytes{0x11});  // equal times are allowed
  writer.write(1001, Bytes(kHidMaxReportBytes, 0xab));
  writer.close();
  CHECK_THROWS_AS(writer.write(2000, Bytes{0x10}), std::logic_error);
  const HidRecording got = readHidRecording(path);
  REQUIRE(got.reports.size() == 3);
  CHECK(got.reports[2].bytes.size() == kHidMaxReportBytes);
  CHECK(one.starts_with(header));

  HidRecordingWriter negative(dir.path() / "negative.hid", stylus());
  CHECK_THROWS_AS(negative.write(-1, Bytes{0x10}), std::invalid_argument);
}

TEST_CASE("hid_recording: the writer refuses bad options and devices", "[devices]") {
  TempDir dir;
  const auto path = dir.path() / "options.hid";
  CHECK_THROWS_AS(HidRecordingWriter(path, stylus(), flushEveryReports(0)), std::invalid_argument);
  HidRecordingWriterOptions comments;
  comments.comments = {"two\nlines"};
  CHECK_THROWS_AS(HidRecordingWriter(path, stylus(), comments), std::invalid_argument);
  HidRecordedDevice device = stylus();
  device.name = "cr\r";
  CHECK_THROWS_AS(HidRecordingWriter(path, device), std::invalid_argument);
  device = stylus();
  device.descriptor.clear();
  CHECK_THROWS_AS(HidRecordingWriter(path, device), std::invalid_argument);
  device.descriptor.assign(4097, 0);
  CHECK_THROWS_AS(HidRecordingWriter(path, device), std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(path));  // refused before the file is made
  CHECK_THROWS_AS(HidRecordingWriter(dir.path() / "missing" / "x.hid", stylus()), std::system_error);
}

TEST_CASE("hid_recording: reports reach the file every flush_every reports while the writer is open", "[devices]") {
  TempDir dir;
  const auto path = dir.path() / "flush.hid";
  const std::vector<TimedReport> reports = randomReports(2, 25);
  HidRecordingWriter writer(path, stylus(), flushEveryReports(10));
  CHECK(readHidRecording(path).reports.empty());  // the device is there from the start
  for (std::size_t i = 0; i < reports.size(); ++i) {
    writer.write(reports[i].time_us, reports[i].bytes);
    const std::size_t flushed = (i + 1) / 10 * 10;
    REQUIRE(writer.reportsFlushed() == flushed);
    requireReports(readHidRecording(path),
                   std::vector<TimedReport>(reports.begin(), reports.begin() + static_cast<std::ptrdiff_t>(flushed)),
                   6);
  }
  HidRecordingWriter moved(std::move(writer));  // the moved-from writer owns nothing and flushes nothing
  moved.flush();
  CHECK(moved.reportsFlushed() == 25);
  CHECK(writer.reportsWritten() == 0);
  requireReports(readHidRecording(path), reports, 6);
}

TEST_CASE("hid_recording: a writer killed by SIGKILL leaves every flushed report, bit-exact, and no more",
          "[devices]") {
  TempDir dir;
  const auto path = dir.path() / "killed.hid";
  const std::vector<TimedReport> reports = randomReports(3, 137);
  Pipe pipe;
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    // Child: no Catch2 here, and no exit handlers: it dies by SIGKILL with 7 reports still buffered.
    ::close(pipe.read_fd);
    try {
      HidRecordingWriterOptions options = flushEveryReports(10);
      options.comments = {"generator: crash test"};
      HidRecordingWriter writer(path, stylus(), options);
      for (const TimedReport& r : reports) writer.write(r.time_us, r.bytes);
      report(pipe.write_fd, writer.reportsFlushed());
      ::raise(SIGKILL);  // killed with the writer alive: its destructor never runs
    } catch (...) {
    }
    ::_exit(3);
  }
  Child child(pid);
  ::close(pipe.write_fd);
  pipe.write_fd = -1;
  std::size_t flushed = 0;
  REQUIRE(receive(pipe.read_fd, flushed));
  const int status = child.wait();
  REQUIRE(WIFSIGNALED(status));
  REQUIRE(WTERMSIG(status) == SIGKILL);
  CHECK(flushed == 130);

  HidRecording got;
  REQUIRE_NOTHROW(got = readHidRecording(path));
  CHECK_FALSE(got.truncated_tail);
  CHECK(got.comments == std::vector<std::string>{"generator: crash test"});
  REQUIRE(got.devices.size() == 1);
  CHECK(got.devices[0].descriptor == stylus().descriptor);
  requireReports(got, std::vector<TimedReport>(reports.begin(), reports.begin() + 130), 7);
}

TEST_CASE("hid_recording: a writer killed during one big write leaves a readable prefix", "[devices][slow]") {
  // One write(2) of ~20 MB killed while it runs: Linux leaves part of it, usually cut inside a line.
  const std::vector<TimedReport> reports = randomReports(4, 60000);
  std::mt19937 rng(4);
  std::uniform_int_distribution<unsigned> delay_us_of(0, 15000);
  int truncated_tails = 0;
  for (int round = 0; round < 8; ++round) {
    const unsigned delay_us = delay_us_of(rng);
    INFO("round " << round << ": killed " << delay_us << " us into the write");
    TempDir dir;
    const auto path = dir.path() / "anytime.hid";
    Pipe pipe;
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      ::close(pipe.read_fd);
      try {
        HidRecordingWriter writer(path, stylus(), flushEveryReports(reports.size()));
        for (std::size_t i = 0; i < reports.size(); ++i) {
          if (i + 1 == reports.size()) report(pipe.write_fd, 0);  // "kill me soon"
          writer.write(reports[i].time_us, reports[i].bytes);
        }
        for (;;) ::pause();
      } catch (...) {
      }
      ::_exit(3);
    }
    Child child(pid);
    ::close(pipe.write_fd);
    pipe.write_fd = -1;
    std::size_t ignored = 0;
    REQUIRE(receive(pipe.read_fd, ignored));
    ::usleep(delay_us);
    child.kill();
    const int status = child.wait();
    REQUIRE(WIFSIGNALED(status));

    HidRecording got;
    REQUIRE_NOTHROW(got = readHidRecording(path));
    truncated_tails += got.truncated_tail ? 1 : 0;
    REQUIRE(got.reports.size() <= reports.size());
    requireReports(
        got,
        std::vector<TimedReport>(reports.begin(), reports.begin() + static_cast<std::ptrdiff_t>(got.reports.size())),
        6);
  }
  if (truncated_tails == 0) WARN("no kill landed inside a write(2): the cut-line case was not exercised");
}
