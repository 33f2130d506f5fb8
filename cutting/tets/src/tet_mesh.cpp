#include "incise/tets/tet_mesh.h"
#include "incise/core/atomic_file.h"
#include "incise/core/format.h"
#include "incise/core/union_find.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "incise/mesh/surface_mesh.h"

namespace incise::tets {
namespace {

constexpr int kOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

double orientation(const TetMesh& mesh, const std::array<int, 4>& t) {
  const Eigen::Vector3d& a = mesh.nodes_m[static_cast<size_t>(t[0])];
  Eigen::Matrix3d m;
  m.col(0) = mesh.nodes_m[static_cast<size_t>(t[1])] - a;
  m.col(1) = mesh.nodes_m[static_cast<size_t>(t[2])] - a;
  m.col(2) = mesh.nodes_m[static_cast<size_t>(t[3])] - a;
  return m.determinant();
}

bool validTet(const TetMesh& mesh, const std::array<int, 4>& t) {
  const int n = static_cast<int>(mesh.nodes_m.size());
  for (int i = 0; i < 4; ++i) {
    if (t[static_cast<size_t>(i)] < 0 || t[static_cast<size_t>(i)] >= n) return false;
    for (int j = 0; j < i; ++j)
      if (t[static_cast<size_t>(i)] == t[static_cast<size_t>(j)]) return false;
  }
  return true;
}

// One side of a face: its sorted node triple, the tet and the local index of the opposite node, and the
// parity of the permutation that sorts the outward triple (two tets on opposite sides have opposite parity).
struct FaceSide {
  std::array<int, 3> key;
  int tet, local;
  bool odd;
};

FaceSide makeSide(const std::array<int, 3>& f, int tet, int local) {
  std::array<int, 3> k = f;
  bool odd = false;
  if (k[0] > k[1]) std::swap(k[0], k[1]), odd = !odd;
  if (k[1] > k[2]) std::swap(k[1], k[2]), odd = !odd;
  if (k[0] > k[1]) std::swap(k[0], k[1]), odd = !odd;
  return {k, tet, local, odd};
}

// Sides of the faces of tets with valid node indices, sorted by key (then tet, local: deterministic).
std::vector<FaceSide> sortedSides(const TetMesh& mesh) {
  std::vector<FaceSide> sides;
  sides.reserve(mesh.tets.size() * 4);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    if (!validTet(mesh, mesh.tets[t])) continue;
    for (int i = 0; i < 4; ++i) sides.push_back(makeSide(faceOpposite(mesh.tets[t], i), static_cast<int>(t), i));
  }
  std::sort(sides.begin(), sides.end(), [](const FaceSide& x, const FaceSide& y) {
    return std::tie(x.key, x.tet, x.local) < std::tie(y.key, y.tet, y.local);
  });
  return sides;
}

// Calls visit(first, count) for each run of equal keys.
template <typename Visit>
void forEachFace(const std::vector<FaceSide>& sides, Visit visit) {
  for (size_t i = 0; i < sides.size();) {
    size_t j = i + 1;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    visit(i, j - i);
    i = j;
  }
}

void requireValidIndices(const TetMesh& mesh) {
  const long long n = static_cast<long long>(mesh.nodes_m.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t])
      if (v < 0 || v >= n)
        throw std::invalid_argument("tet " + std::to_string(t) + ": node index " + std::to_string(v) +
                                    " out of range (" + std::to_string(n) + " nodes)");
}

}  // namespace

std::array<int, 3> faceOpposite(const std::array<int, 4>& tet, int i) {
  const int* f = kOpposite[i];
  return {tet[static_cast<size_t>(f[0])], tet[static_cast<size_t>(f[1])], tet[static_cast<size_t>(f[2])]};
}

void buildAdjacency(TetMesh& mesh) {
  requireValidIndices(mesh);
  mesh.neighbours.assign(mesh.tets.size(), {-1, -1, -1, -1});
  const std::vector<FaceSide> sides = sortedSides(mesh);
  forEachFace(sides, [&](size_t first, size_t count) {
    if (count != 2) return;
    const FaceSide& x = sides[first];
    const FaceSide& y = sides[first + 1];
    mesh.neighbours[static_cast<size_t>(x.tet)][static_cast<size_t>(x.local)] = y.tet;
    mesh.neighbours[static_cast<size_t>(y.tet)][static_cast<size_t>(y.local)] = x.tet;
  });
}

std::vector<std::array<int, 3>> boundaryFaces(const TetMesh& mesh) {
  const std::vector<FaceSide> sides = sortedSides(mesh);
  std::vector<std::pair<int, int>> found;  // (tet, local)
  forEachFace(sides, [&](size_t first, size_t count) {
    if (count == 1) found.emplace_back(sides[first].tet, sides[first].local);
  });
  std::sort(found.begin(), found.end());
  std::vector<std::array<int, 3>> faces;
  faces.reserve(found.size());
  for (const auto& [t, i] : found) faces.push_back(faceOpposite(mesh.tets[static_cast<size_t>(t)], i));
  return faces;
}

double tetVolume(const TetMesh& mesh, int tet) {
  return orientation(mesh, mesh.tets.at(static_cast<size_t>(tet))) / 6.0;
}

double tetMinDihedralAngleDeg(const TetMesh& mesh, int tet) {
  const auto& t = mesh.tets.at(static_cast<size_t>(tet));
  std::array<Eigen::Vector3d, 4> normal;  // outward unit normal of the face opposite node i
  for (int i = 0; i < 4; ++i) {
    const auto f = faceOpposite(t, i);
    const Eigen::Vector3d& a = mesh.nodes_m[static_cast<size_t>(f[0])];
    const Eigen::Vector3d n =
        (mesh.nodes_m[static_cast<size_t>(f[1])] - a).cross(mesh.nodes_m[static_cast<size_t>(f[2])] - a);
    const double length = n.norm();
    if (!(length > 0)) return 0.0;  // a degenerate face: the tet is flat
    normal[static_cast<size_t>(i)] = n / length;
  }
  // The dihedral angle at the edge shared by faces i and j is pi minus the angle between their normals.
  double smallest = 180.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double c = std::clamp(-normal[static_cast<size_t>(i)].dot(normal[static_cast<size_t>(j)]), -1.0, 1.0);
      smallest = std::min(smallest, std::acos(c) * 180.0 / std::numbers::pi);
    }
  return smallest;
}

double volume(const TetMesh& mesh) {
  requireValidIndices(mesh);
  double sum = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t) sum += tetVolume(mesh, static_cast<int>(t));
  return sum;
}

std::vector<double> pieceVolumes(const TetMesh& mesh) {
  requireValidIndices(mesh);
  std::vector<int> storage;
  core::detail::UnionFind sets(storage, mesh.nodes_m.size());
  for (const auto& t : mesh.tets)
    for (size_t i = 1; i < 4; ++i) sets.unite(t[0], t[i]);
  std::vector<double> by_root(mesh.nodes_m.size(), 0.0);
  std::vector<std::uint8_t> used(mesh.nodes_m.size(), 0);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto root = static_cast<size_t>(sets.find(mesh.tets[t][0]));
    by_root[root] += tetVolume(mesh, static_cast<int>(t));
    used[root] = 1;
  }
  std::vector<double> out;
  for (size_t n = 0; n < by_root.size(); ++n)
    if (used[n]) out.push_back(by_root[n]);
  std::sort(out.rbegin(), out.rend());
  return out;
}

double minDihedralAngleDeg(const TetMesh& mesh) {
  requireValidIndices(mesh);
  double smallest = 180.0;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    smallest = std::min(smallest, tetMinDihedralAngleDeg(mesh, static_cast<int>(t)));
  return smallest;
}

TetCheck checkConforming(const TetMesh& mesh) {
  TetCheck check{true, 0, 0, 0, 0, 0, {}};
  auto problem = [&](const std::string& text) {
    if (check.first_problem.empty()) check.first_problem = text;
  };
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    if (!validTet(mesh, tet)) {
      ++check.bad_tets;
      problem("tet " + std::to_string(t) + ": node indices out of range or repeated (" + std::to_string(tet[0]) + ", " +
              std::to_string(tet[1]) + ", " + std::to_string(tet[2]) + ", " + std::to_string(tet[3]) + ")");
      continue;
    }
    const double det = orientation(mesh, tet);
    if (!(det > 0)) {
      ++check.inverted_tets;
      problem("tet " + std::to_string(t) + " is inverted or flat (det " + std::to_string(det) + ")");
    }
  }
  const std::vector<FaceSide> sides = sortedSides(mesh);
  std::vector<std::array<int, 4>> implied(mesh.tets.size(), {-1, -1, -1, -1});
  forEachFace(sides, [&](size_t first, size_t count) {
    const FaceSide& x = sides[first];
    if (count == 1) {
      ++check.boundary_faces;
    } else if (count == 2 && sides[first + 1].odd != x.odd) {
      ++check.interior_faces;
      const FaceSide& y = sides[first + 1];
      implied[static_cast<size_t>(x.tet)][static_cast<size_t>(x.local)] = y.tet;
      implied[static_cast<size_t>(y.tet)][static_cast<size_t>(y.local)] = x.tet;
    } else {
      ++check.non_manifold_faces;
      problem("face " + core::formatIndices(x.key) + " shared by " + std::to_string(count) + " tets" +
              (count == 2 ? " on the same side" : "") + " (tet " + std::to_string(x.tet) + ", tet " +
              std::to_string(sides[first + 1].tet) + ")");
    }
  });
  if (mesh.neighbours.size() == mesh.tets.size() && check.first_problem.empty()) {
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (size_t i = 0; i < 4; ++i)
        if (mesh.neighbours[t][i] != implied[t][i]) {
          problem("tet " + std::to_string(t) + ": neighbours[" + std::to_string(i) + "] is " +
                  std::to_string(mesh.neighbours[t][i]) + ", the faces imply " + std::to_string(implied[t][i]));
          break;
        }
  }
  check.conforming = check.first_problem.empty();
  return check;
}

namespace {

void requireValidFields(const TetMesh& mesh, const std::map<std::string, std::vector<int>>& cell_fields,
                        const char* who) {
  for (const auto& [name, values] : cell_fields) {
    if (name.empty() || name.find_first_of("\"<>& \n\t") != std::string::npos)
      throw std::invalid_argument(std::string(who) + ": bad field name '" + name + "'");
    if (values.size() != mesh.tets.size())
      throw std::invalid_argument(std::string(who) + ": field '" + name + "' has " + std::to_string(values.size()) +
                                  " values for " + std::to_string(mesh.tets.size()) + " tets");
  }
}

// The three coordinates of a node, 17 significant digits each, separated by spaces.
void writeNode(core::AtomicFile& out, const Eigen::Vector3d& p) {
  out.number17(p[0]) << " ";
  out.number17(p[1]) << " ";
  out.number17(p[2]);
}

void writeVtu(const TetMesh& mesh, const std::filesystem::path& path,
              const std::map<std::string, std::vector<int>>& cell_fields) {
  core::AtomicFile out(path);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << mesh.nodes_m.size() << "\" NumberOfCells=\"" << mesh.tets.size() << "\">\n"
      << "      <Points>\n"
      << "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : mesh.nodes_m) {
    out << "          ";
    writeNode(out, p);
    out << "\n";
  }
  out << "        </DataArray>\n"
      << "      </Points>\n"
      << "      <Cells>\n"
      << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : mesh.tets) out << "          " << t[0] << " " << t[1] << " " << t[2] << " " << t[3] << "\n";
  out << "        </DataArray>\n"
      << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (size_t t = 0; t < mesh.tets.size(); ++t) out << "          " << 4 * (t + 1) << "\n";
  out << "        </DataArray>\n"
      << "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (size_t t = 0; t < mesh.tets.size(); ++t) out << "          10\n";
  out << "        </DataArray>\n"
      << "      </Cells>\n";
  if (!cell_fields.empty()) {
    out << "      <CellData>\n";
    for (const auto& [name, values] : cell_fields) {
      out << "        <DataArray type=\"Int32\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (int v : values) out << "          " << v << "\n";
      out << "        </DataArray>\n";
    }
    out << "      </CellData>\n";
  }
  out << "    </Piece>\n"
      << "  </UnstructuredGrid>\n"
      << "</VTKFile>\n";
  out.commit();
}

void writeNodeEle(const TetMesh& mesh, const std::filesystem::path& stem,
                  const std::map<std::string, std::vector<int>>& cell_fields) {
  core::AtomicFile node(stem.string() + ".node");
  node << mesh.nodes_m.size() << " 3 0 0\n";
  for (size_t v = 0; v < mesh.nodes_m.size(); ++v) {
    node << v << " ";
    writeNode(node, mesh.nodes_m[v]);
    node << "\n";
  }
  core::AtomicFile ele(stem.string() + ".ele");
  ele << mesh.tets.size() << " 4 " << cell_fields.size() << "\n";
  if (!cell_fields.empty()) {
    ele << "# attributes:";
    for (const auto& field : cell_fields) ele << " " << field.first;
    ele << "\n";
  }
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    ele << t << " " << tet[0] << " " << tet[1] << " " << tet[2] << " " << tet[3];
    for (const auto& field : cell_fields) ele << " " << field.second[t];
    ele << "\n";
  }
  // Both closed before either is renamed: a write failure leaves both previous files.
  node.close();
  ele.close();
  node.commit();
  ele.commit();
}

}  // namespace

void saveVtu(const TetMesh& mesh, const std::filesystem::path& path,
             const std::map<std::string, std::vector<int>>& cell_fields) {
  requireValidIndices(mesh);
  requireValidFields(mesh, cell_fields, "saveVtu");
  for (size_t v = 0; v < mesh.nodes_m.size(); ++v)
    if (!mesh.nodes_m[v].allFinite())
      throw mesh::MeshError("cannot save " + path.string() + ": node " + std::to_string(v) + " is not finite");

  core::rethrowFileErrorAs<mesh::MeshError>([&] { writeVtu(mesh, path, cell_fields); });
}

void saveNodeEle(const TetMesh& mesh, const std::filesystem::path& stem,
                 const std::map<std::string, std::vector<int>>& cell_fields) {
  requireValidIndices(mesh);
  requireValidFields(mesh, cell_fields, "saveNodeEle");
  for (size_t v = 0; v < mesh.nodes_m.size(); ++v)
    if (!mesh.nodes_m[v].allFinite())
      throw mesh::MeshError("cannot save " + stem.string() + ".node: node " + std::to_string(v) + " is not finite");
  core::rethrowFileErrorAs<mesh::MeshError>([&] { writeNodeEle(mesh, stem, cell_fields); });
}

}  // namespace incise::tets
