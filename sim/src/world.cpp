#include "incise/sim/world.h"

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/tets/tet_cutter.h"
#include "incise/tets/tetrahedralize.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <semaphore>
#include <stdexcept>
#include <string>
#include <thread>

namespace incise::sim {

namespace {

void requireNonNegative(double value, const char* name) {
  if (!(std::isfinite(value) && value >= 0.0))
    throw std::invalid_argument(std::string("World: ") + name + " = " + std::to_string(value) +
                                " must be finite and >= 0");
}

// The frame's cutting work in inversions (about us_per_inversion each): all of it for the surface, or half
// for the surface and half for the tets when the tissue has them.
int workBudget(const WorldOptions& options) {
  const int total = std::max(1, static_cast<int>(options.cut_budget_us / options.us_per_inversion));
  return options.tets.enabled ? std::max(1, total / 2) : total;
}

// The surface cutter's options in this world: the frame's budget, and no local refinement in a tet tissue
// (the tets are not bisected with it yet: the surface must keep matching their boundary; loadTissue refuses
// a tet tissue too coarse to be cut without it).
incision::CutterOptions withBudget(incision::CutterOptions cutter, const WorldOptions& options) {
  cutter.max_inversions_per_call = workBudget(options);
  if (options.tets.enabled) cutter.refine = incision::CutterOptions::Refine::Off;
  return cutter;
}

// A tet tissue is cut without local refinement (withBudget), so one whose surface (the tets' boundary, which
// TetGen keeps) is coarse next to the lattice is refused at load rather than cut into a groove that falls
// short: its mean edge must be at most half the lattice's width across the cut, where a face the cut
// crosses still has vertices inside the lattice. Checked after TetGen, so a broken surface (open,
// self-intersecting) is reported as such first. Throws std::invalid_argument.
void requireFineTets(const mesh::SurfaceMesh& tissue, const tets::TetCutter& tets,
                     const incision::IncisionOptions& lattice) {
  const double width_m = (lattice.across_controls - 1) * lattice.alpha_m;
  const mesh::EdgeLengths edges = mesh::edgeLengths(tissue.mesh());
  if (edges.mean_m <= 0.5 * width_m) return;
  char text[640];
  std::snprintf(text, sizeof text,
                "the tet tissue (tissue.tets) is coarse next to the lattice: its boundary's edges are %.2f mm on "
                "average (longest %.2f mm), its tets' median edge %.2f mm, the lattice %.2f mm across the cut; local "
                "refinement does not split tets yet, so a tet tissue's surface must have a mean edge of at most "
                "%.2f mm: raise tissue.subdivide or give a finer mesh",
                1e3 * edges.mean_m, 1e3 * edges.longest_m, 1e3 * tets.medianEdgeM(), 1e3 * width_m,
                1e3 * 0.5 * width_m);
  throw std::invalid_argument(std::string("World: ") + text);
}

}  // namespace

// A thread that computes the surface cutter's through-cuts (SurfaceCutter::computeThrough: one CGAL
// Boolean difference, O(mesh), allocating) while the sim thread goes on with its frames; the sim thread
// applies the result in a later frame. post() wakes it (a semaphore's release: no wait, no allocation).
class World::ThroughWorker {
 public:
  explicit ThroughWorker(incision::SurfaceCutter& cutter) : cutter_(cutter), thread_([this] { run(); }) {}
  ~ThroughWorker() {
    stop_.store(true, std::memory_order_release);
    wake_.release();
    thread_.join();
  }
  ThroughWorker(const ThroughWorker&) = delete;
  ThroughWorker& operator=(const ThroughWorker&) = delete;
  void post() noexcept { wake_.release(); }

 private:
  void run() {
    while (true) {
      wake_.acquire();
      if (stop_.load(std::memory_order_acquire)) return;
      cutter_.computeThrough();
    }
  }
  incision::SurfaceCutter& cutter_;
  std::counting_semaphore<> wake_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: started once the rest is built
};

World::World(mesh::SurfaceMesh tissue, const WorldOptions& options) : options_(options) {
  requireNonNegative(options.tissue.stiffness_N_per_m, "stiffness_N_per_m");
  requireNonNegative(options.tissue.damping_N_s_per_m, "damping_N_s_per_m");
  requireNonNegative(options.tissue.cutting_resistance_N, "cutting_resistance_N");
  requireNonNegative(options.tissue.max_force_N, "max_force_N");
  if (!(options.tool.blade_length_m > 0.0 && std::isfinite(options.tool.blade_length_m)))
    throw std::invalid_argument("World: blade_length_m must be finite and > 0");
  if (options.tool.cut_button < -1 || options.tool.cut_button > 31)
    throw std::invalid_argument("World: cut_button = " + std::to_string(options.tool.cut_button) +
                                " is outside [-1, 31]");
  if (!(options.cut_budget_us > 0.0 && options.us_per_inversion > 0.0))
    throw std::invalid_argument("World: cut_budget_us and us_per_inversion must be > 0");
  probe_m_ = std::min(options.tool.blade_length_m, options.cutter.incision.depth_m + 0.002);
  queued_ = std::make_unique<PoseQueue<kQueuedPoses>>();
  proxy_ = std::make_unique<ContactProxy>();
  tissue_ = std::make_unique<mesh::SurfaceMesh>(std::move(tissue));
  cutter_ = std::make_unique<incision::SurfaceCutter>(*tissue_, withBudget(options.cutter, options));
  through_worker_ = std::make_unique<ThroughWorker>(*cutter_);
  if (options.physics.enabled && !options.tets.enabled)
    throw std::invalid_argument("World: a simulated tissue (physics) needs its tets (tets.enabled)");
  if (options.tets.enabled) {
    tets::TetCutterOptions tet_options = options.tets.cutter;
    tet_options.max_inversions_per_call = workBudget(options);
    tets::TetMesh mesh = tets::tetrahedralize(*tissue_, options.tets.mesh);
    // The model is built from the cutter's load mesh (same node and tet order) and follows its journal.
    if (options.physics.enabled) {
      PhysicsOptions physics = options.physics;
      physics.press_stiffness_N_per_m = options.tissue.stiffness_N_per_m;  // the haptic force's spring
      physics_ = std::make_unique<TissuePhysics>(mesh, physics);
    }
    tets_ = std::make_unique<tets::TetCutter>(std::move(mesh), tet_options);
    requireFineTets(*tissue_, *tets_, options.cutter.incision);
    tets_->prepare(options.cutter.incision);  // the sim thread then allocates nothing for the first incision
    if (physics_) tets_->recordChanges(true);
  }
}

World::~World() { through_worker_.reset(); }
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

int World::incisions() const noexcept { return cutter_->stats().incisions; }

void World::recordMeshChanges(bool on) {
  // The tets' journal stays on for the physics; the physics has read it all (cut() collects), and it is
  // cleared here.
  stream_records_ = on;
  cutter_->recordChanges(on);
  if (tets_) tets_->recordChanges(on || physics_ != nullptr);
  if (physics_) physics_->journalCleared();
}
const incision::MeshChanges& World::meshChanges() const noexcept { return cutter_->changes(); }
void World::clearMeshChanges() noexcept {
  cutter_->clearChanges();
  if (tets_) tets_->clearChanges();
  if (physics_) physics_->journalCleared();
}

void World::collectTetChanges() noexcept {
  if (!physics_) return;
  physics_->collect(*tets_);
  if (!stream_records_) {  // no other reader: the journal is the physics' alone
    tets_->clearChanges();
    physics_->journalCleared();
  }
}

void World::followTets(tets::TetBudget budget) noexcept {
  if (tets_ && cutter_->incision()) tets_->follow(*cutter_->incision(), cutter_->stats().incisions, budget);
}

Eigen::Vector3d World::handleOf(const devices::PoseSample& pose) const noexcept {
  // Only the blade's last part can meet the surface while it cuts (the tip is at most a little deeper
  // than the cut): probing that part keeps the query local.
  return pose.tip_m - probe_m_ * (pose.orientation * Eigen::Vector3d(0.0, 0.0, -1.0));
}

bool World::buttonDown(const devices::PoseSample& pose) const noexcept {
  return options_.tool.cut_button < 0 || ((pose.buttons >> options_.tool.cut_button) & 1u) != 0;
}

World::Contact World::exactContact(const devices::PoseSample& pose) const noexcept {
  std::optional<mesh::SurfacePoint> hit;
  try {
    // The whole blade: where it enters the skin however deep the tip is (its depth is clamped, not lost).
    const Eigen::Vector3d handle =
        pose.tip_m - options_.tool.blade_length_m * (pose.orientation * Eigen::Vector3d(0.0, 0.0, -1.0));
    hit = cutter_->intersect(handle, pose.tip_m);
  } catch (...) {  // allocation in the grid query: treat as no contact this pose
    hit.reset();
  }
  return hit ? contactAt(pose, hit->point_m, hit->normal) : Contact{};
}

World::Contact World::contactAt(const devices::PoseSample& pose, const Eigen::Vector3d& point_m,
                                const Eigen::Vector3d& normal) const noexcept {
  Contact c;
  c.penetration_m = std::max(0.0, (point_m - pose.tip_m).dot(normal));
  c.contact = c.penetration_m > 0.0;
  c.point_m = point_m;
  c.normal = normal;
  c.cutting = c.contact && buttonDown(pose);
  return c;
}

void World::hapticContact(const devices::PoseSample& pose, HapticState& state) noexcept {
  const Eigen::Vector3d handle = handleOf(pose);
  state.tip_m = pose.tip_m;
  state.orientation = pose.orientation;
  if (!proxy_->covers(handle, pose.tip_m)) {
    state.proxy_miss = true;
    ++counters_.proxy_misses;
    return;
  }
  // The pose's crossing was found for its press already (a simulated tissue: pressOf, the same pose).
  std::optional<ProxyHit> hit =
      physics_ && pose.time_s == press_hit_time_s_ ? press_hit_ : proxy_->firstCrossing(handle, pose.tip_m);
  const Eigen::Vector3d moved = pose.tip_m - haptic_tip_m_;
  if (!hit && has_haptic_tip_ && moved.squaredNorm() > 0.0 && proxy_->covers(haptic_tip_m_, pose.tip_m)) {
    hit = proxy_->firstCrossing(haptic_tip_m_, pose.tip_m);  // the tip went through the skin since last frame
    if (hit && hit->normal.dot(moved) >= 0.0) hit.reset();   // ... inwards
    state.swept = hit.has_value();
    if (state.swept) ++counters_.swept_contacts;
  }
  if (!hit) return;
  const Contact c = contactAt(pose, hit->point_m, hit->normal);
  state.penetration_m = c.penetration_m;
  state.contact = c.contact;
  state.contact_m = c.point_m;
  state.normal = c.normal;
  state.cutting = c.cutting;
}

ToolPress World::pressOf(const devices::PoseSample& pose) noexcept {
  const Eigen::Vector3d handle = handleOf(pose);
  std::optional<ProxyHit>& hit = press_hit_;
  hit.reset();
  if (proxy_->covers(handle, pose.tip_m)) hit = proxy_->firstCrossing(handle, pose.tip_m);
  press_hit_time_s_ = pose.time_s;
  const Contact c = hit ? contactAt(pose, hit->point_m, hit->normal) : Contact{};
  // A blade deep enough to cut (World::cutPose's rule) is in the tissue, not pressing on it.
  if (!c.contact || (c.cutting && c.penetration_m >= options_.cutter.incision.min_depth_m)) {
    press_ = ToolPress{};
  } else if (!press_.on) {  // a new press: the skin point the tip touched, which sticks to it while it presses
    press_.on = true;
    press_.rest_point_m = c.point_m;
    press_.rest_normal = c.normal;
  }
  return press_;
}

bool World::pressContact(HapticState& state) noexcept {
  if (!press_.on) return false;
  const PressPoint p = physics_->pressPointAt(last_raw_pose_.time_s);
  if (!p.on) return false;  // the press's first steps not mapped yet: the contact at rest
  const double gap_m = (p.point_m - last_raw_pose_.tip_m).dot(p.normal);
  state.contact = gap_m > 0.0;
  state.penetration_m = std::max(0.0, gap_m);
  state.normal = p.normal;
  state.cutting = false;
  return true;
}

Eigen::Vector3d World::force(const HapticState& state, const Eigen::Vector3d& velocity) const noexcept {
  if (!state.contact) return Eigen::Vector3d::Zero();
  const TissueOptions& t = options_.tissue;
  const double normal_speed = velocity.dot(state.normal);
  const double normal_N = std::max(0.0, t.stiffness_N_per_m * state.penetration_m - t.damping_N_s_per_m * normal_speed);
  Eigen::Vector3d f = normal_N * state.normal;
  const Eigen::Vector3d tangential = velocity - normal_speed * state.normal;
  if (state.cutting && tangential.norm() > 1e-6) f -= t.cutting_resistance_N * tangential.normalized();
  const double magnitude = f.norm();
  return magnitude > t.max_force_N ? Eigen::Vector3d(f * (t.max_force_N / magnitude)) : f;
}

devices::PoseSample World::toRestFrame(const devices::PoseSample& pose) noexcept {
  const physics::RestMap map = physics_->restMapAt(pose.time_s);
  if (!map.located) return pose;  // the identity
  devices::PoseSample rest = pose;
  rest.tip_m = map.toRest(pose.tip_m);
  const Eigen::Vector3d blade = pose.orientation * Eigen::Vector3d(0.0, 0.0, -1.0);
  const Eigen::Vector3d mapped = map.directionToRest(blade);
  if (!rest.tip_m.allFinite() || !mapped.allFinite() || !(mapped.norm() > 0.0)) return pose;
  rest.orientation = (Eigen::Quaterniond::FromTwoVectors(blade, mapped) * pose.orientation).normalized();
  return rest;
}

HapticState World::updateTool(std::span<const devices::PoseSample> poses, double dt_s) noexcept {
  HapticState state;
  bool pressing = false;  // the contact is a dent's (pressContact)
  for (const devices::PoseSample& raw : poses) {
    if (!raw.tip_m.allFinite() || !raw.orientation.coeffs().allFinite() || !std::isfinite(raw.time_s) ||
        (has_pose_ && !(raw.time_s > last_pose_.time_s))) {
      ++state.poses_rejected;
      continue;
    }
    // A simulated tissue: the pose in the rest frame, where the tissue's surface and the incision are.
    const devices::PoseSample pose = physics_ ? toRestFrame(raw) : raw;
    if (physics_) track_.record(raw.time_s, raw.tip_m, pressOf(pose));
    if (!queued_->push(pose)) {
      ++state.poses_rejected;
      ++counters_.poses_overflowed;
      continue;
    }
    ++state.poses;
    if (has_pose_) {
      velocity_m_per_s_ = (pose.tip_m - last_pose_.tip_m) / (pose.time_s - last_pose_.time_s);
      world_velocity_m_per_s_ = (raw.tip_m - last_raw_pose_.tip_m) / (raw.time_s - last_raw_pose_.time_s);
    }
    last_pose_ = pose;
    last_raw_pose_ = raw;
    has_pose_ = true;
  }
  if (has_pose_) {  // the newest pose (with none new, the tool stays where it was)
    hapticContact(last_pose_, state);
    pressing = physics_ && pressContact(state);
    state.world_tip_m = last_raw_pose_.tip_m;
    state.world_orientation = last_raw_pose_.orientation;
    noteToolMotion();
    haptic_tip_m_ = last_pose_.tip_m;
    haptic_handle_m_ = handleOf(last_pose_);
    haptic_time_s_ = last_pose_.time_s;
    has_haptic_tip_ = true;
  }
  // A dent's contact is in the world: its damping against the tool's velocity there.
  state.force_N = force(state, pressing ? world_velocity_m_per_s_ : velocity_m_per_s_);
  if (std::isfinite(dt_s) && dt_s > 0.0) period_s_ = dt_s;
  return state;
}

void World::queueBegin(const incision::StrokeSample& sample, const devices::PoseSample& pose) noexcept {
  begin_waiting_ = true;
  begin_sample_ = sample;
  begin_direction_ = pose.orientation * Eigen::Vector3d::UnitX();
}

void World::cutPose(const devices::PoseSample& pose) noexcept {
  const Contact c = exactContact(pose);
  // A blade that only scratches the skin (less than min_depth_m in) makes no groove.
  if (c.cutting && c.penetration_m >= options_.cutter.incision.min_depth_m) {
    const incision::StrokeSample sample{c.point_m, c.normal, pose.time_s, c.penetration_m};
    if (!cutter_->active()) {  // a new incision: it begins once the previous one's work is done
      queueBegin(sample, pose);
    } else if (const incision::SampleStatus status =
                   cutter_->addSample(sample, incision::SampleOrigin::OnSurface).sample;  // on the surface by contact
               (status == incision::SampleStatus::SkippedJump || status == incision::SampleStatus::EndedAtCorner) &&
               !cutter_->active()) {
      // The blade is farther than a step from the stroke for a second pose (poses were lost), or the stroke
      // turned at a corner: the incision ended where it was, and a new one begins here.
      queueBegin(sample, pose);
    }
  } else if (cutter_->active()) {
    cutter_->finish(incision::FinishWork::Later);  // the blade left the tissue (or the button was released)
  }
}

bool World::readyToBegin(bool at_once) noexcept {
  // The previous incision's work in the order begin() did it at once: the surface cut and settled, then
  // the tets caught up with it (a follow after the settle, so they see its final opening).
  if (!surface_settled_) surface_settled_ = cutter_->prepareBegin(at_once);
  if (!surface_settled_) return false;
  if (tets_) {
    followTets(at_once ? tets::TetBudget::All : tets::TetBudget::PerCall);
    if (tets_->pending()) return false;
  }
  surface_settled_ = false;
  return true;
}

bool World::takeQueuedPoses(bool at_once) noexcept {
  while (true) {
    if (begin_waiting_) {
      if (!readyToBegin(at_once)) {
        ++counters_.waited_frames;
        if (!wait_counted_) ++counters_.waits;
        wait_counted_ = true;
        return false;
      }
      cutter_->begin(begin_sample_, begin_direction_);
      begin_waiting_ = wait_counted_ = false;
    }
    devices::PoseSample pose;
    if (!queued_->pop(pose)) return true;
    cutPose(pose);
  }
}

// How far the blade (tip or probe end) moved since the last haptic frame, at most as far as kProxySpeedMPerS
// covers in the poses' time between them: a frame that starts late (the machine busy) finds the tool further
// on, a jump faster than a hand (a trace's strokes, a device re-homing) is not a motion to follow.
void World::noteToolMotion() noexcept {
  tool_motion_m_ = 0.0;
  if (!has_haptic_tip_) return;
  const double moved_m =
      std::max((last_pose_.tip_m - haptic_tip_m_).norm(), (handleOf(last_pose_) - haptic_handle_m_).norm());
  const double gap_s = last_pose_.time_s - haptic_time_s_;
  if (std::isfinite(moved_m) && gap_s > 0.0) tool_motion_m_ = std::min(moved_m, kProxySpeedMPerS * gap_s);
}

double World::proxyReachM() const noexcept {
  const double nominal_m = 2.0 * kProxySpeedMPerS * (period_s_ + kProxyLateS);
  return std::clamp(std::max(nominal_m, 2.0 * tool_motion_m_), kProxyReachMinM, kProxyReachMaxM);
}

void World::refreshProxy() noexcept {
  if (!has_pose_) return;
  const Eigen::Vector3d handle = handleOf(last_pose_);
  const int stamp = cutter_->stats().incisions;
  const bool skin_moved = options_.cutter.refine == incision::CutterOptions::Refine::PnTriangles &&
                          cutter_->stats().refined_vertices != proxy_refined_;
  if (!skin_moved && !proxy_->refillDue(handle, last_pose_.tip_m, stamp)) return;
  proxy_->refill(*cutter_, handle, last_pose_.tip_m, proxyReachM(), stamp);
  proxy_refined_ = cutter_->stats().refined_vertices;
  counters_.proxy_refills = proxy_->refills();
  counters_.proxy_overflows = proxy_->overflows();
  counters_.proxy_largest = proxy_->largest();
}

incision::CutStep World::cut(double t_s, core::WorkBudget::Clock::time_point deadline) noexcept {
  cutter_->setDeadline(deadline);
  // Against the clock a through-cut's Boolean runs on the worker (the frame goes on); else in the frame that
  // makes it, at the same simulated time whatever the machine (a simulated tissue's motion depends on when
  // the next incision begins).
  cutter_->setThroughOnWorker(through_worker_ && deadline != core::WorkBudget::Clock::time_point::max());
  const std::size_t queued = queued_->sizeApprox();  // exact: this thread is both ends
  counters_.queue_peak = std::max(counters_.queue_peak, static_cast<int>(queued));
  const bool at_once = queued > kQueuedPoses / 2;  // the queue must not fill: do the waiting work now
  if (at_once && begin_waiting_) ++counters_.catch_ups;
  // The proxy first when the blade nears its edge: the refill (a grid query and a copy of a few hundred faces,
  // 50-300 us) then spends the frame's deadline, and the cutting work after it gets what is left, so the two
  // do not add up past the budget. The rest surface it copies is the same before and after this frame's
  // work (the current incision changes it only where its own walls are, which the proxy leaves out).
  refreshProxy();
  incision::CutStep step;
  if (takeQueuedPoses(at_once)) {
    step = cutter_->advance(t_s);
    followTets(tets::TetBudget::PerCall);
  }
  if (through_worker_ && cutter_->postThrough()) through_worker_->post();  // a through-cut to compute
  refreshProxy();  // again only when an incision began in this frame or PN refinement moved the skin
  collectTetChanges();
  if (step.deadline_hit) ++counters_.deadline_stops;
  counters_.reserve_overflows = cutter_->stats().reserve_overflows + (tets_ ? tets_->stats().reserve_overflows : 0);
  return step;
}

bool World::pending() const noexcept { return queued_->sizeApprox() > 0 || begin_waiting_ || cutter_->pending(); }

std::size_t World::queuedPoses() const noexcept { return queued_->sizeApprox(); }

}  // namespace incise::sim
