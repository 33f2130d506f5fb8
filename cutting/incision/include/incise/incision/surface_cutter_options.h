// The surface cutter's options and per-call results (cutting/incision/include/incise/incision/surface_cutter.h), in
// a header without OpenMesh so that sim's public headers can hold them. Units: metres; counts per call.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "incise/incision/incision.h"

namespace incise::incision {

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
  // Local refinement ahead of the cut (a tissue coarse next to the lattice: the 3-5 mm triangles of a
  // segmentation, a CAD export or a model library against a lattice 6 mm across): before a lattice column is
  // cut, every skin face whose bounding box at rest meets the column's control-point hull and whose longest
  // edge is longer than refineEdgeLength() is split by longest-edge bisection (Rivara's LEPP: the longest
  // edge of the face's longest-edge propagation path is halved, so both faces across it are halved along
  // their longest edge; conforming, no T-junction, angles bounded below by half the input's). Only where the
  // cut goes, grown with the stroke, under the same per-call budget (one unit a split). Off: a coarse mesh
  // is cut as it is, and the incision's figures say so (Shortfall::CoarseMesh).
  //   Linear       the new vertex is the edge's midpoint: the surface's shape is kept exactly (flat stays flat)
  //   PnTriangles  the midpoint of the edge's cubic in Vlachos et al.'s curved PN triangles (2001), from the
  //                end points' normals at rest: a coarse curved model gets rounder where it is refined (an
  //                edge with an end on a crease, a face around it over 30 degrees off its normal, is halved
  //                straight: a CAD model's flat faces stay flat)
  enum class Refine : std::uint8_t { Off, Linear, PnTriangles };
  Refine refine = Refine::Linear;
  double refine_edge_m = 0.0;               // longest edge kept (m); 0 = a quarter of the lattice's width
                                            // across the cut, (l - 1) alpha / 4 (1.5 mm by default), so a face
                                            // that the cut crosses has vertices inside the lattice
  int max_refine_splits_per_column = 4096;  // a column's refinement stops there (counted: CutStats)
  // What one incision may use without allocating (reserved at construction, kept from incision to
  // incision, so the sim thread allocates nothing after it starts): the vertices it binds (those the lattice
  // moves, with the seam's copies and the walls' vertices). An incision that needs more grows the arrays
  // (an allocation on the caller's thread) and counts it in CutStats::reserve_overflows. >= 64.
  int reserved_bound_vertices = 1 << 15;
};

// The longest edge refinement keeps (CutterOptions::refine_edge_m, or its default), in metres.
double refineEdgeLength(const CutterOptions& options) noexcept;
const char* toString(CutterOptions::Refine refine) noexcept;

// What one call did. Counts are for the call; totals live in CutStats.
struct CutStep {
  SampleStatus sample = SampleStatus::Accepted;
  bool left_surface = false;  // the sample was off the surface: the incision was finished
  bool failed = false;        // an internal topology failure stopped the incision (message in CutStats)
  int columns = 0;            // lattice columns processed
  int vertices_bound = 0;     // vertices parameterised
  int edges_split = 0;
  int vertices_duplicated = 0;
  int wall_faces = 0;         // wall faces (re)built
  int vertices_moved = 0;     // re-deformed
  int edges_refined = 0;      // edges bisected ahead of the cut (CutterOptions::refine)
  bool deadline_hit = false;  // the call's deadline (SurfaceCutter::setDeadline) stopped its work
};

// Why an incision's groove is much shorter than its stroke (IncisionFigures::shortfall): the first reason
// that applies, in this order. None: the groove is about as long as the stroke (or the work is not done).
enum class Shortfall : std::uint8_t {
  None,
  Failed,           // an internal topology failure stopped the incision (CutStats::failure)
  NoContact,        // the first sample was not on the surface: nothing to cut
  CoarseMesh,       // lattice columns along the stroke held no surface vertex: the mesh's edges are longer
                    // than the lattice (subdivide the mesh, or refine it along the stroke)
  InversionFailed,  // vertices inside the lattice whose parameters (F0's inverse) were not found
  NoCrossing,       // no edge crossed the cut inside the blade's window (above its depth, within the stroke)
  SeamBroken,       // seam vertices were made but the chain from the first one did not reach most of them
  TooShort,         // the stroke is shorter than the lattice needs to open a groove
  Unexplained,      // none of the above, and still much shorter
};
const char* toString(Shortfall shortfall) noexcept;

// What one incision made, for a user to check that the cut did what the scalpel did. The counts are this
// incision's; the last fields are set once its work is done (the shortfall test: the groove is shorter
// than the stroke by more than max(4 spacing_m, 20 %), or is 0 while the stroke is not).
// A cut through the tissue: None (the blade never reached the far side), Made (the blade's path was removed
// down through the far side), Failed (the Boolean difference was refused: the groove stays as deep as the
// tissue allowed; CutStats::failure says why).
enum class ThroughCut : std::uint8_t { None, Made, Failed };
const char* toString(ThroughCut through) noexcept;

struct IncisionFigures {
  double stroke_length_m = 0.0;       // of the stroke in contact: its samples smoothed (Incision::pathLength)
  double groove_length_m = 0.0;       // arc length, at rest, of the seam opened: the chain of seam vertices from
                                      // its start to its tip once one of them is duplicated; 0 while none is
  int inversions_failed = 0;          // vertices in their own slab whose inversion did not converge
  int seam_vertices = 0;              // seam vertices made (edges split and vertices snapped)
  int crossings_outside = 0;          // crossing edges outside the blade's window (not split)
  int uncapped_ends = 0;              // ends of the seam that no face beside them could carry to the cut's end
  int thickness_limited_samples = 0;  // samples cut shallower than the blade went: the tissue below was thinner
  int through_samples = 0;            // of those, samples whose blade reached the far side: the cut goes through
  int depth_clamped_samples = 0;      // samples over 5% deeper than incision.depth_m, cut that deep
  int refined_vertices = 0;           // vertices the local refinement added ahead of the cut (one an edge bisected)
  int refined_faces = 0;              // faces it added (two an edge bisected on a closed mesh)
  // Set when the work is done:
  bool done = false;
  int row_limited_stations = 0;   // stations whose rows the tissue's far side along them made shallower (the
                                  // rows lag the surface over a sharp edge and can reach it sideways)
  int columns = 0;                // lattice columns from the stroke's first station to its last
  int empty_columns = 0;          // of those, columns whose slab held no vertex of the surface
  double first_empty_at_m = -1;   // arc length along the stroke of the first empty column (-1: none)
  double groove_start_m = 0.0;    // where the chain of seam vertices starts and ends, as arc length along the
  double groove_end_m = 0.0;      // stroke from its first station (0 and 0 without a chain)
  int seam_vertices_chained = 0;  // of seam_vertices, those in the chain
  double mean_edge_m = 0.0;       // the surface's mean edge length when the cutter was made
  double lattice_width_m = 0.0;   // the lattice's extent across the cut ((l - 1) alpha)
  double min_stroke_m = 0.0;      // the shortest stroke that opens a groove (Incision::minOpeningStations)
  Shortfall shortfall = Shortfall::None;
  // Set when the incision settles, for a cut through the tissue (through_samples > 0):
  ThroughCut through = ThroughCut::None;
  int pieces = 0;  // closed pieces the tissue is made of afterwards (a piece cut free is one more)
  static constexpr int kListedPieces = 4;
  std::array<double, kListedPieces> piece_volumes_m3{};  // the largest pieces' volumes, largest first
};

// A sentence for a user: why the groove is short and where along the stroke ("" for Shortfall::None),
// e.g. "the mesh is coarse next to the lattice: 61 of 70 lattice columns along the stroke held no vertex
// (the first at 0.5 mm) ...". Allocates: not for the sim thread.
std::string describeShortfall(const IncisionFigures& figures);

// The mesh elements a cutter changed, for a reader that mirrors the mesh (sim's GeometryStream): indices
// (OpenMesh handle indices) of every vertex added or moved and of every face added, changed (its vertices
// or kind) or deleted, in the order of the changes; an index may repeat. Filled only while recording is on
// (SurfaceCutter::recordChanges); the consumer clears it. Vertices are deleted only by a cut through the
// tissue (IncisionFigures::through): they keep their index and position, with no face.
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
  int slivers_flipped = 0;    // skin edges beside the seam flipped to leave no seam vertex nearly on a face's
                              // far edge (SurfaceCutter::relieveSlivers), totals
  int refined_vertices = 0;   // vertices and faces the local refinement added, totals (CutterOptions::refine)
  int refined_faces = 0;
  int refine_refused = 0;     // faces left coarse: every edge that would refine them touches the current
                              // incision's bound vertices or a wall (the cut already passed there)
  int refine_limited = 0;     // columns whose refinement stopped at max_refine_splits_per_column or at the
                              // mesh's reserved headroom
  int through_on_worker = 0;  // through-cuts whose Boolean a worker computed (SurfaceCutter::setThroughOnWorker)
  int reserve_overflows = 0;  // arrays an incision grew past CutterOptions::reserved_bound_vertices and the
                              // room reserved for its seam and walls (each an allocation on the sim thread)
  std::string failure;        // first internal failure, empty if none
  // One entry per incision, in order (the current one last). Room for kReservedIncisions is reserved at
  // construction: more incisions than that grow the vector once in a while (amortised).
  std::vector<IncisionFigures> figures;
  static constexpr std::size_t kReservedIncisions = 256;
};

}  // namespace incise::incision
