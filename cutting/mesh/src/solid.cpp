// subtractSolid through CGAL's corefinement (compiled in the mesh module's CGAL object library), and the
// pieces of a closed surface.
#include "incise/mesh/solid.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <exception>
#include <unordered_map>
#include <utility>

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <Eigen/Geometry>

#include "incise/core/union_find.h"
#include "incise/mesh/cgal_mesh.h"

namespace incise::mesh {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using detail::CgalMesh;
using Face = CgalMesh::Face_index;
using OriginMap = CgalMesh::Property_map<Face, int>;
constexpr int kFromSolid = -2;  // a face of the solid's boundary
constexpr int kUnknown = -1;

// Follows every face of the result back to the tissue face it is a piece of (its OpenMesh index), or to the
// solid (kFromSolid). Copied by CGAL's named parameters: the maps are handles onto the meshes' properties.
struct OriginVisitor : PMP::Corefinement::Default_visitor<CgalMesh> {
  const CgalMesh* tissue = nullptr;
  const CgalMesh* out = nullptr;
  OriginMap tissue_origin, out_origin;
  int splitting = kUnknown;  // the origin of the face being split
  void before_subface_creations(Face split, CgalMesh& tm) {
    splitting = &tm == tissue ? tissue_origin[split] : kFromSolid;
  }
  void after_subface_created(Face made, CgalMesh& tm) {
    if (&tm == tissue) tissue_origin[made] = splitting;
  }
  void after_face_copy(Face from, const CgalMesh& source, Face made, CgalMesh& target) {
    if (&target == out) out_origin[made] = &source == tissue ? tissue_origin[from] : kFromSolid;
  }
};

struct PointHash {
  std::size_t operator()(const std::array<double, 3>& p) const noexcept {
    std::uint64_t bits[3];
    std::memcpy(bits, p.data(), sizeof bits);
    return static_cast<std::size_t>((bits[0] * 0x9E3779B97F4A7C15ULL) ^ (bits[1] * 0xC2B2AE3D27D4EB4FULL) ^
                                    (bits[2] * 0x165667B19E3779F9ULL));
  }
};

std::array<double, 3> key(const detail::CgalPoint& p) { return {p.x(), p.y(), p.z()}; }

// The corefined difference of `tissue` and `solid` as a CGAL mesh with each face's origin; throws what CGAL
// throws, MeshError when it reports failure.
CgalMesh difference(const TriMesh& tissue, const TriMesh& solid, OriginMap& origin) {
  std::vector<int> face_handles;
  CgalMesh a = detail::toCgal(tissue, "subtractSolid (tissue)", &face_handles);
  CgalMesh b = detail::toCgal(solid, "subtractSolid (solid)");
  CgalMesh out;
  OriginVisitor visitor;
  visitor.tissue = &a;
  visitor.out = &out;
  visitor.tissue_origin = a.add_property_map<Face, int>("f:incise_origin", kUnknown).first;
  visitor.out_origin = out.add_property_map<Face, int>("f:incise_origin", kUnknown).first;
  for (const Face f : a.faces()) visitor.tissue_origin[f] = face_handles[static_cast<std::size_t>(f.idx())];
  const bool valid = PMP::corefine_and_compute_difference(
      a, b, out, CGAL::parameters::visitor(visitor).throw_on_self_intersection(true),
      CGAL::parameters::throw_on_self_intersection(true));
  if (!valid) throw MeshError("CGAL's difference is not a closed two-manifold");
  // Two crossings a rounding apart (an edge of the solid passing within an ulp of an edge of the tissue)
  // become two vertices at one point: the faces between them have no area. CGAL collapses them.
  if (!PMP::remove_degenerate_faces(out)) throw MeshError("CGAL could not remove the difference's degenerate faces");
  out.collect_garbage();
  origin = visitor.out_origin;
  return out;
}

// Where the solid's surface passes near a vertex or an edge of the tissue, the pieces of the tissue's faces
// are needles and caps (two crossings of the cut a hair apart, a vertex a hair from the cut): among the faces
// that touch the cut (a vertex of the result not in the tissue), CGAL collapses edges shorter than a
// fiftieth of the tissue's mean edge `mean_edge_m` and flips caps that low. Nothing moves farther than that:
// the cut stays where it was to within a fiftieth of an edge (the kerf the surface cutter removes is wider).
void removeSlivers(CgalMesh& out, const OriginMap& origin, const TriMesh& tissue, double mean_edge_m) {
  std::unordered_map<std::array<double, 3>, int, PointHash> old;
  old.reserve(tissue.n_vertices());
  for (const auto v : tissue.vertices()) {
    const auto& p = tissue.point(v);
    old.emplace(std::array<double, 3>{p[0], p[1], p[2]}, v.idx());
  }
  std::vector<Face> near;
  for (const Face f : out.faces()) {
    bool touches = origin[f] == kFromSolid;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out))
      touches = touches || !old.count(key(out.point(v)));
    if (touches) near.push_back(f);
  }
  constexpr double kCapCosine = -0.94;  // an angle over about 160 degrees
  constexpr double kNeedleRatio = 6.0;  // the longest edge over six times the shortest
  const double small_m = 0.02 * mean_edge_m;
  PMP::experimental::remove_almost_degenerate_faces(near, out, kCapCosine, kNeedleRatio, small_m,
                                                    CGAL::parameters::flip_triangle_height_threshold(small_m));
  out.collect_garbage();
}

// Applies `out` to `tissue` in place (see subtractSolid). Throws MeshError when OpenMesh refuses a face.
void apply(SurfaceMesh& tissue, const CgalMesh& out, const OriginMap& origin, SubtractResult& result,
           std::vector<int>* changed_vertices, std::vector<int>* changed_faces) {
  TriMesh& m = tissue.mesh();
  const int old_vertices = static_cast<int>(m.n_vertices());
  std::unordered_map<std::array<double, 3>, int, PointHash> old_vertex;
  old_vertex.reserve(m.n_vertices());
  for (const auto v : m.vertices()) {
    const auto& p = m.point(v);
    old_vertex.emplace(std::array<double, 3>{p[0], p[1], p[2]}, v.idx());
  }
  std::vector<TriMesh::VertexHandle> vertex(out.num_vertices());
  for (const auto v : out.vertices()) {
    const auto found = old_vertex.find(key(out.point(v)));
    if (found != old_vertex.end()) vertex[static_cast<std::size_t>(v.idx())] = TriMesh::VertexHandle(found->second);
  }
  // Faces of the result that are faces of the tissue, same corners in the same order, are kept.
  std::vector<std::uint8_t> kept(m.n_faces(), 0);
  std::vector<Face> added;
  for (const Face f : out.faces()) {
    std::array<TriMesh::VertexHandle, 3> c;
    int i = 0;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out))
      c[static_cast<std::size_t>(i++ % 3)] = vertex[static_cast<std::size_t>(v.idx())];
    if (i != 3) throw MeshError("CGAL's difference has a face with " + std::to_string(i) + " corners");
    bool same = c[0].is_valid() && c[1].is_valid() && c[2].is_valid();
    if (same) {
      const auto h = m.find_halfedge(c[0], c[1]);
      same = h.is_valid() && m.face_handle(h).is_valid() && m.to_vertex_handle(m.next_halfedge_handle(h)) == c[2];
      if (same) kept[static_cast<std::size_t>(m.face_handle(h).idx())] = 1;
    }
    if (!same) added.push_back(f);
  }
  std::vector<FaceKind> old_kind(m.n_faces());
  std::vector<TriMesh::VertexHandle> touched;
  for (const auto f : m.faces()) {
    old_kind[static_cast<std::size_t>(f.idx())] = tissue.kind(f);
    if (kept[static_cast<std::size_t>(f.idx())]) continue;
    for (const auto v : m.fv_range(f)) touched.push_back(v);
    m.delete_face(f, false);
    ++result.faces_removed;
    if (changed_faces) changed_faces->push_back(f.idx());
  }
  for (const auto v : out.vertices()) {
    auto& h = vertex[static_cast<std::size_t>(v.idx())];
    if (h.is_valid()) continue;
    const auto& p = out.point(v);
    h = tissue.addVertex(Eigen::Vector3d(p.x(), p.y(), p.z()), VertexKind::Wall);
    ++result.vertices_added;
    if (changed_vertices) changed_vertices->push_back(h.idx());
  }
  for (const Face f : added) {
    std::vector<TriMesh::VertexHandle> c;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out))
      c.push_back(vertex[static_cast<std::size_t>(v.idx())]);
    const int from = origin[f];
    const FaceKind kind = from == kFromSolid                                                        ? FaceKind::Wall
                          : from >= 0 && old_kind[static_cast<std::size_t>(from)] == FaceKind::Wall ? FaceKind::Wall
                                                                                                    : FaceKind::Split;
    const auto made = tissue.addFace(c[0], c[1], c[2], kind);
    ++result.faces_added;
    if (changed_faces) changed_faces->push_back(made.idx());
    for (const auto v : c) touched.push_back(v);
  }
  for (const auto v : touched) {
    if (m.status(v).deleted()) continue;
    if (m.is_isolated(v)) {
      m.delete_vertex(v, false);
      ++result.vertices_removed;
    } else if (v.idx() >= old_vertices) {
      bool all_wall = true;
      for (const auto f : m.vf_range(v)) all_wall = all_wall && tissue.kind(f) == FaceKind::Wall;
      tissue.setKind(v, all_wall ? VertexKind::Wall : VertexKind::Seam);
    }
    if (changed_vertices) changed_vertices->push_back(v.idx());
  }
  m.update_normals();
}

}  // namespace

SubtractResult subtractSolid(SurfaceMesh& tissue, const SurfaceMesh& solid, std::vector<int>* changed_vertices,
                             std::vector<int>* changed_faces) {
  SubtractResult result;
  OriginMap origin;
  CgalMesh out;
  try {
    out = difference(tissue.mesh(), solid.mesh(), origin);
  } catch (const PMP::Corefinement::Self_intersection_exception&) {
    result.message = "the tissue or the solid crosses itself where they meet";
    return result;
  } catch (const std::exception& e) {
    result.message = std::string("CGAL's difference failed: ") + e.what();
    return result;
  }
  origin = out.property_map<Face, int>("f:incise_origin").first;
  try {
    removeSlivers(out, origin, tissue.mesh(), edgeLengths(tissue.mesh()).mean_m);
  } catch (const std::exception& e) {
    result.message = std::string("CGAL could not remove the cut's slivers: ") + e.what();
    return result;
  }
  const SurfaceMesh before = tissue;  // restored whole if OpenMesh refuses a face
  const std::size_t vertices_journal = changed_vertices ? changed_vertices->size() : 0;
  const std::size_t faces_journal = changed_faces ? changed_faces->size() : 0;
  try {
    apply(tissue, out, origin, result, changed_vertices, changed_faces);
  } catch (const std::exception& e) {
    tissue = before;
    if (changed_vertices) changed_vertices->resize(vertices_journal);
    if (changed_faces) changed_faces->resize(faces_journal);
    const SubtractResult failed{false, std::string("the difference could not be applied: ") + e.what()};
    return failed;
  }
  result.ok = true;
  return result;
}

std::vector<Piece> pieces(const TriMesh& mesh) {
  std::vector<int> storage;
  core::detail::UnionFind sets(storage, mesh.n_vertices());
  for (const auto f : mesh.faces()) {
    auto v = mesh.cfv_iter(f);
    const int first = v->idx();
    for (++v; v.is_valid(); ++v) sets.unite(first, v->idx());
  }
  std::unordered_map<int, Piece> by_root;
  for (const auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int i = 0, root = -1;
    for (const auto v : mesh.fv_range(f)) {
      if (i == 0) root = sets.find(v.idx());
      if (i < 3) p[static_cast<std::size_t>(i)] = toEigen(mesh.point(v));
      ++i;
    }
    Piece& piece = by_root[root];
    ++piece.faces;
    piece.volume_m3 += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  std::vector<Piece> out;
  out.reserve(by_root.size());
  for (const auto& [root, piece] : by_root) out.push_back(piece);
  std::sort(out.begin(), out.end(), [](const Piece& a, const Piece& b) {
    return a.volume_m3 != b.volume_m3 ? a.volume_m3 > b.volume_m3 : a.faces > b.faces;
  });
  return out;
}

}  // namespace incise::mesh
