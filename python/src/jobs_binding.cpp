// The CLI's jobs from Python: cut (`incise cut`), replay (`incise replay`), score (`incise score`), traces and
// JIGSAWS files read as pose arrays. Each calls the same incise::jobs code as the CLI, so the same options
// give the same bytes. The thin package (incise/__init__.py) checks arguments and turns the JSON into dicts.
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "incise/devices/jigsaws.h"
#include "incise/devices/trace_csv.h"
#include "incise/jobs/cut_job.h"
#include "incise/jobs/run_report.h"
#include "incise/jobs/score_traces.h"

namespace incise::python {

namespace {

Eigen::Vector3d vector3(const py::handle& value, const char* name) {
  const std::vector<double> v = value.cast<std::vector<double>>();
  if (v.size() != 3) throw std::invalid_argument(std::string(name) + ": expected 3 numbers");
  return {v[0], v[1], v[2]};
}

// The options dict (the CLI's option names, without the dashes) over jobs::CutJobOptions's defaults.
jobs::CutJobOptions cutOptions(const std::string& mesh_path, const py::dict& given) {
  jobs::CutJobOptions o;
  o.mesh = mesh_path;
  incision::IncisionOptions& i = o.cutter.incision;
  for (const auto& [key_handle, value] : given) {
    const std::string key = py::str(key_handle);
    if (key == "scale")
      o.scale = value.cast<double>();
    else if (key == "subdivide")
      o.subdivide = value.cast<int>();
    else if (key == "start")
      o.start_m = vector3(value, "start");
    else if (key == "direction")
      o.direction = vector3(value, "direction");
    else if (key == "length")
      o.length_m = value.cast<double>();
    else if (key == "bend")
      o.bend_m = value.cast<double>();
    else if (key == "speed")
      o.speed_m_per_s = value.cast<double>();
    else if (key == "depth")
      i.depth_m = value.cast<double>();
    else if (key == "opening")
      i.opening_m = value.cast<double>();
    else if (key == "alpha")
      i.alpha_m = value.cast<double>();
    else if (key == "beta")
      i.beta_m = value.cast<double>();
    else if (key == "spacing")
      i.spacing_m = value.cast<double>();
    else if (key == "refine")
      o.cutter.refine = refineMode(value.cast<std::string>());
    else if (key == "refine_edge")
      o.cutter.refine_edge_m = value.cast<double>();
    else
      throw std::invalid_argument("cut: unknown option '" + key + "'");
  }
  return o;
}

py::tuple runCut(const std::string& mesh_path, const py::dict& given) {
  const jobs::CutJobOptions options = cutOptions(mesh_path, given);
  std::shared_ptr<jobs::CutJob> job;
  std::string summary, failure;
  bool ok = false;
  {
    py::gil_scoped_release release;
    job = std::make_shared<jobs::CutJob>(options);
    job->run();
    const mesh::MeshSummary cut = mesh::summarize(job->mesh());
    summary = job->summary(cut).dump();
    failure = job->failure();
    ok = job->ok(cut);
  }
  const mesh::SurfaceMesh* mesh = &job->mesh();
  return py::make_tuple(MeshView(std::move(job), mesh), summary, ok, failure);
}

py::tuple runReplay(const std::string& scenario, bool fast) {
  std::vector<std::string> warnings;
  std::shared_ptr<jobs::ScenarioRun> run;
  std::string report;
  {
    py::gil_scoped_release release;
    run = std::make_shared<jobs::ScenarioRun>(
        jobs::loadScenarioRun(scenario, [&warnings](const std::string& text) { warnings.push_back(text); }));
    const sim::ReplayOptions options =
        jobs::scenarioReplayOptions(run->scenario, fast ? sim::ReplayPace::Fast : sim::ReplayPace::RealTime);
    const sim::ReplayReport result = sim::replay(*run->world, run->poses, options);
    report = jobs::replayReport(*run, options, result).dump();
  }
  const mesh::SurfaceMesh* mesh = &run->world->tissue();
  return py::make_tuple(MeshView(std::move(run), mesh), report, warnings);
}

// Each trace is ("name", path) or ("name", N x 10 poses); the lines as `incise score` prints them.
py::tuple runScore(const std::string& scenario, const py::list& traces) {
  std::vector<std::string> names, paths, warnings;
  std::vector<std::vector<devices::PoseSample>> given;
  for (const py::handle item : traces) {
    const py::tuple pair = item.cast<py::tuple>();
    names.push_back(pair[0].cast<std::string>());
    if (py::isinstance<py::str>(pair[1])) {
      paths.push_back(pair[1].cast<std::string>());
      given.emplace_back();
    } else {
      paths.emplace_back();
      posesFromArray(pair[1].cast<py::array_t<double, py::array::c_style | py::array::forcecast>>(),
                     given.emplace_back());
    }
  }
  std::vector<std::string> lines;
  {
    py::gil_scoped_release release;
    const jobs::ScoringScenario scoring = jobs::loadScoringScenario(scenario);
    const jobs::Warn warn = [&warnings](const std::string& text) { warnings.push_back(text); };
    for (std::size_t i = 0; i < names.size(); ++i)  // every trace read and checked before any is scored
      if (!paths[i].empty()) given[i] = jobs::readScoreTrace(paths[i], scoring, warn);
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (given[i].empty()) throw std::invalid_argument(names[i] + ": the trace is empty (no pose to score)");
      lines.push_back(jobs::scoreLine(names[i], sim::scoreSession(scoring.scenario, scoring.tissue, given[i])));
    }
  }
  return py::make_tuple(lines, warnings);
}

std::string scoreSummary(const std::vector<std::string>& lines) {
  std::vector<nlohmann::ordered_json> parsed;
  for (const std::string& line : lines) parsed.push_back(nlohmann::ordered_json::parse(line));
  return jobs::scoreSummary(parsed).dump();
}

py::array_t<double> readJigsaws(const std::filesystem::path& path, const std::string& arm, double scale,
                                const py::handle& offset, double gripper_closed_below_rad) {
  devices::JigsawsOptions options;
  const std::optional<devices::JigsawsArm> chosen = devices::parseJigsawsArm(arm);
  if (!chosen) throw std::invalid_argument("arm: '" + arm + "' is not one of mtm-left, mtm-right, psm-left, psm-right");
  options.arm = *chosen;
  options.scale = scale;
  options.offset_m = vector3(offset, "offset");
  options.gripper_closed_below_rad = gripper_closed_below_rad;
  std::vector<devices::PoseSample> poses;
  {
    py::gil_scoped_release release;
    poses = devices::readJigsaws(path, options);
  }
  return posesToArray(poses);
}

}  // namespace

incision::CutterOptions::Refine refineMode(const std::string& name) {
  if (name == "off") return incision::CutterOptions::Refine::Off;
  if (name == "linear") return incision::CutterOptions::Refine::Linear;
  if (name == "pn") return incision::CutterOptions::Refine::PnTriangles;
  throw std::invalid_argument("refine: '" + name + "' is not one of linear, pn, off");
}

void bindJobs(py::module_& m) {
  m.def("_cut", &runCut, py::arg("mesh_path"), py::arg("options"),
        "incise.cut's work: (Mesh, summary JSON, ok, failure). Releases the GIL.");
  m.def("_replay", &runReplay, py::arg("scenario"), py::arg("fast"),
        "incise.replay's work: (Mesh, report JSON, warnings). Releases the GIL.");
  m.def("_score", &runScore, py::arg("scenario"), py::arg("traces"),
        "incise.score's work: (JSON lines, warnings). Releases the GIL.");
  m.def("_score_summary", &scoreSummary, py::arg("lines"), "incise.score_summary's work: the summary's JSON.");
  m.def(
      "_cut_defaults",
      [] {
        const jobs::CutJobOptions o;
        const incision::IncisionOptions& i = o.cutter.incision;
        py::dict d;
        d["scale"] = o.scale, d["subdivide"] = o.subdivide;
        d["start"] = py::make_tuple(o.start_m.x(), o.start_m.y(), o.start_m.z());
        d["direction"] = py::make_tuple(o.direction.x(), o.direction.y(), o.direction.z());
        d["length"] = o.length_m, d["bend"] = o.bend_m, d["speed"] = o.speed_m_per_s;
        d["depth"] = i.depth_m, d["opening"] = i.opening_m, d["alpha"] = i.alpha_m, d["beta"] = i.beta_m;
        d["spacing"] = i.spacing_m, d["refine"] = incision::toString(o.cutter.refine);
        d["refine_edge"] = o.cutter.refine_edge_m;
        return d;
      },
      "The defaults of incise.cut's options (those of `incise cut`).");
  m.def(
      "read_trace",
      [](const std::filesystem::path& path) {
        std::vector<devices::PoseSample> poses;
        {
          py::gil_scoped_release release;
          poses = devices::TraceReader::readAll(path);
        }
        return posesToArray(poses);
      },
      py::arg("path"), R"doc(
The poses of a CSV trace (devices/TRACE_FORMAT.md) as an N x 10 float64 array (a new array): time_s, tip
x y z (metres), orientation w x y z, buttons, pressure (NaN where the device has no sensor). Raises
incise.InputError naming the file, line and column at fault.
)doc");
  m.def("read_jigsaws", &readJigsaws, py::arg("path"), py::arg("arm") = "psm-right", py::arg("scale") = 1.0,
        py::arg("offset") = std::vector<double>{0.0, 0.0, 0.0}, py::arg("gripper_closed_below") = 0.0, R"doc(
One arm of a JIGSAWS kinematics file (da Vinci recordings at 30 Hz, 76 columns a line) as poses, an N x 10
array like read_trace's: the tip scaled then offset (metres), the rotation as the nearest unit quaternion,
button 0 held while the gripper angle is below `gripper_closed_below` (radians). `arm`: mtm-left,
mtm-right, psm-left or psm-right. Raises incise.InputError naming the file, line and column at fault.
)doc");
}

}  // namespace incise::python
