// The Python module's pieces (module.cpp joins them): meshes as numpy arrays (MeshView), poses from and to
// numpy, and the registration of each part. Arrays cross as numpy arrays: vertices N x 3 float64, faces
// M x 3 int64, kinds uint8, poses N x 10 float64 in the trace's columns (time_s, tip x y z in metres,
// orientation w x y z, buttons, pressure or NaN).
// Threads: the GIL's owner (long calls release it; a World refuses a second caller while one runs). Cost:
// as each call says. Failure: C++ exceptions become Python ones (module.cpp: incise.InputError for bad
// files and meshes, ValueError for bad arguments).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "incise/devices/pose_sample.h"
#include "incise/incision/surface_cutter_options.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::python {

namespace py = pybind11;

// A surface mesh that does not change any more (a loaded mesh, a cut's or a replay's result, a world's
// snapshot), kept alive by `owner`, with its faces and kinds gathered once on first use.
class MeshView {
 public:
  MeshView(std::shared_ptr<const void> owner, const mesh::SurfaceMesh* mesh) : owner_(std::move(owner)), mesh_(mesh) {}
  static MeshView owning(mesh::SurfaceMesh mesh);

  const mesh::SurfaceMesh& mesh() const noexcept { return *mesh_; }
  // Live vertices x 3 doubles: the mesh's own storage when no vertex is deleted (the cutter never deletes
  // one), else a compact copy made once. The count is taken once (O(V)): the mesh does not change.
  const double* vertices() const;
  std::size_t vertexCount() const;
  const std::vector<std::int64_t>& faces() const;  // live faces x 3, made once
  const std::vector<std::uint8_t>& faceKinds() const;

 private:
  void gatherFaces() const;
  void countVertices() const;
  std::shared_ptr<const void> owner_;
  const mesh::SurfaceMesh* mesh_;
  mutable std::vector<double> compact_vertices_;
  mutable std::vector<std::int64_t> faces_;
  mutable std::vector<std::uint8_t> face_kinds_;
  mutable std::size_t vertex_count_ = 0;
  mutable bool counted_ = false, contiguous_ = false, gathered_ = false, compacted_ = false;
};

// A read-only numpy view of `count` x `columns` elements at `data`, kept alive by `base`.
template <typename T>
py::array readOnlyView(const T* data, std::size_t count, std::size_t columns, py::handle base) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)},
      strides{static_cast<py::ssize_t>(columns * sizeof(T))};
  if (columns > 1) shape.push_back(static_cast<py::ssize_t>(columns)), strides.push_back(sizeof(T));
  py::array array(py::dtype::of<T>(), shape, strides, data, base);
  array.attr("setflags")(py::arg("write") = false);
  return array;
}

// Copies of a live mesh's arrays (for a world, whose mesh changes on).
py::array_t<double> copyVertices(const mesh::SurfaceMesh& mesh);
py::tuple copyFaces(const mesh::SurfaceMesh& mesh);  // (faces M x 3 int64, kinds M uint8)

// "linear", "pn" or "off" (the CLI's --refine names); std::invalid_argument for another.
incision::CutterOptions::Refine refineMode(const std::string& name);

inline constexpr int kPoseColumns = 10;
// Poses from an N x 10 (or 10) float64 array into `out` (cleared first). Throws std::invalid_argument for
// another shape.
void posesFromArray(const py::array_t<double, py::array::c_style | py::array::forcecast>& array,
                    std::vector<devices::PoseSample>& out);
py::array_t<double> posesToArray(std::span<const devices::PoseSample> poses);

void bindMesh(py::module_& m);
void bindJobs(py::module_& m);
void bindWorld(py::module_& m);

}  // namespace incise::python
