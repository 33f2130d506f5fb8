// The tissue as the viewer draws it, kept up to date from a GeometryMirror (sim/geometry_mirror.h), or a
// tet tissue's boundary from its TetMirror (sim/tet_mirror.h): float
// positions, smooth normals and one triangle per face index (a deleted face is the degenerate 0, 0, 0),
// with the face kinds that colour the wound's walls apart from the skin. Only what changed is redone: a
// moved vertex re-normalises the vertices of its faces, a changed face those of its old and new vertices.
//
// Normals are area-weighted averages over the vertex's skin faces (Original and Split): the walls are drawn
// flat (their normal from the triangle itself), so a lip vertex shared by skin and wall keeps the skin's
// smooth shading. A vertex with no skin face has a zero normal.
// Shapes: positions() and normals() 3 floats per vertex (metres; unit vectors), indices() 3 per face,
// faceKinds() 1 per face (mesh::FaceKind, or sim::kDeletedFace), faceTexCoords() 6 per face (u, v per corner,
// in indices()' order) and faceMaterials() 1 per face (the material's index, sim::kNoMaterial for none)
// for a textured tissue's surface, else empty. Threads: one (the viewer's). Cost:
// update() O(V + F) after a reset, else O(changed elements x their neighbourhoods); allocates as the mesh
// grows. Failure: nothing throws but std::bad_alloc.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/sim/geometry_mirror.h"
#include "incise/sim/tissue_physics.h"
#include "incise/viewer/skin_embedding.h"

namespace incise::viewer {

class SurfaceModel {
 public:
  // Takes the mirror's changes (call after GeometryMirror::pull and before its clearChanges()). Does nothing
  // and returns false while the mirror is not complete (a partial mesh is not drawn).
  bool update(const sim::GeometryMirror& mirror);
  // The tet mesh's boundary instead (sim::TetMirror: its cut faces drawn as walls), rebuilt whole when the
  // tets changed since the last call (O(boundary), so a viewer calls it a few times a second at most).
  // Does nothing and returns false while the tets are not complete or have not changed.
  bool update(const sim::TetMirror& tets);
  // The same boundary as simulated: every node below state.nodes at its position in `state` (a simulated
  // tissue's node positions after a physics step, sim::TissuePhysics::latestState; indexed as the tets'
  // nodes), the others where the mirror has them. Rebuilt whole when the tets or the state's step changed
  // (O(boundary) at most once a physics step: a viewer calls it every display frame).
  bool update(const sim::TetMirror& tets, const sim::PhysicsState& state);
  // The mirror's surface as simulated: its faces and kinds, each vertex where `skin` (embedded in the
  // mirror's tets) puts it at `state`'s node positions. Rebuilt whole when the state's step or the
  // embedding changed (O(V + F) at most once a physics step: faces the cut changed without a new vertex
  // show at the next step). Does nothing and returns false while the mirror is not complete or nothing
  // changed.
  bool update(const sim::GeometryMirror& mirror, const SkinEmbedding& skin, const sim::PhysicsState& state);
  // Everything is to be uploaded again (a renderer that drew another model meanwhile).
  void markAllDirty() noexcept { dirty_.all = true; }

  const std::vector<float>& positions() const noexcept { return positions_; }
  const std::vector<float>& normals() const noexcept { return normals_; }
  const std::vector<std::uint32_t>& indices() const noexcept { return indices_; }
  const std::vector<std::uint8_t>& faceKinds() const noexcept { return kinds_; }
  const std::vector<float>& faceTexCoords() const noexcept { return texcoords_; }
  const std::vector<std::uint8_t>& faceMaterials() const noexcept { return materials_; }
  bool textured() const noexcept { return !texcoords_.empty(); }
  std::size_t vertexCount() const noexcept { return positions_.size() / 3; }
  std::size_t faceCount() const noexcept { return kinds_.size(); }
  std::size_t liveFaces() const noexcept { return live_faces_; }
  std::size_t wallFaces() const noexcept { return wall_faces_; }
  bool ready() const noexcept { return ready_; }

  // What changed since the last takeDirty(): everything (all), or sorted vertex indices whose position or
  // normal changed and sorted face indices whose triangle, kind or texture coordinates changed. For the GPU
  // upload.
  struct Dirty {
    bool all = false;
    std::vector<std::uint32_t> vertices, faces;
  };
  const Dirty& dirty() const noexcept { return dirty_; }
  void clearDirty();

  // The skin normal of the vertex nearest `p_m` (zero without vertices). O(V).
  Eigen::Vector3d normalNear(const Eigen::Vector3d& p_m) const;
  // The bounding box of the live vertices. O(V).
  Eigen::AlignedBox3d bounds() const;

 private:
  // update(tets) and update(tets, state): the boundary, its nodes where `state` (if any) has them.
  bool updateTets(const sim::TetMirror& tets, const sim::PhysicsState* state);
  void rebuild(const std::vector<std::array<double, 3>>& positions_m,
               const std::vector<std::array<std::int32_t, 3>>& faces, const std::vector<std::uint8_t>& kinds);
  void setFace(std::uint32_t f, const std::array<std::int32_t, 3>& t, std::uint8_t kind);
  // The mirror's texture coordinates and material of face `f` (zeros and none where it has none yet); all
  // faces: copyTexCoords(m).
  void copyTexCoords(const sim::GeometryMirror& mirror, std::uint32_t f);
  void copyTexCoords(const sim::GeometryMirror& mirror);
  void recomputeNormal(std::uint32_t v);
  void markNormal(std::uint32_t v);

  std::vector<double> positions_m_;  // the mirror's doubles, for the normals' cross products
  std::vector<float> positions_, normals_;
  std::vector<std::uint32_t> indices_;
  std::vector<std::uint8_t> kinds_;
  std::vector<float> texcoords_;
  std::vector<std::uint8_t> materials_;
  std::vector<std::vector<std::uint32_t>> vertex_faces_;
  std::vector<std::uint8_t> normal_dirty_, vertex_dirty_, face_dirty_;
  std::vector<std::uint32_t> normal_list_;
  Dirty dirty_;
  std::size_t live_faces_ = 0, wall_faces_ = 0;
  bool ready_ = false;
  std::uint64_t tets_version_ = 0;
  std::int64_t state_step_ = -1;  // the physics state drawn (update(tets, state)); -1: none
  // What update(mirror, skin, state) drew: the mirror's resets, the embedding's version.
  bool skin_drawn_ = false;
  std::int64_t skin_resets_ = -1;
  std::uint64_t skin_version_ = 0;
  std::vector<std::array<double, 3>> skin_m_;
};

}  // namespace incise::viewer
