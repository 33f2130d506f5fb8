// The compiled part of the Python package `incise` (incise._incise): meshes, the CLI's jobs, worlds, and
// incise's errors as Python exceptions. The package (incise/__init__.py) is the public face.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/jigsaws.h"
#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario_error.h"

PYBIND11_MODULE(_incise, m) {
  namespace py = pybind11;
  using namespace incise;
  m.doc() = "incise's compiled core; use the package `incise` (help(incise)).";
  m.attr("__version__") = INCISE_PROJECT_VERSION_STRING;
  // A file, mesh, scenario or trace incise refused: the message says what and where (file:line, element).
  static py::exception<std::runtime_error> input_error(m, "InputError", PyExc_ValueError);
  input_error.attr("__doc__") =
      "A file, mesh, scenario or trace incise refused (a ValueError): the message says what and where "
      "(file:line, key path, element index).";
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const mesh::MeshError& e) {
      input_error(e.what());
    } catch (const sim::ScenarioError& e) {
      input_error(e.what());
    } catch (const devices::TraceError& e) {
      input_error(e.what());
    } catch (const devices::JigsawsError& e) {
      input_error(e.what());
    } catch (const devices::HidRecordingError& e) {
      input_error(e.what());
    } catch (const devices::HidDescriptorError& e) {
      input_error(e.what());
    } catch (const devices::HidProfileError& e) {
      input_error(e.what());
    }
  });
  python::bindMesh(m);
  python::bindJobs(m);
  python::bindWorld(m);
}
