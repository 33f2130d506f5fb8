// Loading and saving surface meshes (surface_mesh.h): the OBJ reader, the choice of reader by extension
// (OFF, STL, PLY in surface_mesh_off/stl/ply.cpp), the loader's checks and the OpenMesh mesh built from the
// triangle list; OBJ and PLY output.
#include "incise/mesh/surface_mesh.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "incise/core/atomic_file.h"
#include "incise/core/format.h"
#include "surface_mesh_internal.h"

namespace incise::mesh {

namespace {

using detail::countOf;
using detail::fail;
using detail::parseCoordinate;
using detail::RawMesh;
using detail::splitTokens;
using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;

// ---------------------------------------------------------------------------------------------------------
// OBJ parsing

// A 1-based OBJ index (negative: counting back from the last of `so_far` elements), resolved to 0-based.
// `what` names the element ("face index", "texture coordinate index") and `elements` its plural.
int resolveObjIndex(std::string_view text, std::string_view token, int so_far, const std::string& where,
                    const char* what, const char* elements) {
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    fail(where + what + " '" + std::string(token) + "' is not an integer");
  if (value == 0) fail(where + what + " 0 is invalid (OBJ indices start at 1)");
  if (value < 0) {
    const long long resolved = so_far + value;
    if (resolved < 0)
      fail(where + what + " " + std::to_string(value) + " out of range (" + std::to_string(so_far) + " " + elements +
           " so far)");
    return static_cast<int>(resolved);
  }
  if (value > std::numeric_limits<int>::max()) fail(where + what + " " + std::to_string(value) + " out of range");
  return static_cast<int>(value - 1);
}

// The vertex part of `a`, `a/t`, `a//n` or `a/t/n`, resolved to a 0-based index. Positive indices may
// point past the vertices read so far (checked at the end); negative ones count back from the last.
int parseFaceIndex(std::string_view token, int vertices_so_far, const std::string& where) {
  return resolveObjIndex(token.substr(0, token.find('/')), token, vertices_so_far, where, "face index", "vertices");
}

// The texture part `t` of `a/t` or `a/t/n`, 0-based; nullopt for `a` and `a//n`.
std::optional<int> parseTexCoordIndex(std::string_view token, int texcoords_so_far, const std::string& where) {
  const size_t slash = token.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  const std::string_view rest = token.substr(slash + 1);
  const std::string_view text = rest.substr(0, rest.find('/'));
  if (text.empty()) return std::nullopt;
  return resolveObjIndex(text, token, texcoords_so_far, where, "texture coordinate index", "texture coordinates");
}

// What the OBJ reader carries from line to line.
struct ObjState {
  std::filesystem::path folder;  // the OBJ's, where its MTL files are
  std::vector<std::string_view> tokens;
  std::vector<int> polygon, polygon_texcoords;
  bool all_textured = true;  // every face so far gave a texture coordinate at every corner
  int material = -1;         // the last usemtl's, -1 before any
  bool named_material = false;
};

// The index of the material called `name` in `materials`, added (with no statements) when new.
int materialNamed(std::vector<Material>& materials, const std::string& name) {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return static_cast<int>(i);
  materials.push_back(Material{name, {}});
  return static_cast<int>(materials.size()) - 1;
}

bool isMapStatement(std::string_view keyword) {
  return keyword.substr(0, 4) == "map_" || keyword == "bump" || keyword == "disp" || keyword == "decal" ||
         keyword == "refl" || keyword == "norm";
}

// One MTL statement as written back: its tokens joined by single spaces, a texture map's path (its last
// token) made absolute against the MTL file's folder.
std::string mtlStatement(const std::vector<std::string_view>& tokens, const std::filesystem::path& folder) {
  std::string statement;
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    std::string token(tokens[k]);
    if (k + 1 == tokens.size() && k > 0 && isMapStatement(tokens[0])) {
      const std::filesystem::path map(token);
      if (map.is_relative()) token = (folder / map).lexically_normal().string();
    }
    if (k > 0) statement += ' ';
    statement += token;
  }
  return statement;
}

// The materials an MTL file defines, merged into `materials` by name; a file that cannot be opened, is not
// a regular file (a device, a folder) or is over kMaxMtlBytes adds nothing (the OBJ still loads, its
// materials named only).
constexpr std::uintmax_t kMaxMtlBytes = 16u << 20;

void readMtl(const std::filesystem::path& path, std::vector<Material>& materials) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error) || std::filesystem::file_size(path, error) > kMaxMtlBytes || error)
    return;
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  std::string line;
  std::vector<std::string_view> tokens;
  int current = -1;
  while (std::getline(in, line)) {
    splitTokens(std::string_view(line).substr(0, line.find('#')), tokens);
    if (tokens.empty()) continue;
    if (tokens[0] == "newmtl") {
      current = tokens.size() > 1 ? materialNamed(materials, std::string(tokens[1])) : -1;
      if (current >= 0) materials[static_cast<std::size_t>(current)].statements.clear();
    } else if (current >= 0) {
      materials[static_cast<std::size_t>(current)].statements.push_back(mtlStatement(tokens, path.parent_path()));
    }
  }
}

void parseVertex(const std::vector<std::string_view>& tokens, double scale, int line, RawMesh& raw) {
  const std::string where = raw.at(line);
  if (tokens.size() < 4) fail(where + "expected 3 coordinates, got " + std::to_string(tokens.size() - 1));
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) p[a] = parseCoordinate(tokens[static_cast<size_t>(a + 1)], where);
  raw.addPoint(p, scale, line);
}

void parseTexCoord(const std::vector<std::string_view>& tokens, int line, RawMesh& raw) {
  const std::string where = raw.at(line);
  if (tokens.size() < 3 || tokens.size() > 4)
    fail(where + "expected 2 texture coordinates (and an optional w), got " + std::to_string(tokens.size() - 1));
  raw.texcoords.emplace_back(parseCoordinate(tokens[1], where), parseCoordinate(tokens[2], where));
}

void parseFace(int line, RawMesh& raw, ObjState& state) {
  const auto& tokens = state.tokens;
  const std::string where = raw.at(line);
  if (tokens.size() < 4) fail(where + "a face needs at least 3 vertices, got " + std::to_string(tokens.size() - 1));
  const int so_far = static_cast<int>(raw.points.size());
  const int texcoords_so_far = static_cast<int>(raw.texcoords.size());
  state.polygon.clear();
  state.polygon_texcoords.clear();
  for (size_t k = 1; k < tokens.size(); ++k) {
    state.polygon.push_back(parseFaceIndex(tokens[k], so_far, where));
    if (const std::optional<int> t = parseTexCoordIndex(tokens[k], texcoords_so_far, where))
      state.polygon_texcoords.push_back(*t);
  }
  raw.addPolygon(state.polygon, line);
  state.all_textured = state.all_textured && state.polygon_texcoords.size() == state.polygon.size();
  if (state.all_textured) raw.addPolygonTexCoords(state.polygon_texcoords);
  raw.triangle_materials.insert(raw.triangle_materials.end(), state.polygon.size() - 2, state.material);
}

// `mtllib a.mtl b.mtl`: each file's materials; `usemtl name`: the material of the faces that follow.
void parseMaterialStatement(RawMesh& raw, ObjState& state) {
  const auto& tokens = state.tokens;
  if (tokens[0] == "mtllib") {
    for (std::size_t k = 1; k < tokens.size(); ++k) readMtl(state.folder / std::string(tokens[k]), raw.materials);
  } else if (tokens.size() > 1) {
    state.material = materialNamed(raw.materials, std::string(tokens[1]));
    state.named_material = true;
  }
}

// After the last line: without a usemtl, no materials; with, the faces before the first get "default".
void finishMaterials(RawMesh& raw, const ObjState& state) {
  if (!state.named_material) {
    raw.materials.clear();
    raw.triangle_materials.clear();
    return;
  }
  for (int& m : raw.triangle_materials)
    if (m < 0) m = materialNamed(raw.materials, "default");
}

bool ignoredStatement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 5> kIgnored = {"vn", "vp", "g", "o", "s"};
  return std::find(kIgnored.begin(), kIgnored.end(), keyword) != kIgnored.end();
}

void parseObjLine(std::string_view line, double scale, int number, RawMesh& raw, ObjState& state) {
  line = line.substr(0, line.find('#'));
  splitTokens(line, state.tokens);
  const auto& tokens = state.tokens;
  if (tokens.empty() || ignoredStatement(tokens[0])) return;
  if (tokens[0] == "v") return parseVertex(tokens, scale, number, raw);
  if (tokens[0] == "vt") return parseTexCoord(tokens, number, raw);
  if (tokens[0] == "f") return parseFace(number, raw, state);
  if (tokens[0] == "mtllib" || tokens[0] == "usemtl") return parseMaterialStatement(raw, state);
  fail(raw.at(number) + "unsupported OBJ statement '" + std::string(tokens[0]) + "'");
}

void checkIndexRange(const RawMesh& raw) {
  const int n = static_cast<int>(raw.points.size());
  for (size_t t = 0; t < raw.triangles.size(); ++t)
    for (int v : raw.triangles[t])
      if (v >= n)
        fail(raw.faceAt(static_cast<int>(t)) + "face index " + std::to_string(v + 1) + " out of range (" +
             std::to_string(n) + " vertices)");
  const int nt = static_cast<int>(raw.texcoords.size());
  for (size_t t = 0; t < raw.triangle_texcoords.size(); ++t)
    for (int i : raw.triangle_texcoords[t])
      if (i >= nt)
        fail(raw.faceAt(static_cast<int>(t)) + "texture coordinate index " + std::to_string(i + 1) + " out of range (" +
             std::to_string(nt) + " texture coordinates)");
}

RawMesh readObj(const std::filesystem::path& path, double scale) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  RawMesh raw;
  raw.file = path.string();
  std::string line;
  ObjState state;
  state.folder = path.parent_path();
  for (int number = 1; std::getline(in, line); ++number) parseObjLine(line, scale, number, raw, state);
  if (in.bad()) fail(raw.file + ": read error");
  if (!state.all_textured) raw.triangle_texcoords.clear();  // some face gave none: the mesh has none
  finishMaterials(raw, state);
  checkIndexRange(raw);
  return raw;
}

// Each face's corners (built from raw.triangles in order: face t is FaceHandle t) take their coordinates.
void setTexCoords(const RawMesh& raw, SurfaceMesh& surface) {
  surface.addTexCoords();
  TriMesh& mesh = surface.mesh();
  for (size_t t = 0; t < raw.triangles.size(); ++t) {
    const FaceHandle f(static_cast<int>(t));
    for (const auto h : mesh.fh_range(f)) {
      const int v = mesh.to_vertex_handle(h).idx();
      for (size_t c = 0; c < 3; ++c)
        if (raw.triangles[t][c] == v) {
          const Eigen::Vector2d& uv = raw.texcoords[static_cast<size_t>(raw.triangle_texcoords[t][c])];
          mesh.property(surface.texCoordProperty(), h) = OpenMesh::Vec2d(uv.x(), uv.y());
        }
    }
  }
}

SurfaceMesh buildMesh(const RawMesh& raw) {
  SurfaceMesh surface;
  TriMesh& mesh = surface.mesh();
  mesh.reserve(raw.points.size(), 3 * raw.triangles.size() / 2, raw.triangles.size());
  for (const Eigen::Vector3d& p : raw.points) mesh.add_vertex(toOpenMesh(p));
  for (size_t t = 0; t < raw.triangles.size(); ++t) {
    const auto [a, b, c] = raw.triangles[t];
    const FaceHandle f = mesh.add_face(VertexHandle(a), VertexHandle(b), VertexHandle(c));
    if (!f.is_valid()) fail(raw.faceAt(static_cast<int>(t)) + "OpenMesh rejected face " + std::to_string(t));
  }
  if (!raw.triangle_texcoords.empty()) setTexCoords(raw, surface);
  if (!raw.triangle_materials.empty()) {
    for (const Material& material : raw.materials) surface.addMaterial(material);
    for (size_t t = 0; t < raw.triangle_materials.size(); ++t)
      mesh.property(surface.materialProperty(), FaceHandle(static_cast<int>(t))) = raw.triangle_materials[t];
  }
  mesh.update_normals();
  return surface;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

RawMesh readRaw(const std::filesystem::path& path, const std::string& ext, double scale) {
  if (ext == ".obj") return readObj(path, scale);
  if (ext == ".off") return detail::readOff(path, scale);
  if (ext == ".stl") return detail::readStl(path, scale);
  if (ext == ".ply") return detail::readPly(path, scale);
  fail(path.string() + ": unsupported mesh format '" + ext + "' (obj, ply, off, stl)");
}

// ---------------------------------------------------------------------------------------------------------
// Saving

// New 0-based indices of non-deleted vertices (-1 for deleted ones), in handle order. Throws for a
// non-finite position before anything is written.
std::vector<int> compactVertices(const TriMesh& mesh, const std::filesystem::path& path) {
  std::vector<int> index(mesh.n_vertices(), -1);
  int next = 0;
  for (const VertexHandle v : mesh.vertices()) {
    if (!toEigen(mesh.point(v)).allFinite())
      fail("cannot save " + path.string() + ": vertex " + std::to_string(v.idx()) + " has a non-finite position");
    index[static_cast<size_t>(v.idx())] = next++;
  }
  return index;
}

void writeFaceVertices(core::AtomicFile& out, const TriMesh& mesh, FaceHandle f, const std::vector<int>& index,
                       int base) {
  for (const VertexHandle v : mesh.fv_range(f)) {
    out << ' ' << index[static_cast<size_t>(v.idx())] + base;
  }
}

// The OBJ groups, in file order: tissue (original and split faces), then wall.
enum class ObjGroup { Tissue, Wall };

bool inGroup(const SurfaceMesh& surface, FaceHandle f, ObjGroup group) {
  return (surface.kind(f) == FaceKind::Wall) == (group == ObjGroup::Wall);
}

// The distinct corner texture coordinates in the order the written faces first use them, and each
// halfedge's index among them (-1: no face, or a face not written).
struct ObjTexCoords {
  std::vector<OpenMesh::Vec2d> values;
  std::vector<int> of_halfedge;
};

ObjTexCoords objTexCoords(const SurfaceMesh& surface) {
  const TriMesh& mesh = surface.mesh();
  ObjTexCoords result;
  result.of_halfedge.assign(mesh.n_halfedges(), -1);
  std::map<std::pair<double, double>, int> seen;
  for (const ObjGroup group : {ObjGroup::Tissue, ObjGroup::Wall})
    for (const FaceHandle f : mesh.faces()) {
      if (!inGroup(surface, f, group)) continue;
      for (const auto h : mesh.fh_range(f)) {
        const OpenMesh::Vec2d& uv = mesh.property(surface.texCoordProperty(), h);
        const auto [it, added] = seen.try_emplace({uv[0], uv[1]}, static_cast<int>(result.values.size()));
        if (added) result.values.push_back(uv);
        result.of_halfedge[static_cast<size_t>(h.idx())] = it->second;
      }
    }
  return result;
}

// The material statement before face f, when the mesh has materials: the wall's once at the wall group's
// start, a tissue face's when it differs from the face written before it (`last`).
void writeUseMaterial(core::AtomicFile& out, const SurfaceMesh& surface, FaceHandle f, ObjGroup group, int& last) {
  if (!surface.hasMaterials()) return;
  const int material = group == ObjGroup::Wall ? -2 : surface.material(f);
  if (material == last) return;
  last = material;
  out << "usemtl "
      << (material >= 0 ? surface.materials()[static_cast<size_t>(material)].name : std::string(kWallMaterialName))
      << '\n';
}

void writeObjGroup(core::AtomicFile& out, const SurfaceMesh& surface, const std::vector<int>& index,
                   const ObjTexCoords* texcoords, ObjGroup group) {
  const TriMesh& mesh = surface.mesh();
  bool header = false;
  int last_material = -3;
  for (const FaceHandle f : mesh.faces()) {
    if (!inGroup(surface, f, group)) continue;
    if (!header) out << (group == ObjGroup::Wall ? "g wall\n" : "g tissue\n");
    header = true;
    writeUseMaterial(out, surface, f, group, last_material);
    out << 'f';
    if (texcoords == nullptr) {
      writeFaceVertices(out, mesh, f, index, 1);
    } else {
      // Corner by corner from the face's halfedge, as faceCorners and fv_range go.
      for (const auto h : mesh.fh_range(f))
        out << ' ' << index[static_cast<size_t>(mesh.to_vertex_handle(h).idx())] + 1 << '/'
            << texcoords->of_halfedge[static_cast<size_t>(h.idx())] + 1;
    }
    out << '\n';
  }
}

void writePoint(core::AtomicFile& out, const OpenMesh::Vec3d& p) {
  for (int a = 0; a < 3; ++a) {
    if (a > 0) out << ' ';
    out.number17(p[a]);
  }
}

void writePlyHeader(core::AtomicFile& out, const TriMesh& mesh, bool texcoords) {
  out << "ply\nformat ascii 1.0\ncomment incise surface mesh; vertex kind 0 original, 1 seam, 2 wall; "
         "face kind 0 original, 1 split, 2 wall\nelement vertex "
      << countOf(mesh.vertices())
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar kind\nelement face "
      << countOf(mesh.faces()) << "\nproperty list uchar int vertex_indices\nproperty uchar kind\n"
      << (texcoords ? "property list uchar double texcoord\n" : "") << "end_header\n";
}

}  // namespace

SurfaceMesh loadSurfaceMesh(const std::filesystem::path& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0)
    throw std::invalid_argument("loadSurfaceMesh: scale must be finite and > 0, got " + core::formatNumber(scale));
  const RawMesh raw = readRaw(path, lowerExtension(path), scale);
  detail::checkTriangles(raw);
  return buildMesh(raw);
}

// The MTL file beside an OBJ: the mesh's materials as read, then the walls' (unless the mesh has it).
void saveMtl(const SurfaceMesh& surface, const std::filesystem::path& path) {
  core::rethrowFileErrorAs<MeshError>([&] {
    core::AtomicFile out(path);
    out << "# incise materials: the tissue's, then its walls' (" << kWallMaterialName << ")\n";
    bool wall = false;
    for (const Material& material : surface.materials()) {
      out << "\nnewmtl " << material.name << '\n';
      for (const std::string& statement : material.statements) out << statement << '\n';
      wall = wall || material.name == kWallMaterialName;
    }
    if (!wall)
      out << "\nnewmtl " << kWallMaterialName
          << "\n# the wound's walls: flesh\nKa 0.2 0.05 0.05\nKd 0.62 0.16 0.14\nKs 0.25 0.25 0.25\nNs 30\n"
          << (surface.hasTexCoords() ? std::string("map_Kd ") + kWallTextureFile + "\n" : std::string());
    if (!wall && surface.hasTexCoords()) {
      const std::span<const unsigned char> png = detail::wallTexturePng();
      core::writeFileAtomically(path.parent_path() / kWallTextureFile,
                                std::string(reinterpret_cast<const char*>(png.data()), png.size()));
    }
    out.commit();
  });
}

void saveObj(const SurfaceMesh& surface, const std::filesystem::path& path) {
  const TriMesh& mesh = surface.mesh();
  const std::vector<int> index = compactVertices(mesh, path);
  const std::filesystem::path mtl = std::filesystem::path(path).replace_extension(".mtl");
  if (surface.hasMaterials()) saveMtl(surface, mtl);
  core::rethrowFileErrorAs<MeshError>([&] {
    core::AtomicFile out(path);
    out << "# incise surface mesh: groups tissue (original and split faces) and wall\n";
    if (surface.hasMaterials()) out << "mtllib " << mtl.filename().string() << '\n';
    for (const VertexHandle v : mesh.vertices()) {
      out << "v ";
      writePoint(out, mesh.point(v));
      out << '\n';
    }
    std::optional<ObjTexCoords> texcoords;
    if (surface.hasTexCoords()) texcoords = objTexCoords(surface);
    if (texcoords)
      for (const OpenMesh::Vec2d& uv : texcoords->values) {
        out << "vt ";
        out.number17(uv[0]);
        out << ' ';
        out.number17(uv[1]);
        out << '\n';
      }
    writeObjGroup(out, surface, index, texcoords ? &*texcoords : nullptr, ObjGroup::Tissue);
    writeObjGroup(out, surface, index, texcoords ? &*texcoords : nullptr, ObjGroup::Wall);
    out.commit();
  });
}

void savePly(const SurfaceMesh& surface, const std::filesystem::path& path) {
  const TriMesh& mesh = surface.mesh();
  const std::vector<int> index = compactVertices(mesh, path);
  core::rethrowFileErrorAs<MeshError>([&] {
    core::AtomicFile out(path);
    writePlyHeader(out, mesh, surface.hasTexCoords());
    for (const VertexHandle v : mesh.vertices()) {
      writePoint(out, mesh.point(v));
      out << ' ' << static_cast<int>(surface.kind(v)) << '\n';
    }
    for (const FaceHandle f : mesh.faces()) {
      out << static_cast<long long>(mesh.valence(f));
      writeFaceVertices(out, mesh, f, index, 0);
      out << ' ' << static_cast<int>(surface.kind(f));
      if (surface.hasTexCoords()) {
        out << ' ' << 2 * static_cast<long long>(mesh.valence(f));
        for (const auto h : mesh.fh_range(f)) {  // the corners in fv_range's order, as the indices
          const OpenMesh::Vec2d& uv = mesh.property(surface.texCoordProperty(), h);
          out << ' ';
          out.number17(uv[0]);
          out << ' ';
          out.number17(uv[1]);
        }
      }
      out << '\n';
    }
    out.commit();
  });
}

}  // namespace incise::mesh
