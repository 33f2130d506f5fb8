#include "incise/jobs/cut_job.h"

#include <chrono>

#include "incise/jobs/run_report.h"

namespace incise::jobs {

namespace {

std::vector<double> list(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json optionsJson(const CutJobOptions& a) {
  const incision::IncisionOptions& i = a.cutter.incision;
  return {{"mesh", a.mesh.string()},
          {"scale", a.scale},
          {"subdivide", a.subdivide},
          {"start_m", list(a.start_m)},
          {"direction", list(a.direction)},
          {"length_m", a.length_m},
          {"bend_m", a.bend_m},
          {"speed_m_per_s", a.speed_m_per_s},
          {"depth_m", i.depth_m},
          {"opening_m", i.opening_m},
          {"alpha_m", i.alpha_m},
          {"beta_m", i.beta_m},
          {"spacing_m", i.spacing_m},
          {"order", i.order},
          {"retraction_time_s", i.retraction_time_s},
          {"wall_rows", a.cutter.wall_rows},
          {"refine", toString(a.cutter.refine)},
          {"refine_edge_m", incision::refineEdgeLength(a.cutter)}};
}

// What the cutter did: counts, what refinement added, and per incision where its groove runs.
nlohmann::json statsJson(const incision::CutStats& stats) {
  return {{"edges_split", stats.edges_split},
          {"seam_vertices_duplicated", stats.vertices_duplicated},
          {"refined_vertices", stats.refined_vertices},
          {"refined_faces", stats.refined_faces},
          {"incision_figures", incisionFiguresJson(stats.figures)}};
}

}  // namespace

CutJob::CutJob(const CutJobOptions& options) : options_(options) {
  if (!(options.subdivide >= 0 && options.subdivide <= 5))
    throw std::invalid_argument("subdivide " + std::to_string(options.subdivide) + " is outside [0, 5]");
  mesh_ = std::make_unique<mesh::SurfaceMesh>(
      mesh::subdivided(mesh::loadSurfaceMesh(options.mesh, options.scale), options.subdivide));
  euler_before_ = mesh::checkManifold(mesh_->mesh()).euler_characteristic;
  incision::StrokePathOptions path;
  path.start_m = options.start_m;
  path.direction = options.direction;
  path.length_m = options.length_m;
  path.bend_m = options.bend_m;
  path.speed_m_per_s = options.speed_m_per_s;
  stroke_ = incision::strokeAlongPath(*mesh_, path);
  cutter_ = std::make_unique<incision::SurfaceCutter>(*mesh_, options.cutter);
}

CutJob::~CutJob() = default;

void CutJob::run(const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto time = [&](auto&& call) {
    const auto start = std::chrono::steady_clock::now();
    const incision::CutStep step = call();
    sample_us_.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    if (step.sample != incision::SampleStatus::Accepted) ++skipped_;
    return step;
  };
  time([&] { return cutter_->begin(stroke_.first, stroke_.blade_direction); });
  for (std::size_t k = 0; k < stroke_.samples.size(); ++k) {
    const incision::StrokeSample& sample = stroke_.samples[k];
    // A stroke that turns at a corner goes on as a new incision from there (Incision::extend); the begin,
    // which settles the incision before it, is not a sample's time.
    if (time([&] { return cutter_->extend(sample); }).sample == incision::SampleStatus::EndedAtCorner)
      cutter_->begin(sample, stroke_.blade_direction);
    if (progress) progress(k + 1, stroke_.samples.size());
  }
  cutter_->finish();
  cutter_->settle();  // the wound at its final opening; where the blade went through, cut through
}

std::string CutJob::failure() const {
  std::string failure = cutFailure(cutter_->stats());
  if (failure.empty() && totalGroove_m(cutter_->stats().figures) == 0.0) failure = "no groove was opened";
  return failure;
}

bool CutJob::ok(const mesh::MeshSummary& cut) const {
  // A cut through the tissue adds a handle (a slot) or a piece (one cut free): the Euler characteristic
  // changes; the surface must still be closed.
  bool through = false;
  for (const incision::IncisionFigures& f : cutter_->stats().figures)
    through = through || f.through == incision::ThroughCut::Made;
  return cut.closed_two_manifold && (through || cut.euler_characteristic == euler_before_) && failure().empty();
}

nlohmann::json CutJob::summary(const mesh::MeshSummary& cut) const {
  nlohmann::json report = statsJson(cutter_->stats());
  report.update({{"options", optionsJson(options_)},
                 {"mesh", nlohmann::json::parse(mesh::toJson(cut))},
                 {"euler_characteristic_before", euler_before_},
                 {"samples", samples()},
                 {"samples_not_accepted", skipped_},
                 {"per_sample", timingSummary(sample_us_)},
                 {"failure", failure()}});
  return report;
}

}  // namespace incise::jobs
