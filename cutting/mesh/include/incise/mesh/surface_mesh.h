// The tissue surface: a closed, consistently oriented triangle mesh (OpenMesh TriMesh) that the incision
// code cuts. Every vertex and face carries a kind, so a cut's lips (Seam vertices, Split faces) and walls
// (Wall vertices and faces) stay recognisable for drawing and checking. Plus OBJ/OFF/STL/PLY input, OBJ/PLY output, a
// closed-two-manifold check, a JSON summary and Loop subdivision (to make large test meshes).
//
// Shapes: triangles only; handles are OpenMesh handles into mesh(); face and vertex indices in messages of
// checkManifold are 0-based handle indices. Loader messages give vertex numbers as the file does (1-based
// for OBJ, 0-based for PLY/OFF/STL; each message says which) and faces as "face i" (0-based index in the
// triangulated face list, which is the loaded mesh's FaceHandle index) plus the file:line (or byte) it came from.
// Units: positions in metres in incise (the loader's `scale` converts, e.g. 0.001 for a file in mm).
// Threads: const members and free functions on distinct or const meshes may run concurrently (loading
// included); mutators need exclusive access.
// Failure: MeshError (a std::runtime_error naming the file and line, or the element) for bad files and
// I/O failures; std::invalid_argument for bad arguments (with the value); std::out_of_range for invalid
// handles. Loading, saving and checking allocate: not for the sim thread.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
// OpenMesh's VectorT default constructor leaves its elements uninitialised on purpose; GCC 12 then warns
// (-Wmaybe-uninitialized, reported through libstdc++ despite the system headers) when PropertyT::push_back
// copies one, in builds without -march=native. Silenced for OpenMesh's code only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace incise::mesh {

// Double-precision points and normals; status bits so the incision code can delete elements and
// garbage-collect later; face and vertex normals (filled by loadSurfaceMesh, then by
// mesh().update_normals()).
struct MeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge | OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// Seam: on a cut's lip, created by splitting an edge or duplicating a vertex. Wall: inside a cut's walls.
enum class VertexKind : std::uint8_t { Original = 0, Seam = 1, Wall = 2 };
// Split: a piece of an original face cut by the seam. Wall: inside the cut.
enum class FaceKind : std::uint8_t { Original = 0, Split = 1, Wall = 2 };

// "original", "seam", "wall" / "original", "split", "wall"; "unknown" for other values.
const char* toString(VertexKind kind) noexcept;
const char* toString(FaceKind kind) noexcept;

struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A material of the skin as an OBJ's MTL file defines it: its name and the statements after its `newmtl`
// line (comments and blank lines dropped; the path of a texture map, `map_Kd` and the like, made absolute
// against the MTL file's folder when it was read), written back as they are.
struct Material {
  std::string name;
  std::vector<std::string> statements;
  bool operator==(const Material&) const = default;
};
// The material saveObj gives the walls of a mesh with materials (a flesh colour), and, when the mesh has
// texture coordinates, its image: written beside the MTL under this name (scenarios/textures/flesh.png,
// compiled in: wallTexturePng).
inline constexpr const char* kWallMaterialName = "incise_wall";
inline constexpr const char* kWallTextureFile = "incise_flesh.png";
namespace detail {
std::span<const unsigned char> wallTexturePng();  // the PNG file's bytes
}

inline Eigen::Vector3d toEigen(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d toOpenMesh(const Eigen::Vector3d& p) { return {p[0], p[1], p[2]}; }

// A TriMesh plus per-vertex and per-face kinds, stored as OpenMesh properties named "incise:vertex_kind" and
// "incise:face_kind". Elements added through mesh() directly (add_vertex, split, ...) get Original, the
// value-initialised default. Copyable (the copy has its own properties) and movable.
class SurfaceMesh {
 public:
  SurfaceMesh();
  // Adopts `mesh`; keeps its kind properties if it has them (a TriMesh copied out of a SurfaceMesh), else
  // all elements are Original. Cost O(V + F) when the properties are added.
  explicit SurfaceMesh(TriMesh mesh);

  TriMesh& mesh() { return mesh_; }
  const TriMesh& mesh() const { return mesh_; }

  // Throw std::out_of_range for a handle that is invalid or beyond mesh()'s elements. O(1).
  VertexKind kind(TriMesh::VertexHandle v) const;
  void setKind(TriMesh::VertexHandle v, VertexKind kind);
  FaceKind kind(TriMesh::FaceHandle f) const;
  void setKind(TriMesh::FaceHandle f, FaceKind kind);

  // Adds a vertex at p with the kind. Throws std::invalid_argument for a non-finite p. O(1) amortised.
  TriMesh::VertexHandle addVertex(const Eigen::Vector3d& p, VertexKind kind = VertexKind::Original);
  // Adds the triangle (v0, v1, v2), counter-clockwise seen from outside, with the kind. Throws
  // std::out_of_range for bad handles and MeshError when OpenMesh refuses the face (repeated vertex,
  // complex edge or vertex: the face would make the mesh non-manifold); the mesh is then unchanged.
  TriMesh::FaceHandle addFace(TriMesh::VertexHandle v0, TriMesh::VertexHandle v1, TriMesh::VertexHandle v2,
                              FaceKind kind = FaceKind::Original);

  // Texture coordinates, per face corner: a halfedge's is the coordinate of its to-vertex in its face, so a
  // vertex on a texture seam has one per side. Stored as the OpenMesh halfedge property "incise:texcoord"
  // (OpenMesh::Vec2d, (u, v) as in OBJ's `vt`), present only on a mesh that has them: a mesh without them
  // carries nothing and costs nothing. addTexCoords adds the property (every corner (0, 0)); no-op when
  // present. texCoord/setTexCoord throw std::logic_error on a mesh without them and std::out_of_range for a
  // bad handle. O(1) (addTexCoords O(halfedges)).
  bool hasTexCoords() const noexcept { return texcoord_.is_valid(); }
  void addTexCoords();
  Eigen::Vector2d texCoord(TriMesh::HalfedgeHandle h) const;
  void setTexCoord(TriMesh::HalfedgeHandle h, const Eigen::Vector2d& uv);
  // The property itself, for code that walks many corners (invalid without texture coordinates).
  OpenMesh::HPropHandleT<OpenMesh::Vec2d> texCoordProperty() const noexcept { return texcoord_; }

  // Materials (OBJ `usemtl`): the list, stored as the OpenMesh mesh property "incise:materials" (so it
  // travels with every copy of the TriMesh), and each face's index into it, the face property
  // "incise:material"; present only on a mesh whose file named a material. addMaterial adds both properties
  // on first use (every face then has material 0) and returns the index of the material of that name (added
  // at the end when new; statements given replace empty ones). material(f) is -1 on a mesh without
  // materials; setMaterial throws std::out_of_range for a bad face or index. O(1) (addMaterial O(materials)).
  bool hasMaterials() const noexcept { return materials_.is_valid(); }
  const std::vector<Material>& materials() const noexcept;
  int addMaterial(const Material& material);
  int material(TriMesh::FaceHandle f) const;
  void setMaterial(TriMesh::FaceHandle f, int index);
  OpenMesh::FPropHandleT<int> materialProperty() const noexcept { return face_material_; }

 private:
  void attachKinds();

  TriMesh mesh_;
  OpenMesh::VPropHandleT<VertexKind> vertex_kind_;
  OpenMesh::FPropHandleT<FaceKind> face_kind_;
  OpenMesh::HPropHandleT<OpenMesh::Vec2d> texcoord_;         // invalid: no texture coordinates
  OpenMesh::MPropHandleT<std::vector<Material>> materials_;  // invalid: no materials
  OpenMesh::FPropHandleT<int> face_material_;
};

// Wall faces' texture coordinates are metres over this tile (a wall texture repeats every centimetre).
inline constexpr double kWallTextureTile_m = 0.01;

// The corners of face f as (vertex, texture coordinate) in the face's order (counter-clockwise from the
// halfedge OpenMesh stores for it). Requires mesh.hasTexCoords(). O(1).
struct FaceCorners {
  std::array<TriMesh::VertexHandle, 3> vertex;
  std::array<Eigen::Vector2d, 3> uv;
  // The coordinate of v in this face; nullopt if v is not a corner.
  std::optional<Eigen::Vector2d> at(TriMesh::VertexHandle v) const noexcept;
};
FaceCorners faceCorners(const SurfaceMesh& mesh, TriMesh::FaceHandle f);

// The texture coordinate of point p in the triangle with corners x and corner coordinates uv: p projected
// on the triangle's plane, barycentric there (uv[0] for a degenerate triangle). O(1).
Eigen::Vector2d interpolateTexCoord(const std::array<Eigen::Vector3d, 3>& x, const std::array<Eigen::Vector2d, 3>& uv,
                                    const Eigen::Vector3d& p);
// A wall or cap face's texture coordinates: its corners x projected on its own plane (axes from its normal
// and z, or x when the face is nearly horizontal), in metres over kWallTextureTile_m. O(1).
std::array<Eigen::Vector2d, 3> planarTexCoords(const std::array<Eigen::Vector3d, 3>& x);
// Texture coordinates made for a whole mesh (a scenario's "map": "box", for a tissue without its own):
// each face projected along the axis (x, y or z) its normal is nearest onto the other two, in metres over
// `tile_m`, so a tileable image repeats every tile_m on any side; a seam where neighbours choose different
// axes. Adds the property when missing, replaces every corner's. std::invalid_argument unless tile_m is
// finite and > 0. O(F).
void boxTexCoords(SurfaceMesh& mesh, double tile_m);

// Reads a closed, consistently oriented triangle mesh and multiplies positions by `scale` (finite, > 0,
// else std::invalid_argument). All kinds Original; normals computed.
// OBJ (by extension, case-insensitive) goes through incise's own parser: `v x y z` (a w or colour after
// the three coordinates is ignored), `f a b c ...` with `a`, `a/t`, `a//n`, `a/t/n` and negative (relative)
// indices, polygons fan-triangulated (a b c d -> a b c, a c d), `#` comments; `vt u v [w]` texture
// coordinates (w ignored): when every face gives one at every corner (`a/t`, `a/t/n`) the mesh has them
// (hasTexCoords), else (a face or a corner without) it has none; `mtllib a.mtl ...` reads each MTL file
// beside the OBJ (`newmtl` blocks; a file that cannot be opened, is not a regular file or is over 16 MiB
// is skipped: the materials keep their names only) and `usemtl name` gives the faces after it that material (hasMaterials; faces before the first
// `usemtl` get one named "default"); vn vp g o s ignored; any other statement is an error. Errors name file:line ("bunny.obj:1234: face index 9999 out of range (1839
// vertices)", "...: expected 3 coordinates", "...: coordinate 'abc' is not a number", "...: coordinate 'nan'
// is not finite", "...: texture coordinate index 7 out of range (4 texture coordinates)", "...: expected 2
// texture coordinates (and an optional w), got 1").
// The triangle list is then checked before the mesh is built (first failing check reported, in this
// order): index range; degenerate faces (repeated vertex or exactly zero area); unreferenced vertices;
// every undirected edge in exactly 2 faces ("non-manifold edge (a, b) shared by 3 faces", then
// "open surface: edge (a, b) has 1 face (face 17, file:line)"), with opposite orientations
// ("inconsistent orientation at edge (a, b)"); each vertex's faces form a single fan ("non-manifold
// vertex 42").
// OFF, STL and PLY go through incise's own readers too (CGAL's polygon-soup readers load the same files
// but only say true or false, with no line or byte), into the same checks, with vertex numbers 0-based:
// .off: text OFF, COFF, NOFF, CNOFF, STOFF (what follows x y z on a vertex line, or the indices on a face
// line — a colour — is ignored), `#` comments and blank lines anywhere, the counts on the keyword's line or
// the next; 4OFF, nOFF and binary OFF refused. .stl: binary when the size is exactly 84 + 50 * the count at
// byte 80 (even if the header begins with "solid"), ASCII when the text begins with "solid" and has no NUL
// byte; exactly equal positions welded (vertices numbered in order of first use). .ply: ascii,
// binary_little_endian, binary_big_endian; x y z of "vertex" (any numeric type) and the list
// "vertex_indices" (or "vertex_index") of "face" (any integer types); texture coordinates from the face's
// list "texcoord" (u v per corner), else from the vertex's "s" "t", "texture_u" "texture_v" or "u" "v"
// (one per vertex: no texture seam); other properties and elements ignored. Polygons of every format become fans from their first vertex (right for convex polygons).
// Errors name file:line for text ("bad.off:16: face 5 has index 12 but there are 8 vertices"), the byte
// offset for binary data ("x.ply: byte 463: the file ends inside face 1") or both sizes ("x.stl: binary STL
// declares 1200 triangles (60084 bytes) but the file has 5000 bytes"). Any input gives a mesh or a
// MeshError: a declared count is checked against the file's size before memory is reserved for it.
// Throws MeshError (missing or unreadable file, unknown extension, any check above). Cost O(n log n) plus
// the file's size in memory while it is read.
SurfaceMesh loadSurfaceMesh(const std::filesystem::path& path, double scale = 1.0);

struct ManifoldReport {
  bool closed_two_manifold;   // no problem of any kind below, and at least one face
  int boundary_edges;         // edges with a missing face on either side (isolated edges included)
  int non_manifold_vertices;  // faces around the vertex not one fan (the vertex's circulator misses faces
                              // that use it, or it has > 1 outgoing boundary halfedge), or isolated vertex
  int non_manifold_edges;     // extra edges joining an already joined vertex pair, or an edge whose two
                              // sides are the same face
  int euler_characteristic;   // V - E + F over non-deleted elements
  int components;             // connected components of the vertex-edge graph (non-deleted elements)
  std::string first_problem;  // the first problem found, with 0-based handle indices; empty when closed
  int degenerate_faces = 0;   // faces with a repeated vertex or exactly zero area
};

// Works on a mesh with deleted, not yet garbage-collected elements (they are skipped). A closed two-manifold
// of genus g has euler_characteristic 2 - 2g per component. Cost O(V + E log E + F).
ManifoldReport checkManifold(const TriMesh& mesh);

// Writes non-deleted vertices as `v x y z` (%.17g, which round-trips exactly; locale-independent), then
// faces as `f a b c` (1-based, re-indexed past deleted vertices) in two groups: `g tissue` (Original and
// Split faces) and `g wall` (Wall faces); an empty group is left out. A mesh with texture coordinates gets
// `vt u v` lines (each distinct corner coordinate once, in the order faces first use it) and faces
// `f a/t b/t c/t`. A mesh with materials gets `mtllib` naming an MTL file written beside it (path with the
// extension .mtl, written first, atomically too): its materials as read, then kWallMaterialName (a flesh
// colour; with texture coordinates also `map_Kd` kWallTextureFile, written beside it first) unless it has
// one; `usemtl` before each run of tissue faces of one material, and the wall group with kWallMaterialName. Kinds are not stored otherwise (use
// savePly). Writes path + ".tmp", then renames it to path: nothing half-written on failure. Same mesh ->
// same bytes. Throws MeshError naming the path on I/O failure (the .tmp is removed) or for a non-finite
// vertex position (nothing written). Cost O(V + F).
void saveObj(const SurfaceMesh& mesh, const std::filesystem::path& path);

// ASCII PLY: `element vertex` with double x y z and `uchar kind` (0 original, 1 seam, 2 wall), `element
// face` with `list uchar int vertex_indices` (0-based) and `uchar kind` (0 original, 1 split, 2 wall), and
// with texture coordinates `list uchar double texcoord` (u v per corner, in the indices' order: MeshLab's).
// Deleted elements skipped and re-indexed. Same atomic write, determinism and failures as saveObj.
void savePly(const SurfaceMesh& mesh, const std::filesystem::path& path);

struct MeshSummary {
  int vertices, faces;  // non-deleted
  int wall_faces, split_faces, seam_vertices, wall_vertices;
  int boundary_edges, euler_characteristic;
  bool closed_two_manifold;
  int self_intersections;  // pairs of faces that cross other than along what they share (findSelfIntersections)
};

// The mean and longest length of the non-deleted edges (metres; 0 and 0 without edges). Cost O(E).
struct EdgeLengths {
  double mean_m = 0.0;
  double longest_m = 0.0;
};
EdgeLengths edgeLengths(const TriMesh& mesh);

// Counts over non-deleted elements; manifold fields from checkManifold, self_intersections from
// findSelfIntersections on a closed two-manifold (-1 on any other mesh). Cost as both: O(F log F + pairs of
// overlapping boxes); allocates (not for the sim thread).
MeshSummary summarize(const SurfaceMesh& mesh);
// A JSON object with the field names as keys, pretty-printed with indent 2.
std::string toJson(const MeshSummary& summary);

// `iterations` rounds of Loop subdivision (OpenMesh's LoopT): each multiplies the face count by 4
// (3674 bunny triangles -> 58,784 after 2, 235,136 after 3, 940,544 after 4). Deleted elements are
// garbage-collected first; kinds and other custom properties of the input are not carried meaningfully.
// Throws std::invalid_argument for iterations < 0. Cost O(F * 4^iterations) time and memory.
TriMesh subdivideLoop(const TriMesh& mesh, int iterations);
// The same on a SurfaceMesh; every element of the result is Original. Materials are kept (each fine face
// its coarse face's). Texture coordinates, when the mesh has them, are subdivided linearly within each face (a new edge vertex takes the mean of its edge's two
// corners on each side, so a texture seam stays a seam; the positions are smoothed, the coordinates not, as
// modelling tools do with UV smoothing off).
SurfaceMesh subdivided(const SurfaceMesh& mesh, int iterations);

// Deletes the triangle f as OpenMesh's PolyConnectivity::delete_face(f, false) does (OpenMesh 9.0,
// src/OpenMesh/Core/Mesh/PolyConnectivity.cc, BSD-3-Clause, RWTH Aachen: the same steps in the same order,
// so the same connectivity), without its two std::vectors: allocation-free for the sim thread. The face's
// vertices stay, even when isolated. f must be a valid, undeleted triangle. O(1).
void deleteTriangle(TriMesh& m, TriMesh::FaceHandle f) noexcept;

}  // namespace incise::mesh
