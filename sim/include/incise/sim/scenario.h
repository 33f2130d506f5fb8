// Scenarios: one JSON file describes a run — the tissue, the tool and tissue parameters, the incision's
// lattice, the pose source (a trace, generated strokes or a HID recording), the rate and the budget —
// shared by the tests, the CLI and the benchmarks. docs/scenarios.md lists every key with its type, unit,
// default and range; every key is optional except tissue.mesh (or .shape) and pose_source; relative paths
// are relative to the scenario file.
//
// Threads: any. Failure: loadScenario throws ScenarioError with "file:line:column: ..." for JSON syntax
// errors and "file: key.path: ..." for a missing, mistyped or out-of-range value or a missing file.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "incise/devices/hid_profile.h"
#include "incise/sim/scenario_error.h"
#include "incise/sim/world.h"

namespace incise::sim {

// A generated pose source ("kind": "strokes") lists strokes over the tissue — start_m [x, y, z] above the
// surface, direction, length_m, bend_m, speed_m_per_s, pause_s before it — and is how the shipped traces
// were made (`incise record`).
struct StrokeSpec {
  Eigen::Vector3d start_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double length_m = 0.05;
  double bend_m = 0.0;
  double wave_m = 0.0;  // an S sideways (incision::StrokePathOptions::wave_m)
  double speed_m_per_s = 0.05;
  double pause_s = 0.1;       // tool idle above the surface before the stroke
  double depth_m = -1.0;      // the blade tip's depth below the surface at the start; < 0: incision.depth_m
  double depth_end_m = -1.0;  // ... at the end, in a straight ramp along the stroke; < 0: depth_m
};

// A hid-recorder recording replayed through the HID parser and profile (devices/hid_recording_poses.h),
// with the profile's mapping into tissue space; `synthesis`, when given, says how `path` was made
// (`incise hid synth`): from the strokes of another scenario, through a real descriptor.
struct HidSynthesis {
  bool given = false;
  std::filesystem::path from;        // a scenario whose pose source is "strokes"
  std::filesystem::path descriptor;  // hex bytes (scenarios/hid/descriptors/)
  std::string name;                  // the N: line
  std::uint16_t vid = 0, pid = 0;
  double rate_hz = 200.0;
};

// A recorded HID stream ("kind": "hid-recording") names a hid-recorder file and the pen or 6-DOF mapping:
//   "pose_source": { "kind": "hid-recording", "path": "hid/bunny-pen-wacom.hid", "device": 0,
//                    "pen": { "origin_m": [..], "x_edge_m": [..], "y_edge_m": [..], "max_depth_m": 0.02, ... },
//                    "six_dof": { "start_m": [..], "max_speed_m_per_s": 0.1, ... },
//                    "synthesis": { "from": "generate/bunny-straight.json", "descriptor": "hid/descriptors/...",
//                                   "vid": "056a", "pid": "0357", "name": "...", "rate_hz": 200 } }
struct HidRecordingSource {
  std::filesystem::path path;
  int device = 0;  // the D: index in the recording
  devices::HidMapping mapping;
  HidSynthesis synthesis;
};

// The tissue made by the program instead of read from a file: "tissue": {"shape": "pad", "size_m": [x, y, z],
// "grid_m": g} (mesh::makeSkinPad: the top at y = 0, a regular grid of g on top).
struct TissueShape {
  bool given = false;
  Eigen::Vector3d size_m{0.1, 0.02, 0.1};
  double grid_m = 0.001;
};

// A textured tissue's look ("tissue": {"texture": {"map": "box", "tile_m": 0.02, "skin": "textures/skin.png",
// "wall": "textures/flesh.png"}}): texture coordinates made for it (map "box": mesh::boxTexCoords over
// tile_m) or, without "map", the mesh file's own (a mesh without them is refused at load); the images the
// viewer, render and train draw on the skin and the walls (PNG paths; none: each material's map_Kd or Kd colour,
// else the plain skin colour; incise's flesh for the walls).
struct TextureSpec {
  bool given = false;
  bool box_map = false;
  double tile_m = 0.02;
  std::filesystem::path skin_image, wall_image;
};

// A planned incision ("plan"): a polyline in metres, projected onto the tissue's surface at load
// (sim/include/incise/sim/plan.h), the target depth below the surface, and the tolerances (lateral: the FLS
// pattern-cut tolerance, 2 mm; depth 1 mm). Checked at load: at least 2 points, tolerances > 0.
struct PlanSpec {
  bool given = false;
  std::vector<Eigen::Vector3d> points_m;
  double depth_m = 0.004;
  double lateral_tolerance_m = 0.002;
  double depth_tolerance_m = 0.001;
};

struct Scenario {
  std::string name;
  std::filesystem::path file;
  std::filesystem::path mesh;
  TissueShape shape;               // given: the tissue is made, not read from `mesh`
  TextureSpec texture;             // given: the tissue is textured
  PlanSpec plan;                   // given: the session is scored against it (score.h)
  double force_threshold_N = 3.0;  // tissue.force_threshold_N: the scoring's "too much force" line
  double scale = 1.0;
  int subdivide = 0;
  WorldOptions world;
  double rate_hz = 1000.0;
  double settle_s = 0.2;  // simulated time after the last pose, for the wound to settle
  enum class Source { Trace, Strokes, HidRecording } source = Source::Trace;
  std::filesystem::path trace;
  std::vector<StrokeSpec> strokes;
  HidRecordingSource hid;

  std::int64_t periodUs() const { return static_cast<std::int64_t>(std::llround(1e6 / rate_hz)); }
};

// The scenario in `file`, e.g.
//   { "name": "bunny-straight",
//     "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01, "subdivide": 2,
//                 "stiffness_N_per_m": 400, "damping_N_s_per_m": 2, "cutting_resistance_N": 0.6 },
//     "tool": { "blade_length_m": 0.03, "cut_button": 0, "max_force_N": 8 },
//     "incision": { "depth_m": 0.004, "opening_m": 0.002, "alpha_m": 0.0015, "beta_m": 0.002,
//                   "spacing_m": 0.0005, "order": 4, "retraction_time_s": 0.05, "wall_rows": 3 },
//     "pose_source": { "kind": "trace", "path": "traces/bunny-straight.csv" },
//     "rate_hz": 1000, "cut_budget_us": 300, "settle_s": 0.2 }
Scenario loadScenario(const std::filesystem::path& file);

// The scenario's tissue mesh: loaded, scaled and subdivided, or made (shape), then box-mapped when its
// texture says so; throws mesh::MeshError (also for a texture without a map on a mesh without coordinates).
mesh::SurfaceMesh loadTissue(const Scenario& scenario);

}  // namespace incise::sim
