// Tool poses from the kinematics of JIGSAWS (the JHU-ISI Gesture and Skill Assessment Working Set: da Vinci
// recordings of suturing, knot tying and needle passing), one arm at a time: real surgeons' hand and
// instrument motion as PoseSamples, to replay through the simulation. A kinematics file has one line of 76
// numbers per 30 Hz frame, four arms of 19 columns (the format: above kJigsawsColumns); each frame of the
// chosen arm becomes one pose (readJigsaws).
//
// Units: metres, radians, seconds. Threads: any (a pure function of the file). Cost: O(file size); a frame
// costs one 3x3 SVD. Failure: std::invalid_argument for bad options; JigsawsError "path:line: ..." for a
// file that cannot be read or does not follow the format, naming the line and the column (readJigsaws).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "incise/devices/pose_sample.h"

namespace incise::devices {

// Format (a kinematics file, e.g. Suturing/kinematics/AllGestures/Suturing_B001.txt): one line per frame,
// frames at 30 Hz, 76 floating-point numbers per line separated by spaces or tabs (the files pad with
// leading and trailing spaces; a '\r' before the '\n' is ignored; the last line may lack its '\n'). Four
// arms of 19 columns each, in this order:
//     columns  1-19  master tool manipulator, left   (MTM: the surgeon's hand controller)
//     columns 20-38  master tool manipulator, right
//     columns 39-57  patient-side manipulator, left  (PSM, "slave": the instrument)
//     columns 58-76  patient-side manipulator, right
//   within an arm (offset 0 = its first column):
//     0-2    tool tip x, y, z, metres
//     3-11   rotation matrix R of the tool tip, row-major (R11 R12 R13 R21 ... R33)
//     12-14  tip linear velocity, m/s            (not used)
//     15-17  tip angular velocity, rad/s         (not used)
//     18     gripper angle, radians
//   Numbers are what std::from_chars reads (general format, '.' as decimal point, optional exponent);
//   NaN and infinities are refused. An empty (or blank) line is refused where a frame is expected: it
//   would shift every later frame's time; blank lines after the last frame are ignored.
inline constexpr int kJigsawsColumns = 76;
inline constexpr int kJigsawsArmColumns = 19;
// ||R - nearest rotation||_F at most this. Six printed digits leave ~1e-6; a swapped or lost entry is ~1.
inline constexpr double kJigsawsRotationTolerance = 0.05;

enum class JigsawsArm : std::uint8_t { MtmLeft, MtmRight, PsmLeft, PsmRight };

// "mtm-left", "mtm-right", "psm-left", "psm-right": the names the CLI and messages use.
std::string_view jigsawsArmName(JigsawsArm arm);
// The arm of that name; std::nullopt for any other text.
std::optional<JigsawsArm> parseJigsawsArm(std::string_view name);
// The arm's first column, 1-based: 1, 20, 39 or 58.
int jigsawsFirstColumn(JigsawsArm arm);

struct JigsawsOptions {
  JigsawsArm arm = JigsawsArm::PsmRight;  // the instrument in the surgeon's right hand
  double scale = 1.0;                     // applied to the tip before the offset; > 0
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
  double rate_hz = 30.0;  // the data set's frame rate
  // Closed (button 0 down) below this angle. JIGSAWS documents the angle in radians without a "closed"
  // value and its arms are not calibrated to each other: 0 is a convention (the angle's sign), not a
  // measurement; set it per recording (look at the angle while the jaws hold the needle).
  double gripper_closed_below_rad = 0.0;
};

// A kinematics file that cannot be read: what() is "path:line: what is wrong", e.g.
//   Suturing_B001.txt:12: column 42 (psm-left R11): 'abc' is not a number
// ("path: ..." when the problem is not on one line).
class JigsawsError : public std::runtime_error {
 public:
  JigsawsError(const std::string& message, std::filesystem::path path, std::size_t line, int column)
      : std::runtime_error(message), path_(std::move(path)), line_(line), column_(column) {}
  const std::filesystem::path& path() const { return path_; }
  // 1-based line; 0 when the error is about the whole file.
  std::size_t line() const { return line_; }
  // 1-based column (1..76); 0 when the error is not about one column.
  int column() const { return column_; }

 private:
  std::filesystem::path path_;
  std::size_t line_;
  int column_;
};

// The poses of `options.arm` in the kinematics file at `path`, one per frame:
// Pose k (k = 0, 1, ... over the frames):
//   time_s      k / rate_hz
//   tip_m       scale * (x, y, z) + offset_m
//   orientation the rotation nearest R (polar decomposition by SVD, R = U V^T, the last column of U
//               negated if det < 0), as a unit quaternion with w > 0 (w == 0: the first non-zero of x, y, z
//               positive), so the output is deterministic. R must be within kJigsawsRotationTolerance of
//               it (Frobenius norm): the data set's matrices are rounded to a few digits, not garbled.
//   buttons     bit 0 set when the gripper angle < gripper_closed_below_rad (the jaws closed: the cut
//               button of the simulation's default tool); no other bit
//   pressure    std::nullopt (the da Vinci reports none)
// Failure: std::invalid_argument for bad options (rate_hz, scale not finite and > 0; offset, threshold not
// finite); JigsawsError "path:line: ..." for: a file that cannot be opened or read; an empty file (no frame);
// a line with other than 76 columns (the message says how many); a column that is not a number or not
// finite (it names the column, its arm and its meaning); a blank line between frames; the chosen arm's
// rotation matrix singular, a reflection or further than kJigsawsRotationTolerance from a rotation (the
// other arms' matrices are not looked at: a recording with one broken arm still gives the others).
std::vector<PoseSample> readJigsaws(const std::filesystem::path& path, const JigsawsOptions& options = {});

}  // namespace incise::devices
