#include "incise/devices/jigsaws.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <system_error>

#include <Eigen/SVD>

#include "message_text.h"

namespace incise::devices {
namespace {

using detail::quoteField;
using detail::shortest;

constexpr std::array<std::string_view, 4> kArmNames = {"mtm-left", "mtm-right", "psm-left", "psm-right"};
// Within an arm, offset i (0-based) is kArmFields[i].
constexpr std::array<std::string_view, kJigsawsArmColumns> kArmFields = {
    "x_m", "y_m", "z_m", "R11", "R12", "R13", "R21", "R22", "R23",        "R31",
    "R32", "R33", "vx",  "vy",  "vz",  "wx",  "wy",  "wz",  "gripper_rad"};
constexpr int kRotationOffset = 3;
constexpr int kGripperOffset = 18;
constexpr std::string_view kLineBlank = " \t";
// Below this smallest singular value a matrix is singular, not merely far from a rotation.
constexpr double kSingularBelow = 1e-9;

// "column 42 (psm-left R11)".
std::string armColumnLabel(int column) {
  const int arm = (column - 1) / kJigsawsArmColumns;
  const int field = (column - 1) % kJigsawsArmColumns;
  return "column " + std::to_string(column) + " (" + std::string(kArmNames[static_cast<std::size_t>(arm)]) + " " +
         std::string(kArmFields[static_cast<std::size_t>(field)]) + ")";
}

void checkOptions(const JigsawsOptions& options) {
  if (!(std::isfinite(options.rate_hz) && options.rate_hz > 0.0))
    throw std::invalid_argument("readJigsaws: rate_hz must be finite and > 0, not " + shortest(options.rate_hz));
  if (!(std::isfinite(options.scale) && options.scale > 0.0))
    throw std::invalid_argument("readJigsaws: scale must be finite and > 0, not " + shortest(options.scale));
  if (!options.offset_m.allFinite()) throw std::invalid_argument("readJigsaws: offset_m must be finite");
  if (!std::isfinite(options.gripper_closed_below_rad))
    throw std::invalid_argument("readJigsaws: gripper_closed_below_rad must be finite");
}

// w > 0; when w == 0 the first non-zero of x, y, z positive: one of q and -q, always the same one.
Eigen::Quaterniond canonical(Eigen::Quaterniond q) {
  q.normalize();
  const std::array<double, 4> c = {q.w(), q.x(), q.y(), q.z()};
  for (const double v : c) {
    if (v == 0.0) continue;
    if (v < 0.0) q.coeffs() = -q.coeffs();
    break;
  }
  return q;
}

class Reader {
 public:
  Reader(std::filesystem::path path, const JigsawsOptions& options) : path_(std::move(path)), options_(options) {}
  std::vector<PoseSample> read();

 private:
  [[noreturn]] void fail(int column, const std::string& what) const {
    std::string message = path_.string() + ":" + std::to_string(line_) + ": ";
    if (column > 0) message += armColumnLabel(column) + ": ";
    throw JigsawsError(message + what, path_, line_, column);
  }
  PoseSample parseFrame(std::string_view line, std::size_t frame) const;
  Eigen::Quaterniond orientationOf(const Eigen::Matrix3d& m, int first_column) const;

  std::filesystem::path path_;
  const JigsawsOptions& options_;
  std::size_t line_ = 0;
};

std::vector<PoseSample> Reader::read() {
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    const int error = errno;
    throw JigsawsError(path_.string() + ": cannot open (" + std::generic_category().message(error) + ")", path_, 0, 0);
  }
  std::vector<PoseSample> poses;
  std::size_t blank_line = 0;  // the first blank line since the last frame
  std::string line;
  while (std::getline(in, line)) {
    ++line_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(kLineBlank) == std::string::npos) {
      if (blank_line == 0) blank_line = line_;
      continue;
    }
    if (blank_line != 0) {
      line_ = blank_line;
      fail(0, "empty line between frames (each line is one frame at 1/" + shortest(options_.rate_hz) +
                  " s: a gap would shift every later frame's time)");
    }
    poses.push_back(parseFrame(line, poses.size()));
  }
  if (in.bad())
    throw JigsawsError(path_.string() + ": read error after line " + std::to_string(line_), path_, line_, 0);
  if (poses.empty()) {
    line_ = 1;
    fail(0, "empty file; expected frames of " + std::to_string(kJigsawsColumns) + " numbers");
  }
  return poses;
}

PoseSample Reader::parseFrame(std::string_view line, std::size_t frame) const {
  std::array<double, kJigsawsColumns> values{};
  int count = 0;
  std::size_t start = line.find_first_not_of(kLineBlank);
  while (start != std::string_view::npos) {
    const std::size_t end = std::min(line.find_first_of(kLineBlank, start), line.size());
    const std::string_view field = line.substr(start, end - start);
    start = line.find_first_not_of(kLineBlank, end);
    if (++count > kJigsawsColumns) continue;  // counted, to say how many
    double value = 0.0;
    const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
    if (result.ec == std::errc::result_out_of_range) fail(count, quoteField(field) + " is out of range for a double");
    if (result.ec != std::errc() || result.ptr != field.data() + field.size())
      fail(count, quoteField(field) + " is not a number");
    if (!std::isfinite(value)) fail(count, quoteField(field) + " is not finite");
    values[static_cast<std::size_t>(count - 1)] = value;
  }
  if (count != kJigsawsColumns)
    fail(0, std::to_string(count) + " columns, expected " + std::to_string(kJigsawsColumns) + " (" +
                std::to_string(kJigsawsArmColumns) + " for each of the 4 arms)");

  const int first = jigsawsFirstColumn(options_.arm);
  auto at = [&](int offset) { return values[static_cast<std::size_t>(first - 1 + offset)]; };
  PoseSample pose;
  pose.time_s = static_cast<double>(frame) / options_.rate_hz;
  pose.tip_m = options_.scale * Eigen::Vector3d(at(0), at(1), at(2)) + options_.offset_m;
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = at(kRotationOffset + 3 * r + c);
  pose.orientation = orientationOf(m, first + kRotationOffset);
  pose.buttons = at(kGripperOffset) < options_.gripper_closed_below_rad ? 1u : 0u;
  return pose;
}

Eigen::Quaterniond Reader::orientationOf(const Eigen::Matrix3d& m, int first_column) const {
  const std::string where = "columns " + std::to_string(first_column) + "-" + std::to_string(first_column + 8) + " (" +
                            std::string(jigsawsArmName(options_.arm)) + " R): the matrix ";
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sigma = svd.singularValues();  // decreasing
  if (sigma(2) < kSingularBelow)
    fail(0, where + "is singular (singular values " + shortest(sigma(0)) + ", " + shortest(sigma(1)) + ", " +
                shortest(sigma(2)) + "), not a rotation");
  const double det = m.determinant();
  if (det < 0.0) fail(0, where + "is a reflection (determinant " + shortest(det) + "), not a rotation");
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d r = u * svd.matrixV().transpose();
  if (r.determinant() < 0.0) {
    u.col(2) = -u.col(2);
    r = u * svd.matrixV().transpose();
  }
  const double distance = (m - r).norm();
  if (!(distance <= kJigsawsRotationTolerance))
    fail(0, where + "is " + shortest(distance) + " from the nearest rotation (Frobenius norm), more than " +
                shortest(kJigsawsRotationTolerance));
  return canonical(Eigen::Quaterniond(r));
}

}  // namespace

std::string_view jigsawsArmName(JigsawsArm arm) { return kArmNames[static_cast<std::size_t>(arm)]; }

std::optional<JigsawsArm> parseJigsawsArm(std::string_view name) {
  for (std::size_t i = 0; i < kArmNames.size(); ++i)
    if (kArmNames[i] == name) return static_cast<JigsawsArm>(i);
  return std::nullopt;
}

int jigsawsFirstColumn(JigsawsArm arm) { return 1 + kJigsawsArmColumns * static_cast<int>(arm); }

std::vector<PoseSample> readJigsaws(const std::filesystem::path& path, const JigsawsOptions& options) {
  checkOptions(options);
  return Reader(path, options).read();
}

}  // namespace incise::devices
