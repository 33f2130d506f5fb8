// A reader's copy of the tissue surface (and, with a tet tissue, of its tets: tets()), rebuilt from a GeometryStream (geometry_stream.h): positions,
// faces and kinds as plain arrays, indexed as the sim's mesh is, and the elements each pull() changed, so
// that a viewer updates only those (its GPU buffers, its smooth normals).
//
// The first pull() asks the stream for a full re-sync; records before the Reset that answers it are
// ignored (they describe a state this copy never had). After that every record is applied in order; at a
// Frame record the copy is the mesh as of that frame (exact() when the Frame said so), except for elements
// the writer has not sent yet (backlog()). complete() once every element has arrived since the last Reset:
// before that the copy is a partial mesh, which a viewer should not draw.
//
// Shapes: positions_m()[v] (metres, the sim's doubles bit for bit), faces()[f] (vertex indices,
// counter-clockwise from outside), face_kind()[f] (mesh::FaceKind, or kDeletedFace), vertex_kind()[v],
// faceTexCoords()[f] (a textured tissue's: u, v per corner) and faceMaterial()[f] (its material's index,
// kNoMaterial for none).
// Threads: one reader thread (the one that calls GeometryStream::read). Cost: O(records) per pull; the
// arrays grow with the mesh (amortised). Failure: nothing throws but std::bad_alloc.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "incise/sim/geometry_stream.h"
#include "incise/sim/tet_mirror.h"

namespace incise::sim {

class GeometryMirror {
 public:
  // Reads up to `max_records` records from `stream` and applies them. Returns how many were read.
  std::size_t pull(GeometryStream& stream, std::size_t max_records = SIZE_MAX);
  void apply(const GeometryRecord& record);
  // Forget the copy and ask the stream for a full re-sync (at the next pull).
  void restart() noexcept { requested_ = false, started_ = false; }

  const std::vector<std::array<double, 3>>& positions_m() const noexcept { return positions_m_; }
  const std::vector<std::array<std::int32_t, 3>>& faces() const noexcept { return faces_; }
  const std::vector<std::uint8_t>& faceKind() const noexcept { return face_kind_; }
  const std::vector<std::uint8_t>& vertexKind() const noexcept { return vertex_kind_; }
  // A textured tissue's corners' texture coordinates per face (u, v per corner, faces()' order, floats);
  // empty until the first FaceTexCoords record since the last Reset (a tissue without them: always).
  const std::vector<std::array<float, 6>>& faceTexCoords() const noexcept { return face_texcoords_; }
  // As faceTexCoords: empty until the first FaceTexCoords record since the last Reset.
  const std::vector<std::uint8_t>& faceMaterial() const noexcept { return face_material_; }

  std::int64_t frame() const noexcept { return frame_; }  // of the last Frame record; -1 before one
  bool complete() const noexcept { return (flags_ & kFrameComplete) != 0; }
  bool exact() const noexcept { return (flags_ & kFrameExact) != 0; }
  std::uint32_t backlog() const noexcept { return backlog_; }
  std::int64_t resets() const noexcept { return resets_; }
  std::size_t liveFaces() const noexcept;  // faces not deleted; O(F)
  // The tet tissue's working mesh and boundary (empty, !present(), without one).
  const TetMirror& tets() const noexcept { return tets_; }

  // What changed since the last clearChanges(): everything after a Reset (rebuilt()), else these lists
  // (each index once).
  bool rebuilt() const noexcept { return rebuilt_; }
  const std::vector<std::uint32_t>& changedVertices() const noexcept { return changed_vertices_; }
  const std::vector<std::uint32_t>& changedFaces() const noexcept { return changed_faces_; }
  void clearChanges() noexcept;

 private:
  void touch(std::vector<std::uint8_t>& flags, std::vector<std::uint32_t>& list, std::uint32_t index);

  std::vector<std::array<double, 3>> positions_m_;
  std::vector<std::array<std::int32_t, 3>> faces_;
  std::vector<std::uint8_t> face_kind_, vertex_kind_;
  std::vector<std::array<float, 6>> face_texcoords_;
  std::vector<std::uint8_t> face_material_;
  std::vector<std::uint8_t> vertex_changed_, face_changed_;
  std::vector<std::uint32_t> changed_vertices_, changed_faces_;
  bool requested_ = false, started_ = false, rebuilt_ = false;
  std::int64_t frame_ = -1, resets_ = 0;
  std::uint8_t flags_ = 0;
  std::uint32_t backlog_ = 0;
  TetMirror tets_;
};

// The world's mesh as it is now, into `mirror` (which ends exact), through a stream of its own written and
// read on this thread: for pictures after a run. Not during a run (the sim thread owns the world then).
// Leaves the world's change journal off. Allocates (a 2 MiB ring). O(V + F).
void copyGeometry(World& world, std::int64_t frame, GeometryMirror& mirror);
// The same, with a simulated tissue's surface as simulated (TissuePhysics::deformedSurface: each vertex at
// its tet's deformed position; the faces and kinds as at rest) and its tets' nodes as simulated. After the physics thread
// has stopped; the rest surface when it runs or the tissue is not simulated. O(V x tets near a vertex).
void copySimulatedGeometry(World& world, std::int64_t frame, GeometryMirror& mirror);

}  // namespace incise::sim
