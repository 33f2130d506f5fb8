#include "incise/devices/trace_csv.h"

#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <catch2/catch.hpp>

#include "trace_fixture.h"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using incise::devices::kTraceHeader;
using incise::devices::PoseSample;
using incise::devices::TraceError;
using incise::devices::TraceReader;
using incise::devices::TraceWriter;
using incise::devices::TraceWriterOptions;
using incise::devices::testing::bitExact;
using incise::devices::testing::Pressure;
using incise::devices::testing::randomSamples;
using incise::devices::testing::readText;
using incise::devices::testing::TempPath;
using incise::devices::testing::writeText;

namespace {

// (Designated initializers would be shorter, but GCC 12 -Wextra warns about every field left out.)
TraceWriterOptions flushEvery(std::size_t samples) {
  TraceWriterOptions options;
  options.flush_every = samples;
  return options;
}

TraceWriterOptions withComments(std::vector<std::string> comments) {
  TraceWriterOptions options;
  options.comments = std::move(comments);
  return options;
}

const std::string kHeaderLine = "time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure\n";

// A valid sample line at time t.
std::string goodLine(double t) {
  char text[96];
  std::snprintf(text, sizeof text, "%.17g,0.01,0.02,0.03,1,0,0,0,1,0.5\n", t);
  return text;
}

// Reads the whole trace `text`; returns the TraceError it must raise.
TraceError errorFor(const TempPath& file, const std::string& text) {
  writeText(file.path(), text);
  try {
    TraceReader::readAll(file.path());
  } catch (const TraceError& error) {
    return error;
  }
  FAIL("no TraceError for:\n" << text);
  throw std::logic_error("unreachable");
}

// The error's message must be exactly "path" + suffix, at `line` and `column`.
void requireError(const std::string& text, const std::string& suffix, std::size_t line, int column) {
  TempPath file("bad");
  const TraceError error = errorFor(file, text);
  CHECK(std::string(error.what()) == file.string() + suffix);
  CHECK(error.line() == line);
  CHECK(error.column() == column);
  CHECK(error.path() == file.path());
}

std::vector<PoseSample> writeAndRead(const std::vector<PoseSample>& samples, const TraceWriterOptions& options = {}) {
  TempPath file("roundtrip");
  {
    TraceWriter writer(file.path(), options);
    for (const PoseSample& s : samples) writer.write(s);
  }
  TraceReader reader(file.path());
  std::vector<PoseSample> read;
  while (auto s = reader.next()) read.push_back(*s);
  CHECK_FALSE(reader.truncatedTail());
  return read;
}

void requireBitExact(const std::vector<PoseSample>& got, const std::vector<PoseSample>& expected) {
  REQUIRE(got.size() == expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    INFO("sample " << i);
    REQUIRE(bitExact(got[i], expected[i]));
    REQUIRE(got[i] == expected[i]);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Format and round trip

TEST_CASE("trace_csv: the header is the documented one, comments follow it as '# ' lines", "[devices]") {
  CHECK(std::string(kTraceHeader) + "\n" == kHeaderLine);
  TempPath file("header");
  { TraceWriter writer(file.path(), withComments({"generator: incise tests", "", "seed: 7"})); }
  CHECK(readText(file.path()) == kHeaderLine + "# generator: incise tests\n#\n# seed: 7\n");
  TraceReader reader(file.path());
  CHECK(reader.comments() == std::vector<std::string>{"generator: incise tests", "", "seed: 7"});
  CHECK_FALSE(reader.next());
  CHECK_FALSE(reader.truncatedTail());
}

TEST_CASE("trace_csv: numbers are written as %.17g, pressure empty when absent", "[devices]") {
  TempPath file("exact");
  {
    TraceWriter writer(file.path());
    writer.write({.time_s = 0.5,
                  .tip_m = {0.1, -0.0, 5e-324},
                  .orientation = Eigen::Quaterniond(1, 0, 0, 0),
                  .buttons = 4294967295u,
                  .pressure = std::nullopt});
    writer.write({.time_s = 1e300,
                  .tip_m = {1.0 / 3.0, 123456789.0, -2.5e-7},
                  .orientation = Eigen::Quaterniond(0, 0, -1, 0),
                  .buttons = 0,
                  .pressure = 0.25});
  }
  CHECK(readText(file.path()) == kHeaderLine +
                                     "0.5,0.10000000000000001,-0,4.9406564584124654e-324,1,0,0,0,4294967295,\n"
                                     "1.0000000000000001e+300,0.33333333333333331,123456789,-2.4999999999999999e-07,"
                                     "0,0,-1,0,0,0.25\n");
}

TEST_CASE("trace_csv: 1000 random samples with pressure read back bit-exactly", "[devices]") {
  const auto samples = randomSamples(1, 1000, Pressure::Always);
  requireBitExact(writeAndRead(samples), samples);
}

TEST_CASE("trace_csv: 1000 random samples without pressure read back bit-exactly", "[devices]") {
  const auto samples = randomSamples(2, 1000, Pressure::Never);
  requireBitExact(writeAndRead(samples), samples);
}

TEST_CASE("trace_csv: samples with and without pressure mixed read back bit-exactly, whatever flush_every",
          "[devices]") {
  const auto samples = randomSamples(3, 1000, Pressure::Sometimes);
  for (const std::size_t flush_every : {std::size_t{1}, std::size_t{7}, std::size_t{50}, std::size_t{5000}}) {
    INFO("flush_every " << flush_every);
    requireBitExact(writeAndRead(samples, flushEvery(flush_every)), samples);
  }
}

TEST_CASE("trace_csv: readAll returns what next() returns", "[devices]") {
  const auto samples = randomSamples(4, 100, Pressure::Sometimes);
  TempPath file("readall");
  {
    TraceWriter writer(file.path());
    for (const PoseSample& s : samples) writer.write(s);
  }
  requireBitExact(TraceReader::readAll(file.path()), samples);
}

TEST_CASE("trace_csv: the example in TRACE_FORMAT.md reads", "[devices]") {
  const std::string doc = readText(std::filesystem::path(INCISE_DEVICES_DIR) / "TRACE_FORMAT.md");
  const std::size_t begin = doc.find("```\ntime_s");
  REQUIRE(begin != std::string::npos);
  const std::size_t end = doc.find("```", begin + 3);
  TempPath file("doc");
  writeText(file.path(), doc.substr(begin + 4, end - begin - 4));
  TraceReader reader(file.path());
  CHECK(reader.comments().size() == 2);
  const auto first = reader.next();
  const auto second = reader.next();
  REQUIRE(first);
  REQUIRE(second);
  CHECK_FALSE(first->pressure);
  CHECK(second->pressure == 0.25);
  CHECK(second->buttons == 1);
  CHECK_FALSE(reader.next());
  CHECK_FALSE(reader.truncatedTail());
}

TEST_CASE("trace_csv: comments after the first sample are skipped and lines still count", "[devices]") {
  TempPath file("comments");
  writeText(file.path(), kHeaderLine + "# a\n" + goodLine(0.1) + "# device reconnected\n" + goodLine(0.2) + "abc\n");
  TraceReader reader(file.path());
  CHECK(reader.comments() == std::vector<std::string>{"a"});
  CHECK(reader.next());
  CHECK(reader.next());
  CHECK_THROWS_WITH(reader.next(), StartsWith(file.string() + ":6: column 2 (tip_x_m)"));
}

TEST_CASE("trace_csv: CRLF line ends and a byte-order mark read like plain LF", "[devices]") {
  TempPath file("crlf");
  writeText(file.path(), std::string("\xEF\xBB\xBF") + std::string(kTraceHeader) +
                             std::string("\r\n# c\r\n0.1,1,2,3,1,0,0,0,2,\r\n") + "0.2,1,2,3,1,0,0,0,2,0.5\r\n");
  TraceReader reader(file.path());
  CHECK(reader.comments() == std::vector<std::string>{"c"});
  const auto a = reader.next();
  const auto b = reader.next();
  REQUIRE(a);
  REQUIRE(b);
  CHECK_FALSE(a->pressure);
  CHECK(b->pressure == 0.5);
  CHECK_FALSE(reader.next());
}

TEST_CASE("trace_csv: exponents, integers and a unit quaternion within 1e-6 are accepted", "[devices]") {
  TempPath file("lenient");
  writeText(file.path(), kHeaderLine + "1e-3,-2E2,0,.5,1.0000005,0,0,0,007,1\n");
  const auto samples = TraceReader::readAll(file.path());
  REQUIRE(samples.size() == 1);
  CHECK(samples[0].time_s == 1e-3);
  CHECK(samples[0].tip_m == Eigen::Vector3d(-200, 0, 0.5));
  CHECK(samples[0].buttons == 7);
  CHECK(samples[0].pressure == 1.0);
}

TEST_CASE("trace_csv: describe() names the file and the line", "[devices]") {
  TempPath file("describe");
  writeText(file.path(), kHeaderLine + goodLine(1));
  TraceReader reader(file.path());
  reader.next();
  CHECK(reader.describe() == "trace '" + file.string() + "' (line 2)");
}

// ---------------------------------------------------------------------------------------------------
// Bad input: every error says where

TEST_CASE("trace_csv: a NaN value is an error at its line and column", "[devices]") {
  requireError(kHeaderLine + "# generator: test\n" + goodLine(0.25) + "0.5,nan,0.2,0.3,1,0,0,0,0,\n",
               ":4: column 2 (tip_x_m): 'nan' is not finite", 4, 2);
}

TEST_CASE("trace_csv: an infinite value is an error at its line and column", "[devices]") {
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0,0,0,0,-inf\n", ":2: column 10 (pressure): '-inf' is not finite", 2,
               10);
}

TEST_CASE("trace_csv: a non-numeric value is an error at its line and column", "[devices]") {
  std::string text = kHeaderLine;
  for (int i = 0; i < 15; ++i) text += goodLine(0.001 * (i + 1));
  text += "0.5,0.1,abc,0.3,1,0,0,0,0,\n";
  requireError(text, ":17: column 3 (tip_y_m): 'abc' is not a number", 17, 3);
}

TEST_CASE("trace_csv: trailing garbage, spaces and a '+' make a value not a number", "[devices]") {
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3x,1,0,0,0,0,\n", ":2: column 4 (tip_z_m): '0.3x' is not a number", 2, 4);
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1, 0,0,0,0,\n", ":2: column 6 (q_x): ' 0' is not a number", 2, 6);
  requireError(kHeaderLine + "+0.5,0.1,0.2,0.3,1,0,0,0,0,\n", ":2: column 1 (time_s): '+0.5' is not a number", 2, 1);
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0,0,0,0,0,5\n",
               ":2: column 11: unexpected field '5' (the line has 11 fields, expected 10)", 2, 11);
}

TEST_CASE("trace_csv: an empty number field is an error at its line and column", "[devices]") {
  requireError(kHeaderLine + "0.5,0.1,0.2,,1,0,0,0,0,\n", ":2: column 4 (tip_z_m): empty; expected a number", 2, 4);
}

TEST_CASE("trace_csv: a value beyond double range is an error at its line and column", "[devices]") {
  requireError(kHeaderLine + "0.5,1e999,0.2,0.3,1,0,0,0,0,\n",
               ":2: column 2 (tip_x_m): '1e999' is out of range for a double", 2, 2);
}

TEST_CASE("trace_csv: a header missing a column is an error naming it", "[devices]") {
  const std::string expected = "; expected exactly '" + std::string(kTraceHeader) + "'";
  requireError("time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons\n",
               ":1: bad header: missing column(s) pressure" + expected, 1, 0);
  requireError("time_s,tip_x_m,tip_z_m,q_w,q_x,q_y,buttons,pressure\n",
               ":1: bad header: missing column(s) tip_y_m, q_z" + expected, 1, 0);
}

TEST_CASE("trace_csv: a header with an unknown, renamed or repeated column is an error naming it", "[devices]") {
  const std::string expected = "; expected exactly '" + std::string(kTraceHeader) + "'";
  requireError(std::string(kTraceHeader) + ",force_N\n", ":1: bad header: column 11 'force_N' is unknown" + expected, 1,
               11);
  requireError("time_s,tip_x,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure\n",
               ":1: bad header: column 2 'tip_x' is unknown; missing column(s) tip_x_m" + expected, 1, 2);
  requireError(std::string(kTraceHeader) + ",q_w\n", ":1: bad header: column 11 'q_w' repeats column 5" + expected, 1,
               11);
}

TEST_CASE("trace_csv: a header with the columns out of order is an error naming the first", "[devices]") {
  requireError(
      "time_s,tip_y_m,tip_x_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure\n",
      ":1: bad header: column 2 is 'tip_y_m', expected 'tip_x_m'; expected exactly '" + std::string(kTraceHeader) + "'",
      1, 2);
}

TEST_CASE("trace_csv: an empty file, a header without end of line and a missing file are errors", "[devices]") {
  requireError("", ":1: empty file; expected the header '" + std::string(kTraceHeader) + "'", 1, 0);
  requireError(std::string(kTraceHeader), ":1: the header line is incomplete (no end of line)", 1, 0);
  TempPath missing("missing");
  CHECK_THROWS_MATCHES(TraceReader(missing.path()), TraceError,
                       Catch::Matchers::Message(missing.string() + ": cannot open (No such file or directory)"));
}

TEST_CASE("trace_csv: a line with too few or too many fields is an error at the first wrong column", "[devices]") {
  requireError(kHeaderLine + goodLine(0.1) + "0.5,0.1,0.2,0.3,1,0,0,0,0\n",
               ":3: column 10 (pressure): missing (the line has 9 fields, expected 10)", 3, 10);
  requireError(kHeaderLine + "0.5,0.1,0.2\n", ":2: column 4 (tip_z_m): missing (the line has 3 fields, expected 10)", 2,
               4);
  requireError(kHeaderLine + goodLine(0.1) + "\n" + goodLine(0.2),
               ":3: empty line; expected a sample of 10 fields or a '#' comment", 3, 0);
}

TEST_CASE("trace_csv: time going back is an error naming both times", "[devices]") {
  requireError(kHeaderLine + goodLine(0.75) + goodLine(0.5),
               ":3: column 1 (time_s): time goes back (0.5 s after 0.75 s on line 2); time_s must strictly increase", 3,
               1);
}

TEST_CASE("trace_csv: time standing still is an error naming both times", "[devices]") {
  requireError(kHeaderLine + goodLine(0.5) + "# same time again\n" + goodLine(0.5),
               ":4: column 1 (time_s): time stands still (0.5 s after 0.5 s on line 2); time_s must strictly "
               "increase",
               4, 1);
}

TEST_CASE("trace_csv: a quaternion off unit length by more than 1e-6 is an error", "[devices]") {
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0.1,0,0,0,\n",
               ":2: columns 5-8 (q_w..q_z): quaternion (1, 0.1, 0, 0) has norm 1.004987562112089, not 1 within 1e-06",
               2, 5);
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,0.999998,0,0,0,0,\n",
               ":2: columns 5-8 (q_w..q_z): quaternion (0.999998, 0, 0, 0) has norm 0.999998, not 1 within 1e-06", 2,
               5);
}

TEST_CASE("trace_csv: buttons that are not a 32-bit non-negative integer are an error", "[devices]") {
  for (const std::string bad : {"-1", "1.5", "4294967296", "0x3", "", "one"}) {
    INFO("buttons '" << bad << "'");
    requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0,0,0," + bad + ",\n",
                 ":2: column 9 (buttons): '" + bad + "' is not a button mask (an integer in 0..4294967295)", 2, 9);
  }
}

TEST_CASE("trace_csv: pressure outside [0, 1] is an error", "[devices]") {
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0,0,0,0,1.5\n", ":2: column 10 (pressure): 1.5 is outside [0, 1]", 2,
               10);
  requireError(kHeaderLine + "0.5,0.1,0.2,0.3,1,0,0,0,0,-0.25\n", ":2: column 10 (pressure): -0.25 is outside [0, 1]",
               2, 10);
}

// ---------------------------------------------------------------------------------------------------
// The truncated tail a killed writer leaves

TEST_CASE("trace_csv: a truncated last line ends the trace and everything before it reads back", "[devices]") {
  const auto samples = randomSamples(5, 20, Pressure::Sometimes);
  TempPath file("tail");
  {
    TraceWriter writer(file.path(), withComments({"tail test"}));
    for (const PoseSample& s : samples) writer.write(s);
  }
  const std::string whole = readText(file.path());
  const std::size_t last_line = whole.rfind('\n', whole.size() - 2) + 1;
  // Every cut inside the last line: fewer fields, a cut number, a complete-looking line without '\n'.
  for (std::size_t cut = last_line + 1; cut < whole.size(); ++cut) {
    INFO("file cut to " << cut << " of " << whole.size() << " bytes");
    writeText(file.path(), whole.substr(0, cut));
    TraceReader reader(file.path());
    std::vector<PoseSample> read;
    while (auto s = reader.next()) read.push_back(*s);
    CHECK(reader.truncatedTail());
    requireBitExact(read, std::vector<PoseSample>(samples.begin(), samples.end() - 1));
    CHECK_FALSE(reader.next());
  }
  writeText(file.path(), whole);
  TraceReader reader(file.path());
  while (reader.next()) {
  }
  CHECK_FALSE(reader.truncatedTail());
}

TEST_CASE("trace_csv: a truncated tail is not checked, even when it is garbage", "[devices]") {
  TempPath file("garbage");
  writeText(file.path(), kHeaderLine + goodLine(0.5) + "0.25,nan,abc");
  TraceReader reader(file.path());
  CHECK(reader.next());
  CHECK_FALSE(reader.next());
  CHECK(reader.truncatedTail());
  CHECK(TraceReader::readAll(file.path()).size() == 1);
}

TEST_CASE("trace_csv: a trace cut inside the comments has no samples and a truncated tail", "[devices]") {
  TempPath file("cutcomment");
  writeText(file.path(), kHeaderLine + "# generator: inc");
  TraceReader reader(file.path());
  CHECK(reader.comments().empty());
  CHECK_FALSE(reader.next());
  CHECK(reader.truncatedTail());
}

// ---------------------------------------------------------------------------------------------------
// The writer

TEST_CASE("trace_csv: the writer rejects a sample the reader would reject and writes nothing", "[devices]") {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  TempPath file("reject");
  TraceWriter writer(file.path(), flushEvery(1));
  PoseSample good;
  good.time_s = 1.0;
  good.tip_m = {0.1, 0.2, 0.3};
  writer.write(good);
  const std::string before = readText(file.path());

  auto rejected = [&](PoseSample s, const std::string& what) {
    CHECK_THROWS_MATCHES(writer.write(s), std::invalid_argument,
                         Catch::Matchers::Message("TraceWriter '" + file.string() + "': sample 2: " + what));
  };
  PoseSample s = good;
  s.time_s = 2.0;
  s.tip_m.y() = kNaN;
  rejected(s, "column 3 (tip_y_m): nan is not finite");
  s = good;
  s.time_s = kInf;
  rejected(s, "column 1 (time_s): inf is not finite");
  s = good;
  s.time_s = 2.0;
  s.orientation.x() = kNaN;
  rejected(s, "column 6 (q_x): nan is not finite");
  s = good;
  s.time_s = 2.0;
  s.pressure = kNaN;
  rejected(s, "column 10 (pressure): nan is not finite");
  s = good;
  rejected(s, "column 1 (time_s): time stands still (1 s after 1 s); time_s must strictly increase");
  s.time_s = 0.5;
  rejected(s, "column 1 (time_s): time goes back (0.5 s after 1 s); time_s must strictly increase");
  s = good;
  s.time_s = 2.0;
  s.orientation = Eigen::Quaterniond(1, 0, 0, 0.01);
  rejected(s, "columns 5-8 (q_w..q_z): quaternion (1, 0, 0, 0.01) has norm 1.0000499987500624, not 1 within 1e-06");
  s = good;
  s.time_s = 2.0;
  s.pressure = 1.25;
  rejected(s, "column 10 (pressure): 1.25 is outside [0, 1]");

  writer.flush();
  CHECK(readText(file.path()) == before);
  CHECK(writer.samplesWritten() == 1);
  s = good;
  s.time_s = 2.0;
  writer.write(s);
  writer.close();
  requireBitExact(TraceReader::readAll(file.path()), {good, s});
}

TEST_CASE("trace_csv: the writer rejects flush_every 0 and comments with a newline", "[devices]") {
  TempPath file("options");
  CHECK_THROWS_AS(TraceWriter(file.path(), flushEvery(0)), std::invalid_argument);
  CHECK_THROWS_AS(TraceWriter(file.path(), withComments({"two\nlines"})), std::invalid_argument);
  CHECK_THROWS_AS(TraceWriter(file.path(), withComments({"cr\r"})), std::invalid_argument);
}

TEST_CASE("trace_csv: the writer cannot create a file in a missing folder: std::system_error", "[devices]") {
  TempPath folder("nofolder");
  CHECK_THROWS_AS(TraceWriter(folder.path() / "trace.csv"), std::system_error);
}

TEST_CASE("trace_csv: samples reach the file every flush_every samples while the writer is open", "[devices]") {
  const auto samples = randomSamples(6, 25, Pressure::Sometimes);
  TempPath file("flush");
  TraceWriter writer(file.path(), flushEvery(10));
  CHECK(TraceReader::readAll(file.path()).empty());  // the header is there from the start
  for (std::size_t i = 0; i < samples.size(); ++i) {
    writer.write(samples[i]);
    const std::size_t flushed = (i + 1) / 10 * 10;
    CHECK(writer.samplesWritten() == i + 1);
    REQUIRE(writer.samplesFlushed() == flushed);
    requireBitExact(TraceReader::readAll(file.path()),
                    std::vector<PoseSample>(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(flushed)));
  }
  writer.flush();
  CHECK(writer.samplesFlushed() == 25);
  requireBitExact(TraceReader::readAll(file.path()), samples);
}

TEST_CASE("trace_csv: the writer's destructor flushes and close() ends writing", "[devices]") {
  const auto samples = randomSamples(8, 7, Pressure::Always);
  TempPath file("close");
  {
    TraceWriter writer(file.path(), flushEvery(100));
    for (const PoseSample& s : samples) writer.write(s);
    TraceWriter moved(std::move(writer));  // the moved-from writer owns nothing and flushes nothing
  }
  requireBitExact(TraceReader::readAll(file.path()), samples);

  TraceWriterOptions options = flushEvery(100);
  options.fsync_on_close = true;
  TraceWriter writer(file.path(), options);
  writer.write(samples[0]);
  writer.close();
  writer.close();
  CHECK_THROWS_AS(writer.write(samples[1]), std::logic_error);
  requireBitExact(TraceReader::readAll(file.path()), {samples[0]});
}
