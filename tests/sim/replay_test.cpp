#include "incise/incision/surface_cutter.h"
#include "incise/sim/simulation.h"
#include "incise/tets/tet_cutter.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "incise/devices/trace_csv.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/sim/scenario.h"
#include "incise/sim/stroke_poses.h"
#include "scenario_fixture.h"
#include "shipped_scenario.h"

using namespace incise;

namespace {

struct Run {
  sim::ReplayReport report;
  std::uint64_t hash;
  int seam_vertices;
};

Run replayScenario(const char* name, sim::ReplayPace pace, sim::ForceSink* sink = nullptr) {
  const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  Run run{sim::replay(world, poses, options, sink), mesh::geometryHash(world.tissue()),
          world.cutter().stats().vertices_duplicated};
  REQUIRE(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
  return run;
}

// A force sink that records the forces and, at one frame, stalls the sim thread for 3 ms.
struct StallingSink : sim::ForceSink {
  std::atomic<int> frames{0};
  std::atomic<double> max_force_N{0.0};
  int stall_at = -1;
  void apply(const Eigen::Vector3d& f, double) noexcept override {
    if (frames++ == stall_at) std::this_thread::sleep_for(std::chrono::milliseconds(3));
    if (f.norm() > max_force_N) max_force_N = f.norm();
  }
};

}  // namespace

TEST_CASE("replay: a coarse pad (4 mm grid) is cut through local refinement, the same fast and in real time", "[sim]") {
  // The pad-straight trace over the same pad meshed 16x coarser than shipped.
  sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/pad-straight.json");
  s.shape.grid_m = 0.004;
  // The scenario's budget: in real time frames stop at their deadline and poses come several to a frame
  // when the machine is busy, so the refinement ahead of the cut has got less far when a pose's contact is
  // taken; contact with the faces as the incision began (their rest parents) makes that change nothing.
  const auto poses = devices::TraceReader::readAll(s.trace);
  std::array<std::uint64_t, 2> hashes{};
  for (const sim::ReplayPace pace : {sim::ReplayPace::Fast, sim::ReplayPace::RealTime}) {
    sim::World world(sim::loadTissue(s), s.world);
    sim::ReplayOptions options;
    options.pace = pace;
    options.period_us = s.periodUs();
    options.settle_s = s.settle_s;
    sim::replay(world, poses, options);
    const incision::CutStats& stats = world.cutter().stats();
    INFO(incision::describeShortfall(stats.figures.back()));
    REQUIRE(stats.failure.empty());
    REQUIRE(stats.refined_vertices > 0);
    for (const incision::IncisionFigures& f : stats.figures) REQUIRE(f.shortfall == incision::Shortfall::None);
    REQUIRE(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
    hashes[pace == sim::ReplayPace::Fast ? 0 : 1] = mesh::geometryHash(world.tissue());
  }
  REQUIRE(hashes[0] == hashes[1]);
}

TEST_CASE("replay: fast and real-time replays give the same geometry", "[sim]") {
  const Run fast = replayScenario("bunny-straight", sim::ReplayPace::Fast);
  const Run realtime = replayScenario("bunny-straight", sim::ReplayPace::RealTime);
  REQUIRE(fast.seam_vertices > 50);
  REQUIRE(fast.hash == realtime.hash);
  REQUIRE(fast.report.frames == realtime.report.frames);
  REQUIRE(realtime.report.poses == fast.report.poses);
  REQUIRE(realtime.report.poses_dropped == 0);
  // Frames in real time last as long as the trace (plus settling): the loop really paced them.
  REQUIRE(realtime.report.wall_s > 0.9 * realtime.report.simulated_s);
  REQUIRE(fast.report.latency.frames == fast.report.frames);
}

namespace {

// The bunny-tets scenario replayed at `pace` along `trace` (the scenario's own when empty), the sim thread's
// forces through `sink`: its cut tets, deformed, and the replay's report.
struct TetReplay {
  tets::TetView tets;
  sim::ReplayReport report;
};
TetReplay replayTets(sim::ReplayPace pace, const std::string& trace = {}, sim::ForceSink* sink = nullptr) {
  sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-tets.json");
  if (!trace.empty()) s.trace = std::string(INCISE_SCENARIOS_DIR) + "/traces/" + trace;
  sim::World world(sim::loadTissue(s), s.world);
  REQUIRE(world.tets() != nullptr);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  TetReplay run;
  run.report = sim::replay(world, devices::TraceReader::readAll(s.trace), options, sink);
  REQUIRE_FALSE(world.tets()->pending());
  REQUIRE(world.tets()->stats().failure.empty());
  run.tets = world.tets()->view(tets::TetShape::Deformed);
  return run;
}

void requireSameTets(const tets::TetView& fast, const tets::TetView& realtime) {
  REQUIRE(fast.mesh.tets == realtime.mesh.tets);
  REQUIRE(fast.side == realtime.side);
  REQUIRE(fast.mesh.nodes_m.size() == realtime.mesh.nodes_m.size());
  int differ = 0;
  double largest_m = 0.0;
  for (std::size_t n = 0; n < fast.mesh.nodes_m.size(); ++n)
    if (fast.mesh.nodes_m[n] != realtime.mesh.nodes_m[n])
      ++differ, largest_m = std::max(largest_m, (fast.mesh.nodes_m[n] - realtime.mesh.nodes_m[n]).norm());
  INFO(differ << " of " << fast.mesh.nodes_m.size() << " nodes differ, by up to " << largest_m << " m");
  REQUIRE(differ == 0);  // bit for bit
}

// Threads that keep every core busy while they live, so that a real-time replay beside them has its frames
// and its pose feeder descheduled: frames that take several poses at once, frames late.
class BusyCores {
 public:
  BusyCores() {
    const unsigned cores = std::max(2u, std::thread::hardware_concurrency());
    for (unsigned i = 0; i < cores; ++i)
      threads_.emplace_back([this] {
        std::uint64_t x = 1;
        while (!stop_.load(std::memory_order_relaxed)) x = x * 6364136223846793005ull + 1442695040888963407ull;
        sink_.fetch_add(x, std::memory_order_relaxed);
      });
  }
  ~BusyCores() {
    stop_.store(true);
    for (std::thread& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> sink_{0};
  std::vector<std::thread> threads_;
};

// A force sink that stalls the sim thread for 3 ms every `every` frames: the poses released meanwhile are
// taken together by the next frame, whatever the machine's load.
struct StallEvery : sim::ForceSink {
  explicit StallEvery(int frames) : every(frames) {}
  int every;
  int frames = 0;
  void apply(const Eigen::Vector3d&, double) noexcept override {
    if (++frames % every == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
};

}  // namespace

TEST_CASE("replay: a tet tissue is cut, the same bits fast and in real time", "[sim]") {
  const tets::TetView fast = replayTets(sim::ReplayPace::Fast).tets;
  const tets::TetView realtime = replayTets(sim::ReplayPace::RealTime).tets;
  REQUIRE(fast.split.end() - std::find(fast.split.begin(), fast.split.end(), 1) > 50);  // pieces of cut tets
  REQUIRE(tets::checkConforming(fast.mesh).conforming);
  REQUIRE(fast.inverted_tets == 0);
  requireSameTets(fast, realtime);
}

TEST_CASE("replay: two crossing incisions through a tet tissue, real time on a loaded machine, give the fast bits",
          "[sim]") {
  // The real-time replay runs beside threads that keep every core busy and stalls its own sim thread now
  // and then: its frames take the poses in other groups than the fast replay's one per frame, its incision
  // opens by other steps and its tets' budgeted work falls into other calls. The tets' deformed nodes
  // depend on the samples alone: the same bits.
  const TetReplay fast = replayTets(sim::ReplayPace::Fast, "bunny-crossing.csv");
  TetReplay realtime;
  {
    const BusyCores busy;
    StallEvery stalls(97);
    realtime = replayTets(sim::ReplayPace::RealTime, "bunny-crossing.csv", &stalls);
    REQUIRE(stalls.frames > 1000);
  }
  REQUIRE(fast.report.incisions >= 2);
  REQUIRE(realtime.report.incisions == fast.report.incisions);
  // The stalls made the loop skip deadlines: the poses released meanwhile landed together in later frames.
  REQUIRE(realtime.report.loop.skipped_deadlines > 0);
  REQUIRE(tets::checkConforming(fast.tets.mesh).conforming);
  REQUIRE(fast.tets.inverted_tets == 0);
  requireSameTets(fast.tets, realtime.tets);
}

namespace {

struct ThroughRun {
  int incisions = 0, pieces = 0, on_worker = 0;
  incision::ThroughCut through = incision::ThroughCut::None;
  std::uint64_t hash = 0;
};

// slab-through's stroke (through the slab, edge to edge), then a shallow stroke beside it, which begins
// only once the through-cut is applied.
ThroughRun replayThroughAndAfter(sim::ReplayPace pace) {
  incise::test::ShippedScenario l = incise::test::loadShipped("slab-through");
  sim::StrokeSpec second = l.scenario.strokes.front();
  second.start_m = Eigen::Vector3d(0.005, 0.01, -0.015);
  second.direction = Eigen::Vector3d(0.0, 0.0, 1.0);
  second.length_m = 0.01;
  second.depth_m = 0.001;
  const auto poses = sim::posesForStrokes(l.world->tissue(), {l.scenario.strokes.front(), second}, l.scenario.world,
                                          l.scenario.rate_hz);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = l.scenario.periodUs();
  options.settle_s = l.scenario.settle_s;
  const sim::ReplayReport report = sim::replay(*l.world, poses, options);
  const incision::CutStats& stats = l.world->cutter().stats();
  REQUIRE(mesh::checkManifold(l.world->tissue().mesh()).closed_two_manifold);
  return ThroughRun{report.incisions, stats.figures.front().pieces, stats.through_on_worker,
                    stats.figures.front().through, mesh::geometryHash(l.world->tissue())};
}

}  // namespace

TEST_CASE("replay: a cut through the slab, its Boolean on the worker in real time, gives the fast bytes",
          "[sim][threads]") {
  // Fast, the frame that makes the through-cut computes it; in real time the world's worker does while the
  // frames go on, and a later frame applies it. The second stroke waits for it in both.
  const ThroughRun fast = replayThroughAndAfter(sim::ReplayPace::Fast);
  const ThroughRun realtime = replayThroughAndAfter(sim::ReplayPace::RealTime);
  CHECK(fast.on_worker == 0);
  CHECK(realtime.on_worker == 1);
  for (const ThroughRun& run : {fast, realtime}) {
    CHECK(run.incisions == 2);
    CHECK(run.through == incision::ThroughCut::Made);
    CHECK(run.pieces == 2);
  }
  CHECK(fast.hash == realtime.hash);
}

TEST_CASE("replay: the crossing scenario gives the same geometry fast and in real time", "[sim][slow]") {
  REQUIRE(replayScenario("bunny-crossing", sim::ReplayPace::Fast).hash ==
          replayScenario("bunny-crossing", sim::ReplayPace::RealTime).hash);
}

TEST_CASE("replay: snapshots are read from another thread while the loop runs", "[sim][threads]") {
  const sim::Scenario s = sim::loadScenario(INCISE_SCENARIOS_DIR "/bunny-curved.json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions options;
  options.pace = sim::ReplayPace::RealTime;
  std::int64_t last_frame = -1;
  int seen = 0, out_of_order = 0, columns_went_back = 0, last_done = 0, last_incisions = 0, timed = 0;
  options.observer = [&](const sim::Snapshot& snapshot) {  // runs on the reader thread
    ++seen;
    if (snapshot.frame <= last_frame) ++out_of_order;
    if (snapshot.frame > 0 && snapshot.profile.frame_us > 0.0 && snapshot.profile.publish_us >= 0.0) ++timed;
    if (snapshot.incisions == last_incisions && snapshot.columns_done < last_done) ++columns_went_back;
    last_frame = snapshot.frame;
    last_done = snapshot.columns_done;
    last_incisions = snapshot.incisions;
  };
  const sim::ReplayReport report = sim::replay(world, poses, options);
  REQUIRE(report.snapshots_read == seen);
  REQUIRE(seen > 100);  // about one every 2 ms over ~1.4 s
  REQUIRE(out_of_order == 0);
  REQUIRE(columns_went_back == 0);
  REQUIRE(timed >= seen - 1);  // every snapshot after the first carries the previous frame's times
  REQUIRE(last_frame == report.frames - 1);
}

TEST_CASE("replay: period error and deadline misses are measured and reported", "[sim]") {
  StallingSink sink;
  sink.stall_at = 300;
  const Run run = replayScenario("bunny-straight", sim::ReplayPace::RealTime, &sink);
  REQUIRE(sink.frames == run.report.frames);
  REQUIRE(sink.max_force_N > 0.1);  // the sink received real forces
  REQUIRE(run.report.latency.deadline_misses >= 1);
  REQUIRE(run.report.latency.frame_us.max >= 3000.0);
  REQUIRE(run.report.loop.overruns + run.report.loop.skipped_deadlines >= 1);
  REQUIRE(run.report.latency.period_error_us.max > 0.0);
  // The cut still finished, and the stall changed nothing in it.
  REQUIRE(run.hash == replayScenario("bunny-straight", sim::ReplayPace::Fast).hash);
}

TEST_CASE("replay: pose-to-visible latency stays within 3 frames", "[sim]") {
  const Run run = replayScenario("bunny-curved", sim::ReplayPace::Fast);
  REQUIRE(run.report.latency.pose_to_visible_frames.count > 20);
  REQUIRE(run.report.latency.pose_to_visible_frames.p99 <= 3.0);
}

// ---- Strokes that cross open grooves: a stroke crossing an open groove keeps cutting beyond it --

namespace {

// A straight line of the plan in the xz plane (the strokes' rays go down -y onto the bunny's back).
struct PlanLine {
  Eigen::Vector2d start;  // (x, z), metres
  Eigen::Vector2d direction;
  double length_m;
  Eigen::Vector2d at(double s_m) const { return start + s_m * direction.normalized(); }
  double distanceTo(const Eigen::Vector2d& p) const {  // to the segment
    const Eigen::Vector2d d = direction.normalized();
    const double s = std::clamp((p - start).dot(d), 0.0, length_m);
    return (p - at(s)).norm();
  }
};

// The stations (every 0.5 mm) of `plan` that no wall face covers: none of the output mesh's wall faces
// has its centroid within 0.5 mm along and 1.5 mm across the plan there (in xz). Stations within 1.5 mm of
// an earlier groove's line, and within 1 mm of the plan's ends, are not asked for.
std::vector<double> uncoveredStations(const mesh::SurfaceMesh& tissue, const PlanLine& plan,
                                      const std::vector<PlanLine>& earlier) {
  const mesh::TriMesh& m = tissue.mesh();
  // Each wall face seen from above (x, z): its corners. A station is covered by a face whose extent along
  // the plan reaches within 0.5 mm of it and whose centroid lies within 1.5 mm across (the wall's fan at a
  // groove's end spans from the last doubled seam vertex to the chain's end: its centroid lies inside).
  std::vector<std::array<Eigen::Vector2d, 3>> walls;
  for (const auto f : m.faces()) {
    if (tissue.kind(f) != mesh::FaceKind::Wall) continue;
    std::array<Eigen::Vector2d, 3> corners;
    int i = 0;
    for (auto v = m.cfv_iter(f); v.is_valid() && i < 3; ++v, ++i) corners[i] = {m.point(*v)[0], m.point(*v)[2]};
    walls.push_back(corners);
  }
  const Eigen::Vector2d d = plan.direction.normalized(), across(-d.y(), d.x());
  std::vector<double> uncovered;
  for (double s = 0.001; s <= plan.length_m - 0.001; s += 0.0005) {
    const Eigen::Vector2d p = plan.at(s);
    if (std::any_of(earlier.begin(), earlier.end(), [&](const PlanLine& g) { return g.distanceTo(p) < 0.0015; }))
      continue;
    const bool covered = std::any_of(walls.begin(), walls.end(), [&](const std::array<Eigen::Vector2d, 3>& w) {
      const double a0 = (w[0] - p).dot(d), a1 = (w[1] - p).dot(d), a2 = (w[2] - p).dot(d);
      const Eigen::Vector2d centroid = (w[0] + w[1] + w[2]) / 3.0;
      return std::min({a0, a1, a2}) <= 0.0005 && std::max({a0, a1, a2}) >= -0.0005 &&
             std::abs((centroid - p).dot(across)) <= 0.0015;
    });
    if (!covered) uncovered.push_back(s);
  }
  return uncovered;
}

std::string strokeJson(const PlanLine& line, double pause_s) {
  const Eigen::Vector2d d = line.direction.normalized();
  std::ostringstream s;
  s.precision(17);
  s << R"({ "start_m": [)" << line.start.x() << ", 0.0, " << line.start.y() << R"(], "direction": [)" << d.x()
    << ", 0, " << d.y() << R"(], "length_m": )" << line.length_m << R"(, "speed_m_per_s": 0.05, "pause_s": )" << pause_s
    << " }";
  return s.str();
}

// The bunny-crossing scenario's tissue and lattice with generated strokes along `lines`, in order.
sim::Scenario crossingScenario(const std::string& name, const std::vector<PlanLine>& lines) {
  std::string strokes;
  for (std::size_t i = 0; i < lines.size(); ++i) strokes += (i ? ", " : "") + strokeJson(lines[i], i ? 0.3 : 0.1);
  const std::string text = R"({ "name": ")" + name + R"(",
    "tissue": { "mesh": "meshes/bunny.obj", "scale": 0.01, "subdivide": 2 },
    "tool": { "blade_length_m": 0.03, "cut_button": 0 },
    "incision": { "depth_m": 0.004, "opening_m": 0.002, "alpha_m": 0.0015, "beta_m": 0.002, "spacing_m": 0.0005 },
    "pose_source": { "kind": "strokes", "strokes": [ )" +
                           strokes + R"( ] } })";
  return sim::loadScenario(incise::test::scenarioDir().scenario(name, text));
}

struct CrossingRun {
  std::uint64_t hash = 0;
  std::vector<std::vector<double>> uncovered;  // per stroke after the first
  std::vector<incision::IncisionFigures> figures;
  int manifold_failures = 0;  // checks after each new incision (fast only) that failed
};

// Replays the strokes; in fast mode checks the surface after each incision begins (closed two-manifold,
// Euler characteristic kept) and measures each later stroke's wall coverage at the end.
CrossingRun replayCrossing(const sim::Scenario& s, const std::vector<PlanLine>& lines, sim::ReplayPace pace) {
  sim::World world(sim::loadTissue(s), s.world);
  const int euler = mesh::checkManifold(world.tissue().mesh()).euler_characteristic;
  const auto poses = sim::posesForStrokes(world.tissue(), s.strokes, s.world, s.rate_hz);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  CrossingRun run;
  int incisions = 0;
  if (pace == sim::ReplayPace::Fast) {
    options.observer = [&](const sim::Snapshot& snapshot) {
      if (snapshot.incisions == incisions) return;
      incisions = snapshot.incisions;
      const mesh::ManifoldReport r = mesh::checkManifold(world.tissue().mesh());
      if (!r.closed_two_manifold || r.euler_characteristic != euler) ++run.manifold_failures;
    };
  }
  sim::replay(world, poses, options);
  const mesh::ManifoldReport end = mesh::checkManifold(world.tissue().mesh());
  if (!end.closed_two_manifold || end.euler_characteristic != euler) ++run.manifold_failures;
  run.hash = mesh::geometryHash(world.tissue());
  run.figures = world.cutter().stats().figures;
  for (std::size_t i = 1; i < lines.size(); ++i)
    run.uncovered.push_back(uncoveredStations(
        world.tissue(), lines[i], std::vector<PlanLine>(lines.begin(), lines.begin() + static_cast<long>(i))));
  return run;
}

void requireCrossingCut(const char* name, const std::vector<PlanLine>& lines) {
  const sim::Scenario s = crossingScenario(name, lines);
  const CrossingRun fast = replayCrossing(s, lines, sim::ReplayPace::Fast);
  for (std::size_t i = 0; i < fast.uncovered.size(); ++i) {
    INFO(name << ": stroke " << i + 2 << ": " << fast.uncovered[i].size() << " stations uncovered, first at "
              << (fast.uncovered[i].empty() ? -1.0 : fast.uncovered[i].front()) << " m along the plan");
    CHECK(fast.uncovered[i].empty());
  }
  CHECK(fast.manifold_failures == 0);
  // Every incision made a groove about as long as its stroke in contact.
  for (const incision::IncisionFigures& f : fast.figures) {
    INFO("stroke in contact " << f.stroke_length_m << " m, groove " << f.groove_length_m << " m");
    CHECK(f.groove_length_m > 0.8 * f.stroke_length_m - 0.002);
  }
}

const PlanLine kFirstGroove{{-0.010, 0.018}, {1.0, 0.0}, 0.035};  // the shipped crossing's first stroke

}  // namespace

TEST_CASE("replay: the crossing scenario's second stroke cuts its whole length beyond the first groove", "[sim]") {
  const sim::Scenario s = sim::loadScenario(INCISE_SCENARIOS_DIR "/bunny-crossing.json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions options;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  sim::replay(world, poses, options);
  const PlanLine second{{0.004, 0.006}, {0.0, 1.0}, 0.025};
  const std::vector<double> uncovered = uncoveredStations(world.tissue(), second, {kFirstGroove});
  INFO(uncovered.size() << " stations uncovered, first at " << (uncovered.empty() ? -1.0 : uncovered.front()));
  CHECK(uncovered.empty());
  REQUIRE(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
  // The report's figures: the second stroke is cut as two incisions, one each side of the groove.
  const auto& figures = world.cutter().stats().figures;
  REQUIRE(figures.size() == 3);
  for (const incision::IncisionFigures& f : figures) CHECK(f.groove_length_m > 0.8 * f.stroke_length_m);
  CHECK(figures[1].stroke_length_m + figures[2].stroke_length_m > 0.025 * 0.9 - 0.003);
}

TEST_CASE("replay: a stroke crossing a groove at 45 degrees cuts beyond it", "[sim]") {
  requireCrossingCut("crossing-45", {kFirstGroove, PlanLine{{-0.004, 0.008}, {1.0, 1.0}, 0.026}});
}

TEST_CASE("replay: a third stroke crossing two grooves cuts beyond both", "[sim]") {
  requireCrossingCut("crossing-third", {kFirstGroove, PlanLine{{0.004, 0.006}, {0.0, 1.0}, 0.025},
                                        PlanLine{{0.016, 0.010}, {-1.0, 1.4}, 0.026}});
}

TEST_CASE("replay: crossing strokes give the same geometry fast and in real time", "[sim][slow]") {
  const std::vector<std::pair<const char*, std::vector<PlanLine>>> scenes{
      {"crossing-45-realtime", {kFirstGroove, PlanLine{{-0.004, 0.008}, {1.0, 1.0}, 0.026}}},
      {"crossing-third-realtime",
       {kFirstGroove, PlanLine{{0.004, 0.006}, {0.0, 1.0}, 0.025}, PlanLine{{0.016, 0.010}, {-1.0, 1.4}, 0.026}}}};
  for (const auto& [name, lines] : scenes) {
    INFO(name);
    const sim::Scenario s = crossingScenario(name, lines);
    const CrossingRun fast = replayCrossing(s, lines, sim::ReplayPace::Fast);
    const CrossingRun realtime = replayCrossing(s, lines, sim::ReplayPace::RealTime);
    CHECK(realtime.manifold_failures == 0);
    REQUIRE(fast.hash == realtime.hash);
    for (const auto& u : realtime.uncovered) CHECK(u.empty());
  }
}
