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

namespace incise::global_dffd {
namespace {

using Kernel = mesh::detail::CgalKernel;
using Point = mesh::detail::CgalPoint;
using CgalMesh = mesh::detail::CgalMesh;
namespace PMP = CGAL::Polygon_mesh_processing;

const char* sideName(KeepSide keep) { return keep == KeepSide::Below ? "below" : "above"; }

// `mesh` (garbage-collected, triangles only) as a SurfaceMesh; vertices within `tolerance` of the plane get
// x[axis] = value exactly, and any vertex beyond the plane on the far side by more than that is an error.
mesh::SurfaceMesh fromCgal(const CgalMesh& mesh, int axis, double value, KeepSide keep, double tolerance) {
  mesh::TriMesh out;
  out.reserve(mesh.number_of_vertices(), mesh.number_of_edges(), mesh.number_of_faces());
  std::vector<mesh::TriMesh::VertexHandle> index(mesh.num_vertices());
  const double sign = keep == KeepSide::Below ? 1.0 : -1.0;  // sign * (x - value) > 0 on the far side
  for (const auto v : mesh.vertices()) {
    const Point& q = mesh.point(v);
    OpenMesh::Vec3d p(q.x(), q.y(), q.z());
    const double beyond = sign * (p[axis] - value);
    if (std::abs(p[axis] - value) <= tolerance) {
      p[axis] = value;
    } else if (beyond > 0) {
      throw mesh::MeshError("clipAndCap: CGAL left vertex " + core::formatPoint(mesh::toEigen(p)) + " " +
                            core::formatNumber(beyond) + " beyond the plane x[" + std::to_string(axis) +
                            "] = " + core::formatNumber(value) + ", on the side not kept");
    }
    index[static_cast<std::size_t>(v.idx())] = out.add_vertex(p);
  }
  for (const auto f : mesh.faces()) {
    std::vector<mesh::TriMesh::VertexHandle> corners;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      corners.push_back(index[static_cast<std::size_t>(v.idx())]);
    }
    if (corners.size() != 3 || !out.add_face(corners).is_valid()) {
      throw mesh::MeshError("clipAndCap: the clipped mesh cannot be rebuilt as an OpenMesh triangle mesh (face " +
                            std::to_string(f.idx()) + " with " + std::to_string(corners.size()) + " vertices refused)");
    }
  }
  out.update_normals();
  return mesh::SurfaceMesh(std::move(out));
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

  CgalMesh cgal = mesh::detail::toCgal(tri, "clipAndCap");
  // clip keeps the negative side of the plane, where a x + b y + c z + d < 0: normal +e_axis keeps
  // x[axis] < value, normal -e_axis keeps x[axis] > value.
  const double n = keep == KeepSide::Below ? 1.0 : -1.0;
  const Kernel::Plane_3 plane(axis == 0 ? n : 0.0, axis == 1 ? n : 0.0, axis == 2 ? n : 0.0, -n * value);
  const std::string where = "clipAndCap: keeping " + std::string(sideName(keep)) + " x[" + std::to_string(axis) +
                            "] = " + core::formatNumber(value) + ": ";
  try {
    const bool manifold = PMP::clip(
        cgal, plane, CGAL::parameters::clip_volume(true).use_compact_clipper(true).throw_on_self_intersection(true));
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
  return fromCgal(cgal, axis, value, keep, 1e-12 * std::max(std::abs(value), size));
}

}  // namespace incise::global_dffd
