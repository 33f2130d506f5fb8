// The simulated world: the tissue (a surface mesh, and with `tets` a tet mesh too, cut by local DFFD
// incisions, paper §4; with `physics` the tets are simulated, tissue_physics.h) and the scalpel, advanced one
// frame at a time by the sim thread in calls that the caller times apart without the world reading a clock:
// updateTool() (the haptic part), cut() (the cut phase), then stepPhysics() (a simulated tissue's steps,
// inline or handed to its physics thread). The cut depends only on the pose samples and their order, never on
// which frame handled them: a trace replayed as fast as possible or in real time gives the same geometry
// (ARCHITECTURE.md, "One frame").
//
// Units: metres, seconds, newtons. The blade points along the tool's local -z axis (the tip is the pose
// position) and its cutting edge faces the local +x axis (the stroke direction at first contact).
// Threads: one owner, the sim thread; the world starts one worker of its own that computes a through-cut's
// Boolean difference when cut() runs against the clock (ARCHITECTURE.md, "Data flow and threads"). Cost: updateTool O(poses + ContactProxy::kCapacity); cut as
// SurfaceCutter under its budget plus one exact contact per pose and, now and then, a proxy refill.
// Allocation: the queue and the proxy at construction; per frame none beyond the cutters' own. Failure: the
// constructor throws (std::invalid_argument for bad parameters, mesh::MeshError for a tissue that is not a
// closed two-manifold, intersects itself or that TetGen refuses); updateTool and cut never throw.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/core/work_budget.h"
#include "incise/devices/pose_sample.h"
#include "incise/incision/surface_cutter_options.h"
#include "incise/sim/contact_proxy.h"
#include "incise/sim/pose_queue.h"
#include "incise/sim/tissue_physics.h"
#include "incise/tets/tet_cutter_options.h"
#include "incise/tets/tetrahedralize_options.h"

// OpenMesh stays out of sim's public headers: the tissue and its cutters are held through pointers, and
// a caller that reads them includes incise/mesh/surface_mesh.h, surface_cutter.h or tet_cutter.h.
namespace incise::mesh {
class SurfaceMesh;
}
namespace incise::incision {
class SurfaceCutter;
}
namespace incise::tets {
class TetCutter;
}

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
  tets::TetrahedralizeOptions mesh;
  tets::TetCutterOptions cutter;  // its per-call budget comes from cut_budget_us: half of it, the
                                  // surface cutter getting the other half
};

struct WorldOptions {
  incision::CutterOptions cutter;
  TetTissueOptions tets;
  PhysicsOptions physics;  // enabled: the tets are simulated (needs tets.enabled)
  ToolOptions tool;
  TissueOptions tissue;
  double cut_budget_us = 300.0;   // per-frame time for cutting work, turned into an inversion budget
  double us_per_inversion = 2.0;  // the conversion (measured on the reference machine; see README)
};

struct HapticState {
  bool contact = false;      // the blade's tip is below the surface
  bool cutting = false;      // ... and the cut button is held (or cutting needs none)
  double penetration_m = 0;  // tip depth below the surface along the normal (a simulated tissue pressed
                             // without cutting: below the dented skin, in the world, with the dent's normal)
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact_m = Eigen::Vector3d::Zero();  // where the blade enters the surface
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // the tool's (blade along local -z)
  // The same pose as the device gave it, in the world. A simulated tissue's tip_m, orientation, contact_m
  // and normal are in its rest frame (where its surface and the incision are), these where the tool is
  // among the deformed tissue; without one they are tip_m and orientation.
  Eigen::Vector3d world_tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond world_orientation = Eigen::Quaterniond::Identity();
  int poses = 0;            // poses used this frame
  int poses_rejected = 0;   // non-finite, not after the previous one in time, or the queue full
  bool swept = false;       // the contact came from the swept test (the probe itself was through the skin)
  bool proxy_miss = false;  // the probe was outside the proxy's region: no contact could be found this frame
};

// What the world counted since it was made (the haptic part's proxy and the cut phase's queue).
struct WorldCounters {
  std::int64_t proxy_misses = 0;      // haptic frames whose probe was outside the proxy (the tool jumped)
  std::int64_t proxy_refills = 0;     // cut phases that refilled it
  std::int64_t proxy_overflows = 0;   // refills that found more than ContactProxy::kCapacity faces
  int proxy_largest = 0;              // the most faces a refill found
  std::int64_t swept_contacts = 0;    // haptic contacts found by the swept test
  std::int64_t waits = 0;             // incisions that waited for the previous one's work
  std::int64_t waited_frames = 0;     // cut phases spent on that work
  std::int64_t catch_ups = 0;         // cut phases that did it at once (the queue over half full)
  std::int64_t poses_overflowed = 0;  // poses rejected because the queue was full
  int queue_peak = 0;                 // the most poses queued at the start of a cut phase
  // Arrays the surface cutter (incision.reserve_vertices) or the tet cutter (TetCutter::kHeadroomNodes) grew
  // past the room reserved at load: each an allocation on the sim thread (0 in every shipped scenario:
  // tests/sim/alloc_free_test.cpp).
  std::int64_t reserve_overflows = 0;
  // Cut phases whose budgeted work stopped at their deadline (real time only: World::cut's `deadline`).
  std::int64_t deadline_stops = 0;
};

struct StepResult {
  HapticState haptic;
  incision::CutStep cut;
};

class World {
 public:
  World(mesh::SurfaceMesh tissue, const WorldOptions& options);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  // One whole frame at time t_s: updateTool(poses, dt_s), cut(t_s), then stepPhysics(t_s). Callers that
  // time the parts (Simulation) call them separately.
  StepResult step(std::span<const devices::PoseSample> poses, double dt_s, double t_s) noexcept {
    StepResult result;
    result.haptic = updateTool(poses, dt_s);
    result.cut = cut(t_s);
    stepPhysics(t_s);
    return result;
  }

  // The haptic part, and nothing else: every pose that arrived this frame, oldest first, is checked
  // (non-finite, or not after the previous one in time: skipped and counted), taken to the rest frame when
  // the tissue is simulated (TissuePhysics::restMapAt: the tissue's surface and the incision are at rest;
  // O(1), never waiting) and queued for the cut phase; then one contact, from the newest pose, against the
  // ContactProxy (contact_proxy.h: a few hundred skin triangles around the blade that the cut phase keeps
  // current), the blade's last depth + 2 mm as a segment towards its tip, and when that finds nothing a swept
  // test from the previous frame's tip to this one (a fast stroke cannot tunnel through the skin); the
  // haptic force: a penalty spring along the contact normal with damping, plus a constant cutting
  // resistance against the blade's tangential motion while it cuts, clamped to max_force_N. No mesh, no grid, no cutting work: O(poses + proxy triangles), a few
  // microseconds. The poses queue in a fixed PoseQueue (kQueuedPoses): a pose that finds it full (more than
  // kQueuedPoses in one call) is rejected and counted.
  HapticState updateTool(std::span<const devices::PoseSample> poses, double dt_s) noexcept;
  // The part of cut_budget_us the surface cutter may spend: all of it, or half with tets (the other half is
  // the tets' inversion budget).
  double surfaceCutBudgetUs() const noexcept {
    return options_.tets.enabled ? 0.5 * options_.cut_budget_us : options_.cut_budget_us;
  }
  // The cut phase: the queued poses in order, each with its exact contact against the skin
  // (SurfaceCutter::intersect, wound walls left out: a blade crossing an open groove is in its air and starts
  // a new incision at the far lip); a pose in contact with the cut button held is a stroke sample (entry
  // point, normal, time). A pose that starts an incision while the previous one still has work (columns not
  // cut, the wound not settled or not re-indexed, the tets behind) waits, with every pose after it, while that
  // work is done within this and later frames' budgets, and begins it then: the same geometry as when begin()
  // does the previous incision's work at once. First the proxy is refilled around the newest pose when the
  // blade nears its edge (inside the frame's deadline); then the cutter's carried work for this frame (the
  // budget from cut_budget_us) and the wound's opening at t_s, the tets' work for the same incision under the
  // same budget; last the proxy again when a new incision (or PN refinement) changed the skin at rest. A cut
  // phase that starts with the pose queue over half full does the waiting work at once, whatever the budget
  // (counted in counters().catch_ups: the same geometry).
  //
  // `deadline`: when the surface cutter's budgeted work stops (against the clock: surfaceCutBudgetUs() after
  // the cut phase began); time_point::max(): the inversion budget alone (fast replays, tests). Where the
  // work stops never changes the surface's bytes. The tets keep to their inversion budget only: their nodes
  // still depend on how their work falls into calls (a known bug, tests/sim/replay_test.cpp), and a deadline
  // would make that depend on the machine's speed too.
  incision::CutStep cut(
      double t_s, core::WorkBudget::Clock::time_point deadline = core::WorkBudget::Clock::time_point::max()) noexcept;
  // The simulated tissue's part of the frame, after cut(): every physics step due at t_s, each after the
  // tets' changes cut() collected before it (tissue_physics.h): taken here, or handed to the physics thread
  // when one runs (TissuePhysics::startThread). Returns the steps made due (0 without a simulated tissue).
  // Never throws.
  int stepPhysics(double t_s) noexcept {
    if (!physics_) return 0;
    const int due = physics_->advance(t_s, &track_);
    physics_->awaitMaps();  // a fast replay: the next frame's poses find their maps made
    return due;
  }
  // The simulated tissue; nullptr unless options.physics.enabled. The mutable one starts and stops its
  // thread (Simulation's replays and live sessions).
  const TissuePhysics* physics() const noexcept { return physics_.get(); }
  TissuePhysics* physics() noexcept { return physics_.get(); }
  // Cutting work left for later frames: queued poses, an incision waiting to begin, or columns not cut.
  bool pending() const noexcept;
  // Poses the haptic part took (HapticState::poses) that the cut phase has not handled yet: how far the cut
  // lags the tool, in poses. O(1).
  std::size_t queuedPoses() const noexcept;
  const WorldCounters& counters() const noexcept { return counters_; }
  static constexpr std::size_t kQueuedPoses = 8192;
  // The proxy's reach: a refill is due when the blade comes within half the reach of the region's edge, and
  // the next refill comes a frame later, or later still when the frame starts late. So the reach is
  // 2 x speed x (period + lateness) for a blade moving kProxySpeedMPerS with frames up to kProxyLateS late:
  // 2 mm at 1 kHz, 1.25 mm at 4 kHz. A refill's faces grow with the region's width squared (the probe plus
  // twice the reach): bunny-crossing's largest refill is 798 faces at a 4 mm reach and 417 at 2 mm, its
  // frame p99 290-300 and 220 us; at 0.5 mm (4 kHz) the tool leaves the region more often
  // (docs/benchmarks.md, "the contact proxy's refill inside the deadline"). A frame that starts later still
  // (the machine busy) finds the tool moved further: the reach is at least twice the last frame's motion,
  // that motion taken at most kProxySpeedMPerS over the poses' time (World::noteToolMotion), so the next
  // frame, as late, still finds its contact.
  static constexpr double kProxySpeedMPerS = 0.5, kProxyLateS = 0.001;
  static constexpr double kProxyReachMinM = 0.0005, kProxyReachMaxM = 0.02;
  // From the period updateTool was last given (1 kHz before the first) and the tool's motion in that frame.
  double proxyReachM() const noexcept;

  const mesh::SurfaceMesh& tissue() const noexcept { return *tissue_; }
  const incision::SurfaceCutter& cutter() const noexcept { return *cutter_; }
  const WorldOptions& options() const noexcept { return options_; }
  int incisions() const noexcept;
  // The tissue's tets and their cutter; nullptr unless options.tets.enabled.
  const tets::TetCutter* tets() const noexcept { return tets_.get(); }
  // The cutters' change journals (the surface's incision::MeshChanges here, the tets' in tets()->changes()),
  // for a reader of the geometry (GeometryStream): off by default; recordMeshChanges(true) reserves their
  // room (load time, allocates); clearMeshChanges() clears both.
  void recordMeshChanges(bool on);
  const incision::MeshChanges& meshChanges() const noexcept;
  void clearMeshChanges() noexcept;

 private:
  struct Contact {
    bool contact = false, cutting = false;
    double penetration_m = 0.0;
    Eigen::Vector3d point_m = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
  };
  Eigen::Vector3d handleOf(const devices::PoseSample& pose) const noexcept;  // the probe's far end
  bool buttonDown(const devices::PoseSample& pose) const noexcept;
  Contact exactContact(const devices::PoseSample& pose) const noexcept;  // cut phase: SurfaceCutter::intersect
  Contact contactAt(const devices::PoseSample& pose, const Eigen::Vector3d& point_m,
                    const Eigen::Vector3d& normal) const noexcept;  // the tip's penetration at a skin point
  void hapticContact(const devices::PoseSample& pose, HapticState& state) noexcept;  // the proxy
  // A simulated tissue: where a (rest-frame) pose's tool presses the skin without cutting in (the proxy),
  // the skin point it first touched while it keeps pressing (press_).
  ToolPress pressOf(const devices::PoseSample& pose) noexcept;
  // A simulated tissue pressed: the contact is the dent's, in the world (TissuePhysics::pressPointAt);
  // false (state untouched) when the tool is not pressing or the press's steps are not mapped yet.
  bool pressContact(HapticState& state) noexcept;
  void noteToolMotion() noexcept;               // tool_motion_m_ from last_pose_ and the last haptic frame
  bool takeQueuedPoses(bool at_once) noexcept;  // false: an incision waits for the previous one's work
  // A new incision from this sample, begun once the previous one's work is done (takeQueuedPoses).
  void queueBegin(const incision::StrokeSample& sample, const devices::PoseSample& pose) noexcept;
  void cutPose(const devices::PoseSample& pose) noexcept;
  bool readyToBegin(bool at_once) noexcept;
  void refreshProxy() noexcept;
  void followTets(tets::TetBudget budget) noexcept;
  void collectTetChanges() noexcept;  // the tets' journal into the physics' change buffer
  // A simulated tissue: the pose's blade (tip and axis) taken to the rest frame (TissuePhysics::restMapAt).
  devices::PoseSample toRestFrame(const devices::PoseSample& pose) noexcept;
  Eigen::Vector3d force(const HapticState& state, const Eigen::Vector3d& velocity_m_per_s) const noexcept;

  // The through-cut's worker (SurfaceCutter::setThroughOnWorker): first, so a move-assignment ends it
  // before the cutter it reads is replaced; ~World() ends it before anything else.
  class ThroughWorker;
  std::unique_ptr<ThroughWorker> through_worker_;
  std::unique_ptr<mesh::SurfaceMesh> tissue_;  // stable address: the cutter keeps a reference
  std::unique_ptr<incision::SurfaceCutter> cutter_;
  std::unique_ptr<tets::TetCutter> tets_;
  std::unique_ptr<TissuePhysics> physics_;
  ToolTrack track_;                    // the tool's tips in the world, for the physics' rest maps
  ToolPress press_;                    // the newest pose's press (pressOf)
  std::optional<ProxyHit> press_hit_;  // ... and its crossing with the proxy's skin, for the haptic contact
  double press_hit_time_s_ = std::numeric_limits<double>::quiet_NaN();
  bool stream_records_ = false;  // a geometry reader owns the journals (recordMeshChanges(true))
  WorldOptions options_;
  double probe_m_ = 0.0;  // the blade's part that can meet the skin: its depth + 2 mm (at most its length)
  // The haptic part's state: the newest pose, the tool's velocity, the previous frame's tip.
  devices::PoseSample last_pose_{};      // in the rest frame (a simulated tissue's)
  devices::PoseSample last_raw_pose_{};  // as the device gave it
  bool has_pose_ = false;
  Eigen::Vector3d velocity_m_per_s_ = Eigen::Vector3d::Zero();        // the rest frame's
  Eigen::Vector3d world_velocity_m_per_s_ = Eigen::Vector3d::Zero();  // the device's
  Eigen::Vector3d haptic_tip_m_ = Eigen::Vector3d::Zero();            // the tool as the last haptic frame saw it
  Eigen::Vector3d haptic_handle_m_ = Eigen::Vector3d::Zero();         // its probe's other end
  double haptic_time_s_ = 0.0;
  bool has_haptic_tip_ = false;
  double tool_motion_m_ = 0.0;  // since the haptic frame before (noteToolMotion), for the proxy's reach
  std::unique_ptr<ContactProxy> proxy_;
  // The cut phase's queue (the project's PoseQueue, here with one thread at both ends) and the incision that
  // waits to begin.
  std::unique_ptr<PoseQueue<kQueuedPoses>> queued_;
  bool begin_waiting_ = false, surface_settled_ = false, wait_counted_ = false;
  incision::StrokeSample begin_sample_{};
  Eigen::Vector3d begin_direction_ = Eigen::Vector3d::UnitX();
  double period_s_ = 0.001;  // the frame period updateTool was last given (the proxy's reach)
  int proxy_refined_ = 0;    // the cutter's refined vertices at the last refill (PN midpoints move the skin)
  WorldCounters counters_;
};

}  // namespace incise::sim
