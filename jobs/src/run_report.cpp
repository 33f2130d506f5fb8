#include "incise/jobs/run_report.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/physics/tissue_model.h"
#include "incise/tets/tet_cutter.h"

namespace incise::jobs {

namespace {

nlohmann::json latencyJson(const sim::SampleSummary& s) {
  return {{"count", s.count}, {"p50", s.p50}, {"p99", s.p99}, {"p999", s.p999}, {"max", s.max}, {"mean", s.mean}};
}

}  // namespace

nlohmann::json incisionFiguresJson(const std::vector<incision::IncisionFigures>& figures) {
  nlohmann::json list = nlohmann::json::array();
  for (const incision::IncisionFigures& f : figures) {
    nlohmann::json volumes = nlohmann::json::array();
    for (int i = 0; i < std::min(f.pieces, incision::IncisionFigures::kListedPieces); ++i)
      volumes.push_back(f.piece_volumes_m3[static_cast<std::size_t>(i)]);
    list.push_back({{"stroke_length_m", f.stroke_length_m},
                    {"groove_length_m", f.groove_length_m},
                    {"groove_start_m", f.groove_start_m},
                    {"groove_end_m", f.groove_end_m},
                    {"lattice_columns", f.columns},
                    {"empty_columns", f.empty_columns},
                    {"seam_vertices", f.seam_vertices},
                    {"refined_vertices", f.refined_vertices},
                    {"refined_faces", f.refined_faces},
                    {"thickness_limited_samples", f.thickness_limited_samples},
                    {"row_limited_stations", f.row_limited_stations},
                    {"depth_clamped_samples", f.depth_clamped_samples},
                    {"through_samples", f.through_samples},
                    {"through", incision::toString(f.through)},
                    {"pieces", f.pieces},
                    {"piece_volumes_m3", volumes},
                    {"shortfall", incision::toString(f.shortfall)},
                    {"why", incision::describeShortfall(f)}});
  }
  return list;
}

std::string cutFailure(const incision::CutStats& stats) {
  if (!stats.failure.empty()) return stats.failure;
  for (std::size_t i = 0; i < stats.figures.size(); ++i)
    if (stats.figures[i].shortfall != incision::Shortfall::None)
      return "incision " + std::to_string(i + 1) + " of " + std::to_string(stats.figures.size()) + ": " +
             incision::describeShortfall(stats.figures[i]);
  return "";
}

std::string noIncision(const sim::ReplayReport& report) {
  if (report.incisions > 0 || report.poses == 0) return "";
  return "no incision: none of the " + std::to_string(report.poses) +
         " poses cut the tissue (the blade's tip stayed above the surface or the cut button was up)";
}

double totalGroove_m(const std::vector<incision::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const incision::IncisionFigures& f : figures) sum_m += f.groove_length_m;
  return sum_m;
}

double totalStroke_m(const std::vector<incision::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const incision::IncisionFigures& f : figures) sum_m += f.stroke_length_m;
  return sum_m;
}

nlohmann::json timingSummary(std::vector<double> values_us) {
  if (values_us.empty()) return {{"count", 0}};
  std::sort(values_us.begin(), values_us.end());
  const auto rank = [&](double q) {
    const size_t r = static_cast<size_t>(std::ceil(q * static_cast<double>(values_us.size())));
    return values_us[std::min(values_us.size() - 1, r == 0 ? 0 : r - 1)];
  };
  return {
      {"count", values_us.size()},
      {"p50_us", rank(0.5)},
      {"p99_us", rank(0.99)},
      {"max_us", values_us.back()},
      {"mean_us", std::accumulate(values_us.begin(), values_us.end(), 0.0) / static_cast<double>(values_us.size())}};
}

nlohmann::json tetsReport(const tets::TetCutter& tets, const tets::TetView& deformed) {
  const tets::TetCutStats& stats = tets.stats();
  const auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  return {{"tets", deformed.mesh.tets.size()},
          {"nodes", deformed.mesh.nodes_m.size()},
          {"volume_m3", tets::volume(deformed.mesh)},
          {"rest_volume_m3", tets::volume(tets.view(tets::TetShape::Rest).mesh)},
          {"min_dihedral_deg", tets::minDihedralAngleDeg(deformed.mesh)},
          {"min_split_dihedral_deg", deformed.min_split_dihedral_deg},
          {"min_split_volume_m3", finite(deformed.min_split_volume_m3)},
          {"inverted_tets", deformed.inverted_tets},
          {"tets_cut", stats.tets_cut},
          {"piece_volumes_m3", tets::pieceVolumes(deformed.mesh)},
          {"edge_points", stats.edge_points},
          {"duplicated_nodes", stats.duplicated_nodes},
          {"snapped_nodes", stats.snapped_nodes},
          {"steiner_nodes", stats.steiner_nodes},
          {"rebased_tets", stats.rebased_tets},
          {"reserve_overflows", stats.reserve_overflows},
          {"pending", tets.pending()},
          {"failure", stats.failure}};
}

// A simulated tissue's figures: its rate and steps, their time on the physics thread (late: finished more
// than a period after they were due), cuts deferred to a later step (a full handoff), poses mapped to the
// rest frame with an older step's map than theirs (stale_maps: the physics thread behind), steps the tool
// pressed the skin in (pressed_steps: a dent), what the model met.
nlohmann::json physicsReport(const sim::TissuePhysics& physics, const sim::LatencySummary& latency) {
  const sim::PhysicsCounters c = physics.counters();
  return {{"physics_rate_hz", physics.rateHz()},
          {"steps", c.steps},
          {"physics_step_us",
           {{"p50", latency.physics_step_us.p50},
            {"p99", latency.physics_step_us.p99},
            {"max", latency.physics_step_us.max}}},
          {"physics_late", latency.physics_late},
          {"physics_deferred", c.deferred},
          {"stale_maps", c.stale_maps},
          {"dropped_maps", c.dropped_maps},
          {"cg_limited_steps", c.cg_limited},
          {"non_finite_steps", c.non_finite},
          {"cuts_applied", c.cuts_applied},
          {"pressed_steps", c.pressed_steps},
          {"pieces_refused", c.pieces_refused},
          {"failed_applies", c.failed_applies},
          {"reserve_overflows", c.reserve_overflows},
          {"max_inverted_elements", c.max_inverted},
          {"nodes", physics.model().nodeCount()},
          {"elements", physics.model().elementCount()},
          {"positions_hash", hexText(physics.positionsHash())}};
}

nlohmann::json replayReport(const ScenarioRun& run, const sim::ReplayOptions& options, const sim::ReplayReport& report,
                            const tets::TetView* deformed) {
  const mesh::SurfaceMesh& tissue = run.world->tissue();
  const incision::CutStats& stats = run.world->cutter().stats();
  nlohmann::json json = {
      {"scenario", run.scenario.name},
      {"mode", options.pace == sim::ReplayPace::RealTime ? "realtime" : "fast"},
      {"period_us", options.period_us},
      {"frames", report.frames},
      {"simulated_s", report.simulated_s},
      {"wall_s", report.wall_s},
      {"poses", report.poses},
      {"poses_dropped", report.poses_dropped},
      {"incisions", report.incisions},
      {"edges_split", stats.edges_split},
      {"seam_vertices_opened", stats.vertices_duplicated},
      {"refined_vertices", stats.refined_vertices},
      {"refined_faces", stats.refined_faces},
      {"reserve_overflows", stats.reserve_overflows},
      {"cut_failure", cutFailure(stats)},
      {"note", noIncision(report)},
      {"incision_figures", incisionFiguresJson(stats.figures)},
      {"geometry_hash", hexText(mesh::geometryHash(tissue))},
      {"mesh", nlohmann::json::parse(mesh::toJson(mesh::summarize(tissue)))},
      {"latency",
       {{"haptic_us", latencyJson(report.latency.haptic_us)},
        {"cut_us", latencyJson(report.latency.cut_us)},
        {"frame_us", latencyJson(report.latency.frame_us)},
        {"period_error_us", latencyJson(report.latency.period_error_us)},
        {"pose_to_visible_frames", latencyJson(report.latency.pose_to_visible_frames)},
        {"deadline_misses", report.latency.deadline_misses}}},
      {"loop",
       {{"overruns", report.loop.overruns},
        {"skipped_deadlines", report.loop.skipped_deadlines},
        {"max_period_error_us", report.loop.max_period_error_us}}},
  };
  if (const tets::TetCutter* tets = run.world->tets())
    json["tets"] = deformed ? tetsReport(*tets, *deformed) : tetsReport(*tets, tets->view(tets::TetShape::Deformed));
  if (const sim::TissuePhysics* physics = run.world->physics())
    json["physics"] = physicsReport(*physics, report.latency);
  return json;
}

sim::ReplayOptions scenarioReplayOptions(const sim::Scenario& scenario, sim::ReplayPace pace) {
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = scenario.periodUs();
  options.settle_s = scenario.settle_s;
  return options;
}

}  // namespace incise::jobs
