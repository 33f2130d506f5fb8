#include "incise/devices/jigsaws.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using incise::devices::JigsawsArm;
using incise::devices::jigsawsArmName;
using incise::devices::JigsawsError;
using incise::devices::jigsawsFirstColumn;
using incise::devices::JigsawsOptions;
using incise::devices::parseJigsawsArm;
using incise::devices::PoseSample;
using incise::devices::readJigsaws;
using incise::test::TempDir;

namespace {

using Row = std::array<double, 76>;
using Rotation = std::array<double, 9>;  // row-major

constexpr Rotation kIdentity = {1, 0, 0, 0, 1, 0, 0, 0, 1};
constexpr Rotation kQuarterTurnZ = {0, -1, 0, 1, 0, 0, 0, 0, 1};  // 90 degrees about z

// One arm's 19 columns: tip, R, velocities (made up, not read), gripper angle.
void setArm(Row& row, JigsawsArm arm, const Eigen::Vector3d& tip, const Rotation& r, double gripper_rad) {
  const std::size_t first = static_cast<std::size_t>(jigsawsFirstColumn(arm) - 1);
  for (std::size_t i = 0; i < 3; ++i) row[first + i] = tip[static_cast<Eigen::Index>(i)];
  for (std::size_t i = 0; i < 9; ++i) row[first + 3 + i] = r[i];
  for (std::size_t i = 0; i < 6; ++i) row[first + 12 + i] = 0.01 * static_cast<double>(i + 1);
  row[first + 18] = gripper_rad;
}

// Every arm at a tip of its own, identity rotation, open gripper.
Row baseRow() {
  Row row{};
  for (int a = 0; a < 4; ++a)
    setArm(row, static_cast<JigsawsArm>(a), Eigen::Vector3d(0.01 * a, 0.02 * a, -0.03 * a), kIdentity, 0.5);
  return row;
}

// As JIGSAWS writes a line: leading spaces, numbers padded with spaces, trailing spaces.
std::string line(const Row& row) {
  std::string text;
  char number[40];
  for (const double v : row) {
    std::snprintf(number, sizeof number, "   %.17g", v);
    text += number;
  }
  return text + "     \n";
}

// `count` copies of `value`, each after a space.
std::string fields(int count, const std::string& value) {
  std::string text;
  for (int i = 0; i < count; ++i) text += " " + value;
  return text;
}

std::filesystem::path write(const TempDir& dir, const std::string& text) {
  return dir.write("Suturing_B001.txt", text);
}

JigsawsOptions armOptions(JigsawsArm arm) {
  JigsawsOptions options;
  options.arm = arm;
  return options;
}

// The JigsawsError that reading `text` raises, its line and column checked, its message containing `what`.
void requireError(const std::string& text, std::size_t line, int column, const std::string& what) {
  TempDir dir;
  const auto path = write(dir, text);
  try {
    readJigsaws(path);
  } catch (const JigsawsError& error) {
    INFO(error.what());
    CHECK(error.line() == line);
    CHECK(error.column() == column);
    CHECK_THAT(error.what(), Contains("Suturing_B001.txt:" + std::to_string(line) + ": "));
    CHECK_THAT(error.what(), Contains(what));
    return;
  }
  FAIL("no JigsawsError for a file of " << text.size() << " bytes");
}

}  // namespace

TEST_CASE("jigsaws: a quarter turn about z, frames at 30 Hz, the tip as recorded", "[devices]") {
  TempDir dir;
  std::string text;
  for (int k = 0; k < 4; ++k) {
    Row row = baseRow();
    setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d(0.1 + 0.001 * k, -0.02, 0.05), kQuarterTurnZ, 0.5);
    text += line(row);
  }
  const std::vector<PoseSample> poses = readJigsaws(write(dir, text));
  REQUIRE(poses.size() == 4);
  for (int k = 0; k < 4; ++k) {
    INFO("frame " << k);
    const PoseSample& p = poses[static_cast<std::size_t>(k)];
    CHECK(p.time_s == static_cast<double>(k) / 30.0);
    CHECK(p.tip_m.x() == 0.1 + 0.001 * k);
    CHECK(p.tip_m.y() == -0.02);
    CHECK(p.tip_m.z() == 0.05);
    CHECK(p.orientation.w() == Approx(std::sqrt(0.5)).margin(1e-15));
    CHECK(p.orientation.x() == Approx(0.0).margin(1e-15));
    CHECK(p.orientation.y() == Approx(0.0).margin(1e-15));
    CHECK(p.orientation.z() == Approx(std::sqrt(0.5)).margin(1e-15));
    // The tool's x axis turns onto the device's y axis.
    CHECK((p.orientation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm() < 1e-15);
    CHECK(p.buttons == 0);
    CHECK_FALSE(p.pressure.has_value());
  }
}

TEST_CASE("jigsaws: scale then offset on the tip, another frame rate", "[devices]") {
  TempDir dir;
  Row row = baseRow();
  setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d(0.1, -0.02, 0.05), kIdentity, 0.5);
  JigsawsOptions options;
  options.scale = 2.5;
  options.offset_m = Eigen::Vector3d(0.001, 0.002, -0.003);
  options.rate_hz = 100.0;
  const std::vector<PoseSample> poses = readJigsaws(write(dir, line(row) + line(row)), options);
  REQUIRE(poses.size() == 2);
  const Eigen::Vector3d expected = 2.5 * Eigen::Vector3d(0.1, -0.02, 0.05) + options.offset_m;
  CHECK(poses[1].tip_m == expected);
  CHECK(poses[1].time_s == 0.01);
  CHECK(poses[0].orientation.coeffs() == Eigen::Quaterniond::Identity().coeffs());
}

TEST_CASE("jigsaws: each arm reads its own 19 columns", "[devices]") {
  TempDir dir;
  const std::array<Rotation, 4> rotations = {Rotation{1, 0, 0, 0, 0, -1, 0, 1, 0},    // 90 about x
                                             Rotation{0, 0, 1, 0, 1, 0, -1, 0, 0},    // 90 about y
                                             kQuarterTurnZ,                           // 90 about z
                                             Rotation{1, 0, 0, 0, -1, 0, 0, 0, -1}};  // 180 about x
  Row row{};
  for (int a = 0; a < 4; ++a)
    setArm(row, static_cast<JigsawsArm>(a), Eigen::Vector3d(a + 1.0, 10.0 * (a + 1), 100.0 * (a + 1)),
           rotations[static_cast<std::size_t>(a)], a % 2 == 0 ? -0.25 : 0.75);
  const auto path = write(dir, line(row));
  for (int a = 0; a < 4; ++a) {
    const JigsawsArm arm = static_cast<JigsawsArm>(a);
    INFO("arm " << jigsawsArmName(arm));
    const std::vector<PoseSample> poses = readJigsaws(path, armOptions(arm));
    REQUIRE(poses.size() == 1);
    CHECK(poses[0].tip_m == Eigen::Vector3d(a + 1.0, 10.0 * (a + 1), 100.0 * (a + 1)));
    CHECK(poses[0].buttons == (a % 2 == 0 ? 1u : 0u));
    const Rotation& r = rotations[static_cast<std::size_t>(a)];
    const Eigen::Matrix3d expected =
        (Eigen::Matrix3d() << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]).finished();
    CHECK((poses[0].orientation.toRotationMatrix() - expected).norm() < 1e-15);
  }
  CHECK(jigsawsFirstColumn(JigsawsArm::MtmLeft) == 1);
  CHECK(jigsawsFirstColumn(JigsawsArm::MtmRight) == 20);
  CHECK(jigsawsFirstColumn(JigsawsArm::PsmLeft) == 39);
  CHECK(jigsawsFirstColumn(JigsawsArm::PsmRight) == 58);
  for (const char* name : {"mtm-left", "mtm-right", "psm-left", "psm-right"})
    CHECK(jigsawsArmName(*parseJigsawsArm(name)) == name);
  CHECK_FALSE(parseJigsawsArm("psm_right").has_value());
  CHECK_FALSE(parseJigsawsArm("").has_value());
}

TEST_CASE("jigsaws: the quaternion's sign is fixed: w > 0, or the first non-zero positive", "[devices]") {
  TempDir dir;
  // -90 degrees about z, and 180 about x written so that a plain conversion may give either sign.
  Row minus_quarter = baseRow(), half_x = baseRow();
  setArm(minus_quarter, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), Rotation{0, 1, 0, -1, 0, 0, 0, 0, 1}, 0.5);
  setArm(half_x, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), Rotation{1, 0, 0, 0, -1, 0, 0, 0, -1}, 0.5);
  const std::vector<PoseSample> poses = readJigsaws(write(dir, line(minus_quarter) + line(half_x)));
  REQUIRE(poses.size() == 2);
  CHECK(poses[0].orientation.w() > 0.0);
  CHECK(poses[0].orientation.z() == Approx(-std::sqrt(0.5)).margin(1e-15));
  CHECK(poses[1].orientation.w() == Approx(0.0).margin(1e-15));
  CHECK(poses[1].orientation.x() == Approx(1.0).margin(1e-15));
}

TEST_CASE("jigsaws: a slightly non-orthonormal matrix becomes the nearest rotation", "[devices]") {
  TempDir dir;
  // A quarter turn about z, its entries rounded to three digits and nudged: 1e-3 off orthonormal.
  const Rotation nudged = {0.0012, -0.9995, 0.0008, 1.0007, 0.0003, -0.0011, 0.0004, 0.0009, 0.9991};
  Row row = baseRow();
  setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), nudged, 0.5);
  const std::vector<PoseSample> poses = readJigsaws(write(dir, line(row)));
  REQUIRE(poses.size() == 1);
  const Eigen::Quaterniond& q = poses[0].orientation;
  CHECK(std::abs(q.norm() - 1.0) < 1e-15);
  const Eigen::Matrix3d r = q.toRotationMatrix();
  CHECK((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-14);
  CHECK(r.determinant() == Approx(1.0).margin(1e-14));
  // Within the nudge of the quarter turn; and nearer the input than the exact quarter turn is.
  const Eigen::Matrix3d exact = (Eigen::Matrix3d() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished();
  const Eigen::Matrix3d input = (Eigen::Matrix3d() << nudged[0], nudged[1], nudged[2], nudged[3], nudged[4], nudged[5],
                                 nudged[6], nudged[7], nudged[8])
                                    .finished();
  CHECK((r - exact).norm() < 3e-3);
  CHECK((input - r).norm() <= (input - exact).norm());
}

TEST_CASE("jigsaws: the gripper closes button 0 below the threshold", "[devices]") {
  TempDir dir;
  std::string text;
  for (const double angle : {-0.2, 0.0, 0.3, 0.6}) {
    Row row = baseRow();
    setArm(row, JigsawsArm::PsmLeft, Eigen::Vector3d::Zero(), kIdentity, angle);
    text += line(row);
  }
  const auto path = write(dir, text);
  auto buttons = [&](double threshold) {
    JigsawsOptions options = armOptions(JigsawsArm::PsmLeft);
    options.gripper_closed_below_rad = threshold;
    std::vector<std::uint32_t> b;
    for (const PoseSample& p : readJigsaws(path, options)) b.push_back(p.buttons);
    return b;
  };
  CHECK(buttons(0.0) == std::vector<std::uint32_t>{1, 0, 0, 0});  // the default: closed below 0 (0 itself open)
  CHECK(buttons(0.5) == std::vector<std::uint32_t>{1, 1, 1, 0});
  CHECK(buttons(-1.0) == std::vector<std::uint32_t>{0, 0, 0, 0});
}

TEST_CASE("jigsaws: CRLF, tabs, trailing blank lines and a last line without its newline are read", "[devices]") {
  TempDir dir;
  std::string crlf = line(baseRow());
  crlf.back() = '\r';
  crlf.push_back('\n');
  std::string tabs = line(baseRow());
  for (char& c : tabs)
    if (c == ' ') c = '\t';
  std::string last = line(baseRow());
  last.pop_back();
  CHECK(readJigsaws(write(dir, crlf + tabs + "\n  \n")).size() == 2);
  CHECK(readJigsaws(write(dir, crlf + last)).size() == 2);
}

TEST_CASE("jigsaws: bad files are refused with path:line, the column and what is wrong", "[devices]") {
  const std::string good = line(baseRow());
  SECTION("too few columns") {
    requireError(good + fields(75, "0.5") + "\n", 2, 0, "75 columns, expected 76 (19 for each of the 4 arms)");
  }
  SECTION("too many columns") { requireError(good + fields(77, "0.5") + "\n", 2, 0, "77 columns, expected 76"); }
  SECTION("a column that is not a number") {
    std::string text = fields(41, "0.5") + " abc" + fields(34, "0.5");
    requireError(good + text + "\n", 2, 42, "column 42 (psm-left R11): 'abc' is not a number");
    requireError(fields(75, "1") + " 1.5.2\n", 1, 76, "column 76 (psm-right gripper_rad): '1.5.2' is not a number");
  }
  SECTION("NaN and infinity") {
    requireError(good + fields(75, "0") + " nan\n", 2, 76, "column 76 (psm-right gripper_rad): 'nan' is not finite");
    requireError("-inf" + fields(75, "0") + "\n", 1, 1, "column 1 (mtm-left x_m): '-inf' is not finite");
  }
  SECTION("a singular matrix") {
    Row row = baseRow();
    setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), Rotation{}, 0.5);
    requireError(good + good + line(row), 3, 0, "columns 61-69 (psm-right R): the matrix is singular");
  }
  SECTION("a matrix far from a rotation") {
    Row row = baseRow();
    setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), Rotation{1.2, 0, 0, 0, 1.2, 0, 0, 0, 1.2}, 0.5);
    requireError(line(row), 1, 0, "the matrix is 0.34641016151377");
    requireError(line(row), 1, 0, "from the nearest rotation (Frobenius norm), more than 0.05");
  }
  SECTION("a reflection") {
    Row row = baseRow();
    setArm(row, JigsawsArm::PsmRight, Eigen::Vector3d::Zero(), Rotation{1, 0, 0, 0, 1, 0, 0, 0, -1}, 0.5);
    requireError(line(row), 1, 0, "is a reflection (determinant -1)");
  }
  SECTION("an empty file, or one of blank lines") {
    requireError("", 1, 0, "empty file");
    requireError("   \n\n", 1, 0, "empty file");
  }
  SECTION("a blank line between frames") { requireError(good + "\n" + good, 2, 0, "empty line between frames"); }
}

TEST_CASE("jigsaws: only the chosen arm's matrix is checked", "[devices]") {
  TempDir dir;
  Row row = baseRow();
  setArm(row, JigsawsArm::MtmLeft, Eigen::Vector3d::Zero(), Rotation{}, 0.5);
  CHECK(readJigsaws(write(dir, line(row))).size() == 1);
  CHECK_THROWS_AS(readJigsaws(write(dir, line(row)), armOptions(JigsawsArm::MtmLeft)), JigsawsError);
}

TEST_CASE("jigsaws: a missing file and bad options", "[devices]") {
  TempDir dir;
  CHECK_THROWS_WITH(readJigsaws(dir.path() / "none.txt"), Contains("none.txt: cannot open"));
  const auto path = write(dir, line(baseRow()));
  JigsawsOptions options;
  options.rate_hz = 0.0;
  CHECK_THROWS_AS(readJigsaws(path, options), std::invalid_argument);
  options = JigsawsOptions();
  options.scale = -1.0;
  CHECK_THROWS_AS(readJigsaws(path, options), std::invalid_argument);
  options = JigsawsOptions();
  options.offset_m.x() = std::nan("");
  CHECK_THROWS_AS(readJigsaws(path, options), std::invalid_argument);
  options = JigsawsOptions();
  options.gripper_closed_below_rad = INFINITY;
  CHECK_THROWS_AS(readJigsaws(path, options), std::invalid_argument);
}
