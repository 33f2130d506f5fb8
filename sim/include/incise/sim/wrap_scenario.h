// Wrap scenarios (`incise wrap`, the global DFFD of paper §3): one JSON file describes a model moved along
// v (y) through static obstacles — the model and the obstacles (a mesh file or a shape), the lattice, the
// treatment of the openings, the motion, the output format and the penetration check. The format is
// documented in docs/scenarios.md ("Wrap scenarios"); every key is optional except model and obstacles;
// relative paths are relative to the scenario file.
//
// Units: metres (degrees for rotate_x_deg). Threads: any. Cost: loading builds the meshes (shapes via
// mesh/shapes.h, files via loadSurfaceMesh, subdivided as asked): O(their size); allocates.
// Failure: loadWrapScenario throws ScenarioError naming the file and the key path, or the obstacle (the
// cases are listed above it).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "incise/global_dffd/global_dffd.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario_error.h"

namespace incise::sim {

// The meshes written per frame.
enum class WrapFormat : std::uint8_t { Obj, Ply };

struct WrapScenario {
  std::string name;                              // [the file's stem]
  mesh::SurfaceMesh model;                       // at its start position
  std::vector<global_dffd::Obstacle> obstacles;  // each named ["obstacle i"]
  global_dffd::GlobalDffdOptions options;        // "lattice"
  global_dffd::OpeningTreatment treatment = global_dffd::OpeningTreatment::Open;
  Eigen::Vector3d translate_m{0.0, 0.1, 0.0};  // the model's move over the run
  int frames = 20;                             // frames + 1 meshes: offsets 0, 1/frames, ..., 1 of translate_m
  WrapFormat format = WrapFormat::Obj;
  double tolerance_m = 1e-6;  // a frame fails when it penetrates an obstacle deeper
};

// The wrap scenario in `file`, e.g.
//   { "name": "sphere-cylinder",
//     "model": { "shape": "sphere", "centre_m": [0, -0.045, 0], "radius_m": 0.02, "stretch": [1, 1, 0.5] },
//     "obstacles": [ { "name": "cylinder", "shape": "cylinder", "base_m": [0, 0, -0.03],
//                      "axis_m": [0, 0, 0.06], "radius_m": 0.006 } ],
//     "lattice": { "order": 4, "controls": [24, 16, 8], "margin_m": 0.025, "kernel": "bspline",
//                  "kernel_width": 6, "clearance_m": 0.0005, "v_knots": true, "on_fold": "refuse" },
//     "treatment": "open", "motion": { "translate_m": [0, 0.07, 0], "frames": 14 },
//     "format": "obj", "penetration_tolerance_m": 1e-6 }
// Failure: loadWrapScenario throws ScenarioError with "file:line:column: JSON syntax error" for JSON
// syntax and "file: key.path: ..." for a missing, mistyped or out-of-range value, a missing file or a
// model validateModel refuses; "file: obstacle 'name': ..." for an obstacle mesh that cannot be made. A model
// or obstacle of more than 262,144 (2^18) triangles is refused at the key that makes it so, from the shape's
// parameters or the file's faces times 4^subdivide, before it is built ("file: model.subdivisions: a sphere
// of 7 subdivisions has 327,680 triangles; a shape may have at most 262,144"): a wrap scene is meant to run
// in real time, a few milliseconds a frame, and larger meshes cannot.
WrapScenario loadWrapScenario(const std::filesystem::path& file);

// The scenario's words: "open", "stitched", "capped"; "obj", "ply" (also the files' extension).
const char* treatmentName(global_dffd::OpeningTreatment treatment);
const char* formatName(WrapFormat format);

}  // namespace incise::sim
