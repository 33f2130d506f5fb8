// The simulated world: the tissue (a surface mesh cut by local DFFD incisions) and the scalpel, advanced
// one frame at a time by the sim thread (ARCHITECTURE.md, "Data flow and threads", steps 1-3).
//
// A frame is two calls, so that the caller can time them separately without the world reading a clock:
//   updateTool(poses, dt_s)  every pose that arrived this frame, oldest first: the tool moves to each in
//                            turn; contact with the tissue is found for each (the blade's last
//                            depth + 2 mm as a segment towards its tip, against the skin through the
//                            cutter's spatial index: wound walls are left out, so a blade crossing an
//                            open groove is in its air, lifts out of the incision, and starts a new one
//                            at the far lip); each pose in contact with the cut button held becomes a
//                            stroke sample (the entry point, the surface normal, the pose's time); the
//                            haptic force is computed from the newest pose: a penalty spring along the
//                            contact normal with damping, plus a constant cutting resistance against the
//                            blade's tangential motion while it cuts, clamped to max_force_N;
//   cut(t_s)                 the cutter's carried work for this frame, bounded by the work budget derived
//                            from cut_budget_us, and the wound's opening at time t_s; then, with a tet
//                            tissue, the tet cutter's work for the same incision under the same budget.
// The cut depends only on the pose samples (their positions and times), never on which frame handled
// them: replaying a trace as fast as possible or in real time gives the same geometry.
//
// Units: metres, seconds, newtons. The blade points along the tool's local -z axis (the tip is the pose
// position) and its cutting edge faces the local +x axis (the stroke direction at first contact).
// Threads: one owner, the sim thread. Cost: updateTool O(poses * vertices near the blade); cut as
// SurfaceCutter under its budget. Allocation: none per frame beyond the cutter's mesh growth (reserved).
// Failure: the constructor throws (std::invalid_argument for bad parameters, cutting::MeshError for a
// tissue that is not a closed two-manifold, intersects itself or that TetGen refuses); updateTool and cut never throw (bad poses are skipped and
// counted).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/cutting/surface_cutter_options.h"
#include "incise/cutting/tet_cutter_options.h"
#include "incise/cutting/tetrahedralize_options.h"
#include "incise/devices/pose_sample.h"

// OpenMesh stays out of sim's public headers: the tissue and its cutters are held through pointers, and
// a caller that reads them includes incise/cutting/surface_mesh.h, surface_cutter.h or tet_cutter.h.
namespace incise::cutting {
class SurfaceMesh;
class SurfaceCutter;
class TetCutter;
}  // namespace incise::cutting

namespace incise::sim {

struct ToolOptions {
  double blade_length_m = 0.03;  // from the handle end of the blade to its tip
  int cut_button = -1;           // the button bit that enables cutting; -1: the blade always cuts
};

struct TissueOptions {
  double stiffness_N_per_m = 400.0;   // penalty spring along the contact normal
  double damping_N_s_per_m = 2.0;     // against the normal velocity while in contact
  double cutting_resistance_N = 0.6;  // against the tangential motion while cutting
  double max_force_N = 8.0;           // the haptic device's limit: forces are clamped to it
};

// The tissue's volume: tetrahedralised from the surface at load (TetGen) and cut by the same incisions.
struct TetTissueOptions {
  bool enabled = false;
  cutting::TetrahedralizeOptions mesh;
  cutting::TetCutterOptions cutter;  // its per-call budget comes from cut_budget_us: half of it, the
                                     // surface cutter getting the other half
};

struct WorldOptions {
  cutting::CutterOptions cutter;
  TetTissueOptions tets;
  ToolOptions tool;
  TissueOptions tissue;
  double cut_budget_us = 300.0;   // per-frame time for cutting work, turned into an inversion budget
  double us_per_inversion = 2.0;  // the conversion (measured on the reference machine; see README)
};

struct HapticState {
  bool contact = false;      // the blade's tip is below the surface
  bool cutting = false;      // ... and the cut button is held (or cutting needs none)
  double penetration_m = 0;  // tip depth below the surface along the normal
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact_m = Eigen::Vector3d::Zero();  // where the blade enters the surface
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // the tool's (blade along local -z)
  int poses = 0;                                                    // poses used this frame
  int poses_rejected = 0;                                           // non-finite or not after the previous one in time
};

struct StepResult {
  HapticState haptic;
  cutting::CutStep cut;
};

class World {
 public:
  World(cutting::SurfaceMesh tissue, const WorldOptions& options);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  // One whole frame at time t_s: updateTool(poses, dt_s) then cut(t_s). Callers that time the two
  // parts (Simulation) call them separately.
  StepResult step(std::span<const devices::PoseSample> poses, double dt_s, double t_s) noexcept {
    StepResult result;
    result.haptic = updateTool(poses, dt_s);
    result.cut = cut(t_s);
    return result;
  }

  HapticState updateTool(std::span<const devices::PoseSample> poses, double dt_s) noexcept;
  cutting::CutStep cut(double t_s) noexcept;

  const cutting::SurfaceMesh& tissue() const noexcept { return *tissue_; }
  const cutting::SurfaceCutter& cutter() const noexcept { return *cutter_; }
  const WorldOptions& options() const noexcept { return options_; }
  int incisions() const noexcept;
  // The tissue's tets and their cutter; nullptr unless options.tets.enabled.
  const cutting::TetCutter* tets() const noexcept { return tets_.get(); }
  // The cutters' change journals (the surface's cutting::MeshChanges here, the tets' in tets()->changes()),
  // for a reader of the geometry (GeometryStream): off by default; recordMeshChanges(true) reserves their
  // room (load time, allocates); clearMeshChanges() clears both.
  void recordMeshChanges(bool on);
  const cutting::MeshChanges& meshChanges() const noexcept;
  void clearMeshChanges() noexcept;

 private:
  void contact(const devices::PoseSample& pose, HapticState& state) noexcept;
  void followTets(cutting::TetBudget budget) noexcept;
  Eigen::Vector3d force(const HapticState& state, const Eigen::Vector3d& velocity_m_per_s) const noexcept;

  std::unique_ptr<cutting::SurfaceMesh> tissue_;  // stable address: the cutter keeps a reference
  std::unique_ptr<cutting::SurfaceCutter> cutter_;
  std::unique_ptr<cutting::TetCutter> tets_;
  WorldOptions options_;
  devices::PoseSample last_pose_{};
  bool has_pose_ = false;
  Eigen::Vector3d velocity_m_per_s_ = Eigen::Vector3d::Zero();
};

}  // namespace incise::sim
