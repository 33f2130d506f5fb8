// incise.World: a world stepped from Python — poses in as numpy rows, the haptic force and the contact out
// — or run over a whole trace in C++ as `incise replay --fast` runs it; the tissue read as copies (at rest
// and, for a tissue with a material, as simulated).
#include <atomic>
#include <cmath>
#include <map>
#include <stdexcept>

#include <pybind11/stl.h>

#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "incise/incision/surface_cutter.h"
#include "incise/jobs/mesh_arrays.h"
#include "incise/jobs/run_report.h"
#include "incise/jobs/scenario_run.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/physics/tissue_model.h"
#include "incise/sim/simulation.h"
#include "incise/sim/tissue_physics.h"

namespace incise::python {

namespace {

using PoseArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

struct Step {
  sim::StepResult result;
  int incisions = 0;
  bool pending = false;
};

py::array_t<double> vector3(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  std::copy(v.data(), v.data() + 3, out.mutable_data());
  return out;
}

// World options from keyword names (the scenario file's keys, units in the names) over the defaults.
sim::WorldOptions worldOptions(const py::dict& given) {
  sim::WorldOptions o;
  incision::IncisionOptions& i = o.cutter.incision;
  const std::map<std::string, double*> numbers = {{"depth_m", &i.depth_m},
                                                  {"opening_m", &i.opening_m},
                                                  {"alpha_m", &i.alpha_m},
                                                  {"beta_m", &i.beta_m},
                                                  {"spacing_m", &i.spacing_m},
                                                  {"retraction_time_s", &i.retraction_time_s},
                                                  {"refine_edge_m", &o.cutter.refine_edge_m},
                                                  {"blade_length_m", &o.tool.blade_length_m},
                                                  {"stiffness_N_per_m", &o.tissue.stiffness_N_per_m},
                                                  {"damping_N_s_per_m", &o.tissue.damping_N_s_per_m},
                                                  {"cutting_resistance_N", &o.tissue.cutting_resistance_N},
                                                  {"max_force_N", &o.tissue.max_force_N},
                                                  {"cut_budget_us", &o.cut_budget_us}};
  const std::map<std::string, int*> integers = {
      {"order", &i.order}, {"wall_rows", &o.cutter.wall_rows}, {"cut_button", &o.tool.cut_button}};
  for (const auto& [key_handle, value] : given) {
    const std::string key = py::str(key_handle);
    if (const auto n = numbers.find(key); n != numbers.end())
      *n->second = value.cast<double>();
    else if (const auto k = integers.find(key); k != integers.end())
      *k->second = value.cast<int>();
    else if (key == "refine")
      o.cutter.refine = refineMode(value.cast<std::string>());
    else
      throw std::invalid_argument("World: unknown option '" + key + "'");
  }
  return o;
}

class World {
 public:
  World(const MeshView& tissue, const sim::WorldOptions& options)
      : world_(std::make_unique<sim::World>(tissue.mesh(), options)) {}
  explicit World(jobs::ScenarioRun run)
      : world_(std::move(run.world)),
        scenario_poses_(std::move(run.poses)),
        period_us_(run.scenario.periodUs()),
        settle_s_(run.scenario.settle_s) {}

  Step step(const PoseArray& poses, double dt_s, double t_s) {
    const Busy busy(busy_);
    if (!(std::isfinite(dt_s) && dt_s > 0.0) || !std::isfinite(t_s))
      throw std::invalid_argument("step: dt_s must be finite and > 0, t_s finite");
    posesFromArray(poses, scratch_);
    Step s;
    s.result = world_->step(scratch_, dt_s, t_s);
    s.incisions = world_->incisions();
    s.pending = world_->pending();
    return s;
  }

  // The frames `incise replay --fast` runs over `poses` (sim::replay's feeding: frame k at t0 + k period
  // takes the poses due by then, at most Simulation::kMaxPosesPerFrame), until every pose is taken, no
  // cutting work is left and settle_s has passed since the last pose.
  py::dict run(const PoseArray* given, double settle_s) {
    const Busy busy(busy_);
    std::vector<devices::PoseSample> poses;
    if (given) posesFromArray(*given, poses);
    const std::vector<devices::PoseSample>& trace = given ? poses : scenario_poses_;
    if (trace.empty()) throw std::invalid_argument("run: no poses (a world from a mesh needs poses)");
    std::vector<double> t, force, tip, depth;
    std::vector<std::uint8_t> contact, cutting;
    {
      py::gil_scoped_release release;
      const double period_s = static_cast<double>(period_us_) * 1e-6;
      const double dt_s = static_cast<double>(period_us_) / 1e6;
      const double end_s = trace.back().time_s + settle_s;
      std::size_t fed = 0, taken = 0;
      for (std::int64_t k = 0;; ++k) {
        const double t_s = trace.front().time_s + static_cast<double>(k) * period_s;
        while (fed < trace.size() && trace[fed].time_s <= t_s + 1e-12) ++fed;
        const std::size_t n = std::min<std::size_t>(fed - taken, sim::Simulation::kMaxPosesPerFrame);
        const sim::StepResult r = world_->step(std::span(trace.data() + taken, n), dt_s, t_s);
        taken += n;
        t.push_back(t_s);
        force.insert(force.end(), r.haptic.force_N.data(), r.haptic.force_N.data() + 3);
        tip.insert(tip.end(), r.haptic.tip_m.data(), r.haptic.tip_m.data() + 3);
        depth.push_back(r.haptic.penetration_m);
        contact.push_back(r.haptic.contact), cutting.push_back(r.haptic.cutting);
        if (taken == trace.size() && !world_->pending() && t_s >= end_s) break;
      }
    }
    py::dict frames;
    const auto n = static_cast<py::ssize_t>(t.size());
    frames["t_s"] = py::array_t<double>(n, t.data());
    frames["force_N"] = py::array_t<double>({n, py::ssize_t{3}}, force.data());
    frames["tip_m"] = py::array_t<double>({n, py::ssize_t{3}}, tip.data());
    frames["penetration_m"] = py::array_t<double>(n, depth.data());
    frames["contact"] = py::array_t<std::uint8_t>(n, contact.data()).attr("astype")("bool");
    frames["cutting"] = py::array_t<std::uint8_t>(n, cutting.data()).attr("astype")("bool");
    return frames;
  }

  const sim::World& world() const {
    if (busy_.load()) throw std::runtime_error("World: in use by another thread (run)");
    return *world_;
  }
  const std::vector<devices::PoseSample>& scenarioPoses() const { return scenario_poses_; }
  double periodS() const { return static_cast<double>(period_us_) * 1e-6; }
  double settleS() const { return settle_s_; }

 private:
  // One call at a time: a second thread (the GIL is released during run) gets an error, not a race.
  struct Busy {
    explicit Busy(std::atomic<bool>& flag) : flag_(flag) {
      if (flag_.exchange(true)) throw std::runtime_error("World: in use by another thread");
    }
    ~Busy() { flag_.store(false); }
    std::atomic<bool>& flag_;
  };

  std::unique_ptr<sim::World> world_;
  std::vector<devices::PoseSample> scenario_poses_;
  std::int64_t period_us_ = 1000;
  double settle_s_ = 0.2;
  std::vector<devices::PoseSample> scratch_;
  std::atomic<bool> busy_{false};
};

void bindStep(py::module_& m) {
  py::class_<Step>(m, "Step",
                   "What World.step did: the haptic force and contact from the newest pose, and the cut's state.")
      .def_property_readonly(
          "force_N", [](const Step& s) { return vector3(s.result.haptic.force_N); },
          "(3,) float64, newtons: the force to render (a new array).")
      .def_property_readonly(
          "contact", [](const Step& s) { return s.result.haptic.contact; }, "The blade's tip is below the surface.")
      .def_property_readonly(
          "cutting", [](const Step& s) { return s.result.haptic.cutting; },
          "In contact with the cut button held (or cutting needs none).")
      .def_property_readonly(
          "penetration_m", [](const Step& s) { return s.result.haptic.penetration_m; },
          "The tip's depth below the surface, metres.")
      .def_property_readonly(
          "tip_m", [](const Step& s) { return vector3(s.result.haptic.tip_m); },
          "(3,) the blade's tip, metres (a new array).")
      .def_property_readonly(
          "contact_m", [](const Step& s) { return vector3(s.result.haptic.contact_m); },
          "(3,) where the blade enters the surface, metres (a new array).")
      .def_property_readonly(
          "normal", [](const Step& s) { return vector3(s.result.haptic.normal); },
          "(3,) the surface's outward normal there (a new array).")
      .def_property_readonly(
          "poses_used", [](const Step& s) { return s.result.haptic.poses; }, "Poses taken.")
      .def_property_readonly(
          "poses_rejected", [](const Step& s) { return s.result.haptic.poses_rejected; },
          "Poses skipped: non-finite, or not after the previous one in time.")
      .def_property_readonly(
          "incisions", [](const Step& s) { return s.incisions; }, "Incisions begun so far.")
      .def_property_readonly(
          "pending", [](const Step& s) { return s.pending; }, "Cutting work is carried to later steps.")
      .def_property_readonly(
          "cut_failed", [](const Step& s) { return s.result.cut.failed; },
          "An internal topology failure stopped the current incision (World.incision_figures).");
}

// The tissue as simulated (the rest tissue itself when it does not deform).
mesh::SurfaceMesh simulatedTissue(const sim::World& world) {
  const sim::TissuePhysics* physics = world.physics();
  return physics ? physics->deformedSurface(world.tissue()) : world.tissue();
}

py::dict physicsInfo(const sim::World& world) {
  py::dict out;
  const sim::TissuePhysics* physics = world.physics();
  out["simulated"] = physics != nullptr;
  if (!physics) return out;
  const physics::TissueModel& model = physics->model();
  out["rate_hz"] = physics->rateHz();
  out["steps"] = physics->stepsDone();
  out["nodes"] = model.nodeCount();
  out["tets"] = model.elementCount();
  const Eigen::Vector3d press_N = model.toolPressForce_N();
  out["pressing"] = press_N.squaredNorm() > 0.0;
  out["press_force_N"] = vector3(press_N);
  out["max_displacement_m"] = model.maxDisplacement_m();
  return out;
}

// What a world offers to read: its tissue (copies; at rest and as simulated), its mechanics, hash,
// incisions, poses and rates.
void addWorldReads(py::class_<World>& cls) {
  cls.def_property_readonly(
         "vertices", [](const World& w) { return copyVertices(w.world().tissue()); },
         "N x 3 float64, metres: a copy (the mesh changes on as the world steps).")
      .def_property_readonly(
          "faces", [](const World& w) { return py::object(copyFaces(w.world().tissue())[0]); },
          "M x 3 int64 live faces (the cut's deleted faces left out), counter-clockwise from outside: a copy.")
      .def_property_readonly(
          "face_kinds", [](const World& w) { return py::object(copyFaces(w.world().tissue())[1]); },
          "M uint8, as Mesh.face_kinds: a copy.")
      .def(
          "mesh", [](const World& w) { return MeshView::owning(w.world().tissue()); },
          "A snapshot of the tissue as a Mesh (a copy: it stays as it is while the world steps on).")
      .def_property_readonly(
          "simulated_vertices", [](const World& w) { return copyVertices(simulatedTissue(w.world())); },
          "N x 3 float64, metres: the tissue as simulated, row for row as `vertices` (a copy). A tissue with a "
          "material deforms: `vertices` is its rest shape (where the cut is made), these are where the skin and "
          "walls are now, embedded in the deformed tets (each on its own side of every cut). The same as "
          "`vertices` for a tissue that does not deform. Locates every vertex in the tets: milliseconds.")
      .def(
          "simulated_mesh", [](const World& w) { return MeshView::owning(simulatedTissue(w.world())); },
          "A snapshot of the tissue as simulated, as a Mesh (`replay`'s cut.obj; `mesh()` is cut_rest.obj).")
      .def_property_readonly(
          "physics", [](const World& w) { return physicsInfo(w.world()); },
          "The tissue's mechanics as a dict: simulated (bool; False and nothing else for a tissue without a "
          "material), rate_hz, steps, nodes, tets, pressing (the tool dented the skin at the last step), "
          "press_force_N (3,), max_displacement_m (the largest node displacement from rest).")
      .def_property_readonly(
          "geometry_hash", [](const World& w) { return jobs::hexText(mesh::geometryHash(w.world().tissue())); },
          "The tissue's hash as 16 hex digits (report.json's geometry_hash).")
      .def_property_readonly(
          "incisions", [](const World& w) { return w.world().incisions(); }, "Incisions begun.")
      .def_property_readonly(
          "pending", [](const World& w) { return w.world().pending(); }, "Cutting work is left for later steps.")
      .def_property_readonly(
          "incision_figures",
          [](const World& w) {
            const std::string json = jobs::incisionFiguresJson(w.world().cutter().stats().figures).dump();
            return py::module_::import("json").attr("loads")(json);
          },
          "Per incision a dict as report.json's incision_figures: stroke and groove lengths, where the groove "
          "runs, lattice columns, the shortfall and why.")
      .def_property_readonly(
          "poses", [](const World& w) { return posesToArray(w.scenarioPoses()); },
          "The scenario's poses, N x 10 (a copy); empty for a world from a mesh.")
      .def_property_readonly("period_s", &World::periodS,
                             "The scenario's frame period in seconds (0.001 for a world from a mesh).")
      .def_property_readonly("settle_s", &World::settleS,
                             "The scenario's settle time after the last pose, seconds (0.2 for a world from a mesh).");
  ;
}

}  // namespace

void bindWorld(py::module_& m) {
  bindStep(m);
  py::class_<World> cls(m, "World", R"doc(
A tissue and a scalpel, stepped by you: each step takes the poses that arrived since the last one and the
frame's time (you own the clock) and returns the haptic force and the contact; the cut grows along the
poses. The cut depends only on the poses and their order, not on how they are grouped into steps, so
stepping a scenario's poses frame by frame gives the geometry `incise replay` gives.

Poses are rows of 10 float64: time_s, tip x y z (metres), orientation w x y z (the blade along the tool's
-z, its edge along +x), buttons (a bit mask), pressure (NaN: none). One call at a time: a second thread
calling while run() works gets a RuntimeError.
)doc");
  cls.def(py::init([](const MeshView& tissue, const py::kwargs& given) {
            const sim::WorldOptions options = worldOptions(given);  // Python objects: before the GIL goes
            py::gil_scoped_release release;
            return std::make_unique<World>(tissue, options);
          }),
          py::arg("mesh"), R"doc(
A world over a copy of `mesh` (an incise.Mesh). Keywords, with the scenario file's names and units
(docs/scenarios.md) and its defaults: depth_m, opening_m, alpha_m, beta_m, spacing_m, retraction_time_s,
order, wall_rows, refine ('linear', 'pn', 'off'), refine_edge_m, blade_length_m, cut_button (-1: always
cuts), stiffness_N_per_m, damping_N_s_per_m, cutting_resistance_N, max_force_N, cut_budget_us. Raises
incise.InputError for a mesh that is not a closed two-manifold or intersects itself, ValueError for an
unknown keyword or a bad value. Releases the GIL while it builds the world's grids.
)doc")
      .def_static(
          "from_scenario",
          [](const std::filesystem::path& path) {
            std::vector<std::string> warnings;
            std::unique_ptr<World> world;
            {
              py::gil_scoped_release release;
              world = std::make_unique<World>(jobs::loadScenarioRun(
                  path.string(), [&warnings](const std::string& text) { warnings.push_back(text); }));
            }
            for (const std::string& text : warnings)
              py::module_::import("warnings").attr("warn")(text, py::handle(PyExc_UserWarning));
            return world;
          },
          py::arg("path"), R"doc(
The world a scenario file describes (its tissue, tool, cutting, rate), with its poses in World.poses (a
trace, a hid recording decoded, or generated strokes). Raises incise.InputError naming the file and the key
or line at fault. A recording's skipped reports come as a UserWarning.
)doc")
      .def("step", &World::step, py::arg("poses"), py::arg("dt_s"), py::arg("t_s"), R"doc(
One frame at time t_s after dt_s (seconds): `poses` (an N x 10 array, a single row of 10, or N = 0 rows)
oldest first, then the haptic force from the newest and the cutting work within the budget. Returns a
Step. Bad poses are skipped and counted (Step.poses_rejected). Holds the GIL (microseconds).
)doc")
      .def(
          "run",
          [](World& w, std::optional<PoseArray> poses, std::optional<double> settle_s) {
            return w.run(poses ? &*poses : nullptr, settle_s.value_or(w.settleS()));
          },
          py::arg("poses") = py::none(), py::arg("settle_s") = py::none(), R"doc(
Runs frames over `poses` (default: the scenario's) in C++ exactly as `incise replay --fast` does: frame k at
t0 + k period takes the poses due by then, until every pose is taken, no cutting work is left and settle_s
(default: the scenario's) has passed since the last pose. Returns a dict of per-frame arrays (new): t_s,
force_N (F x 3), tip_m (F x 3), penetration_m, contact, cutting. Releases the GIL.
)doc");
  addWorldReads(cls);
}

}  // namespace incise::python
