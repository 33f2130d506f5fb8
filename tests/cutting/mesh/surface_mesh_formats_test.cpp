// Tests for the mesh readers of cutting/mesh/src/surface_mesh_off.cpp, surface_mesh_stl.cpp, surface_mesh_ply.cpp
// and surface_mesh_text.cpp: each format as other tools write it (comments, colours, normals, polygons,
// binary of either byte order, binary STL headed "solid") loads to the same closed cube; each bad file
// gives a message naming what and where (file:line, or the byte offset); no input crashes the loader.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "mesh_fixture.h"
#include "support/temp_dir.h"

namespace incise::mesh {
namespace {

namespace fs = std::filesystem;
using incise::test::TempDir;

// A unit cube of quads, counter-clockwise seen from outside: 8 vertices, 12 triangles once fanned.
const std::array<std::array<int, 3>, 8> kCorners = {
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
const std::array<std::array<int, 4>, 6> kQuads = {
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}}};

using test::loadError;

std::vector<std::array<double, 3>> positions(const SurfaceMesh& s) {
  std::vector<std::array<double, 3>> p;
  for (const auto v : s.mesh().vertices())
    p.push_back({s.mesh().point(v)[0], s.mesh().point(v)[1], s.mesh().point(v)[2]});
  return p;
}

// The cube, closed, with its corners in file order (or in any order when `welded`: STL).
void requireCube(const fs::path& path, bool welded = false) {
  INFO(path);
  const SurfaceMesh s = loadSurfaceMesh(path);
  REQUIRE(s.mesh().n_vertices() == 8);
  REQUIRE(s.mesh().n_faces() == 12);
  REQUIRE(checkManifold(s.mesh()).closed_two_manifold);
  std::vector<std::array<double, 3>> expected, got = positions(s);
  for (const auto& c : kCorners) expected.push_back({double(c[0]), double(c[1]), double(c[2])});
  if (welded) {
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
  }
  REQUIRE(got == expected);
}

std::string cornerLine(int v, const std::string& extra = "") {
  const auto& c = kCorners[static_cast<size_t>(v)];
  return std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + extra + "\n";
}

std::string quadLine(int q, const std::string& prefix, const std::string& extra = "", int base = 0) {
  std::string s = prefix;
  for (int v : kQuads[static_cast<size_t>(q)]) s.append(" ").append(std::to_string(v + base));
  return s + extra + "\n";
}

// An OFF cube: `keyword`, `vertex_extra` after each x y z, `face_extra` after each face's indices.
std::string off(const std::string& keyword, const std::string& vertex_extra = "", const std::string& face_extra = "") {
  std::string s = keyword + "\n8 6 12\n";
  for (int v = 0; v < 8; ++v) s += cornerLine(v, vertex_extra);
  for (int q = 0; q < 6; ++q) s += quadLine(q, "4", face_extra);
  return s;
}

TEST_CASE("surface_mesh: an OFF whose first lines are comments loads (the bunny as CGAL writes it)", "[cutting]") {
  TempDir dir;
  const SurfaceMesh bunny = loadSurfaceMesh(fs::path(INCISE_SCENARIOS_DIR) / "meshes" / "bunny.obj");
  const TriMesh& m = bunny.mesh();
  std::string text = "# written by CGAL\n# 1839 vertices\n#\nOFF\n" + std::to_string(m.n_vertices()) + " " +
                     std::to_string(m.n_faces()) + " 0\n\n";
  char number[128];
  for (const auto v : m.vertices()) {
    std::snprintf(number, sizeof number, "%.17g %.17g %.17g\n", m.point(v)[0], m.point(v)[1], m.point(v)[2]);
    text += number;
  }
  for (const auto f : m.faces()) {
    text += "3";
    for (const auto v : m.fv_range(f)) text.append(" ").append(std::to_string(v.idx()));
    text += "\n";
  }
  const SurfaceMesh read = loadSurfaceMesh(dir.write("bunny.off", text));
  REQUIRE(read.mesh().n_vertices() == m.n_vertices());
  REQUIRE(read.mesh().n_faces() == m.n_faces());
  REQUIRE(positions(read) == positions(bunny));
  REQUIRE(checkManifold(read.mesh()).closed_two_manifold);
}

TEST_CASE("surface_mesh: OFF with comments, blank lines, colours, normals and quads loads the same cube", "[cutting]") {
  TempDir dir;
  requireCube(dir.write("plain.off", off("OFF")));
  requireCube(dir.write("comments.off", "# a comment\n\n# another\n" + off("OFF") + "# trailing\n"));
  std::string after = off("OFF");
  after.insert(after.find('\n') + 1, "# after the keyword\n\n");
  after.insert(after.find("12\n") + 3, "  # after the counts\n\n");
  requireCube(dir.write("after.off", after));
  requireCube(dir.write("face_colours.off", off("OFF", "", " 255 0 0")));
  requireCube(dir.write("coff.off", off("COFF", " 0.5 0.5 0.5 1")));
  requireCube(dir.write("noff.off", off("NOFF", " 0 0 1")));
  requireCube(dir.write("cnoff.off", off("CNOFF", " 0 0 1 255 255 255 255")));
  std::string same_line = off("OFF");
  same_line.replace(0, 4, "OFF ");
  requireCube(dir.write("same_line.off", same_line));
  std::string crlf;
  for (char c : off("OFF")) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  requireCube(dir.write("crlf.off", crlf));
}

TEST_CASE("surface_mesh: an OFF hexagonal prism's polygons become fans from their first vertex", "[cutting]") {
  TempDir dir;
  std::string s = "OFF\n12 8 0\n";
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < 6; ++k)
      s += std::to_string(std::cos(k * M_PI / 3)) + " " + std::to_string(std::sin(k * M_PI / 3)) + " " +
           std::to_string(z) + "\n";
  s += "6 0 5 4 3 2 1\n6 6 7 8 9 10 11\n";
  for (int k = 0; k < 6; ++k) {
    const int n = (k + 1) % 6;
    s += "4 " + std::to_string(k) + " " + std::to_string(n) + " " + std::to_string(n + 6) + " " +
         std::to_string(k + 6) + "\n";
  }
  const SurfaceMesh prism = loadSurfaceMesh(dir.write("prism.off", s));
  REQUIRE(prism.mesh().n_faces() == 20);
  REQUIRE(checkManifold(prism.mesh()).closed_two_manifold);
  std::vector<int> first;
  for (const auto v : prism.mesh().fv_range(TriMesh::FaceHandle(1))) first.push_back(v.idx());
  std::rotate(first.begin(), std::min_element(first.begin(), first.end()), first.end());
  REQUIRE(first == std::vector<int>{0, 4, 3});  // (0 5 4 3 2 1) -> (0 5 4), (0 4 3), ...
}

TEST_CASE("surface_mesh: bad OFF files name what is wrong and the file:line", "[cutting]") {
  TempDir dir;
  std::string bad_index = off("OFF");
  bad_index.replace(bad_index.rfind("4 1 2 6 5"), 9, "4 1 2 6 12");
  // Lines: OFF, counts, 8 vertices (3..10), faces 0..5 on lines 11..16.
  const fs::path p = dir.write("bad.off", bad_index);
  REQUIRE(loadError(p) == p.string() + ":16: face 5 has index 12 but there are 8 vertices");
  REQUIRE_THAT(loadError(dir.write("short.off", off("OFF").substr(0, off("OFF").rfind("4 1")))),
               Catch::Contains("ends after 5 of the 6 faces"));
  REQUIRE_THAT(loadError(dir.write("vertex.off", "OFF\n8 6 0\n0 0\n")),
               Catch::Contains("vertex.off:3: vertex 0: expected 3 coordinates, got 2"));
  REQUIRE_THAT(loadError(dir.write("nan.off", "OFF\n8 6 0\n0 nan 0\n")),
               Catch::Contains("nan.off:3: coordinate 'nan' is not finite"));
  REQUIRE_THAT(loadError(dir.write("header.off", "# c\nOBJ\n")),
               Catch::Contains("header.off:2: expected the OFF header"));
  REQUIRE_THAT(loadError(dir.write("4d.off", "4OFF\n")), Catch::Contains("4d.off:1: '4OFF' (4D or n-dimensional OFF)"));
  REQUIRE_THAT(loadError(dir.write("counts.off", "OFF\n-1 6 0\n")),
               Catch::Contains("counts.off:2: the vertex count '-1'"));
  REQUIRE_THAT(loadError(dir.write("huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n")),
               Catch::Contains("ends after 1 of the 2000000000 vertices"));
  REQUIRE_THAT(loadError(dir.write("list.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n")),
               Catch::Contains("list.off:6: face 0 declares 4 vertices but lists 3"));
  std::string open = off("OFF");
  open.replace(open.find("8 6 12"), 6, "8 5 12");
  REQUIRE_THAT(loadError(dir.write("open.off", open)), Catch::Contains("open surface: edge"));
  REQUIRE_THAT(loadError(dir.write("open.off", open)), Catch::Contains("0-based"));
  REQUIRE_THAT(loadError(dir.write("empty.off", "")), Catch::Contains("empty.off: empty file"));
}

// ---------------------------------------------------------------------------------------------------------
// STL

std::vector<std::array<int, 3>> cubeTriangles() {
  std::vector<std::array<int, 3>> t;
  for (const auto& q : kQuads) {
    t.push_back({q[0], q[1], q[2]});
    t.push_back({q[0], q[2], q[3]});
  }
  return t;
}

void putLittle32(std::string& s, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) s += static_cast<char>((v >> (8 * b)) & 0xff);
}

void putFloat(std::string& s, float f, bool big = false) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof bits);
  for (int b = 0; b < 4; ++b) s += static_cast<char>((bits >> (8 * (big ? 3 - b : b))) & 0xff);
}

std::string binaryStl(const std::string& header80) {
  std::string s = header80;
  s.resize(80, ' ');
  const auto triangles = cubeTriangles();
  putLittle32(s, static_cast<std::uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    for (int a = 0; a < 3; ++a) putFloat(s, 0.0f);  // normal
    for (int v : t)
      for (int a = 0; a < 3; ++a)
        putFloat(s, static_cast<float>(kCorners[static_cast<size_t>(v)][static_cast<size_t>(a)]));
    s += std::string(2, '\0');
  }
  return s;
}

std::string asciiStl() {
  std::string s = "solid cube\n";
  for (const auto& t : cubeTriangles()) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (int v : t) s += "      vertex " + cornerLine(v);
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid cube\n";
}

TEST_CASE("surface_mesh: binary and ASCII STL load the same cube, corners welded", "[cutting]") {
  TempDir dir;
  requireCube(dir.write("binary.stl", binaryStl("made by a tool")), true);
  requireCube(dir.write("solid_header.stl", binaryStl("solid cube exported as binary")), true);
  requireCube(dir.write("ascii.stl", asciiStl()), true);
  requireCube(dir.write("UPPER.STL", asciiStl()), true);
}

TEST_CASE("surface_mesh: bad STL files name what is wrong and where", "[cutting]") {
  TempDir dir;
  const std::string full = binaryStl("x");
  const fs::path cut = dir.write("cut.stl", full.substr(0, 500));
  REQUIRE(loadError(cut) == cut.string() + ": binary STL declares 12 triangles (684 bytes) but the file has 500 bytes");
  const fs::path tiny = dir.write("tiny.stl", "abc");
  REQUIRE_THAT(loadError(tiny), Catch::Contains("too short for binary STL (3 bytes"));
  std::string ascii = asciiStl();
  ascii.replace(ascii.find("endloop"), 7, "endlop");
  REQUIRE_THAT(loadError(dir.write("typo.stl", ascii)),
               Catch::Contains("typo.stl:7: expected 'endloop', got 'endlop'"));
  const std::string no_end = asciiStl().substr(0, asciiStl().rfind("endsolid"));
  REQUIRE_THAT(loadError(dir.write("no_end.stl", no_end)),
               Catch::Contains("no_end.stl: the file ends before 'endsolid'"));
  std::string open = full.substr(0, 84 + 50 * 11);
  open[80] = 11;
  REQUIRE_THAT(loadError(dir.write("open.stl", open)), Catch::Contains("open.stl: byte "));
  REQUIRE_THAT(loadError(dir.write("open.stl", open)), Catch::Contains("open surface"));
}

// ---------------------------------------------------------------------------------------------------------
// OBJ (the reader and its messages are tested in surface_mesh_test.cpp; here: the same cube)

TEST_CASE("surface_mesh: OBJ quads with v/vt/vn, v//vn and negative indices load the same cube", "[cutting]") {
  TempDir dir;
  std::string obj = "vt 0 0\nvn 0 0 1\n";
  for (int v = 0; v < 8; ++v) obj += "v " + cornerLine(v);
  for (int q = 0; q < 6; ++q) {
    std::string line = "f";
    for (int v : kQuads[static_cast<size_t>(q)]) {
      const char* forms[3] = {"/1/1", "//1", ""};  // v/vt/vn, v//vn, and negative (counting back) indices
      line.append(" ").append(std::to_string(q % 3 == 2 ? v - 8 : v + 1)).append(forms[q % 3]);
    }
    obj += line + "\n";
  }
  requireCube(dir.write("cube.obj", obj));
}

// ---------------------------------------------------------------------------------------------------------
// PLY

enum class Ply { Ascii, Little, Big };

void putInt(std::string& s, std::uint64_t v, int bytes, bool big) {
  for (int b = 0; b < bytes; ++b) s += static_cast<char>((v >> (8 * (big ? bytes - 1 - b : b))) & 0xff);
}

// A PLY cube with normals and colours on the vertices, an edge element, and `count`/`index` list types.
std::string ply(Ply format, const std::string& count = "uchar", const std::string& index = "int") {
  const char* name = format == Ply::Ascii    ? "ascii"
                     : format == Ply::Little ? "binary_little_endian"
                                             : "binary_big_endian";
  std::string s = std::string("ply\nformat ") + name +
                  " 1.0\ncomment made by a test\nelement vertex 8\nproperty float x\nproperty float y\n"
                  "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
                  "property uchar green\nproperty uchar blue\nelement face 6\nproperty list " +
                  count + " " + index +
                  " vertex_indices\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  const bool big = format == Ply::Big;
  const int count_bytes = count == "uchar" ? 1 : 4;
  for (int v = 0; v < 8; ++v) {
    if (format == Ply::Ascii) {
      s += cornerLine(v, " 0 0 1 255 128 0");
      continue;
    }
    for (int a = 0; a < 3; ++a)
      putFloat(s, static_cast<float>(kCorners[static_cast<size_t>(v)][static_cast<size_t>(a)]), big);
    for (float n : {0.0f, 0.0f, 1.0f}) putFloat(s, n, big);
    s += "\xff\x80";
    s += '\0';
  }
  for (int q = 0; q < 6; ++q) {
    if (format == Ply::Ascii) {
      s += quadLine(q, "4");
      continue;
    }
    putInt(s, 4, count_bytes, big);
    for (int v : kQuads[static_cast<size_t>(q)]) putInt(s, static_cast<std::uint64_t>(v), 4, big);
  }
  if (format == Ply::Ascii) return s + "0 1\n";
  putInt(s, 0, 4, big);
  putInt(s, 1, 4, big);
  return s;
}

TEST_CASE("surface_mesh: ASCII and binary PLY of either byte order load the same cube", "[cutting]") {
  TempDir dir;
  requireCube(dir.write("ascii.ply", ply(Ply::Ascii)));
  requireCube(dir.write("little.ply", ply(Ply::Little)));
  requireCube(dir.write("big.ply", ply(Ply::Big)));
  requireCube(dir.write("little_int_uint.ply", ply(Ply::Little, "int", "uint")));
  requireCube(dir.write("big_int_uint.ply", ply(Ply::Big, "int", "uint")));
  std::string crlf;
  for (char c : ply(Ply::Ascii)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  requireCube(dir.write("crlf.ply", crlf));
}

TEST_CASE("surface_mesh: bad PLY files name what is wrong and the line or byte offset", "[cutting]") {
  TempDir dir;
  const std::string little = ply(Ply::Little);
  const size_t data = little.find("end_header\n") + 11;
  // 8 vertices of 27 bytes, faces of 17 (count, 4 indices), one edge of 8: the fixed parts fit in 246 bytes
  // but face 1 (bytes 233..249 of the data) does not.
  const fs::path cut = dir.write("cut.ply", little.substr(0, data + 246));
  REQUIRE(loadError(cut) == cut.string() + ": byte " + std::to_string(data + 246) + ": the file ends inside face 1");
  const fs::path fixed = dir.write("fixed.ply", little.substr(0, data + 226));
  REQUIRE(loadError(fixed) == fixed.string() + ": byte " + std::to_string(data) +
                                  ": the header declares 1 edge elements (8 bytes each at least) but only 226 bytes "
                                  "follow the header");
  std::string huge = little;
  huge.replace(huge.find("vertex 8"), 8, "vertex 2000000000");
  REQUIRE_THAT(loadError(dir.write("huge.ply", huge)),
               Catch::Contains("the header declares 2000000000 vertex elements (27 bytes each at least) but only"));
  std::string type = ply(Ply::Ascii);
  type.replace(type.find("float nx"), 5, "real ");
  REQUIRE_THAT(loadError(dir.write("type.ply", type)), Catch::Contains("type.ply:8: unknown PLY property type 'real'"));
  std::string index = ply(Ply::Ascii);
  index.replace(index.find("4 1 2 6 5"), 9, "4 1 2 6 12");
  // 19 header lines, 8 vertices (20..27), faces on 28..33.
  const fs::path bad = dir.write("bad.ply", index);
  REQUIRE(loadError(bad) == bad.string() + ":33: face 5 has index 12 but there are 8 vertices");
  REQUIRE_THAT(loadError(dir.write("none.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n")),
               Catch::Contains("none.ply: the PLY header has no 'end_header' line"));
  REQUIRE_THAT(
      loadError(dir.write(
          "noface.ply",
          "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n")),
      Catch::Contains("noface.ply: the PLY header has no 'element face'"));
  REQUIRE_THAT(loadError(dir.write("magic.ply", "solid\n")), Catch::Contains("magic.ply:1: not a PLY file"));
}

// ---------------------------------------------------------------------------------------------------------
// Any bytes: a MeshError or a mesh, never a crash (the fuzzer's first pass)

TEST_CASE("surface_mesh: truncated and corrupted files of every format throw MeshError or load", "[cutting]") {
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> files = {{"a.off", off("CNOFF", " 0 0 1 1 1 1 1", " 3 4 5")},
                                                                  {"b.stl", binaryStl("solid x")},
                                                                  {"c.stl", asciiStl()},
                                                                  {"d.ply", ply(Ply::Ascii)},
                                                                  {"e.ply", ply(Ply::Big, "int", "uint")},
                                                                  {"f.ply", ply(Ply::Little)}};
  std::mt19937 random(14);
  int loaded = 0, refused = 0;
  for (const auto& [name, text] : files)
    for (int trial = 0; trial < 150; ++trial) {
      std::string bytes = text;
      if (trial < 50) bytes.resize(random() % bytes.size());
      for (int flips = trial < 50 ? 0 : 1 + static_cast<int>(random() % 4); flips > 0; --flips)
        bytes[random() % bytes.size()] = static_cast<char>(random() % 256);
      const fs::path p = dir.write(name, bytes);
      try {
        loadSurfaceMesh(p);
        ++loaded;
      } catch (const MeshError&) {
        ++refused;
      }
    }
  REQUIRE(loaded + refused == 900);
  REQUIRE(refused > 0);
}

}  // namespace
}  // namespace incise::mesh

namespace incise::mesh {
namespace {

// The cube as ASCII PLY with texture coordinates: per vertex (`s t`: u = x + 2 z, v = y) or per corner (a
// face "texcoord" list, each quad on its own unit square at (10 q, 0)).
std::string texturedPly(bool per_corner) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n";
  if (!per_corner) s += "property float s\nproperty float t\n";
  s += "element face 6\nproperty list uchar int vertex_indices\n";
  if (per_corner) s += "property list uchar float texcoord\n";
  s += "end_header\n";
  for (int v = 0; v < 8; ++v) {
    const auto& c = kCorners[static_cast<size_t>(v)];
    // Appended, not " " + ...: GCC 12 -Wrestrict, PR 105651.
    const std::string st =
        std::string(" ").append(std::to_string(c[0] + 2 * c[2])).append(" ").append(std::to_string(c[1]));
    s += cornerLine(v, per_corner ? "" : st);
  }
  const char* square = " 8 0 0 1 0 1 1 0 1";
  for (int q = 0; q < 6; ++q) {
    std::string extra;
    if (per_corner) {
      extra = square;
      extra.replace(3, 1, std::to_string(10 * q));  // the first corner's u
    }
    s += quadLine(q, "4", extra);
  }
  return s;
}

TEST_CASE("surface_mesh: PLY texture coordinates per vertex (s t) and per corner (texcoord) load and save",
          "[cutting]") {
  TempDir dir;
  const SurfaceMesh by_vertex = loadSurfaceMesh(dir.write("st.ply", texturedPly(false)));
  REQUIRE(by_vertex.hasTexCoords());
  for (const auto f : by_vertex.mesh().faces()) {
    const FaceCorners c = faceCorners(by_vertex, f);
    for (size_t i = 0; i < 3; ++i) {
      const auto p = by_vertex.mesh().point(c.vertex[i]);
      CHECK(c.uv[i] == Eigen::Vector2d(p[0] + 2 * p[2], p[1]));
    }
  }
  const SurfaceMesh by_corner = loadSurfaceMesh(dir.write("texcoord.ply", texturedPly(true)));
  REQUIRE(by_corner.hasTexCoords());
  // Quad 0 (0 3 2 1) fans to (0 3 2), (0 2 1): its first triangle's corners (0,0), (1,0), (1,1) in file order.
  const FaceCorners first = faceCorners(by_corner, TriMesh::FaceHandle(0));
  CHECK(first.at(TriMesh::VertexHandle(0)) == Eigen::Vector2d(0, 0));
  CHECK(first.at(TriMesh::VertexHandle(3)) == Eigen::Vector2d(1, 0));
  CHECK(first.at(TriMesh::VertexHandle(2)) == Eigen::Vector2d(1, 1));
  // Saved with a per-corner list and read back the same, corner by corner.
  savePly(by_corner, dir.path() / "out.ply");
  const SurfaceMesh again = loadSurfaceMesh(dir.path() / "out.ply");
  REQUIRE(again.hasTexCoords());
  for (const auto f : by_corner.mesh().faces()) {
    const FaceCorners a = faceCorners(by_corner, f), b = faceCorners(again, f);
    for (size_t i = 0; i < 3; ++i) CHECK(b.at(a.vertex[i]) == a.uv[i]);
  }
  // A list of the wrong length is refused with the line.
  std::string bad = texturedPly(true);
  bad.replace(bad.find(" 8 0 0 1 0 1 1 0 1"), 18, " 6 0 0 1 0 1 1");
  CHECK_THAT(loadError(dir.write("bad.ply", bad)),
             Catch::Matchers::Contains("bad.ply:19: face 0 has 6 texture coordinates for 4 corners (2 each)"));
}

}  // namespace
}  // namespace incise::mesh
