// The surface cutter's options and per-call results (cutting/include/incise/cutting/surface_cutter.h), in
// a header without OpenMesh so that sim's public headers can hold them. Units: metres; counts per call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "incise/cutting/incision.h"

namespace incise::cutting {

// Where a stroke sample comes from: Unchecked, the cutter checks that it lies on the surface; OnSurface,
// the caller found it there (a contact query) and the check is skipped.
enum class SampleOrigin : std::uint8_t { Unchecked, OnSurface };
// When finish() does an incision's remaining work: Now (whatever the budget), or Later (in advance()).
enum class FinishWork : std::uint8_t { Now, Later };

struct CutterOptions {
  IncisionOptions incision;
  int wall_rows = 3;                 // vertices per wall column and side, the bottom included (>= 1)
  double contact_tolerance_m = 0.0;  // a sample farther than this from every vertex has left the surface;
                                     // 0 = 3 x the mesh's mean edge length
  // The per-call work budget, in point inversions (the dominant cost of a column step, about 1-2 us each):
  // a call stops there and the next one resumes, so a frame's cost stays bounded on dense meshes while the
  // cut trails a little more. 0 = no limit (finish everything that is final in each call). The resulting
  // mesh does not depend on it.
  int max_inversions_per_call = 0;
  // Degenerate coincidences (a vertex on the cut's plane or within rounding of it, a stroke along existing
  // edges or through vertices): a vertex inside the cut closer to u = 1/2 than snap_fraction times its
  // shortest edge is put on the cut (it becomes a seam vertex) instead of its edges being split next to it,
  // and no edge is split closer than that to an end point; so every piece of a split face keeps at least
  // that fraction of the face's area. In [0, 0.5); 0 = no snapping (splits at any crossing).
  double snap_fraction = 0.1;
};

// What one call did. Counts are for the call; totals live in CutStats.
struct CutStep {
  SampleStatus sample = SampleStatus::Accepted;
  bool left_surface = false;  // the sample was off the surface: the incision was finished
  bool failed = false;        // an internal topology failure stopped the incision (message in CutStats)
  int columns = 0;            // lattice columns processed
  int vertices_bound = 0;     // vertices parameterised
  int edges_split = 0;
  int vertices_duplicated = 0;
  int wall_faces = 0;      // wall faces (re)built
  int vertices_moved = 0;  // re-deformed
};

// What one incision made, for a user to check that the cut did what the scalpel did.
struct IncisionFigures {
  double stroke_length_m = 0.0;  // arc length of the stroke in contact: the incision's accepted samples
  double groove_length_m = 0.0;  // arc length, at rest, of the seam opened: the chain of seam vertices from
                                 // its start to its tip once one of them is duplicated; 0 while none is
};

// The mesh elements a cutter changed, for a reader that mirrors the mesh (sim's GeometryStream): indices
// (OpenMesh handle indices) of every vertex added or moved and of every face added, changed (its vertices
// or kind) or deleted, in the order of the changes; an index may repeat. Filled only while recording is on
// (SurfaceCutter::recordChanges); the consumer clears it. Vertices are never deleted by the cutter.
struct MeshChanges {
  std::vector<int> vertices;
  std::vector<int> faces;
  void clear() noexcept {
    vertices.clear();
    faces.clear();
  }
};

struct CutStats {
  int incisions = 0;
  int seam_vertices = 0;  // of the current incision's chain
  int edges_split = 0;    // totals over all incisions
  int vertices_duplicated = 0;
  int skipped_crossings = 0;  // crossing edges outside the cut window (not split)
  int vertices_snapped = 0;   // vertices put on the cut (CutterOptions::snap_fraction), totals
  int splits_avoided = 0;     // crossings not split because they lay within the snap distance of an end
  std::string failure;        // first internal failure, empty if none
  // One entry per incision, in order (the current one last). Room for kReservedIncisions is reserved at
  // construction: more incisions than that grow the vector once in a while (amortised).
  std::vector<IncisionFigures> figures;
  static constexpr std::size_t kReservedIncisions = 256;
};

}  // namespace incise::cutting
