#include "incise/tets/tetrahedralize.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifndef TETLIBRARY
#define TETLIBRARY  // TetGen's library interface: failures are thrown as int codes instead of exit()
#endif
#include <tetgen.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace incise::tets {
namespace {

using Vec = Eigen::Vector3d;

// Sign of det(b - a, c - a, d - a): > 0 when d lies on the side of (a, b, c) its normal points to.
int orient3d(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  Eigen::Matrix3d m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  m.col(2) = d - a;
  const double det = m.determinant();
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

std::string number(double x) {
  char s[400];
  const auto r = std::to_chars(s, s + sizeof s, x, std::chars_format::fixed);  // shortest round-trip
  return std::string(s, r.ptr);
}

const char* tetgenMeaning(int code) {
  switch (code) {
    case 1:
      return "out of memory";
    case 2:
      return "internal error";
    case 3:
      return "a self-intersection of the input surface";
    case 4:
      return "a very small input feature size";
    case 5:
      return "two very close input facets";
    case 10:
      return "an input error";
    default:
      return "an unknown error";
  }
}

// The surface's non-deleted vertices and faces as TetGen's input (0-based): one facet of one triangle per
// face. The arrays are TetGen's to free (tetgenio's destructor, with delete[]).
void fillInput(const mesh::TriMesh& mesh, tetgenio& in) {
  in.firstnumber = 0;
  std::vector<int> compact(mesh.n_vertices(), -1);
  int vertices = 0;
  for (const auto v : mesh.vertices())
    if (!mesh.status(v).deleted()) compact[static_cast<size_t>(v.idx())] = vertices++;
  in.numberofpoints = vertices;
  in.pointlist = new REAL[3 * static_cast<size_t>(vertices)];
  for (const auto v : mesh.vertices()) {
    const int i = compact[static_cast<size_t>(v.idx())];
    if (i < 0) continue;
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = mesh.point(v)[k];
  }
  int faces = 0;
  for (const auto f : mesh.faces())
    if (!mesh.status(f).deleted()) ++faces;
  in.numberoffacets = faces;
  in.facetlist = new tetgenio::facet[static_cast<size_t>(faces)];
  int next = 0;
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    tetgenio::facet& facet = in.facetlist[next++];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::polygon& polygon = facet.polygonlist[0];
    tetgenio::init(&polygon);
    polygon.numberofvertices = 3;
    polygon.vertexlist = new int[3];
    int k = 0;
    for (const auto v : mesh.fv_range(f)) polygon.vertexlist[k++] = compact[static_cast<size_t>(v.idx())];
  }
}

// TetGen's tets as a TetMesh, each positively oriented; throws MeshError for a node index out of range.
TetMesh readOutput(const tetgenio& out) {
  TetMesh result;
  result.nodes_m.resize(static_cast<size_t>(out.numberofpoints));
  for (int i = 0; i < out.numberofpoints; ++i)
    result.nodes_m[static_cast<size_t>(i)] = {out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]};
  result.tets.resize(static_cast<size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    std::array<int, 4>& tet = result.tets[static_cast<size_t>(t)];
    for (int k = 0; k < 4; ++k) tet[static_cast<size_t>(k)] = out.tetrahedronlist[4 * t + k] - out.firstnumber;
    for (int k = 0; k < 4; ++k)
      if (tet[static_cast<size_t>(k)] < 0 || tet[static_cast<size_t>(k)] >= out.numberofpoints)
        throw mesh::MeshError("tetrahedralize: TetGen returned tet " + std::to_string(t) + " with node index " +
                              std::to_string(tet[static_cast<size_t>(k)]) + " out of range");
    // TetGen's own orientation convention is the opposite sign; normalise to det(b-a, c-a, d-a) > 0.
    const Vec& a = result.nodes_m[static_cast<size_t>(tet[0])];
    if (orient3d(a, result.nodes_m[static_cast<size_t>(tet[1])], result.nodes_m[static_cast<size_t>(tet[2])],
                 result.nodes_m[static_cast<size_t>(tet[3])]) < 0)
      std::swap(tet[2], tet[3]);
  }
  return result;
}

}  // namespace

TetMesh tetrahedralize(const mesh::SurfaceMesh& surface, const TetrahedralizeOptions& options) {
  if (!std::isfinite(options.radius_edge_ratio) || (options.radius_edge_ratio != 0 && options.radius_edge_ratio < 1.0))
    throw std::invalid_argument("tetrahedralize: radius_edge_ratio " + number(options.radius_edge_ratio) +
                                " is not 0 or a finite value >= 1");
  if (!std::isfinite(options.max_volume_m3) || options.max_volume_m3 < 0)
    throw std::invalid_argument("tetrahedralize: max_volume_m3 " + number(options.max_volume_m3) +
                                " is not a finite value >= 0");
  const mesh::TriMesh& mesh = surface.mesh();
  const mesh::ManifoldReport report = mesh::checkManifold(mesh);
  if (!report.closed_two_manifold)
    throw mesh::MeshError("tetrahedralize: the surface is not a closed two-manifold: " + report.first_problem);
  // TetGen 1.5 may crash instead of failing on a self-intersecting surface: never hand it one.
  if (const auto pair = findSelfIntersection(mesh))
    throw mesh::MeshError("tetrahedralize: the surface intersects itself: face " + std::to_string(pair->first) +
                          " and face " + std::to_string(pair->second));

  tetgenio in, out;  // tetgenio frees its arrays with delete[]
  fillInput(mesh, in);

  // p: the input is a piecewise linear complex; z: 0-based output; Q: quiet. Appended, not "q" + ...:
  // GCC 12 warns falsely on that (-Wrestrict, PR 105651).
  std::string switches = "pzQ";
  if (options.radius_edge_ratio > 0) switches.append("q").append(number(options.radius_edge_ratio));
  if (options.max_volume_m3 > 0) switches.append("a").append(number(options.max_volume_m3));
  if (options.keep_surface) switches += "Y";
  try {
    ::tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw mesh::MeshError("tetrahedralize: TetGen (switches \"" + switches + "\") failed with code " +
                          std::to_string(code) + ": " + tetgenMeaning(code));
  }
  if (out.numberofcorners != 4)
    throw mesh::MeshError("tetrahedralize: TetGen returned " + std::to_string(out.numberofcorners) + "-node tets");

  TetMesh result = readOutput(out);
  buildAdjacency(result);
  return result;
}

}  // namespace incise::tets
