// One scalpel stroke cut across a tissue surface, sample by sample as the simulation would (`incise cut`):
// the mesh loaded (OBJ, PLY, OFF, STL), scaled to metres and Loop-subdivided; a stroke drawn along a path
// over it (incision::strokeAlongPath: rays down -y onto the surface, sampled at 1 kHz); the surface cutter
// (incision::SurfaceCutter) begun at the first sample, extended by each of the others, finished, and the
// wound opened to the last sample's time. Then the cut mesh, what the cutter did and summary.json's document.
// The CLI, the C API and the Python module all cut through this class: the same options give the same
// mesh, to the byte.
//
// Units: metres, seconds. Threads: one owner. Cost: the load and subdivision (O(faces x 4^subdivide)), the
// cutter's construction (O(V)) and the cut (per sample as SurfaceCutter; the default bunny stroke: about
// 0.1-0.3 s). Failure: the constructor throws mesh::MeshError (a bad mesh file, not a closed two-manifold)
// or std::invalid_argument (bad options, a path whose first ray misses the surface), naming what and where;
// run() never throws but std::bad_alloc; a cut that went wrong says so in failure().
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::jobs {

// The options of `incise cut`, with its defaults: a 5 cm stroke along +x across the Stanford bunny's back
// (the bunny's file is in centimetres, hence the scale).
struct CutJobOptions {
  std::filesystem::path mesh;                   // a closed triangle mesh (OBJ, PLY, OFF, STL)
  double scale = 0.01;                          // metres per file unit
  int subdivide = 2;                            // Loop subdivisions before cutting, in [0, 5]
  Eigen::Vector3d start_m{-0.012, 0.0, 0.015};  // the path's first point; rays go down -y onto the surface
  Eigen::Vector3d direction{1.0, 0.0, 0.0};
  double length_m = 0.05;
  double bend_m = 0.0;  // sideways bulge at the middle
  double speed_m_per_s = 0.05;
  incision::CutterOptions cutter;
};

class CutJob {
 public:
  // Loads and subdivides the mesh, draws the stroke over it and makes the cutter (nothing is cut yet).
  explicit CutJob(const CutJobOptions& options);
  CutJob(const CutJob&) = delete;
  CutJob& operator=(const CutJob&) = delete;
  ~CutJob();

  // Cuts the stroke, timing every cutter call; `progress(done, total)` after each sample when given. Once.
  void run(const std::function<void(std::size_t done, std::size_t total)>& progress = {});

  const mesh::SurfaceMesh& mesh() const noexcept { return *mesh_; }
  const incision::CutStats& stats() const noexcept { return cutter_->stats(); }
  const CutJobOptions& options() const noexcept { return options_; }
  std::size_t samples() const noexcept { return stroke_.samples.size() + 1; }  // the first one included
  int samplesNotAccepted() const noexcept { return skipped_; }
  const std::vector<double>& sampleUs() const noexcept { return sample_us_; }  // per cutter call, microseconds
  int eulerBefore() const noexcept { return euler_before_; }
  // After run(): cutFailure (run_report.h), else "no groove was opened" when no groove was, else "".
  std::string failure() const;
  // After run(), with `cut` = mesh::summarize(mesh()) (O(V + E log E): made once by the caller): the mesh is a
  // closed two-manifold with the Euler characteristic it had, and no failure.
  bool ok(const mesh::MeshSummary& cut) const;
  // summary.json's document: the options, what the cutter did (counts, per incision figures), the mesh's
  // summary `cut`, the Euler characteristic before, samples, per-sample timings and the failure ("" if none).
  nlohmann::json summary(const mesh::MeshSummary& cut) const;

 private:
  CutJobOptions options_;
  std::unique_ptr<mesh::SurfaceMesh> mesh_;  // a stable address: the cutter keeps a reference
  int euler_before_ = 0;
  incision::Stroke stroke_;
  std::unique_ptr<incision::SurfaceCutter> cutter_;
  std::vector<double> sample_us_;
  int skipped_ = 0;
};

}  // namespace incise::jobs
