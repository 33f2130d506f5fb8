// subtractSolid through CGAL's corefinement (compiled in the mesh module's CGAL object library), and the
// pieces of a closed surface.
#include "incise/mesh/solid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <optional>
#include <unordered_map>
#include <utility>

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <Eigen/Geometry>

#include "incise/core/union_find.h"
#include "incise/mesh/cgal_mesh.h"
#include "incise/mesh/cgal_origin.h"

namespace incise::mesh {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using detail::CgalMesh;
using Face = CgalMesh::Face_index;
using detail::kFromOther;
using detail::OriginMap;
constexpr int kFromSolid = kFromOther;  // a face of the solid's boundary

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
  detail::OriginVisitor visitor;
  visitor.first = &a;
  visitor.out = &out;
  visitor.first_origin = detail::originsOf(a, face_handles);
  visitor.out_origin = out.add_property_map<Face, int>("f:incise_origin", detail::kOriginUnknown).first;
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

using PointIndex = std::unordered_map<std::array<double, 3>, int, PointHash>;

PointIndex indexPoints(const TriMesh& tissue) {
  PointIndex index;
  index.reserve(tissue.n_vertices());
  for (const auto v : tissue.vertices()) {
    const auto& p = tissue.point(v);
    index.emplace(std::array<double, 3>{p[0], p[1], p[2]}, v.idx());
  }
  return index;
}

// The faces of `out` that touch the cut: from the solid, or with a corner the tissue did not have.
std::vector<Face> facesTouchingCut(const CgalMesh& out, const OriginMap& origin, const PointIndex& old) {
  std::vector<Face> near;
  for (const Face f : out.faces()) {
    bool touches = origin[f] == kFromSolid;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out))
      touches = touches || !old.count(key(out.point(v)));
    if (touches) near.push_back(f);
  }
  return near;
}

// Where the solid's surface passes near a vertex or an edge of the tissue, the pieces of the tissue's faces
// are needles and caps (two crossings of the cut a hair apart, a vertex a hair from the cut): among the faces
// that touch the cut (a vertex of the result not in the tissue), CGAL collapses edges shorter than a
// fiftieth of the tissue's mean edge `mean_edge_m` and flips caps that low. Nothing moves farther than that:
// the cut stays where it was to within a fiftieth of an edge (the kerf the surface cutter removes is wider).
void removeSlivers(CgalMesh& out, const OriginMap& origin, const PointIndex& old, double mean_edge_m) {
  std::vector<Face> near = facesTouchingCut(out, origin, old);
  constexpr double kCapCosine = -0.94;  // an angle over about 160 degrees
  constexpr double kNeedleRatio = 6.0;  // the longest edge over six times the shortest
  const double small_m = 0.02 * mean_edge_m;
  PMP::experimental::remove_almost_degenerate_faces(near, out, kCapCosine, kNeedleRatio, small_m,
                                                    CGAL::parameters::flip_triangle_height_threshold(small_m));
  out.collect_garbage();
}

// Whether two faces of `out` cross near the cut: the faces whose bounding boxes meet the box round the faces
// touching the cut (every face that could cross one of them, and every face a sliver's collapse moved),
// tested pairwise with CGAL's exact predicates. Cost O(k log k) in those faces.
bool crossesNearCut(const CgalMesh& out, const OriginMap& origin, const PointIndex& old) {
  CGAL::Bbox_3 cut_box;
  for (const Face f : facesTouchingCut(out, origin, old))
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out)) cut_box += out.point(v).bbox();
  std::vector<Face> region;
  for (const Face f : out.faces()) {
    CGAL::Bbox_3 box;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out)) box += out.point(v).bbox();
    if (CGAL::do_overlap(box, cut_box)) region.push_back(f);
  }
  return PMP::does_self_intersect(region, out);
}

// The corners' texture coordinates of an added face (corners c, from `from`: a tissue face or the solid).
std::array<Eigen::Vector2d, 3> addedTexCoords(const SurfaceMesh& tissue, const SolidDifference& d,
                                              const std::array<int, 3>& c, int from) {
  std::array<Eigen::Vector3d, 3> x;
  for (std::size_t i = 0; i < 3; ++i)
    x[i] = c[i] < d.vertices_before ? toEigen(tissue.mesh().point(TriMesh::VertexHandle(c[i])))
                                    : d.added_points_m[static_cast<std::size_t>(c[i] - d.vertices_before)];
  if (from < 0) return planarTexCoords(x);
  const FaceCorners corners = faceCorners(tissue, TriMesh::FaceHandle(from));
  std::array<Eigen::Vector3d, 3> y;
  for (std::size_t i = 0; i < 3; ++i) y[i] = toEigen(tissue.mesh().point(corners.vertex[i]));
  std::array<Eigen::Vector2d, 3> uv;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<Eigen::Vector2d> at = corners.at(TriMesh::VertexHandle(c[i]));
    uv[i] = at ? *at : interpolateTexCoord(y, corners.uv, x[i]);
  }
  return uv;
}

// `out` (tissue minus solid) as changes to `tissue`: faces of the result that are faces of the tissue, same
// corners in the same order, are kept; every other tissue face is removed, the result's other faces added.
void describe(const SurfaceMesh& tissue, const PointIndex& old, const CgalMesh& out, const OriginMap& origin,
              SolidDifference& d) {
  const TriMesh& m = tissue.mesh();
  d.vertices_before = static_cast<int>(m.n_vertices());
  d.faces_before = static_cast<int>(m.n_faces());
  std::vector<int> vertex(out.num_vertices(), -1);
  for (const auto v : out.vertices()) {
    const auto found = old.find(key(out.point(v)));
    if (found != old.end()) {
      vertex[static_cast<std::size_t>(v.idx())] = found->second;
    } else {
      const auto& p = out.point(v);
      vertex[static_cast<std::size_t>(v.idx())] = d.vertices_before + static_cast<int>(d.added_points_m.size());
      d.added_points_m.emplace_back(p.x(), p.y(), p.z());
    }
  }
  std::vector<std::uint8_t> kept(m.n_faces(), 0);
  for (const Face f : out.faces()) {
    std::array<int, 3> c{};
    int i = 0;
    for (const auto v : CGAL::vertices_around_face(out.halfedge(f), out))
      c[static_cast<std::size_t>(i++ % 3)] = vertex[static_cast<std::size_t>(v.idx())];
    if (i != 3) throw MeshError("CGAL's difference has a face with " + std::to_string(i) + " corners");
    if (c[0] < d.vertices_before && c[1] < d.vertices_before && c[2] < d.vertices_before) {
      const auto h = m.find_halfedge(TriMesh::VertexHandle(c[0]), TriMesh::VertexHandle(c[1]));
      if (h.is_valid() && m.face_handle(h).is_valid() && m.to_vertex_handle(m.next_halfedge_handle(h)).idx() == c[2]) {
        kept[static_cast<std::size_t>(m.face_handle(h).idx())] = 1;
        continue;
      }
    }
    const int from = origin[f];
    const bool wall = from == kFromSolid || (from >= 0 && tissue.kind(TriMesh::FaceHandle(from)) == FaceKind::Wall);
    d.added_faces.push_back(c);
    d.added_kinds.push_back(wall ? FaceKind::Wall : FaceKind::Split);
    if (tissue.hasTexCoords()) d.added_texcoords.push_back(addedTexCoords(tissue, d, c, from));
    if (tissue.hasMaterials()) d.added_materials.push_back(from >= 0 ? tissue.material(TriMesh::FaceHandle(from)) : 0);
    d.touched_vertices.insert(d.touched_vertices.end(), c.begin(), c.end());
  }
  for (const auto f : m.faces()) {
    if (kept[static_cast<std::size_t>(f.idx())]) continue;
    d.removed_faces.push_back(f.idx());
    for (const auto v : m.fv_range(f)) d.touched_vertices.push_back(v.idx());
  }
  std::sort(d.touched_vertices.begin(), d.touched_vertices.end());
  d.touched_vertices.erase(std::unique(d.touched_vertices.begin(), d.touched_vertices.end()), d.touched_vertices.end());
}

// Applies `d` (see applyDifference); throws MeshError when OpenMesh refuses a face.
void apply(SurfaceMesh& tissue, const SolidDifference& d, SubtractResult& result) {
  TriMesh& m = tissue.mesh();
  for (const int f : d.removed_faces) deleteTriangle(m, TriMesh::FaceHandle(f));  // OpenMesh's delete_face allocates
  result.faces_removed = static_cast<int>(d.removed_faces.size());
  for (const Eigen::Vector3d& p : d.added_points_m) tissue.addVertex(p, VertexKind::Wall);
  result.vertices_added = static_cast<int>(d.added_points_m.size());
  for (std::size_t i = 0; i < d.added_faces.size(); ++i) {
    const std::array<int, 3>& c = d.added_faces[i];
    const auto made = tissue.addFace(TriMesh::VertexHandle(c[0]), TriMesh::VertexHandle(c[1]),
                                     TriMesh::VertexHandle(c[2]), d.added_kinds[i]);
    if (made.idx() != d.faces_before + static_cast<int>(i)) throw MeshError("a face of the difference was refused");
    if (tissue.hasMaterials() && i < d.added_materials.size())
      m.property(tissue.materialProperty(), made) = d.added_materials[i];
    if (tissue.hasTexCoords() && i < d.added_texcoords.size())
      for (const auto h : m.fh_range(made))
        for (std::size_t k = 0; k < 3; ++k)
          if (m.to_vertex_handle(h).idx() == c[k])
            m.property(tissue.texCoordProperty(), h) =
                OpenMesh::Vec2d(d.added_texcoords[i][k].x(), d.added_texcoords[i][k].y());
    m.update_normal(made);
  }
  result.faces_added = static_cast<int>(d.added_faces.size());
  for (const int id : d.touched_vertices) {
    const TriMesh::VertexHandle v(id);
    if (m.status(v).deleted()) continue;
    if (m.is_isolated(v)) {
      m.status(v).set_deleted(true);  // OpenMesh's delete_vertex of a vertex with no faces, without its array
      ++result.vertices_removed;
      continue;
    }
    if (id >= d.vertices_before) {
      bool all_wall = true;
      for (const auto f : m.vf_range(v)) all_wall = all_wall && tissue.kind(f) == FaceKind::Wall;
      tissue.setKind(v, all_wall ? VertexKind::Wall : VertexKind::Seam);
    }
    m.update_normal(v);
  }
}

}  // namespace

SolidDifference differenceOf(const SurfaceMesh& tissue, const SurfaceMesh& solid) {
  SolidDifference d;
  try {
    OriginMap origin;
    CgalMesh out = difference(tissue.mesh(), solid.mesh(), origin);
    origin = out.property_map<Face, int>("f:incise_origin").first;
    const PointIndex old = indexPoints(tissue.mesh());
    CgalMesh corefined = out;  // with its slivers
    try {
      removeSlivers(out, origin, old, edgeLengths(tissue.mesh()).mean_m);
    } catch (const std::exception& e) {
      d.message = std::string("CGAL could not remove the cut's slivers: ") + e.what();
      return d;
    }
    // A collapse or a flip can fold a face through its neighbour: the result with its slivers instead.
    if (crossesNearCut(out, origin, old)) {
      out = std::move(corefined);
      origin = out.property_map<Face, int>("f:incise_origin").first;
      d.slivers_kept = true;
    }
    describe(tissue, old, out, origin, d);
  } catch (const PMP::Corefinement::Self_intersection_exception&) {
    d.message = "the tissue or the solid crosses itself where they meet";
    return d;
  } catch (const std::exception& e) {
    d.message = std::string("CGAL's difference failed: ") + e.what();
    return d;
  }
  // Applied to a copy first: what OpenMesh refuses is known here, so the owner's apply cannot fail.
  SurfaceMesh copy = tissue;
  SubtractResult tried;
  try {
    apply(copy, d, tried);
  } catch (const std::exception& e) {
    d.message = std::string("the difference could not be applied: ") + e.what();
    return d;
  }
  d.pieces = pieces(copy.mesh());
  d.ok = true;
  return d;
}

SubtractResult applyDifference(SurfaceMesh& tissue, const SolidDifference& d) noexcept {
  SubtractResult result;
  const TriMesh& m = tissue.mesh();
  if (!d.ok || static_cast<int>(m.n_vertices()) != d.vertices_before || static_cast<int>(m.n_faces()) != d.faces_before)
    return result;  // not this mesh's difference (or a failed one): nothing applied
  try {
    apply(tissue, d, result);
  } catch (const std::exception&) {  // refused on the copy already: cannot happen
    return result;
  }
  result.ok = true;
  return result;
}

SubtractResult subtractSolid(SurfaceMesh& tissue, const SurfaceMesh& solid, std::vector<int>* changed_vertices,
                             std::vector<int>* changed_faces) {
  const SolidDifference d = differenceOf(tissue, solid);
  if (!d.ok) return SubtractResult{false, d.message};
  const SubtractResult result = applyDifference(tissue, d);
  if (!result.ok) return SubtractResult{false, "the difference was computed on another mesh"};
  if (changed_vertices)
    changed_vertices->insert(changed_vertices->end(), d.touched_vertices.begin(), d.touched_vertices.end());
  if (changed_faces) {
    changed_faces->insert(changed_faces->end(), d.removed_faces.begin(), d.removed_faces.end());
    for (int i = 0; i < static_cast<int>(d.added_faces.size()); ++i) changed_faces->push_back(d.faces_before + i);
  }
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
