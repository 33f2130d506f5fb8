// HID traffic in the text format of hid-tools' `hid-recorder` (what Linux users capture a stylus, a mouse
// or a 6-DOF controller with, from /dev/hidraw*, and replay with `hid-replay`): a reader, and a writer that
// survives being killed (HidRecordingWriter). Only the bytes: what a report means is the report descriptor's
// business. The format, as hid-tools 0.12 prints and parses it, is above readHidRecording.
//
// Units: time in integer microseconds (exact, as the file has it); time_s() in seconds for the rest of
// incise. Threads: a HidRecording is a plain value; readHidRecording runs on any thread; a writer belongs to
// one thread at a time, off the sim thread. Cost: O(file size). Failure: HidRecordingError "path:line: ..."
// from the reader; the writer's exceptions are listed above HidRecordingWriter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace incise::devices {

namespace detail {
class RecordStream;  // devices/src/record_stream.h
}  // namespace detail

// The kernel's HID_MAX_DESCRIPTOR_SIZE: no report descriptor is longer.
inline constexpr std::size_t kHidMaxDescriptorBytes = 4096;
// What one read(2) of a hidraw node returns at most in hid-recorder (its read buffer): no longer report.
inline constexpr std::size_t kHidMaxReportBytes = 4096;

struct HidRecordedDevice {
  int index = 0;                         // its D: number (its place in HidRecording::devices)
  std::string name;                      // N:
  std::string phys;                      // P:
  std::uint32_t bus = 0;                 // I: bus type (linux/input.h: 3 USB, 5 Bluetooth, 0x18 I2C)
  std::uint16_t vid = 0;                 // I: vendor id
  std::uint16_t pid = 0;                 // I: product id
  std::vector<std::uint8_t> descriptor;  // R: the report descriptor
};

struct HidRecordedReport {
  int device = 0;                   // index into HidRecording::devices
  std::int64_t time_us = 0;         // microseconds on the recorder's clock, >= 0
  std::vector<std::uint8_t> bytes;  // the report as read from hidraw (report id first when numbered)
  std::size_t line = 0;             // 1-based line of its E: in the file (0 when it did not come from a file)
  // The double nearest time_us / 10^6 (exact division, correctly rounded).
  double time_s() const { return static_cast<double>(time_us) / 1e6; }
};

struct HidRecording {
  std::vector<HidRecordedDevice> devices;  // at least one, each with its descriptor
  std::vector<HidRecordedReport> reports;  // in file order (several devices interleave)
  // The comment lines at the top of the file, before its first other line, without the '#' and one space
  // after it, in order: the writer's provenance; for a single-device hid-recorder file, the device's name
  // and its decoded descriptor.
  std::vector<std::string> comments;
  // The file ended in a line without '\n', which was dropped (a writer killed mid-write, or an editor that
  // dropped the last newline).
  bool truncated_tail = false;
};

// A recording that cannot be read: what() is "path:line: what is wrong", e.g.
//   pen.hid:17: E: length 8 but 7 bytes follow
// ("path: ..." when the problem is not on one line).
class HidRecordingError : public std::runtime_error {
 public:
  HidRecordingError(const std::string& message, std::filesystem::path path, std::size_t line)
      : std::runtime_error(message), path_(std::move(path)), line_(line) {}
  const std::filesystem::path& path() const { return path_; }
  // 1-based line in the file; 0 when the error is about the whole file.
  std::size_t line() const { return line_; }

 private:
  std::filesystem::path path_;
  std::size_t line_;
};

// Format (hid-recorder's, as hid-tools 0.12 prints it and its hid-replay parses it). Lines end in '\n'
// (a '\r' before it is ignored; a UTF-8 byte-order mark at the start too). Each line starts with a
// prefix in its first column:
//   #            a comment, skipped wherever it stands. hid-recorder prints the device's name and the
//                decoded descriptor as comments before its R: line ("# 0x05, 0x01,   // Usage Page ..."),
//                an empty "# " after it, and each report's decoding before its E: line ("#  Button: 1 ...").
//   D: n         the device the following lines belong to, n decimal. hid-recorder prints it only when it
//                records several devices (the older C hid-recorder always); without one, device 0.
//                Devices are numbered 0, 1, 2, ... in order of their first D: line; a D: line may go
//                back to an earlier device (reports interleave), never skip one.
//   R: len b..   the device's report descriptor: its length in bytes (decimal, 1..kHidMaxDescriptorBytes),
//                then that many bytes in hex, one or two digits each ("05 01 09 02 ...").
//   N: name      the device's name, the rest of the line after "N: " as it is (may be empty).
//   P: phys      its physical path, as N:. hid-tools' recorder does not print it; the C one did.
//   I: b v p     bus type, vendor id, product id, in hex without 0x ("I: 3 046d c24e": USB). b < 2^32,
//                v and p < 2^16.
//   E: s.u len b..  one report of the current device: time as seconds '.' microseconds (hid-recorder
//                prints "%06d.%06d", the C one "%lu.%06u": any number of digits for the seconds, exactly
//                six for the microseconds; time 0 is the first report), the report's length in bytes
//                (decimal, 1..kHidMaxReportBytes) and its bytes in hex as in R:.
//   Fields are separated by one or more spaces or tabs; trailing spaces and tabs are ignored (except in
//   N: and P:, kept verbatim). Empty lines are skipped. Each device has at most one R:, N:, P: and I:
//   line; N:, P: and I: may be missing (name and phys "", bus, vid and pid 0), R: may not. A device's
//   E: lines come after its R: line, and their times never go back (equal times are allowed:
//   hid-recorder stamps every report of one read with the same time). Times are compared per device:
//   two devices' reports interleave in arrival order.
//   A final line without its '\n' is not part of the recording: it is what a writer killed in the middle of
//   a write leaves behind (even a complete-looking report there may be cut: "E: ... 8 01 02" of "... 01 02 03").
//
// Reads the whole recording at `path`.
// Failure: HidRecordingError with path and line, for: a file that cannot be opened or read; an empty file;
// a line with an unknown prefix; a D: index that is not a number or skips a device; a second R:, N:, P: or
// I: line for one device; a length that is not a number, 0 or over the maximum, or that disagrees with the
// bytes that follow (more or fewer, or none); a byte that is not hex, or over 0xff; an I: field that is not
// hex or too large; an E: time that is not "seconds.microseconds" or goes back (the message names both
// times and the earlier line); an E: line before its device's R: line; a device without an R: line (named
// by its D: line), or a file without any.
HidRecording readHidRecording(const std::filesystem::path& path);

struct HidRecordingWriterOptions {
  // Reports buffered in memory before they are handed to the OS with one write(2). 1 = every report.
  // Must be >= 1.
  std::size_t flush_every = 50;
  // fsync(2) the file in close() and in the destructor: survives power loss and OS crashes too, at a
  // cost of milliseconds. The crash guarantee below does not need it.
  bool fsync_on_close = false;
  // Comment lines written first as "# <text>" ("#" for an empty one): provenance (generator, date). No
  // '\n' or '\r' inside. HidRecording::comments returns them as given.
  std::vector<std::string> comments;
};

// Records one device's reports in the format above: the comments, then "D: 0", R:, N:, P:, I:, then one
// E: line per report (time printed "%06d.%06d" as hid-recorder does, bytes as two lower-case hex digits).
// The device's index is not written (the file holds one device, number 0).
//
// Crash guarantee. The constructor writes the comments and the device's lines with write(2) before it
// returns; the file appears at its path only then, header complete (written to path + ".tmp", renamed
// onto the path; a previous file there stays whole until the rename; a kill before it leaves the .tmp).
// Reports are buffered in this process's memory and handed to the kernel with write(2) (no stdio
// or iostream buffer in between) when the buffer holds options.flush_every reports, on flush(), close()
// and in the destructor. Once one of these calls has returned, its reports are in the kernel's page cache:
// if the process then dies in any way (SIGKILL, abort, a crash, _exit) the file holds the comments, the
// device and every such report, and readHidRecording reads them back bit-exactly without an error.
// Reports still buffered are lost whole. A process killed *during* a write(2) may leave part of that
// write: complete lines, which read back as reports, and at most one cut last line, which
// readHidRecording drops (truncated_tail). reportsFlushed() says how many reports are covered by the
// guarantee. Power loss and OS crashes are covered only for data that was fsync'ed (sync(), or
// fsync_on_close).
//
// Cost: O(report length) per write(); one write(2) system call per flush_every reports.
// Threads: one thread at a time (the recorder's); write() may block on the disk during a flush, so keep it
// off the sim thread.
// Failure: the constructor throws std::invalid_argument (flush_every == 0; a comment, name or phys with a
// newline; a descriptor empty or over kHidMaxDescriptorBytes) or std::system_error (the file cannot be
// created or written). write() throws std::invalid_argument, writing nothing, for a report the reader would
// reject: empty or over kHidMaxReportBytes, time negative or before the previous report's (equal is
// allowed); std::logic_error after close(); std::system_error when a flush fails (the report is then
// accepted, and the unwritten bytes stay buffered for the next flush to retry).
class HidRecordingWriter {
 public:
  // Creates or truncates `path` (mode 0644 before umask).
  HidRecordingWriter(std::filesystem::path path, const HidRecordedDevice& device,
                     HidRecordingWriterOptions options = {});
  // Flushes, fsyncs if asked and closes; errors are swallowed here (call close() to see them).
  ~HidRecordingWriter();
  HidRecordingWriter(HidRecordingWriter&& other) noexcept;
  HidRecordingWriter& operator=(HidRecordingWriter&& other) noexcept;
  HidRecordingWriter(const HidRecordingWriter&) = delete;
  HidRecordingWriter& operator=(const HidRecordingWriter&) = delete;

  // Appends one report; flushes when flush_every reports are buffered.
  void write(std::int64_t time_us, std::span<const std::uint8_t> report);
  // Hands every buffered report to the kernel (write(2)). No-op when nothing is buffered.
  void flush();
  // flush() then fsync(2): the reports so far survive power loss too.
  void sync();
  // flush(), fsync if options.fsync_on_close, close(2). Further write() calls throw std::logic_error;
  // close() again does nothing.
  void close();

  // Reports accepted by write().
  std::size_t reportsWritten() const;
  // Reports handed to the kernel: what a kill at this moment leaves in the file.
  std::size_t reportsFlushed() const;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::unique_ptr<detail::RecordStream> stream_;  // null once moved from
  std::optional<std::int64_t> previous_time_us_;
};

}  // namespace incise::devices
