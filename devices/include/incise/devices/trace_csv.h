// Recorded pose traces as CSV text: the format, a reader that is a PoseSource, and a writer that
// survives being killed. The format is also described, with an example, in devices/TRACE_FORMAT.md;
// here above kTraceHeader.
//
// Units: seconds, metres. Threads: a reader or a writer belongs to one thread at a time; keep the writer off
// the sim thread (a flush may block on the disk). Cost: O(line length) per sample. Failure: the reader
// throws TraceError with path, line and column; the writer std::invalid_argument or std::system_error.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "incise/devices/pose_source.h"

namespace incise::devices {

namespace detail {
class RecordStream;  // devices/src/record_stream.h: the buffered write(2) stream both recorders use
}  // namespace detail

// The first line of every trace, without its '\n'.
// Format. Lines end in '\n' (a '\r' before it is ignored; a UTF-8 byte-order mark before the header too).
//   line 1    exactly   time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure
//   then      any number of comment lines, '#' in the first column (provenance: "# generator: ...").
//             Comments may also stand between samples; they are skipped there.
//   then      one sample per line: 10 comma-separated fields, no quoting, no spaces, no empty lines.
//     column  name       meaning                                                       PoseSample field
//     1       time_s     seconds, device clock; strictly increasing from sample to sample    time_s
//     2-4     tip_*_m    tool tip, metres, device frame                                       tip_m
//     5-8     q_w..q_z   orientation (tool frame -> device frame), unit within 1e-6       orientation
//     9       buttons    bit mask as a decimal integer in [0, 4294967295]                   buttons
//     10      pressure   normalised [0, 1], or empty when the device has no pressure sensor  pressure
//   Numbers are what std::from_chars reads in its general format: '.' as decimal point whatever the
//   locale, optional exponent, no '+', no hex, no surrounding spaces. NaN and infinities are rejected.
//   The writer prints doubles as "%.17g" (via std::to_chars), so every double reads back bit-exactly
//   (-0.0 and subnormals included).
//   A final line without its '\n' is not part of the trace: it is what a writer killed in the middle of
//   a write leaves behind, and even a complete-looking number there may be cut ("0.12" of "0.125").
inline constexpr std::string_view kTraceHeader = "time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure";
// The same names one by one; column c (1-based) is kTraceColumns[c - 1].
inline constexpr std::array<std::string_view, 10> kTraceColumns = {
    "time_s", "tip_x_m", "tip_y_m", "tip_z_m", "q_w", "q_x", "q_y", "q_z", "buttons", "pressure"};
// A sample's orientation must satisfy | |q| - 1 | <= kTraceQuaternionTolerance.
inline constexpr double kTraceQuaternionTolerance = 1e-6;

// A trace that cannot be read: what() is "path:line: column c (name): what is wrong", e.g.
//   trace.csv:17: column 3 (tip_y_m): 'abc' is not a number
// ("path:line: ..." when the problem is not in one column, "path: ..." when not on one line).
class TraceError : public std::runtime_error {
 public:
  TraceError(const std::string& message, std::filesystem::path path, std::size_t line, int column)
      : std::runtime_error(message), path_(std::move(path)), line_(line), column_(column) {}

  const std::filesystem::path& path() const { return path_; }
  // 1-based line in the file (the header is line 1); 0 when the error is about the whole file.
  std::size_t line() const { return line_; }
  // 1-based column (field index, see the table above); 0 when the error is not about one column.
  int column() const { return column_; }

 private:
  std::filesystem::path path_;
  std::size_t line_;
  int column_;
};

// Reads a trace file lazily, one line per sample. The constructor opens the file and reads the header
// and the comment lines right after it; next() reads and checks one sample line.
// Cost: O(line length) per next(); memory O(longest line). Threads: one thread at a time (see PoseSource).
// Failure: every problem throws TraceError with path, line and column:
//   - the file cannot be opened or read, is empty, or its header line has no '\n';
//   - the header is not exactly kTraceHeader (the message names missing, unknown, duplicate or
//     misplaced columns);
//   - a line has the wrong number of fields, is empty, or has a field that is not a number, NaN or
//     infinite, out of double range, buttons not an integer in [0, 2^32 - 1], pressure outside [0, 1];
//   - time_s does not strictly increase (the message names both times and the earlier line);
//   - the quaternion's norm is off 1 by more than kTraceQuaternionTolerance (it is not normalised
//     silently: a bad recording should be fixed where it was made).
// After a TraceError the reader stands at the following line; callers normally stop there.
// A final line without '\n' ends the trace without an error: next() returns std::nullopt and
// truncatedTail() becomes true.
class TraceReader final : public PoseSource {
 public:
  explicit TraceReader(std::filesystem::path path);

  std::optional<PoseSample> next() override;
  // "trace 'path' (line N)", N the last line read.
  std::string describe() const override;

  // True once the reader has met a final line without '\n' (a writer killed mid-write, or an editor
  // that dropped the last newline: that line is not read either way). Meaningful after next() has
  // returned std::nullopt.
  bool truncatedTail() const { return truncated_tail_; }
  // The comment lines between the header and the first sample, without the '#' and one space after
  // it, in order.
  const std::vector<std::string>& comments() const { return comments_; }
  const std::filesystem::path& path() const { return path_; }

  // All samples of the trace at `path`. Same failures as next(); a truncated tail is dropped silently
  // (use a TraceReader to learn about it). Cost O(file size).
  static std::vector<PoseSample> readAll(const std::filesystem::path& path);

 private:
  // One line without its '\n' (and '\r'); false at the end of the file or at a final line without
  // '\n' (then truncated_tail_ is set).
  bool readLine(std::string& line);
  void checkHeader(std::string_view header) const;
  PoseSample parseSample(std::string_view line) const;
  [[noreturn]] void fail(int column, const std::string& what) const;

  std::filesystem::path path_;
  std::ifstream in_;
  std::size_t line_ = 0;
  bool truncated_tail_ = false;
  bool at_end_ = false;
  std::optional<PoseSample> previous_;
  std::size_t previous_line_ = 0;
  std::vector<std::string> comments_;
  std::string buffer_;
};

struct TraceWriterOptions {
  // Samples buffered in memory before they are handed to the OS with one write(2). 1 = every sample.
  // Must be >= 1.
  std::size_t flush_every = 50;
  // fsync(2) the file in close() and in the destructor: survives power loss and OS crashes too, at a
  // cost of milliseconds. The crash guarantee below does not need it.
  bool fsync_on_close = false;
  // Comment lines written right after the header as "# <text>" ("#" for an empty one): provenance
  // (generator, device, date). No '\n' or '\r' inside. TraceReader::comments() returns them as given.
  std::vector<std::string> comments;
};

// Records samples to a trace file in the format above.
//
// Crash guarantee. The constructor writes the header and the comments with write(2) before it returns.
// The file appears at its path only then, header complete (written to path + ".tmp", renamed onto the
// path; a previous file there stays whole until the rename; a kill before it leaves only the .tmp).
// Samples are buffered in this process's memory and handed to the kernel with write(2) (no stdio or
// iostream buffer in between) when the buffer holds options.flush_every samples, on flush(), close()
// and in the destructor. Once one of these calls has returned, its samples are in the kernel's page
// cache: if the process then dies in any way (SIGKILL, abort, a crash, _exit) the file holds the header,
// the comments and every such sample, and TraceReader reads them back bit-exactly without an error.
// Samples still buffered are lost whole. A process killed *during* a write(2) may leave part of that
// write: complete lines, which read back as samples, and at most one cut last line, which TraceReader
// drops (truncatedTail()). samplesFlushed() says how many samples are covered by the guarantee.
// Power loss and OS crashes are covered only for data that was fsync'ed (sync(), or fsync_on_close).
//
// Cost: O(1) amortised per write(); one write(2) system call per flush_every samples.
// Threads: one thread at a time (the recorder's); write() may block on the disk during a flush, so keep
// it off the sim thread.
// Failure: the constructor throws std::invalid_argument (flush_every == 0, a comment with a newline) or
// std::system_error (the file cannot be created or written). write() throws std::invalid_argument,
// writing nothing, for a sample the reader would reject: NaN or infinite values, time_s not after the
// previous sample's, a quaternion off unit length by more than kTraceQuaternionTolerance, pressure outside
// [0, 1]; std::logic_error after close(); std::system_error when a flush fails (the sample is then
// accepted, and the unwritten bytes stay buffered for the next flush to retry).
class TraceWriter {
 public:
  // Creates or truncates `path` (mode 0644 before umask).
  explicit TraceWriter(std::filesystem::path path, TraceWriterOptions options = {});
  // Flushes, fsyncs if asked and closes; errors are swallowed here (call close() to see them).
  ~TraceWriter();
  TraceWriter(TraceWriter&& other) noexcept;
  TraceWriter& operator=(TraceWriter&& other) noexcept;
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  // Appends one sample line; flushes when flush_every samples are buffered.
  void write(const PoseSample& sample);
  // Hands every buffered sample to the kernel (write(2)). No-op when nothing is buffered.
  void flush();
  // flush() then fsync(2): the samples so far survive power loss too.
  void sync();
  // flush(), fsync if options.fsync_on_close, close(2). Further write() calls throw std::logic_error;
  // close() again does nothing.
  void close();

  // Samples accepted by write().
  std::size_t samplesWritten() const;
  // Samples handed to the kernel: what a kill at this moment leaves in the file.
  std::size_t samplesFlushed() const;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  TraceWriterOptions options_;
  std::unique_ptr<detail::RecordStream> stream_;  // null once moved from
  std::optional<double> previous_time_s_;
};

}  // namespace incise::devices
