// The tet cutter's options and per-call results (cutting/tets/include/incise/tets/tet_cutter.h), in a header
// without OpenMesh so that sim's public headers can hold them. Units: metres; counts per call.
#pragma once

#include <cstdint>
#include <string>

namespace incise::tets {

// How much of the carried tet work a follow() call does: PerCall, at most max_inversions_per_call node
// inversions; All, everything that is final (a new incision's catch-up).
enum class TetBudget : std::uint8_t { PerCall, All };
// Which node positions a TetView holds: Deformed (rest + the incision's displacement) or Rest.
enum class TetShape : std::uint8_t { Deformed, Rest };

struct TetCutterOptions {
  double snap_tolerance_m = 0.0;    // nodes closer than this to the cut are put on it; 0 = 0.2 x the median
                                    // edge length; < 0 is refused
  int max_inversions_per_call = 0;  // per-call budget in node inversions (the dominant cost); 0 = none.
                                    // Carried work resumes in the next call; the mesh does not depend on it.
};

// What one follow() call did.
struct TetStep {
  int columns = 0;          // lattice columns finished
  int nodes_bound = 0;      // nodes parameterised
  int tets_cut = 0;         // tets split along the cut
  int tets_subdivided = 0;  // tets (re)subdivided, cut or conforming
  int nodes_moved = 0;
  bool failed = false;
};

struct TetCutStats {
  int incisions = 0;
  int tets_cut = 0;
  int edge_points = 0;        // points placed on crossing edges
  int snapped_nodes = 0;      // nodes put on the cut by the snap tolerance
  int steiner_nodes = 0;      // points added inside pieces that could not be coned from a vertex
  int duplicated_nodes = 0;   // nodes on the cut that have a copy for the u >= 1/2 side
  int rebased_tets = 0;       // base tets a new incision replaced by the previous one's pieces (the rebase)
  int reserve_overflows = 0;  // arrays grown past the room reserved at load (each an allocation in follow())
  std::string failure;        // empty unless the cutter stopped
};

}  // namespace incise::tets
