#include "incise/devices/trace_csv.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <system_error>
#include <utility>

#include "message_text.h"
#include "record_stream.h"

namespace incise::devices {
namespace {

using detail::quoteField;
using detail::shortest;

constexpr int kColumnCount = static_cast<int>(kTraceColumns.size());
constexpr int kTimeColumn = 1;
constexpr int kTipColumn = 2;
constexpr int kQuaternionColumn = 5;
constexpr int kButtonsColumn = 9;
constexpr int kPressureColumn = 10;

// "%.17g" without the locale: what the file holds.
void appendExact(std::string& out, double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::general, 17);
  out.append(text, result.ptr);
}

std::string columnLabel(int column) {
  std::string label = "column " + std::to_string(column);
  if (column >= 1 && column <= kColumnCount) label += " (" + std::string(kTraceColumns[column - 1]) + ")";
  return label;
}

std::vector<std::string_view> splitCommaFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

// The checks the reader and the writer share, on a sample whose numbers are already parsed. The
// same arithmetic on the same bits in both places: whatever the writer accepts, the reader accepts.
struct Problem {
  int column;
  std::string message;
};

double quaternionNorm(const Eigen::Quaterniond& q) {
  return std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
}

std::optional<Problem> checkSample(const PoseSample& sample, const std::optional<double>& previous_time_s,
                                   std::size_t previous_line) {
  const std::array<double, 8> values = {sample.time_s,          sample.tip_m.x(),       sample.tip_m.y(),
                                        sample.tip_m.z(),       sample.orientation.w(), sample.orientation.x(),
                                        sample.orientation.y(), sample.orientation.z()};
  for (int i = 0; i < 8; ++i)
    if (!std::isfinite(values[static_cast<std::size_t>(i)]))
      return Problem{i + 1, shortest(values[static_cast<std::size_t>(i)]) + " is not finite"};
  if (sample.pressure && !std::isfinite(*sample.pressure))
    return Problem{kPressureColumn, shortest(*sample.pressure) + " is not finite"};

  if (previous_time_s && !(sample.time_s > *previous_time_s)) {
    const std::string where = previous_line > 0 ? " on line " + std::to_string(previous_line) : "";
    const char* what = sample.time_s == *previous_time_s ? "time stands still" : "time goes back";
    return Problem{kTimeColumn, std::string(what) + " (" + shortest(sample.time_s) + " s after " +
                                    shortest(*previous_time_s) + " s" + where + "); time_s must strictly increase"};
  }

  const double norm = quaternionNorm(sample.orientation);
  if (!(std::abs(norm - 1.0) <= kTraceQuaternionTolerance)) {
    const Eigen::Quaterniond& q = sample.orientation;
    return Problem{kQuaternionColumn, "quaternion (" + shortest(q.w()) + ", " + shortest(q.x()) + ", " +
                                          shortest(q.y()) + ", " + shortest(q.z()) + ") has norm " + shortest(norm) +
                                          ", not 1 within " + shortest(kTraceQuaternionTolerance)};
  }

  if (sample.pressure && !(*sample.pressure >= 0.0 && *sample.pressure <= 1.0))
    return Problem{kPressureColumn, shortest(*sample.pressure) + " is outside [0, 1]"};
  return std::nullopt;
}

std::string problemLabel(const Problem& problem) {
  if (problem.column == kQuaternionColumn) return "columns 5-8 (q_w..q_z)";
  return columnLabel(problem.column);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// TraceReader

TraceReader::TraceReader(std::filesystem::path path) : path_(std::move(path)) {
  in_.open(path_, std::ios::binary);
  if (!in_) {
    const int error = errno;
    throw TraceError(path_.string() + ": cannot open (" + std::generic_category().message(error) + ")", path_, 0, 0);
  }
  std::string header;
  if (!std::getline(in_, header)) {
    if (in_.bad()) throw TraceError(path_.string() + ": read error", path_, 0, 0);
    line_ = 1;
    fail(0, "empty file; expected the header '" + std::string(kTraceHeader) + "'");
  }
  line_ = 1;
  if (in_.eof()) fail(0, "the header line is incomplete (no end of line)");
  if (!header.empty() && header.back() == '\r') header.pop_back();
  if (header.starts_with("\xEF\xBB\xBF")) header.erase(0, 3);
  checkHeader(header);

  // Provenance: the comment block right after the header.
  while (in_.peek() == '#') {
    std::string comment;
    if (!readLine(comment)) return;
    std::string_view text = std::string_view(comment).substr(1);
    if (text.starts_with(' ')) text.remove_prefix(1);
    comments_.emplace_back(text);
  }
}

void TraceReader::checkHeader(std::string_view header) const {
  if (header == kTraceHeader) return;
  const std::vector<std::string_view> names = splitCommaFields(header);
  std::string problems;
  int first_column = 0;
  auto add = [&](int column, const std::string& text) {
    if (first_column == 0) first_column = column;
    problems += problems.empty() ? text : "; " + text;
  };

  std::array<int, kTraceColumns.size()> seen_at{};
  for (int c = 1; c <= static_cast<int>(names.size()); ++c) {
    const std::string_view name = names[static_cast<std::size_t>(c - 1)];
    int known = 0;
    for (int k = 1; k <= kColumnCount; ++k)
      if (kTraceColumns[static_cast<std::size_t>(k - 1)] == name) known = k;
    const std::string label = "column " + std::to_string(c) + " " + quoteField(name);
    if (known == 0) {
      add(c, label + " is unknown");
    } else if (seen_at[static_cast<std::size_t>(known - 1)] != 0) {
      add(c, label + " repeats column " + std::to_string(seen_at[static_cast<std::size_t>(known - 1)]));
    } else {
      seen_at[static_cast<std::size_t>(known - 1)] = c;
    }
  }
  std::string missing;
  for (int k = 1; k <= kColumnCount; ++k)
    if (seen_at[static_cast<std::size_t>(k - 1)] == 0)
      missing += (missing.empty() ? "" : ", ") + std::string(kTraceColumns[static_cast<std::size_t>(k - 1)]);
  if (!missing.empty()) add(0, "missing column(s) " + missing);
  if (problems.empty()) {
    // Every name once, none unknown: the order is wrong.
    for (int c = 1; c <= kColumnCount; ++c)
      if (names[static_cast<std::size_t>(c - 1)] != kTraceColumns[static_cast<std::size_t>(c - 1)]) {
        add(c, "column " + std::to_string(c) + " is " + quoteField(names[static_cast<std::size_t>(c - 1)]) +
                   ", expected '" + std::string(kTraceColumns[static_cast<std::size_t>(c - 1)]) + "'");
        break;
      }
  }
  throw TraceError(
      path_.string() + ":1: bad header: " + problems + "; expected exactly '" + std::string(kTraceHeader) + "'", path_,
      1, first_column);
}

bool TraceReader::readLine(std::string& line) {
  if (at_end_) return false;
  if (!std::getline(in_, line)) {
    if (in_.bad())
      throw TraceError(path_.string() + ": read error after line " + std::to_string(line_), path_, line_, 0);
    at_end_ = true;
    return false;
  }
  if (in_.eof()) {
    // getline stopped at the end of the file, not at a '\n': the tail a killed writer leaves.
    at_end_ = true;
    truncated_tail_ = true;
    return false;
  }
  ++line_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

std::optional<PoseSample> TraceReader::next() {
  while (readLine(buffer_)) {
    if (buffer_.empty()) fail(0, "empty line; expected a sample of 10 fields or a '#' comment");
    if (buffer_.front() == '#') continue;
    PoseSample sample = parseSample(buffer_);
    previous_ = sample;
    previous_line_ = line_;
    return sample;
  }
  return std::nullopt;
}

PoseSample TraceReader::parseSample(std::string_view line) const {
  const std::vector<std::string_view> fields = splitCommaFields(line);
  const int count = static_cast<int>(fields.size());
  if (count < kColumnCount)
    fail(count + 1,
         "missing (the line has " + std::to_string(count) + " fields, expected " + std::to_string(kColumnCount) + ")");
  if (count > kColumnCount)
    fail(kColumnCount + 1, "unexpected field " + quoteField(fields[kColumnCount]) + " (the line has " +
                               std::to_string(count) + " fields, expected " + std::to_string(kColumnCount) + ")");

  auto number = [&](int column) {
    const std::string_view field = fields[static_cast<std::size_t>(column - 1)];
    if (field.empty()) fail(column, "empty; expected a number");
    double value = 0.0;
    const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
    if (result.ec == std::errc::result_out_of_range) fail(column, quoteField(field) + " is out of range for a double");
    if (result.ec != std::errc() || result.ptr != field.data() + field.size())
      fail(column, quoteField(field) + " is not a number");
    if (!std::isfinite(value)) fail(column, quoteField(field) + " is not finite");
    return value;
  };

  PoseSample sample;
  sample.time_s = number(kTimeColumn);
  for (int i = 0; i < 3; ++i) sample.tip_m[i] = number(kTipColumn + i);
  const double w = number(kQuaternionColumn), x = number(kQuaternionColumn + 1), y = number(kQuaternionColumn + 2),
               z = number(kQuaternionColumn + 3);
  sample.orientation = Eigen::Quaterniond(w, x, y, z);

  const std::string_view buttons = fields[kButtonsColumn - 1];
  const auto parsed = std::from_chars(buttons.data(), buttons.data() + buttons.size(), sample.buttons);
  if (buttons.empty() || parsed.ec != std::errc() || parsed.ptr != buttons.data() + buttons.size())
    fail(kButtonsColumn, quoteField(buttons) + " is not a button mask (an integer in 0..4294967295)");

  if (!fields[kPressureColumn - 1].empty()) sample.pressure = number(kPressureColumn);

  if (const auto problem =
          checkSample(sample, previous_ ? std::optional(previous_->time_s) : std::nullopt, previous_line_)) {
    throw TraceError(
        path_.string() + ":" + std::to_string(line_) + ": " + problemLabel(*problem) + ": " + problem->message, path_,
        line_, problem->column);
  }
  return sample;
}

void TraceReader::fail(int column, const std::string& what) const {
  std::string message = path_.string() + ":" + std::to_string(line_) + ": ";
  if (column > 0) message += columnLabel(column) + ": ";
  throw TraceError(message + what, path_, line_, column);
}

std::string TraceReader::describe() const {
  return "trace '" + path_.string() + "' (line " + std::to_string(line_) + ")";
}

std::vector<PoseSample> TraceReader::readAll(const std::filesystem::path& path) {
  TraceReader reader(path);
  std::vector<PoseSample> samples;
  while (auto sample = reader.next()) samples.push_back(*sample);
  return samples;
}

// ---------------------------------------------------------------------------------------------------
// TraceWriter

TraceWriter::TraceWriter(std::filesystem::path path, TraceWriterOptions options)
    : path_(std::move(path)), options_(std::move(options)) {
  if (options_.flush_every == 0) throw std::invalid_argument("TraceWriter: flush_every must be >= 1");
  for (const std::string& comment : options_.comments)
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw std::invalid_argument("TraceWriter: a comment line contains a newline: " + quoteField(comment));

  // Roughly 200 bytes a line; one allocation for the whole run.
  stream_ = std::make_unique<detail::RecordStream>(path_, "TraceWriter", options_.flush_every, options_.fsync_on_close,
                                                   options_.flush_every * 200 + 256);
  std::string header(kTraceHeader);
  header.push_back('\n');
  for (const std::string& comment : options_.comments)
    header.append(comment.empty() ? "#" : "# ").append(comment).push_back('\n');
  stream_->writeHeader(header);
}

TraceWriter::~TraceWriter() = default;  // the stream flushes and closes, swallowing errors
TraceWriter::TraceWriter(TraceWriter&& other) noexcept = default;
TraceWriter& TraceWriter::operator=(TraceWriter&& other) noexcept = default;

std::size_t TraceWriter::samplesWritten() const { return stream_ ? stream_->recordsWritten() : 0; }
std::size_t TraceWriter::samplesFlushed() const { return stream_ ? stream_->recordsFlushed() : 0; }

void TraceWriter::write(const PoseSample& sample) {
  if (!stream_ || !stream_->isOpen())
    throw std::logic_error("TraceWriter '" + path_.string() + "': write() after close()");
  if (const auto problem = checkSample(sample, previous_time_s_, 0))
    throw std::invalid_argument("TraceWriter '" + path_.string() + "': sample " +
                                std::to_string(stream_->recordsWritten() + 1) + ": " + problemLabel(*problem) + ": " +
                                problem->message);

  std::string& out = stream_->buffer();
  appendExact(out, sample.time_s);
  for (int i = 0; i < 3; ++i) appendExact(out.append(","), sample.tip_m[i]);
  const Eigen::Quaterniond& q = sample.orientation;
  for (const double c : {q.w(), q.x(), q.y(), q.z()}) appendExact(out.append(","), c);
  char text[16];
  const auto result = std::to_chars(text, text + sizeof text, sample.buttons);
  out.append(",").append(text, result.ptr).append(",");
  if (sample.pressure) appendExact(out, *sample.pressure);
  out.push_back('\n');

  previous_time_s_ = sample.time_s;
  stream_->recordAdded();
}

void TraceWriter::flush() {
  if (stream_) stream_->flush();
}

void TraceWriter::sync() {
  if (stream_) stream_->sync();
}

void TraceWriter::close() {
  if (stream_) stream_->close();
}

}  // namespace incise::devices
