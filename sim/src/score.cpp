// The session: the replay that gathers the frames, and the motion figures (strokes, time, path, economy,
// idle time, force, smoothness). The cut against the plan is in score_cut.cpp, the JSON in score_json.cpp.
#include "incise/sim/score.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/simulation.h"
#include "incise/sim/smoothness.h"

namespace incise::sim {

namespace {

// The samples where a pose arrived, in [first, last] (frame indices).
std::vector<const ScoreFrame*> poseFrames(const std::vector<ScoreFrame>& frames, std::size_t first, std::size_t last) {
  std::vector<const ScoreFrame*> out;
  for (std::size_t i = first; i <= last && i < frames.size(); ++i)
    if (frames[i].new_pose) out.push_back(&frames[i]);
  return out;
}

// Positions resampled at the median interval between poses (linear between them), for the smoothness
// measures, which need a fixed interval.
std::vector<Eigen::Vector3d> resampled(const std::vector<const ScoreFrame*>& samples, double& dt_s) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < samples.size(); ++i) gaps.push_back(samples[i]->t_s - samples[i - 1]->t_s);
  std::vector<Eigen::Vector3d> out;
  if (gaps.empty()) return out;
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  dt_s = gaps[gaps.size() / 2];
  const double t0 = samples.front()->t_s, t1 = samples.back()->t_s;
  std::size_t j = 0;
  for (double t = t0; t <= t1 + 1e-12; t = t0 + dt_s * static_cast<double>(out.size())) {
    while (j + 2 < samples.size() && samples[j + 1]->t_s < t) ++j;
    const ScoreFrame& a = *samples[j];
    const ScoreFrame& b = *samples[std::min(j + 1, samples.size() - 1)];
    const double span = b.t_s - a.t_s;
    const double x = span > 0.0 ? std::clamp((t - a.t_s) / span, 0.0, 1.0) : 0.0;
    out.push_back(a.tip_m + x * (b.tip_m - a.tip_m));
  }
  return out;
}

MotionFigures motionOf(const std::vector<const ScoreFrame*>& samples) {
  MotionFigures m;
  if (samples.empty()) return m;
  m.time_s = samples.back()->t_s - samples.front()->t_s;
  for (std::size_t i = 1; i < samples.size(); ++i)
    m.path_length_m += (samples[i]->tip_m - samples[i - 1]->tip_m).norm();
  m.straight_line_m = (samples.back()->tip_m - samples.front()->tip_m).norm();
  m.mean_speed_m_per_s = m.time_s > 0.0 ? m.path_length_m / m.time_s : 0.0;
  double dt_s = 0.0;
  const std::vector<Eigen::Vector3d> uniform = resampled(samples, dt_s);
  const std::vector<double> speed = speedProfile(uniform, dt_s);
  m.log_dimensionless_jerk = logDimensionlessJerk(speed, dt_s);
  m.sparc = spectralArcLength(speed, dt_s);
  return m;
}

// Runs of contact frames, gaps shorter than gap_s bridged: [first, last] frame indices.
std::vector<std::pair<std::size_t, std::size_t>> contactRuns(const std::vector<ScoreFrame>& frames, double gap_s) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!frames[i].contact) continue;
    if (!runs.empty() && frames[i].t_s - frames[runs.back().second].t_s <= gap_s + 1e-12) {
      runs.back().second = i;
    } else {
      runs.emplace_back(i, i);
    }
  }
  return runs;
}

void scoreForce(const std::vector<ScoreFrame>& frames, Score& score) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const double dt_s = i + 1 < frames.size() ? frames[i + 1].t_s - frames[i].t_s : 0.0;
    score.peak_force_N = std::max(score.peak_force_N, frames[i].force_N);
    const double excess_N = frames[i].force_N - score.force_threshold_N;
    if (excess_N > 0.0) {
      score.time_above_force_threshold_s += dt_s;
      score.impulse_above_force_threshold_N_s += excess_N * dt_s;
    }
  }
}

// Idle: pose-to-pose intervals between the first contact and the last (the whole session without contact)
// where the tip moved slower than the threshold.
double idleTime(const std::vector<const ScoreFrame*>& samples, double threshold_m_per_s) {
  double idle_s = 0.0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const double dt_s = samples[i]->t_s - samples[i - 1]->t_s;
    if (dt_s > 0.0 && (samples[i]->tip_m - samples[i - 1]->tip_m).norm() / dt_s < threshold_m_per_s) idle_s += dt_s;
  }
  return idle_s;
}

}  // namespace

void scoreMotion(const std::vector<ScoreFrame>& frames, const ScoreOptions& options, Score& score) {
  if (frames.empty()) return;
  score.session = motionOf(poseFrames(frames, 0, frames.size() - 1));
  const auto runs = contactRuns(frames, options.stroke_gap_s);
  score.strokes.clear();
  for (const auto& [first, last] : runs) {
    StrokeScore stroke;
    stroke.start_s = frames[first].t_s;
    stroke.end_s = frames[last].t_s;
    stroke.motion = motionOf(poseFrames(frames, first, last));
    stroke.motion.time_s = stroke.end_s - stroke.start_s;
    for (std::size_t i = first; i <= last; ++i) stroke.peak_force_N = std::max(stroke.peak_force_N, frames[i].force_N);
    score.path_length_in_contact_m += stroke.motion.path_length_m;
    score.strokes.push_back(stroke);
  }
  score.strokes_count = static_cast<int>(score.strokes.size());
  if (!runs.empty()) {
    score.time_s = frames[runs.back().second].t_s - frames[runs.front().first].t_s;
    score.idle_time_s =
        idleTime(poseFrames(frames, runs.front().first, runs.back().second), options.idle_speed_m_per_s);
    const double straight_m = (frames[runs.back().second].tip_m - frames[runs.front().first].tip_m).norm();
    const double reference_m = score.has_plan ? score.plan.length_m : straight_m;
    score.economy = score.path_length_in_contact_m > 0.0 ? reference_m / score.path_length_in_contact_m : 0.0;
  } else {
    score.idle_time_s = idleTime(poseFrames(frames, 0, frames.size() - 1), options.idle_speed_m_per_s);
  }
  scoreForce(frames, score);
}

Score scoreSession(const Scenario& scenario, const mesh::SurfaceMesh& tissue,
                   std::span<const devices::PoseSample> trace, const ScoreOptions& options) {
  World world(tissue, scenario.world);
  return scoreReplay(scenario, tissue, world, trace, options);
}

Score scoreReplay(const Scenario& scenario, const mesh::SurfaceMesh& tissue, World& world,
                  std::span<const devices::PoseSample> trace, const ScoreOptions& options) {
  if (trace.empty()) throw std::invalid_argument("scoreSession: the trace is empty (no pose to replay)");
  Score score;
  score.scenario = scenario.name;
  score.force_threshold_N = scenario.force_threshold_N;
  Plan plan;
  if (scenario.plan.given) {
    plan = projectPlan(scenario.plan, tissue, scenario.world.cutter.incision.spacing_m, scenario.file);
    score.has_plan = true;
    score.plan.length_m = plan.length_m;
  }
  ReplayOptions replay_options;
  replay_options.pace = ReplayPace::Fast;
  replay_options.period_us = scenario.periodUs();
  replay_options.settle_s = scenario.settle_s;
  std::vector<ScoreFrame>& frames = score.frames_seen;
  replay_options.observer = [&frames](const Snapshot& s) {
    const HapticState& h = s.haptic;
    frames.push_back(
        {s.t_s, h.tip_m, h.force_N.norm(), h.contact, h.cutting, h.poses > 0, h.penetration_m, h.contact_m});
  };
  const ReplayReport report = replay(world, trace, replay_options);
  score.frames = report.frames;
  score.poses = report.poses;
  score.incisions = report.incisions;
  for (const auto& f : world.cutter().stats().figures) score.groove_length_m += f.groove_length_m;
  if (score.has_plan) {
    score.plan = scoreCut(plan, world.tissue(), score.groove_length_m, options);
    scoreBladeDepth(plan, frames, options, score.plan);
  }
  scoreMotion(frames, options, score);
  return score;
}

}  // namespace incise::sim
