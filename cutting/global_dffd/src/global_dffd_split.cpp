// The model split at the discontinuities (§3.2): splitAtDiscontinuities, its index maps (DffdSplit),
// deformSplit and DffdBinding; validateModel. The openings it leaves are closed in global_dffd_openings.cpp.
#include "incise/global_dffd/global_dffd.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "global_dffd_internal.h"
#include "incise/mesh/surface_query.h"

namespace incise::global_dffd {
namespace {

using detail::Soup;

Soup soupOf(const mesh::SurfaceMesh& model) {
  const mesh::TriMesh& mesh = model.mesh();
  Soup s;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (const auto v : mesh.vertices())
    if (!mesh.status(v).deleted())
      index[static_cast<size_t>(v.idx())] = s.add(mesh::toEigen(mesh.point(v)), v.idx(), {-1, -1}, -1);
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    std::array<int, 3> t{};
    std::array<Eigen::Vector2d, 3> uv{};
    auto h = mesh.halfedge_handle(f);
    for (size_t i = 0; i < 3; ++i, h = mesh.next_halfedge_handle(h)) {
      t[i] = index[static_cast<size_t>(mesh.to_vertex_handle(h).idx())];
      if (model.hasTexCoords()) uv[i] = model.texCoord(h);
    }
    s.faces.push_back(t);
    if (model.hasTexCoords()) s.uv.push_back(uv);
    if (model.hasMaterials()) s.material.push_back(model.material(f));
  }
  return s;
}

}  // namespace

void detail::soupOf(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces, Soup& s) {
  s.x.assign(positions.begin(), positions.end());
  s.source.resize(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) s.source[v] = static_cast<int>(v);
  s.edge.assign(positions.size(), {-1, -1});
  s.side.assign(positions.size(), 0);
  s.plane.assign(positions.size(), -1);
  s.faces.assign(faces.begin(), faces.end());
  s.uv.clear();
  s.material.clear();
  for (const auto& f : s.faces)
    for (const int v : f)
      if (v < 0 || static_cast<size_t>(v) >= positions.size())
        throw DffdError(DffdErrorKind::BadInput, "splitAtDiscontinuities: a face refers to vertex " +
                                                     std::to_string(v) + " of " + std::to_string(positions.size()));
}

namespace {

// A face being split: its corners' and its new points' texture coordinates (interpolated along the edge
// split, in the face: each side of a texture seam has its own), when the soup carries them. O(1).
struct PieceCorners {
  std::array<int, 5> vertex{};
  std::array<Eigen::Vector2d, 5> uv{};
  int count = 0;
  bool carried = false;  // whether the soup carries texture coordinates (else nothing is recorded)
  void reset(const Soup& s, size_t f) {
    carried = !s.uv.empty();
    if (!carried) return;
    count = 3;
    for (size_t i = 0; i < 3; ++i) {
      vertex[i] = s.faces[f][i];
      uv[i] = s.uv[f][i];
    }
  }
  Eigen::Vector2d uvOf(int v) const {
    for (int i = 0; i < count; ++i)
      if (vertex[static_cast<size_t>(i)] == v) return uv[static_cast<size_t>(i)];
    return Eigen::Vector2d::Zero();
  }
  std::array<Eigen::Vector2d, 3> uvOf(const std::array<int, 3>& t) const {
    return {uvOf(t[0]), uvOf(t[1]), uvOf(t[2])};
  }
  // Records point p made on the face's edge a-b; returns p.
  int point(const Soup& s, int a, int b, int p) {
    if (!carried) return p;
    const auto x = [&](int v) -> const Eigen::Vector3d& { return s.x[static_cast<size_t>(v)]; };
    vertex[static_cast<size_t>(count)] = p;
    uv[static_cast<size_t>(count++)] = detail::uvAlong(x(a), x(b), uvOf(a), uvOf(b), x(p));
    return p;
  }
};

// Puts the vertices within a hair of the plane x = u on it (splitting an edge there would make a sliver);
// whether there were any.
bool snapToPlane(Soup& s, double u, int plane, const Eigen::AlignedBox3d& box) {
  const double snap = detail::snapDistance(box);
  bool snapped = false;
  for (size_t v = 0; v < s.x.size(); ++v) {
    if (std::abs(s.x[v].x() - u) > snap) continue;
    s.x[v].x() = u;
    s.plane[v] = plane;
    snapped = true;
    if (s.steps) s.steps->push_back({detail::SplitStep::Kind::Snap, static_cast<int>(v), -1, u});
  }
  return snapped;
}

// Splits every face crossing the plane x = u and marks the vertices on it. The whole section is split,
// also where the model reaches beyond the box: F is the identity there, so both lips stay together, and
// each closed section curve gives exactly two lips (boundary loops) whatever the model's position.
void splitAt(Soup& s, double u, int plane, const Eigen::AlignedBox3d& box) {
  std::map<std::pair<int, int>, int> points;
  const auto sgn = [&](int v) {
    return s.x[static_cast<size_t>(v)].x() < u ? -1 : s.x[static_cast<size_t>(v)].x() > u ? 1 : 0;
  };
  const bool snapped = snapToPlane(s, u, plane, box);
  const auto point = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    if (const auto it = points.find(key); it != points.end()) return it->second;
    const Eigen::Vector3d p =
        detail::splitPoint(s.x[static_cast<size_t>(key.first)], s.x[static_cast<size_t>(key.second)], u);
    if (s.steps) s.steps->push_back({detail::SplitStep::Kind::Point, key.first, key.second, u});
    const int src_a = s.source[static_cast<size_t>(key.first)], src_b = s.source[static_cast<size_t>(key.second)];
    const int id = s.add(p, -1, {src_a, src_b}, plane);
    points.emplace(key, id);
    return id;
  };
  // In place: a crossing face becomes its first piece, the others go to the end; every piece touches the
  // plane (separate()'s candidates, with the faces of snapped vertices).
  s.touching.clear();
  const size_t count = s.faces.size();
  PieceCorners corners;  // the crossing face's corners and points, with their texture coordinates
  const auto firstPiece = [&](size_t f, std::array<int, 3> t) {
    s.faces[f] = t;
    if (!s.uv.empty()) s.uv[f] = corners.uvOf(t);
    s.touching.push_back(static_cast<int>(f));
  };
  const auto otherPiece = [&](size_t f, std::array<int, 3> t) {
    s.touching.push_back(static_cast<int>(s.faces.size()));
    s.addFace(t, s.uv.empty() ? std::array<Eigen::Vector2d, 3>{} : corners.uvOf(t),
              s.material.empty() ? -1 : s.material[f]);
  };
  for (size_t i = 0; i < count; ++i) {
    const std::array<int, 3> f = s.faces[i];
    const int sa = sgn(f[0]), sb = sgn(f[1]), sc = sgn(f[2]);
    if (!((sa * sb < 0) || (sb * sc < 0) || (sc * sa < 0))) continue;
    corners.reset(s, i);
    // Rotate so that a is the vertex alone on its side (or on the plane).
    int r = 0;
    const int sg[3] = {sa, sb, sc};
    for (int k = 0; k < 3; ++k)
      if (sg[k] != 0 && sg[(k + 1) % 3] != sg[k] && sg[(k + 2) % 3] != sg[k]) r = k;
    const int a = f[static_cast<size_t>(r)], b = f[static_cast<size_t>((r + 1) % 3)],
              c = f[static_cast<size_t>((r + 2) % 3)];
    const int s_b = sg[(r + 1) % 3], s_c = sg[(r + 2) % 3];
    if (s_b == 0) {  // b on the plane: the crossing is on c-a
      const int p = corners.point(s, c, a, point(c, a));
      firstPiece(i, {a, b, p});
      otherPiece(i, {b, c, p});
    } else if (s_c == 0) {  // c on the plane: the crossing is on a-b
      const int p = corners.point(s, a, b, point(a, b));
      firstPiece(i, {a, p, c});
      otherPiece(i, {p, b, c});
    } else {  // a alone: crossings on a-b and c-a
      const int p = corners.point(s, a, b, point(a, b)), q = corners.point(s, c, a, point(c, a));
      firstPiece(i, {a, p, q});
      const auto at = [&](int v) -> const Eigen::Vector3d& { return s.x[static_cast<size_t>(v)]; };
      const bool pc = detail::quadDiagonalPC(at(p), at(b), at(c), at(q));
      if (s.steps) s.steps->push_back({detail::SplitStep::Kind::Diagonal, p, b, 0.0, c, q, pc});
      if (pc) {
        otherPiece(i, {p, b, c});
        otherPiece(i, {p, c, q});
      } else {
        otherPiece(i, {p, b, q});
        otherPiece(i, {b, c, q});
      }
    }
  }
  if (snapped) {  // faces around vertices put on the plane: a full pass (rare)
    s.touching.clear();
    for (size_t f = 0; f < s.faces.size(); ++f)
      for (const int v : s.faces[f])
        if (s.plane[static_cast<size_t>(v)] == plane) {
          s.touching.push_back(static_cast<int>(f));
          break;
        }
  }
}

// Duplicates every vertex on `plane` whose faces lie on both sides (and none across): the + faces get a copy.
void separate(Soup& s, int plane, double u) {
  // (vertex on the plane, face around it), sorted by vertex.
  std::vector<std::pair<int, int>> around;
  for (const int f : s.touching)
    for (const int v : s.faces[static_cast<size_t>(f)])
      if (s.plane[static_cast<size_t>(v)] == plane) around.emplace_back(v, f);
  std::sort(around.begin(), around.end());
  std::vector<int> face_side;
  for (size_t begin = 0; begin < around.size();) {
    const int v = around[begin].first;
    size_t end = begin;
    while (end < around.size() && around[end].first == v) ++end;
    bool minus = false, plus = false, across = false;
    face_side.assign(end - begin, 0);
    for (size_t i = begin; i < end; ++i) {
      int side = 0;
      for (const int w : s.faces[static_cast<size_t>(around[i].second)]) {
        const double x = s.x[static_cast<size_t>(w)].x();
        const int sw = x < u ? -1 : x > u ? 1 : 0;
        if (sw != 0 && side != 0 && sw != side) across = true;
        if (sw != 0) side = sw;
      }
      face_side[i - begin] = side;
      minus = minus || side < 0;
      plus = plus || side > 0;
    }
    if (!across && minus && plus) {  // else the split's end, or a vertex touching the plane from one side
      s.side[static_cast<size_t>(v)] = -1;
      if (s.steps) s.steps->push_back({detail::SplitStep::Kind::Copy, v, -1, 0.0});
      const int copy =
          s.add(s.x[static_cast<size_t>(v)], s.source[static_cast<size_t>(v)], s.edge[static_cast<size_t>(v)], plane);
      s.side[static_cast<size_t>(copy)] = 1;
      for (size_t i = begin; i < end; ++i)
        if (face_side[i - begin] > 0)
          for (int& w : s.faces[static_cast<size_t>(around[i].second)])
            if (w == v) w = copy;
    }
    begin = end;
  }
}

// Gives the faces of `mesh` (made by meshOf from `faces`: the split's, their vertices maybe renumbered)
// the split's texture coordinates and materials, when it has them.
void dress(const DffdSplit& split, const std::vector<std::array<int, 3>>& faces, mesh::SurfaceMesh& mesh) {
  mesh::TriMesh& m = mesh.mesh();
  if (!split.face_uv.empty()) {
    mesh.addTexCoords();
    for (const auto f : m.faces()) {
      const auto& t = faces[static_cast<size_t>(f.idx())];
      for (const auto h : m.fh_range(f)) {
        const int v = m.to_vertex_handle(h).idx();
        const size_t i = v == t[0] ? 0 : v == t[1] ? 1 : 2;  // meshOf's vertex k is faces' index k
        mesh.setTexCoord(h, split.face_uv[static_cast<size_t>(f.idx())][i]);
      }
    }
  }
  if (split.face_material.empty()) return;
  for (const mesh::Material& material : split.materials) mesh.addMaterial(material);
  for (const auto f : m.faces()) mesh.setMaterial(f, split.face_material[static_cast<size_t>(f.idx())]);
}

}  // namespace

mesh::SurfaceMesh detail::meshOf(const std::vector<Eigen::Vector3d>& x, const std::vector<std::array<int, 3>>& faces) {
  mesh::SurfaceMesh mesh;
  mesh::TriMesh& m = mesh.mesh();
  std::vector<mesh::TriMesh::VertexHandle> handles;
  handles.reserve(x.size());
  for (const auto& p : x) handles.push_back(m.add_vertex(mesh::toOpenMesh(p)));
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    if (!m.add_face(handles[static_cast<size_t>(t[0])], handles[static_cast<size_t>(t[1])],
                    handles[static_cast<size_t>(t[2])])
             .is_valid())
      throw DffdError(DffdErrorKind::NotTwoManifold, "splitting the model: face " + std::to_string(f) +
                                                         " cannot be added (the model is not a two-manifold there)");
  }
  return mesh;
}

void detail::splitSoup(Soup& s, const GlobalDffd& dffd, Openings openings, DffdSplit& split) {
  for (size_t i = 0; i < dffd.obstacles().size(); ++i) {
    splitAt(s, dffd.obstacles()[i].u, static_cast<int>(i), dffd.box());
    separate(s, static_cast<int>(i), dffd.obstacles()[i].u);
  }
  split.left_open = 0;
  if (openings == Openings::Leave) {  // nothing welded, every vertex used: hand the buffers over (swapped, both reused)
    std::swap(split.rest_m, s.x);
    std::swap(split.source_vertex, s.source);
    std::swap(split.source_edge, s.edge);
    std::swap(split.side, s.side);
    std::swap(split.plane, s.plane);
    std::swap(split.faces, s.faces);
    std::swap(split.face_uv, s.uv);
    std::swap(split.face_material, s.material);
    return;
  }
  for (size_t i = 0; i < dffd.obstacles().size(); ++i)
    split.left_open += detail::zipOpenings(s, static_cast<int>(i), dffd.box());
  // Compact: vertices no face uses any more (welded away) are dropped. split's buffers keep their capacity.
  s.remap.assign(s.x.size(), -1);
  for (const auto& f : s.faces)
    for (const int v : f) s.remap[static_cast<size_t>(v)] = 0;
  split.rest_m.clear();
  split.source_vertex.clear();
  split.source_edge.clear();
  split.side.clear();
  split.plane.clear();
  for (size_t v = 0; v < s.x.size(); ++v) {
    if (s.remap[v] < 0) continue;
    s.remap[v] = static_cast<int>(split.rest_m.size());
    split.rest_m.push_back(s.x[v]);
    split.source_vertex.push_back(s.source[v]);
    split.source_edge.push_back(s.edge[v]);
    split.side.push_back(s.side[v]);
    split.plane.push_back(s.plane[v]);
  }
  split.face_uv = s.uv;  // faces keep their order
  split.face_material = s.material;
  split.faces.resize(s.faces.size());
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i)
      split.faces[f][static_cast<size_t>(i)] = s.remap[static_cast<size_t>(s.faces[f][static_cast<size_t>(i)])];
}

namespace {

// The working buffers of the splits made on this thread, kept so that a model split frame after frame does
// not map fresh pages every frame (about a third of the frame time on the robot otherwise).
Soup& scratchSoup() {
  thread_local Soup soup;
  return soup;
}

}  // namespace

ModelArrays modelArrays(const mesh::SurfaceMesh& model) {
  Soup soup = soupOf(model);
  return {std::move(soup.x), std::move(soup.faces)};
}

DffdSplit splitAtDiscontinuities(const mesh::SurfaceMesh& model, const GlobalDffd& dffd, Openings openings) {
  Soup soup = soupOf(model);
  DffdSplit split;
  detail::splitSoup(soup, dffd, openings, split);
  split.materials = model.materials();
  return split;
}

DffdSplit splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces,
                                 const GlobalDffd& dffd, Openings openings) {
  DffdSplit split;
  splitAtDiscontinuities(positions, faces, dffd, openings, split);
  return split;
}

void splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces,
                            const GlobalDffd& dffd, Openings openings, DffdSplit& out) {
  Soup& soup = scratchSoup();
  detail::soupOf(positions, faces, soup);
  detail::splitSoup(soup, dffd, openings, out);
}

mesh::SurfaceMesh DffdSplit::surface(std::span<const Eigen::Vector3d> positions) const {
  if (!positions.empty() && positions.size() != rest_m.size())
    throw DffdError(DffdErrorKind::BadInput, "DffdSplit::surface: " + std::to_string(positions.size()) +
                                                 " positions for " + std::to_string(rest_m.size()) + " vertices");
  mesh::SurfaceMesh mesh = detail::meshOf(
      positions.empty() ? rest_m : std::vector<Eigen::Vector3d>(positions.begin(), positions.end()), faces);
  dress(*this, faces, mesh);
  return mesh;
}

void deformSplit(const DffdSplit& split, const GlobalDffd& dffd, std::span<Eigen::Vector3d> out) {
  if (out.size() != split.rest_m.size())
    throw DffdError(DffdErrorKind::BadInput, "deformSplit: " + std::to_string(out.size()) + " output positions for " +
                                                 std::to_string(split.rest_m.size()) + " split vertices");
  // Each vertex on its own: the same bits whichever thread maps it. The blocks are large enough that the
  // scheduling costs little (about 2,048 x 70 ns each).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 2048), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t v = range.begin(); v < range.end(); ++v) out[v] = dffd.map(split.rest_m[v], split.side[v]);
  });
}

// Per vertex of the split: its twin across the plane (a side -1 vertex's side +1 copy and back: the same
// plane, source vertex and source edge), or -1. A key held by more than one pair is left without twins.
std::vector<int> detail::twinsOf(const DffdSplit& split) {
  using Key = std::array<int, 4>;
  std::map<Key, std::array<int, 3>> pairs;  // key -> (minus, plus, count of vertices)
  for (size_t v = 0; v < split.side.size(); ++v) {
    if (split.side[v] == 0) continue;
    const Key key{split.plane[v], split.source_vertex[v], split.source_edge[v][0], split.source_edge[v][1]};
    auto [it, fresh] = pairs.try_emplace(key, std::array<int, 3>{-1, -1, 0});
    it->second[split.side[v] < 0 ? 0 : 1] = static_cast<int>(v);
    ++it->second[2];
  }
  std::vector<int> twin(split.side.size(), -1);
  for (const auto& [key, p] : pairs)
    if (p[2] == 2 && p[0] >= 0 && p[1] >= 0)
      twin[static_cast<size_t>(p[0])] = p[1], twin[static_cast<size_t>(p[1])] = p[0];
  return twin;
}

mesh::SurfaceMesh weldClosedLips(const DffdSplit& split, std::span<const Eigen::Vector3d> positions) {
  if (positions.size() != split.rest_m.size())
    throw DffdError(DffdErrorKind::BadInput, "weldClosedLips: " + std::to_string(positions.size()) + " positions for " +
                                                 std::to_string(split.rest_m.size()) + " vertices");
  const std::vector<int> twin = detail::twinsOf(split);
  const size_t n = positions.size();
  std::vector<char> closed(n, 0);  // a side -1 vertex whose twin's image is its own, bit for bit
  for (size_t v = 0; v < n; ++v)
    closed[v] = split.side[v] < 0 && twin[v] >= 0 && positions[v] == positions[static_cast<size_t>(twin[v])];
  // Weld a closed vertex only where an edge of the opening (both ends closed) welds with it: a closed vertex
  // between open edges would join the surface at a point (not a two-manifold).
  std::vector<char> weld(n, 0);
  for (const auto& t : split.faces)
    for (int i = 0; i < 3; ++i) {
      const auto a = static_cast<size_t>(t[static_cast<size_t>(i)]), b = static_cast<size_t>(t[(i + 1) % 3]);
      if (closed[a] && closed[b]) weld[a] = weld[b] = 1;
    }
  std::vector<int> index(n, -1);  // output index per split vertex
  std::vector<Eigen::Vector3d> x;
  x.reserve(n);
  for (size_t v = 0; v < n; ++v) {
    const bool merged = split.side[v] > 0 && twin[v] >= 0 && weld[static_cast<size_t>(twin[v])];
    if (!merged) index[v] = static_cast<int>(x.size()), x.push_back(positions[v]);
  }
  for (size_t v = 0; v < n; ++v)
    if (index[v] < 0) index[v] = index[static_cast<size_t>(twin[v])];
  std::vector<std::array<int, 3>> faces(split.faces.size());
  for (size_t f = 0; f < faces.size(); ++f)
    for (size_t i = 0; i < 3; ++i) faces[f][i] = index[static_cast<size_t>(split.faces[f][i])];
  mesh::SurfaceMesh mesh = detail::meshOf(x, faces);
  dress(split, faces, mesh);
  return mesh;
}

mesh::SurfaceMesh deformSplit(const DffdSplit& split, const GlobalDffd& dffd) {
  std::vector<Eigen::Vector3d> positions(split.rest_m.size());
  deformSplit(split, dffd, positions);
  return split.surface(positions);
}

namespace {

std::vector<Eigen::Vector3d> restOf(const DffdSplit& split) {
  if (split.side.size() != split.rest_m.size())
    throw DffdError(DffdErrorKind::BadInput, "DffdBinding: the split has " + std::to_string(split.rest_m.size()) +
                                                 " vertices but " + std::to_string(split.side.size()) + " sides");
  return split.rest_m;
}

std::vector<int> insideOf(const std::vector<Eigen::Vector3d>& rest, const Eigen::AlignedBox3d& box) {
  std::vector<int> inside;
  for (size_t v = 0; v < rest.size(); ++v)
    if (box.contains(rest[v])) inside.push_back(static_cast<int>(v));
  return inside;
}

// The parameters map() evaluates F at: u shifted by side * epsilon and clamped to the domain.
std::vector<Eigen::Vector3d> boundParameters(const std::vector<Eigen::Vector3d>& rest, const std::vector<int>& inside,
                                             const DffdSplit& split, const GlobalDffd& dffd) {
  const auto domain = dffd.volume().domain(0);
  std::vector<Eigen::Vector3d> parameters;
  parameters.reserve(inside.size());
  for (const int v : inside) {
    const Eigen::Vector3d& x = rest[static_cast<size_t>(v)];
    const double u =
        std::clamp(x.x() + split.side[static_cast<size_t>(v)] * dffd.options().epsilon, domain[0], domain[1]);
    parameters.emplace_back(u, x.y(), x.z());
  }
  return parameters;
}

}  // namespace

DffdBinding::DffdBinding(const DffdSplit& split, const GlobalDffd& dffd)
    : rest_(restOf(split)),
      inside_(insideOf(rest_, dffd.box())),
      binding_(dffd.volume(), boundParameters(rest_, inside_, split, dffd)) {
  cells_.reserve(inside_.size());
  for (const int v : inside_) {
    double u = 0.0;
    cells_.push_back(dffd.cellOf(rest_[static_cast<size_t>(v)], split.side[static_cast<size_t>(v)], u));
  }
}

void DffdBinding::deform(const GlobalDffd& dffd, std::span<Eigen::Vector3d> out) const {
  if (out.size() != rest_.size())
    throw DffdError(DffdErrorKind::BadInput, "DffdBinding::deform: " + std::to_string(out.size()) +
                                                 " output positions for " + std::to_string(rest_.size()) +
                                                 " split vertices");
  const size_t n = inside_.size();
  // The bound vertices' positions go to out[0, n) first, then each to its own slot, last first: inside_ is
  // increasing with inside_[b] >= b, so a move never overwrites a position still to be moved.
  if (!binding_.deformAll(dffd.volume(), out.first(n)))
    throw DffdError(
        DffdErrorKind::OtherLattice,
        "DffdBinding::deform: the GlobalDffd's lattice (orders or knots) is not the one the split was bound to");
  // As map(): a vertex in a cell where no control moved is its rest position exactly.
  for (size_t b = n; b-- > 0;)
    out[static_cast<size_t>(inside_[b])] =
        dffd.identityCell(cells_[b]) ? rest_[static_cast<size_t>(inside_[b])] : out[b];
  size_t next = 0;  // the vertices outside the box keep their rest position
  for (size_t v = 0; v < rest_.size(); ++v) {
    if (next < n && static_cast<size_t>(inside_[next]) == v) {
      ++next;
      continue;
    }
    out[v] = rest_[v];
  }
}

void validateModel(const mesh::SurfaceMesh& model, ModelClosure closure) {
  const bool closed = closure == ModelClosure::Closed;
  const mesh::ManifoldReport report = mesh::checkManifold(model.mesh());
  if (report.closed_two_manifold) return;
  const bool only_open =
      report.degenerate_faces == 0 && report.non_manifold_edges == 0 && report.non_manifold_vertices == 0;
  if (only_open && !closed && model.mesh().n_faces() > 0) return;  // a two-manifold with boundary
  throw DffdError(DffdErrorKind::BadModel,
                  "the model is not " +
                      std::string(closed ? "a closed two-manifold" : "a two-manifold without degenerate faces") + ": " +
                      report.first_problem);
}

}  // namespace incise::global_dffd
