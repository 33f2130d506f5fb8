// A simulated tissue's surface (skin and the wound's walls) as the viewer draws it: the GeometryMirror's
// vertices embedded in its TetMirror's tets at rest (physics::embedSurfaceVertex, surface_embedding.h: each
// on its own side of every cut, as `replay` embeds them for cut.obj), then evaluated at the node positions
// the physics publishes after every step (sim::PhysicsState). So the skin moves every physics step while
// the sim thread does nothing for it: the embedding is the reader's work.
//
// update() follows the mirror: when the tets changed (TetMirror::version) the locator takes the pieces of
// the base tets that changed (the old ones out, the new ones in; all of them after a reset) and every
// vertex whose embedding consulted a base tet whose pieces changed (physics::EmbedBases) is embedded again;
// a vertex new, moved at rest, or whose faces changed or neighbours moved (its probe beside it depends on
// them) is embedded when it is seen. Shapes: positions in metres, indexed as the mirror's vertices; node
// positions indexed as the tets' nodes. Threads: the viewer's (the one that pulls the mirror). Cost:
// update() O(V + F) to check, O(base tets) to find those whose pieces changed and O(their pieces) to update
// the locator (O(tets) to build it at the first update and after a reset), a few point locations
// per vertex embedded (milliseconds for thousands); positions() O(V). Failure: nothing throws but
// std::bad_alloc.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "incise/physics/embedding.h"
#include "incise/physics/surface_embedding.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/tissue_physics.h"

namespace incise::viewer {

class SkinEmbedding {
 public:
  // Brings the embedding up to date with `mirror` (its surface and tets() at rest). Does nothing and
  // returns false while the mirror or its tets are not complete; else true when a vertex's embedding
  // changed.
  bool update(const sim::GeometryMirror& mirror);
  // Every mirror vertex's position with the tets' nodes at `state`'s positions: a vertex embedded in a tet
  // whose nodes the state holds at its deformed position; one whose tet has nodes the state does not hold
  // yet (a cut the physics has not taken) at rest moved by the mean displacement of the nodes it holds; one
  // with no tet at rest (the mirror's).
  void positions(const sim::GeometryMirror& mirror, const sim::PhysicsState& state,
                 std::vector<std::array<double, 3>>& out_m) const;

  std::size_t embedded() const noexcept { return embedded_; }  // vertices in a tet
  std::size_t rebuilds() const noexcept { return rebuilds_; }  // locator builds and updates so far
  std::uint64_t version() const noexcept { return version_; }  // bumped by every update() that changed one
  // The vertex's tet and weights (nodes -1: none). v < the mirror's vertices at the last update.
  const physics::Embedded& vertex(std::size_t v) const { return vertices_[v]; }

 private:
  void rebuildLocator(const sim::TetMirror& tets);
  void adjacency(const sim::GeometryMirror& mirror);
  void embed(const sim::GeometryMirror& mirror, std::size_t v);

  physics::TetLocator locator_;
  std::vector<physics::Embedded> vertices_;
  std::vector<std::array<double, 3>> embedded_at_m_;  // the rest position each vertex was embedded at
  std::vector<std::uint8_t> tried_;                   // embedded (or tried: none within reach) at that position
  std::vector<physics::EmbedBases> bases_;            // the base tets each vertex's embedding consulted
  std::vector<std::uint64_t> base_hash_;              // per base tet, a hash of its pieces at the last build
  std::vector<std::uint8_t> base_changed_;            // ... and whether that build changed them
  std::vector<std::vector<int>> base_slots_;          // per base tet, its pieces' slots in the locator
  // A hash of each vertex's faces and their corners: when it was embedded, and now.
  std::vector<std::uint64_t> embedded_faces_, faces_now_;
  std::vector<std::uint64_t> face_hash_;  // per live face: its index, corners and their positions
  std::vector<std::uint32_t> face_offsets_, face_list_, face_fill_;  // each vertex's live faces
  std::vector<std::int32_t> neighbour_scratch_;
  std::vector<Eigen::Vector3d> scratch_m_;
  std::uint64_t tets_version_ = 0;
  std::int64_t tets_resets_ = -1;
  std::size_t embedded_ = 0, rebuilds_ = 0;
  std::uint64_t version_ = 0;
};

}  // namespace incise::viewer
