// incise.Mesh: a surface mesh as numpy arrays (views where the mesh outlives them), load_mesh, and the
// poses' array form.
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "incise/jobs/mesh_arrays.h"
#include "incise/jobs/scenario_run.h"
#include "incise/mesh/mesh_hash.h"

namespace incise::python {

MeshView MeshView::owning(mesh::SurfaceMesh mesh) {
  auto owned = std::make_shared<const mesh::SurfaceMesh>(std::move(mesh));
  const mesh::SurfaceMesh* raw = owned.get();
  return MeshView(std::move(owned), raw);
}

void MeshView::countVertices() const {
  if (counted_) return;
  vertex_count_ = jobs::liveVertices(mesh_->mesh());
  contiguous_ = vertex_count_ == mesh_->mesh().n_vertices();
  counted_ = true;
}

const double* MeshView::vertices() const {
  countVertices();
  if (contiguous_) return mesh_->mesh().points()->data();
  if (!compacted_) {
    compact_vertices_.resize(3 * vertex_count_);
    jobs::copyVertices(*mesh_, compact_vertices_);
    compacted_ = true;
  }
  return compact_vertices_.data();
}

std::size_t MeshView::vertexCount() const {
  countVertices();
  return vertex_count_;
}

void MeshView::gatherFaces() const {
  if (gathered_) return;
  const std::size_t n = jobs::liveFaces(mesh_->mesh());
  faces_.resize(3 * n);
  face_kinds_.resize(n);
  jobs::copyFaces(*mesh_, faces_, face_kinds_);
  gathered_ = true;
}

const std::vector<std::int64_t>& MeshView::faces() const {
  gatherFaces();
  return faces_;
}

const std::vector<std::uint8_t>& MeshView::faceKinds() const {
  gatherFaces();
  return face_kinds_;
}

py::array_t<double> copyVertices(const mesh::SurfaceMesh& mesh) {
  const std::size_t n = jobs::liveVertices(mesh.mesh());
  py::array_t<double> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  jobs::copyVertices(mesh, std::span(out.mutable_data(), 3 * n));
  return out;
}

py::tuple copyFaces(const mesh::SurfaceMesh& mesh) {
  const std::size_t n = jobs::liveFaces(mesh.mesh());
  py::array_t<std::int64_t> faces({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  py::array_t<std::uint8_t> kinds(static_cast<py::ssize_t>(n));
  jobs::copyFaces(mesh, std::span(faces.mutable_data(), 3 * n), std::span(kinds.mutable_data(), n));
  return py::make_tuple(faces, kinds);
}

void posesFromArray(const py::array_t<double, py::array::c_style | py::array::forcecast>& array,
                    std::vector<devices::PoseSample>& out) {
  out.clear();
  const bool one = array.ndim() == 1 && array.shape(0) == kPoseColumns;
  if (!one && !(array.ndim() == 2 && array.shape(1) == kPoseColumns))
    throw std::invalid_argument(
        "poses: expected an N x 10 array (time_s, tip x y z, orientation w x y z, buttons, "
        "pressure or NaN), got shape " +
        std::string(py::str(array.attr("shape"))));
  const std::size_t n = one ? 1 : static_cast<std::size_t>(array.shape(0));
  const double* row = array.data();
  for (std::size_t i = 0; i < n; ++i, row += kPoseColumns) {
    devices::PoseSample& p = out.emplace_back();
    p.time_s = row[0];
    p.tip_m = Eigen::Vector3d(row[1], row[2], row[3]);
    p.orientation = Eigen::Quaterniond(row[4], row[5], row[6], row[7]);
    if (!(row[8] >= 0.0 && row[8] <= 4294967295.0 && row[8] == std::floor(row[8])))
      throw std::invalid_argument("poses: row " + std::to_string(i) + ": buttons " + std::to_string(row[8]) +
                                  " is not an integer in [0, 2^32 - 1]");
    p.buttons = static_cast<std::uint32_t>(row[8]);
    if (!std::isnan(row[9])) p.pressure = row[9];
  }
}

py::array_t<double> posesToArray(std::span<const devices::PoseSample> poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{kPoseColumns}});
  double* row = out.mutable_data();
  for (const devices::PoseSample& p : poses) {
    const double values[kPoseColumns] = {p.time_s,
                                         p.tip_m.x(),
                                         p.tip_m.y(),
                                         p.tip_m.z(),
                                         p.orientation.w(),
                                         p.orientation.x(),
                                         p.orientation.y(),
                                         p.orientation.z(),
                                         static_cast<double>(p.buttons),
                                         p.pressure.value_or(std::nan(""))};
    std::copy(values, values + kPoseColumns, row);
    row += kPoseColumns;
  }
  return out;
}

namespace {

py::object jsonToPython(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// The per-element kinds, the summary and the files (bindMeshClass's second half).
void addMeshKindsAndFiles(py::class_<MeshView>& cls) {
  cls.def_property_readonly(
         "wall",
         [](const MeshView& v) {
           const std::vector<std::uint8_t>& kinds = v.faceKinds();
           py::array_t<bool> wall(static_cast<py::ssize_t>(kinds.size()));
           for (std::size_t i = 0; i < kinds.size(); ++i)
             wall.mutable_data()[i] = kinds[i] == static_cast<std::uint8_t>(mesh::FaceKind::Wall);
           return wall;
         },
         "M bool: the face is a wall of the wound (a new array, a copy).")
      .def_property_readonly(
          "vertex_kinds",
          [](const MeshView& v) {
            const mesh::SurfaceMesh& s = v.mesh();
            py::array_t<std::uint8_t> kinds(static_cast<py::ssize_t>(v.vertexCount()));
            std::size_t i = 0;
            for (const auto h : s.mesh().vertices()) kinds.mutable_data()[i++] = static_cast<std::uint8_t>(s.kind(h));
            return kinds;
          },
          "N uint8: 0 original, 1 on a lip of the cut (seam), 2 inside the wound (a new array, a copy).")
      .def_property_readonly(
          "geometry_hash", [](const MeshView& v) { return jobs::hexText(mesh::geometryHash(v.mesh())); },
          "The mesh's FNV-1a hash as 16 hex digits, as `incise replay` writes it (geometry_hash in report.json).")
      .def_property_readonly(
          "summary", [](const MeshView& v) { return jsonToPython(mesh::toJson(mesh::summarize(v.mesh()))); },
          "Counts and checks as a dict: vertices, faces, wall_faces, split_faces, seam_vertices, wall_vertices, "
          "boundary_edges, euler_characteristic, closed_two_manifold.")
      .def(
          "save_obj", [](const MeshView& v, const std::filesystem::path& path) { mesh::saveObj(v.mesh(), path); },
          py::arg("path"),
          "Writes the mesh as OBJ (walls in the group `wall`), the bytes `incise cut` and `incise replay` write; "
          "through a .tmp file, renamed: complete or absent.")
      .def(
          "save_ply", [](const MeshView& v, const std::filesystem::path& path) { mesh::savePly(v.mesh(), path); },
          py::arg("path"), "Writes the mesh as ASCII PLY with vertex and face kinds; atomically as save_obj.")
      .def("__repr__", [](const MeshView& v) {
        return "<incise.Mesh: " + std::to_string(v.vertexCount()) + " vertices, " +
               std::to_string(jobs::liveFaces(v.mesh().mesh())) + " faces>";
      });
}

// Texture coordinates and materials, when the mesh's file had them (None otherwise).
void addMeshTextures(py::class_<MeshView>& cls) {
  cls.def_property_readonly(
         "texcoords",
         [](const MeshView& v) -> py::object {
           const mesh::SurfaceMesh& s = v.mesh();
           if (!s.hasTexCoords()) return py::none();
           const auto n = static_cast<py::ssize_t>(jobs::liveFaces(s.mesh()));
           py::array_t<double> uv({n, py::ssize_t{3}, py::ssize_t{2}});
           jobs::copyTexCoords(s, std::span(uv.mutable_data(), static_cast<std::size_t>(6 * n)));
           return uv;
         },
         "M x 3 x 2 float64: each face's corners' texture coordinates (u, v), the corners in `faces`' order (a "
         "vertex on a texture seam has one per face side), or None for a mesh without them. A new array, a copy.")
      .def_property_readonly(
          "face_materials",
          [](const MeshView& v) -> py::object {
            const mesh::SurfaceMesh& s = v.mesh();
            if (!s.hasMaterials()) return py::none();
            const auto n = static_cast<py::ssize_t>(jobs::liveFaces(s.mesh()));
            py::array_t<std::int32_t> materials(n);
            jobs::copyFaceMaterials(s, std::span(materials.mutable_data(), static_cast<std::size_t>(n)));
            return materials;
          },
          "M int32: each face's index into `materials` (OBJ usemtl), -1 for a wall (written with incise's own "
          "material, `incise_wall`), or None for a mesh without materials. A copy.")
      .def_property_readonly(
          "materials",
          [](const MeshView& v) {
            py::list names;
            for (const mesh::Material& material : v.mesh().materials()) names.append(material.name);
            return names;
          },
          "The materials' names (OBJ newmtl / usemtl), in index order; empty for a mesh without materials.");
}

void bindMeshClass(py::module_& m) {
  py::class_<MeshView> cls(m, "Mesh", R"doc(
A closed triangle surface mesh in metres (incise's tissue), read-only, as numpy arrays.

The arrays hold the live elements in the mesh's order (the cut's deleted faces left out), as `incise cut`
writes them to OBJ. `vertices` and `faces` are read-only views into memory this object keeps (no copy;
they keep the object alive); `wall` and `vertex_kinds` are new arrays on each access.

Make one with incise.load_mesh(), Mesh.from_arrays(), or take one from a cut, a replay or a world.
)doc");
  cls.def_static(
         "from_arrays",
         [](py::array_t<double, py::array::c_style | py::array::forcecast> vertices,
            py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> faces) {
           if (vertices.ndim() != 2 || vertices.shape(1) != 3)
             throw std::invalid_argument("vertices: expected an N x 3 array");
           if (faces.ndim() != 2 || faces.shape(1) != 3) throw std::invalid_argument("faces: expected an M x 3 array");
           return MeshView::owning(jobs::meshFromArrays(std::span(vertices.data(), vertices.size()),
                                                        std::span(faces.data(), faces.size())));
         },
         py::arg("vertices"), py::arg("faces"), R"doc(
A mesh from arrays: vertices N x 3 (metres), faces M x 3 vertex indices (0-based, counter-clockwise seen
from outside). The arrays are copied. Checked as a mesh file is: raises incise.InputError naming the vertex
or face at fault when the mesh is not a closed, consistently oriented two-manifold.
)doc")
      .def_property_readonly(
          "vertices",
          [](py::object self) {
            const MeshView& v = self.cast<const MeshView&>();
            return readOnlyView(v.vertices(), v.vertexCount(), 3, self);
          },
          "N x 3 float64, metres: a read-only view (no copy) that keeps the mesh alive.")
      .def_property_readonly(
          "faces",
          [](py::object self) {
            const MeshView& v = self.cast<const MeshView&>();
            return readOnlyView(v.faces().data(), v.faces().size() / 3, 3, self);
          },
          "M x 3 int64 vertex indices, counter-clockwise from outside: a read-only view (gathered once).")
      .def_property_readonly(
          "face_kinds",
          [](py::object self) {
            const MeshView& v = self.cast<const MeshView&>();
            return readOnlyView(v.faceKinds().data(), v.faceKinds().size(), 1, self);
          },
          "M uint8: 0 original skin, 1 a piece of a face the cut split, 2 a wall of the wound. A read-only view.");
  addMeshKindsAndFiles(cls);
  addMeshTextures(cls);
}

}  // namespace

void bindMesh(py::module_& m) {
  bindMeshClass(m);
  m.def(
      "load_mesh",
      [](const std::filesystem::path& path, double scale, int subdivide) {
        if (subdivide < 0 || subdivide > 5)
          throw std::invalid_argument("subdivide " + std::to_string(subdivide) + " is outside [0, 5]");
        py::gil_scoped_release release;
        return MeshView::owning(mesh::subdivided(mesh::loadSurfaceMesh(path, scale), subdivide));
      },
      py::arg("path"), py::arg("scale") = 1.0, py::arg("subdivide") = 0, R"doc(
Reads a closed triangle mesh (OBJ, PLY, OFF, STL), multiplies its positions by `scale` (metres per file
unit) and applies `subdivide` rounds of Loop subdivision (0..5; each multiplies the faces by 4).
Raises incise.InputError naming the file and line (or byte) at fault. Releases the GIL while it reads.
)doc");
}

}  // namespace incise::python
