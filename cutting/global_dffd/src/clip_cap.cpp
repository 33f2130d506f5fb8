#include "incise/global_dffd/clip_cap.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include "incise/core/format.h"
#include "incise/mesh/cgal_mesh.h"
#include "incise/mesh/cgal_origin.h"

namespace incise::global_dffd {
namespace {

using Kernel = mesh::detail::CgalKernel;
using Point = mesh::detail::CgalPoint;
using CgalMesh = mesh::detail::CgalMesh;
namespace PMP = CGAL::Polygon_mesh_processing;

// The clipping plane x[axis] = value, the side kept, and how near it a vertex is put on it.
struct Plane {
  int axis = 0;
  double value = 0.0;
  KeepSide keep = KeepSide::Below;
  double tolerance = 0.0;
};

const char* sideName(KeepSide keep) { return keep == KeepSide::Below ? "below" : "above"; }

// The vertices of `mesh` (garbage-collected) as OpenMesh points; those within `tolerance` of the plane
// get x[axis] = value exactly, and any vertex beyond the plane on the far side by more than that is an error.
std::vector<Eigen::Vector3d> clippedPoints(const CgalMesh& mesh, int axis, double value, KeepSide keep,
                                           double tolerance) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.number_of_vertices());
  const double sign = keep == KeepSide::Below ? 1.0 : -1.0;  // sign * (x - value) > 0 on the far side
  for (const auto v : mesh.vertices()) {
    const Point& q = mesh.point(v);
    Eigen::Vector3d p(q.x(), q.y(), q.z());
    const double beyond = sign * (p[axis] - value);
    if (std::abs(p[axis] - value) <= tolerance) {
      p[axis] = value;
    } else if (beyond > 0) {
      throw mesh::MeshError("clipAndCap: CGAL left vertex " + core::formatPoint(p) + " " + core::formatNumber(beyond) +
                            " beyond the plane x[" + std::to_string(axis) + "] = " + core::formatNumber(value) +
                            ", on the side not kept");
    }
    points.push_back(p);
  }
  return points;
}

// Face `made` of the result takes what its origin in `source` had: its kind, material and texture
// coordinates (interpolated at its corners); a cap face (from the clipper) is a wall, mapped on its plane.
void inherit(const mesh::SurfaceMesh& source, int origin, mesh::SurfaceMesh& out, mesh::TriMesh::FaceHandle made) {
  const mesh::TriMesh& m = out.mesh();
  const mesh::TriMesh::FaceHandle from(origin);
  const bool cap = origin < 0;  // from the clipper (or, never seen, of no known origin: mapped on its plane too)
  out.setKind(made, origin >= 0                          ? source.kind(from)
                    : origin == mesh::detail::kFromOther ? mesh::FaceKind::Wall
                                                         : mesh::FaceKind::Original);
  if (source.hasMaterials()) out.setMaterial(made, cap ? 0 : source.material(from));
  if (!source.hasTexCoords()) return;
  std::array<Eigen::Vector3d, 3> x;
  auto h = m.halfedge_handle(made);
  for (std::size_t i = 0; i < 3; ++i, h = m.next_halfedge_handle(h))
    x[i] = mesh::toEigen(m.point(m.to_vertex_handle(h)));
  std::array<Eigen::Vector2d, 3> uv;
  if (cap) {
    uv = mesh::planarTexCoords(x);
  } else {
    const mesh::FaceCorners corners = mesh::faceCorners(source, from);
    std::array<Eigen::Vector3d, 3> y;
    for (std::size_t i = 0; i < 3; ++i) y[i] = mesh::toEigen(source.mesh().point(corners.vertex[i]));
    for (std::size_t i = 0; i < 3; ++i) uv[i] = mesh::interpolateTexCoord(y, corners.uv, x[i]);
  }
  h = m.halfedge_handle(made);
  for (std::size_t i = 0; i < 3; ++i, h = m.next_halfedge_handle(h)) out.setTexCoord(h, uv[i]);
}

// `mesh` (garbage-collected, triangles only, each face's origin in `origin`) as a SurfaceMesh with what
// each face inherits from `source`; vertices snapped to the plane as clippedPoints does.
mesh::SurfaceMesh fromCgal(const CgalMesh& mesh, const mesh::detail::OriginMap& origin, const mesh::SurfaceMesh& source,
                           const Plane& plane) {
  mesh::SurfaceMesh out;
  out.mesh().reserve(mesh.number_of_vertices(), mesh.number_of_edges(), mesh.number_of_faces());
  if (source.hasTexCoords()) out.addTexCoords();
  for (const mesh::Material& material : source.materials()) out.addMaterial(material);
  std::vector<mesh::TriMesh::VertexHandle> index;
  index.reserve(mesh.number_of_vertices());
  for (const Eigen::Vector3d& p : clippedPoints(mesh, plane.axis, plane.value, plane.keep, plane.tolerance))
    index.push_back(out.addVertex(p));
  for (const auto f : mesh.faces()) {
    std::vector<mesh::TriMesh::VertexHandle> corners;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      corners.push_back(index[static_cast<std::size_t>(v.idx())]);
    }
    if (corners.size() != 3 || !out.mesh().add_face(corners).is_valid()) {
      throw mesh::MeshError("clipAndCap: the clipped mesh cannot be rebuilt as an OpenMesh triangle mesh (face " +
                            std::to_string(f.idx()) + " with " + std::to_string(corners.size()) + " vertices refused)");
    }
    inherit(source, origin[f], out, mesh::TriMesh::FaceHandle(static_cast<int>(out.mesh().n_faces()) - 1));
  }
  out.mesh().update_normals();
  return out;
}

}  // namespace

mesh::SurfaceMesh clipAndCap(const mesh::SurfaceMesh& mesh, int axis, double value, KeepSide keep) {
  if (axis < 0 || axis > 2) {
    throw std::invalid_argument("clipAndCap: axis must be 0, 1 or 2 (got " + std::to_string(axis) + ")");
  }
  if (!std::isfinite(value)) {
    throw std::invalid_argument("clipAndCap: plane value must be finite (got " + core::formatNumber(value) + ")");
  }
  const mesh::TriMesh& tri = mesh.mesh();
  const mesh::ManifoldReport report = mesh::checkManifold(tri);
  if (!report.closed_two_manifold) {
    throw mesh::MeshError("clipAndCap: the input is not a closed two-manifold: " +
                          (report.first_problem.empty() ? std::string("no faces") : report.first_problem));
  }

  double lo = std::numeric_limits<double>::infinity(), hi = -lo, size = 0;
  {
    OpenMesh::Vec3d bmin(lo, lo, lo), bmax(hi, hi, hi);
    for (const auto v : tri.vertices()) {
      bmin.minimize(tri.point(v));
      bmax.maximize(tri.point(v));
    }
    lo = bmin[axis];
    hi = bmax[axis];
    size = (bmax - bmin).max();
  }
  // The plane misses the volume (or only touches it): decided here rather than by CGAL, which would
  // corefine with a plane that merely touches the surface.
  const bool all_below = hi <= value, all_above = lo >= value;
  if (keep == KeepSide::Below ? all_below : all_above) return mesh;
  if (keep == KeepSide::Below ? all_above : all_below) return mesh::SurfaceMesh();

  std::vector<int> face_handles;
  CgalMesh cgal = mesh::detail::toCgal(tri, "clipAndCap", &face_handles);
  mesh::detail::OriginVisitor visitor;  // the result is the input mesh itself, clipped in place
  visitor.first = visitor.out = &cgal;
  visitor.first_origin = visitor.out_origin = mesh::detail::originsOf(cgal, face_handles);
  // clip keeps the negative side of the plane, where a x + b y + c z + d < 0: normal +e_axis keeps
  // x[axis] < value, normal -e_axis keeps x[axis] > value.
  const double n = keep == KeepSide::Below ? 1.0 : -1.0;
  const Kernel::Plane_3 plane(axis == 0 ? n : 0.0, axis == 1 ? n : 0.0, axis == 2 ? n : 0.0, -n * value);
  const std::string where = "clipAndCap: keeping " + std::string(sideName(keep)) + " x[" + std::to_string(axis) +
                            "] = " + core::formatNumber(value) + ": ";
  try {
    const bool manifold = PMP::clip(
        cgal, plane,
        CGAL::parameters::clip_volume(true).use_compact_clipper(true).throw_on_self_intersection(true).visitor(
            visitor));
    if (!manifold) throw mesh::MeshError(where + "CGAL's clip reports a non-manifold result");
    cgal.collect_garbage();
    // The corefinement gives triangles; a polygon left by a later CGAL would be split here.
    if (!PMP::triangulate_faces(cgal)) {
      throw mesh::MeshError(where + "CGAL could not triangulate a face of the result");
    }
  } catch (const PMP::Corefinement::Self_intersection_exception&) {
    throw mesh::MeshError(where + "the input intersects itself near the plane");
  } catch (const mesh::MeshError&) {
    throw;
  } catch (const std::exception& e) {
    throw mesh::MeshError(where + "CGAL failed: " + e.what());
  }
  const auto origin = cgal.property_map<mesh::detail::CgalFace, int>("f:incise_origin").first;
  return fromCgal(cgal, origin, mesh, {axis, value, keep, 1e-12 * std::max(std::abs(value), size)});
}

}  // namespace incise::global_dffd
