// Scoring a training session: a recorded trace replayed through the same simulation as
// `incise replay --fast` (sim::replay, ReplayPace::Fast, the scenario's period and settle time), every
// frame's haptic state gathered, then the motion measured (strokes, economy, idle time, force, smoothness:
// Score) and the cut the simulation made measured against the scenario's plan (PlanScore). The same scenario
// and trace give the same score, to the byte (the replay is deterministic).
//
// Units: in every name. Threads: any (the replay runs on the caller's thread). Cost: the replay plus
// O((wall vertices + cutting frames) x plan stations + wall faces), O(frames) for the motion and an FFT per
// stroke (benchmark: 1.1-1.3x the replay for a 60 s session, docs/benchmarks.md). Allocation: a ScoreFrame
// kept per frame. Failure: std::invalid_argument for an empty trace; ScenarioError for a plan that does not
// project (plan.h); mesh::MeshError for a bad tissue (World).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "incise/devices/pose_sample.h"
#include "incise/sim/plan.h"
#include "incise/sim/scenario.h"

namespace incise::mesh {
class SurfaceMesh;
}

namespace incise::sim {

struct ScoreOptions {
  double idle_speed_m_per_s = 0.002;  // slower than this: idle
  double stroke_gap_s = 0.02;         // contact gaps shorter than this do not end a stroke
  double capture_m = 0.0;             // wall vertices farther from the plan are not matched; 0: 5 x lateral tolerance
};

// One frame as the scoring sees it.
struct ScoreFrame {
  double t_s = 0.0;
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  double force_N = 0.0;  // |haptic force|
  bool contact = false;
  bool cutting = false;                                 // in contact with the cut button held
  bool new_pose = false;                                // a pose arrived this frame (the tip moved to it)
  double penetration_m = 0.0;                           // the blade's tip below the skin, along the normal
  Eigen::Vector3d contact_m = Eigen::Vector3d::Zero();  // where the blade enters the skin
};

struct MotionFigures {
  double time_s = 0.0;
  double path_length_m = 0.0;
  double straight_line_m = 0.0;  // first point to last
  double mean_speed_m_per_s = 0.0;
  double log_dimensionless_jerk = 0.0;  // NaN: too short or no movement
  double sparc = 0.0;
};

struct StrokeScore {
  double start_s = 0.0, end_s = 0.0;  // first and last frame in contact
  MotionFigures motion;
  double peak_force_N = 0.0;
};

// The plan's bins along its length, for plots and the figures.
struct PlanBin {
  double s_m = 0.0;  // the bin's centre along the plan
  bool cut = false;
  double lateral_m = 0.0;      // mean offset across the plan (cut bins)
  double depth_m = 0.0;        // deepest wall vertex below the surface (cut bins)
  bool blade_seen = false;     // a cutting frame's entry point fell in this bin
  double blade_depth_m = 0.0;  // the deepest the blade's tip went below the skin there
};

// The cut against the plan (a scenario with "plan"): the plan (plan.h) is cut into bins of at most the
// lattice spacing; the cut's Wall faces (surface_mesh.h: the groove's two walls from the lips down to
// its bottom, as the simulation made them) whose vertices lie within capture_m of the plan and not
// beyond its ends each cover the bins whose centres lie within the face's span along the plan (the
// walls tile the groove, so a bin is cut when a face covers it, whatever the mesh's resolution). A cut
// bin's lateral deviation is the mean offset across the plan of its faces' centroids (the walls open
// symmetrically, so the mean is the groove's centre line), its depth their deepest vertex below the
// plan's surface point (along the plan's normal). Lateral: mean |deviation|, RMS, max over the cut bins;
// share of the plan's length cut within the lateral tolerance; share uncut; length cut outside the band
// = the grooves' total length (CutStats figures) less the length cut within it. Depth: mean |depth -
// target| and max overshoot over the cut bins, share of the plan's length cut within the depth tolerance.
// Beside it, the blade's depth: per bin the deepest the tip went below the skin in the cutting frames
// whose entry point lies in the bin, its mean |error| against the target and its max overshoot.
// A session that cut nothing has share_uncut 1 and shares within tolerance 0.
struct PlanScore {
  double length_m = 0.0, target_depth_m = 0.0, lateral_tolerance_m = 0.0, depth_tolerance_m = 0.0;
  double lateral_mean_abs_m = 0.0, lateral_rms_m = 0.0, lateral_max_m = 0.0;
  double share_within_lateral_tolerance = 0.0, share_uncut = 1.0, length_cut_outside_band_m = 0.0;
  double depth_mean_abs_error_m = 0.0, depth_max_overshoot_m = 0.0, share_within_depth_tolerance = 0.0;
  // The blade's own depth (HapticState::penetration_m) where it cut, against the target: what the hand did,
  // beside the groove it cut (the blade's depth clamped to incision.depth_m, none below min_depth_m).
  double blade_depth_mean_abs_error_m = 0.0, blade_depth_max_overshoot_m = 0.0;
  std::vector<PlanBin> bins;
};

// What is measured of the motion:
//  - strokes: a stroke is a blade-in-tissue interval, a run of frames in contact (HapticState::contact;
//    gaps shorter than stroke_gap_s are bridged). Per stroke and overall: time from first contact to last,
//    path length of the tip in contact, mean speed, peak force, smoothness (smoothness.h: log dimensionless
//    jerk and SPARC of the tip's speed, resampled at the median pose interval).
//  - overall: economy = plan length / path length in contact (with a plan) or, without one, the straight
//    line from the first contact to the last over the path in contact; idle time (the tip slower than
//    idle_speed_m_per_s between the first contact and the last); peak force; time above the tissue's force
//    threshold (scenario tissue.force_threshold_N) and the impulse of the excess, integral of
//    max(0, |F| - threshold) dt.
//  - session (every pose, in contact or not; what a JIGSAWS trace, which never touches the tissue, is
//    scored on): duration, path length, straight line from the first pose to the last, economy = straight
//    / path, smoothness.
struct Score {
  std::string scenario;
  std::int64_t frames = 0, poses = 0;
  int strokes_count = 0;
  std::vector<StrokeScore> strokes;
  double time_s = 0.0;                    // first contact to last
  double path_length_in_contact_m = 0.0;  // sum over the strokes
  double economy = 0.0;                   // plan (or straight line) / path in contact; 0 without contact
  double idle_time_s = 0.0;
  double peak_force_N = 0.0, force_threshold_N = 0.0;
  double time_above_force_threshold_s = 0.0, impulse_above_force_threshold_N_s = 0.0;
  MotionFigures session;
  double groove_length_m = 0.0;  // the simulation's grooves, all incisions (CutStats figures)
  int incisions = 0;
  bool has_plan = false;
  PlanScore plan;
  std::vector<ScoreFrame> frames_seen;  // every frame, for plots
};

// The session of `trace` on `tissue` (the scenario's uncut tissue, loadTissue) scored as Score and PlanScore
// say.
Score scoreSession(const Scenario& scenario, const mesh::SurfaceMesh& tissue,
                   std::span<const devices::PoseSample> trace, const ScoreOptions& options = {});

// The same on a world the caller made over a copy of `tissue` (World(tissue, scenario.world)): the replay
// leaves the cut in it (for a picture of the cut).
Score scoreReplay(const Scenario& scenario, const mesh::SurfaceMesh& tissue, World& world,
                  std::span<const devices::PoseSample> trace, const ScoreOptions& options = {});

// The parts, for tests and for a caller that already has the frames: the strokes and motion figures of a
// run's frames (scenario's force threshold), and the cut in `cut_tissue` against `plan`.
void scoreMotion(const std::vector<ScoreFrame>& frames, const ScoreOptions& options, Score& score);
PlanScore scoreCut(const Plan& plan, const mesh::SurfaceMesh& cut_tissue, double groove_length_m,
                   const ScoreOptions& options);
// The blade's depth per bin from the cutting frames (their entry points located on the plan), into `plan`.
void scoreBladeDepth(const Plan& plan, const std::vector<ScoreFrame>& frames, const ScoreOptions& options,
                     PlanScore& score);

// The score as one line of JSON (no newline), units in every key, NaN as null; the per-frame and per-bin
// series are left out. Same score -> same bytes.
std::string scoreJson(const Score& score);

}  // namespace incise::sim
