// Tests for cutting/tets/src/tet_mesh.cpp and cutting/tets/src/tetrahedralize.cpp: adjacency, boundary, the
// conformity check, VTU and .node/.ele output, and TetGen on a cube and the bunny, with bad surfaces refused
// before TetGen sees them.
#include "incise/tets/tet_mesh.h"
#include "incise/mesh/shapes.h"
#include "incise/tets/tetrahedralize.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <catch2/catch.hpp>

#include "support/temp_dir.h"

namespace incise::tets {
namespace {

namespace fs = std::filesystem;
using incise::test::readFile;
using incise::test::TempDir;

const fs::path kBunny = fs::path(INCISE_SCENARIOS_DIR) / "meshes" / "bunny.obj";

bool hasTmpFile(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".tmp") return true;
  return false;
}

// The 12 outward triangles of the cube [lo, lo + size]^3; vertex i is at lo + size * (i & 1, i & 2, i & 4).
void addCube(mesh::SurfaceMesh& s, const Eigen::Vector3d& lo, double size, bool skip_top = false) {
  std::vector<mesh::TriMesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i) v.push_back(s.addVertex(lo + size * Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (int f = 0; f < 12; ++f) {
    if (skip_top && (f == 2 || f == 3)) continue;
    s.addFace(v[static_cast<size_t>(faces[f][0])], v[static_cast<size_t>(faces[f][1])],
              v[static_cast<size_t>(faces[f][2])]);
  }
}

mesh::SurfaceMesh unitCube() {
  mesh::SurfaceMesh s;
  addCube(s, Eigen::Vector3d::Zero(), 1.0);
  return s;
}

// Divergence theorem: sum over triangles of p0 . (p1 x p2) / 6.
double enclosedVolume(const mesh::TriMesh& mesh) {
  double sum = 0;
  for (const auto f : mesh.faces()) {
    std::vector<Eigen::Vector3d> p;
    for (const auto v : mesh.fv_range(f)) p.push_back(mesh::toEigen(mesh.point(v)));
    sum += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  return sum;
}

bool allPositive(const TetMesh& mesh) {
  for (const auto& t : mesh.tets) {
    Eigen::Matrix3d m;
    for (int k = 0; k < 3; ++k)
      m.col(k) =
          mesh.nodes_m[static_cast<size_t>(t[static_cast<size_t>(k + 1)])] - mesh.nodes_m[static_cast<size_t>(t[0])];
    if (!(m.determinant() > 0)) return false;
  }
  return true;
}

// A triangle as its vertex ids rotated so the smallest comes first (orientation kept).
std::array<int, 3> canonical(std::array<int, 3> f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}

std::string tetrahedralizeError(const mesh::SurfaceMesh& s) {
  try {
    tetrahedralize(s);
  } catch (const mesh::MeshError& e) {
    return e.what();
  }
  FAIL("tetrahedralize accepted the surface");
  return {};
}

// Two tets sharing the face (1, 2, 3).
TetMesh twoTets() {
  TetMesh m;
  m.nodes_m = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {4, 1, 3, 2}};
  return m;
}

TEST_CASE("tet_mesh: adjacency, boundary, volume and dihedral angles of two tets", "[cutting]") {
  TetMesh m = twoTets();
  REQUIRE(allPositive(m));
  buildAdjacency(m);
  CHECK(m.neighbours[0] == std::array<int, 4>{1, -1, -1, -1});
  CHECK(m.neighbours[1] == std::array<int, 4>{0, -1, -1, -1});
  const auto boundary = boundaryFaces(m);
  CHECK(boundary.size() == 6);
  // Outward: every boundary face sees the centroid on its negative side.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : m.nodes_m) centroid += p / 5.0;
  for (const auto& f : boundary) {
    const Eigen::Vector3d& a = m.nodes_m[static_cast<size_t>(f[0])];
    const Eigen::Vector3d n =
        (m.nodes_m[static_cast<size_t>(f[1])] - a).cross(m.nodes_m[static_cast<size_t>(f[2])] - a);
    CHECK(n.dot(centroid - a) < 0);
  }
  CHECK(volume(m) == Approx(1.0 / 6.0 + 1.0 / 3.0));
  const TetCheck check = checkConforming(m);
  CHECK(check.conforming);
  CHECK(check.first_problem.empty());
  CHECK(check.interior_faces == 1);
  CHECK(check.boundary_faces == 6);
  // The corner tet's smallest dihedral angle is atan(sqrt 2) ~ 54.7 deg at its slanted face; the other is flatter.
  const double smallest = minDihedralAngleDeg(m);
  CHECK(smallest > 0);
  CHECK(smallest <= std::atan(std::sqrt(2.0)) * 180.0 / std::numbers::pi + 1e-9);
}

TEST_CASE("tet_mesh: checkConforming names an inverted tet, a face of three tets and stale neighbours", "[cutting]") {
  TetMesh inverted = twoTets();
  std::swap(inverted.tets[1][2], inverted.tets[1][3]);
  TetCheck check = checkConforming(inverted);
  CHECK_FALSE(check.conforming);
  CHECK(check.inverted_tets == 1);
  CHECK(check.first_problem.find("tet 1 is inverted") != std::string::npos);

  TetMesh three = twoTets();
  three.nodes_m.push_back({0.4, 0.4, 0.4});  // on the positive side of (1, 2, 3) as well
  three.tets.push_back({5, 1, 3, 2});
  REQUIRE(allPositive(three));
  check = checkConforming(three);
  CHECK_FALSE(check.conforming);
  CHECK(check.non_manifold_faces == 1);
  CHECK(check.first_problem == "face (1, 2, 3) shared by 3 tets (tet 0, tet 1)");

  TetMesh stale = twoTets();
  buildAdjacency(stale);
  stale.neighbours[0][0] = -1;
  check = checkConforming(stale);
  CHECK_FALSE(check.conforming);
  CHECK(check.first_problem == "tet 0: neighbours[0] is -1, the faces imply 1");

  TetMesh bad = twoTets();
  bad.tets[1][0] = 7;
  CHECK_THROWS_AS(buildAdjacency(bad), std::invalid_argument);
  CHECK(checkConforming(bad).bad_tets == 1);
}

TEST_CASE("tetrahedralize: the unit cube fills volume 1 with positive, conforming tets and keeps its 12 triangles",
          "[cutting]") {
  const mesh::SurfaceMesh cube = unitCube();
  REQUIRE_FALSE(findSelfIntersection(cube.mesh()).has_value());
  const TetMesh m = tetrahedralize(cube);
  REQUIRE(!m.tets.empty());
  CHECK(std::abs(volume(m) - 1.0) <= 1e-9);
  CHECK(allPositive(m));
  const TetCheck check = checkConforming(m);
  INFO(check.first_problem);
  CHECK(check.conforming);
  CHECK(check.boundary_faces == 12);
  CHECK(boundaryFaces(m).size() == 12);
  CHECK(m.neighbours.size() == m.tets.size());
  CHECK(minDihedralAngleDeg(m) > 0);

  SECTION("max_volume_m3 gives more, smaller tets when the surface may be refined") {
    // With keep_surface, TetGen 1.5 rejects every Steiner point that encroaches a boundary triangle: the
    // cube's candidates (its centre) all do, so it stays at its few tets.
    TetrahedralizeOptions options;
    options.max_volume_m3 = 0.01;
    CHECK(tetrahedralize(cube, options).tets.size() == m.tets.size());
    options.keep_surface = false;
    const TetMesh fine = tetrahedralize(cube, options);
    CHECK(fine.tets.size() >= 100);
    CHECK(std::abs(volume(fine) - 1.0) <= 1e-9);
    CHECK(checkConforming(fine).conforming);
    CHECK(boundaryFaces(fine).size() > 12);
    double largest = 0;
    for (const auto& t : fine.tets) {
      TetMesh one{fine.nodes_m, {t}, {}};
      largest = std::max(largest, volume(one));
    }
    CHECK(largest <= 0.01);
  }
  SECTION("bad options are refused with the value") {
    TetrahedralizeOptions options;
    options.radius_edge_ratio = 0.5;
    CHECK_THROWS_WITH(tetrahedralize(cube, options), Catch::Contains("radius_edge_ratio 0.5"));
    options = {};
    options.max_volume_m3 = -1;
    CHECK_THROWS_AS(tetrahedralize(cube, options), std::invalid_argument);
  }
}

TEST_CASE("tetrahedralize: an open surface is refused before TetGen", "[cutting]") {
  mesh::SurfaceMesh open;
  addCube(open, Eigen::Vector3d::Zero(), 1.0, /*skip_top=*/true);
  const std::string message = tetrahedralizeError(open);
  CHECK(message.find("not a closed two-manifold") != std::string::npos);
  CHECK(message.find("TetGen") == std::string::npos);
}

TEST_CASE("tetrahedralize: self-intersecting surfaces are refused naming two faces, before TetGen", "[cutting]") {
  SECTION("two overlapping cubes as one mesh") {
    mesh::SurfaceMesh two;
    addCube(two, Eigen::Vector3d::Zero(), 1.0);
    addCube(two, Eigen::Vector3d(0.5, 0.5, 0.5), 1.0);
    REQUIRE(mesh::checkManifold(two.mesh()).closed_two_manifold);
    const auto pair = findSelfIntersection(two.mesh());
    REQUIRE(pair.has_value());
    CHECK(pair->first < 12);
    CHECK(pair->second >= 12);
    const std::string message = tetrahedralizeError(two);
    CHECK(message == "tetrahedralize: the surface intersects itself: face " + std::to_string(pair->first) +
                         " and face " + std::to_string(pair->second));
  }
  SECTION("a cube with a corner pushed through the opposite face") {
    mesh::SurfaceMesh pushed = unitCube();
    pushed.mesh().set_point(mesh::TriMesh::VertexHandle(7), {0.5, 0.5, -0.5});
    REQUIRE(mesh::checkManifold(pushed.mesh()).closed_two_manifold);
    const std::string message = tetrahedralizeError(pushed);
    CHECK(message.find("intersects itself: face ") != std::string::npos);
    CHECK(message.find("TetGen") == std::string::npos);
  }
  SECTION("two cubes touching only at a corner") {
    mesh::SurfaceMesh touching;
    addCube(touching, Eigen::Vector3d::Zero(), 1.0);
    addCube(touching, Eigen::Vector3d(1, 1, 1), 1.0);
    CHECK(findSelfIntersection(touching.mesh()).has_value());
  }
  SECTION("two separate cubes are fine") {
    mesh::SurfaceMesh apart;
    addCube(apart, Eigen::Vector3d::Zero(), 1.0);
    addCube(apart, Eigen::Vector3d(1.5, 0, 0), 1.0);
    CHECK_FALSE(findSelfIntersection(apart.mesh()).has_value());
    const TetMesh m = tetrahedralize(apart);
    CHECK(std::abs(volume(m) - 2.0) <= 2e-9);
    CHECK(checkConforming(m).conforming);
  }
}

TEST_CASE("tetrahedralize: the bunny's tets fill its enclosed volume and keep its triangles", "[cutting]") {
  const mesh::SurfaceMesh bunny = mesh::loadSurfaceMesh(kBunny, 0.01);
  const double expected = enclosedVolume(bunny.mesh());
  REQUIRE(expected > 0);
  const TetMesh m = tetrahedralize(bunny);
  CHECK(std::abs(volume(m) - expected) <= 1e-9 * expected);
  const TetCheck check = checkConforming(m);
  INFO(check.first_problem);
  CHECK(check.conforming);
  CHECK(minDihedralAngleDeg(m) > 0);

  // Boundary triangles = surface triangles, by vertex position and orientation.
  std::map<std::array<double, 3>, int> vertex_at;
  for (const auto v : bunny.mesh().vertices()) {
    const auto& p = bunny.mesh().point(v);
    vertex_at[{p[0], p[1], p[2]}] = v.idx();
  }
  REQUIRE(vertex_at.size() == bunny.mesh().n_vertices());
  std::set<std::array<int, 3>> surface_faces;
  for (const auto f : bunny.mesh().faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (const auto v : bunny.mesh().fv_range(f)) t[static_cast<size_t>(k++)] = v.idx();
    surface_faces.insert(canonical(t));
  }
  std::set<std::array<int, 3>> tet_faces;
  bool all_found = true;
  for (const auto& f : boundaryFaces(m)) {
    std::array<int, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = m.nodes_m[static_cast<size_t>(f[static_cast<size_t>(k)])];
      const auto it = vertex_at.find({p[0], p[1], p[2]});
      if (it == vertex_at.end()) {
        all_found = false;
        break;
      }
      t[static_cast<size_t>(k)] = it->second;
    }
    tet_faces.insert(canonical(t));
  }
  CHECK(all_found);
  // The surface's vertices come first, in handle order.
  REQUIRE(m.nodes_m.size() >= bunny.mesh().n_vertices());
  bool same_first = true;
  for (const auto v : bunny.mesh().vertices())
    same_first = same_first && m.nodes_m[static_cast<size_t>(v.idx())] == mesh::toEigen(bunny.mesh().point(v));
  CHECK(same_first);
  CHECK(boundaryFaces(m).size() == surface_faces.size());
  CHECK(tet_faces == surface_faces);

  // A volume bound adds interior Steiner points and keeps the surface.
  TetrahedralizeOptions options;
  options.max_volume_m3 = expected / 20000;
  const TetMesh fine = tetrahedralize(bunny, options);
  INFO("tets: " << m.tets.size() << " -> " << fine.tets.size());
  CHECK(fine.tets.size() > m.tets.size());
  CHECK(fine.nodes_m.size() > m.nodes_m.size());
  CHECK(std::abs(volume(fine) - expected) <= 1e-9 * expected);
  CHECK(checkConforming(fine).conforming);
  CHECK(boundaryFaces(fine).size() == surface_faces.size());
}

TEST_CASE("tet_mesh: saveVtu and saveNodeEle write files that parse back, with no .tmp left", "[cutting]") {
  const TetMesh m = tetrahedralize(unitCube());
  TempDir dir;
  std::vector<int> ids(m.tets.size());
  for (size_t t = 0; t < ids.size(); ++t) ids[t] = static_cast<int>(t);
  const fs::path vtu = dir.path() / "cube.vtu";
  saveVtu(m, vtu, {{"tet_id", ids}});

  std::ifstream in(vtu);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  CHECK(s.find("NumberOfPoints=\"" + std::to_string(m.nodes_m.size()) + "\"") != std::string::npos);
  CHECK(s.find("NumberOfCells=\"" + std::to_string(m.tets.size()) + "\"") != std::string::npos);
  // Count the connectivity entries and the cell types.
  auto arrayValues = [&](const std::string& name) {
    const size_t begin = s.find(">", s.find("Name=\"" + name + "\"")) + 1;
    const size_t end = s.find("</DataArray>", begin);
    std::istringstream values(s.substr(begin, end - begin));
    std::vector<long long> out;
    long long x;
    while (values >> x) out.push_back(x);
    return out;
  };
  CHECK(arrayValues("connectivity").size() == 4 * m.tets.size());
  const auto types = arrayValues("types");
  CHECK(types.size() == m.tets.size());
  CHECK(std::all_of(types.begin(), types.end(), [](long long t) { return t == 10; }));
  CHECK(arrayValues("tet_id").size() == m.tets.size());
  CHECK(arrayValues("offsets").back() == static_cast<long long>(4 * m.tets.size()));

  saveNodeEle(m, dir.path() / "cube");
  std::ifstream node(dir.path() / "cube.node"), ele(dir.path() / "cube.ele");
  size_t nodes = 0, dim = 0, tets = 0, corners = 0;
  node >> nodes >> dim;
  ele >> tets >> corners;
  CHECK(nodes == m.nodes_m.size());
  CHECK(dim == 3);
  CHECK(tets == m.tets.size());
  CHECK(corners == 4);
  node.ignore(1000, '\n');
  ele.ignore(1000, '\n');
  size_t node_lines = 0, ele_lines = 0;
  std::string line;
  while (std::getline(node, line))
    if (!line.empty()) ++node_lines;
  while (std::getline(ele, line)) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    int i, a, b, c, d;
    if (fields >> i >> a >> b >> c >> d && a >= 0 && static_cast<size_t>(d) < m.nodes_m.size()) ++ele_lines;
  }
  CHECK(node_lines == m.nodes_m.size());
  CHECK(ele_lines == m.tets.size());
  CHECK_FALSE(hasTmpFile(dir.path()));

  // Per-tet fields become .ele attributes, in name order, after the nodes.
  std::vector<int> side(m.tets.size()), split(m.tets.size());
  for (size_t t = 0; t < m.tets.size(); ++t) side[t] = static_cast<int>(t % 3) - 1, split[t] = static_cast<int>(t % 2);
  saveNodeEle(m, dir.path() / "fields", {{"split", split}, {"side", side}});
  std::ifstream with(dir.path() / "fields.ele");
  size_t attributes = 0;
  with >> tets >> corners >> attributes;
  CHECK(attributes == 2);
  with.ignore(1000, '\n');
  std::getline(with, line);
  CHECK(line == "# attributes: side split");
  for (size_t t = 0; t < m.tets.size(); ++t) {
    int i, a, b, c, d, s1, s2;
    REQUIRE(with >> i >> a >> b >> c >> d >> s1 >> s2);
    CHECK(s1 == side[t]);
    CHECK(s2 == split[t]);
  }
  CHECK_THROWS_AS(saveNodeEle(m, dir.path() / "bad", {{"short", {1}}}), std::invalid_argument);

  CHECK_THROWS_AS(saveVtu(m, dir.path() / "bad.vtu", {{"short", {1, 2}}}), std::invalid_argument);
  CHECK_THROWS_AS(saveVtu(m, dir.path() / "missing" / "x.vtu"), mesh::MeshError);
  CHECK_FALSE(fs::exists(dir.path() / "bad.vtu"));
  CHECK_FALSE(hasTmpFile(dir.path()));
}

TEST_CASE("tetrahedralize: flat neighbours are not a self-intersection, so TetGen gets cylinders and robots",
          "[cutting]") {
  // Coplanar faces sharing a vertex on a tilted plane (a cylinder's cap, its side strips) defeat plain
  // double orientation tests; CGAL's exact predicates do not report them.
  const mesh::SurfaceMesh cylinder =
      mesh::makeCylinder(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, -0.4, 1.0), 0.2, 24, 3, 2);
  CHECK_FALSE(findSelfIntersection(cylinder.mesh()).has_value());
  CHECK_FALSE(findSelfIntersection(mesh::makeRobot(0.1, 2).mesh()).has_value());
  const TetMesh tets = tetrahedralize(cylinder);
  CHECK(checkConforming(tets).conforming);
  CHECK(volume(tets) > 0);
}

}  // namespace
}  // namespace incise::tets
