// `incise import jigsaws FILE --arm ARM --out trace.csv`: one arm of a JIGSAWS kinematics file
// (devices/jigsaws.h: the da Vinci's recorded hand controllers and instruments at 30 Hz) as a CSV trace
// (devices/TRACE_FORMAT.md), so surgeons' recorded motion can be replayed by a scenario. The whole file is
// read and checked before anything is written; the trace goes to OUT.tmp, renamed onto OUT when complete,
// so a failure leaves no output and never a torn one. The comments name the generator, the source file,
// the arm, and the scale, offset and gripper threshold used.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "geometry_commands.h"
#include "incise/core/format.h"
#include "incise/devices/jigsaws.h"
#include "incise/devices/trace_csv.h"
#include "json_output.h"
#include "scenario_run.h"

namespace incise::apps::geometry {

namespace {

struct JigsawsImportArgs {
  std::string file;
  std::string arm;
  std::string out;
  double scale = 1.0;
  std::vector<double> offset_m{0.0, 0.0, 0.0};
  double gripper_closed_below_rad = devices::JigsawsOptions().gripper_closed_below_rad;
};

std::vector<std::string> armNames() {
  std::vector<std::string> names;
  for (const auto arm : {devices::JigsawsArm::MtmLeft, devices::JigsawsArm::MtmRight, devices::JigsawsArm::PsmLeft,
                         devices::JigsawsArm::PsmRight})
    names.emplace_back(devices::jigsawsArmName(arm));
  return names;
}

// The trace at `out`, through `out`.tmp: complete or absent.
void writeTrace(const std::vector<devices::PoseSample>& poses, const std::filesystem::path& out,
                std::vector<std::string> comments) {
  writeThroughTemporary(out, [&](const std::filesystem::path& tmp) {
    devices::TraceWriterOptions options;
    options.flush_every = 1000;
    options.comments = std::move(comments);
    devices::TraceWriter writer(tmp, options);
    for (const auto& pose : poses) writer.write(pose);
    writer.close();
  });
}

int runJigsawsImport(const JigsawsImportArgs& a) {
  devices::JigsawsOptions options;
  options.arm = *devices::parseJigsawsArm(a.arm);  // CLI11 has checked the name
  options.scale = a.scale;
  options.offset_m = Eigen::Vector3d(a.offset_m[0], a.offset_m[1], a.offset_m[2]);
  options.gripper_closed_below_rad = a.gripper_closed_below_rad;
  std::vector<devices::PoseSample> poses;
  try {
    poses = devices::readJigsaws(a.file, options);
  } catch (const std::exception& e) {
    failWith("import", e.what());
  }
  const std::string source = std::filesystem::path(a.file).filename().string();
  const int first = devices::jigsawsFirstColumn(options.arm);
  try {
    writeTrace(poses, a.out,
               {"generator: incise import jigsaws " + source, "source: " + source + " (JIGSAWS kinematics)",
                "arm: " + a.arm + " (columns " + std::to_string(first) + "-" +
                    std::to_string(first + devices::kJigsawsArmColumns - 1) + ")",
                "rate_hz: " + core::formatNumber(options.rate_hz), "scale: " + core::formatNumber(options.scale),
                "offset_m: " + core::formatPoint(options.offset_m),
                "gripper_closed_below_rad: " + core::formatNumber(options.gripper_closed_below_rad) +
                    " (button 0 down below it)"});
  } catch (const std::exception& e) {
    failWith("import", e.what());
  }
  std::printf("incise import: %zu poses of %s from %s to %s\n", poses.size(), a.arm.c_str(), a.file.c_str(),
              a.out.c_str());
  return 0;
}

void addJigsawsImport(CLI::App& import) {
  auto args = std::make_shared<JigsawsImportArgs>();
  CLI::App* cmd = import.add_subcommand("jigsaws", "One arm of a JIGSAWS kinematics file (76 columns, 30 Hz)");
  cmd->add_option("file", args->file, "kinematics file (e.g. Suturing/kinematics/AllGestures/Suturing_B001.txt)")
      ->required();
  cmd->add_option("--arm", args->arm,
                  "mtm-left, mtm-right (the surgeon's controllers), psm-left, psm-right (the "
                  "instruments)")
      ->required()
      ->check(CLI::IsMember(armNames()));
  cmd->add_option("--out", args->out, "trace file to write (CSV)")->required();
  cmd->add_option("--scale", args->scale, "applied to the tip before the offset (> 0)")->capture_default_str();
  cmd->add_option("--offset", args->offset_m, "added to the scaled tip: x y z (m)")->expected(3)->capture_default_str();
  cmd->add_option("--gripper-threshold", args->gripper_closed_below_rad,
                  "gripper angle (rad) below which the jaws count as closed: button 0 down")
      ->capture_default_str();
  cmd->callback([args] {
    const int code = runJigsawsImport(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace

void addImportCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("import", "Convert recorded motion from another format to a CSV trace");
  cmd->require_subcommand(1);
  addJigsawsImport(*cmd);
}

}  // namespace incise::apps::geometry
