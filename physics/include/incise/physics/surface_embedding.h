// A cut surface's vertices embedded in the tets at rest, each on its own side of every cut, so that the
// skin and the wound's walls follow the deformed tets and a lip's vertex never follows the other lip's tet
// (embedding.h evaluates them). Shared by the sim (TissuePhysics::embedSurface, over the model's own
// locator) and the viewer (over a TetLocator of the tets it mirrors).
//
// The rule for a vertex x: a probe point just inside the surface beside it (probeBeside) lies in a tet of
// the vertex's side of the cut (or an uncut one); x is embedded in a tet of that side (or uncut): the one
// holding the point kEmbedNudgeM from x towards the probe when x lies on that tet (so that a vertex on a
// face, edge or node shared across a cut goes with its own side whatever the rounding), else the one
// holding x or nearest to it within 1 mm on that side, else the nearest of any side within 1 mm.
//
// Shapes: points in metres, rest frame. Threads: the locator's (TetLocator: const members from any number
// of threads; its locate() allocates nothing once its scratch has grown). Cost: a few locates a vertex.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/mesh/vertex_grid.h"
#include "incise/physics/embedding.h"

namespace incise::physics {

// What embedSurfaceVertex asks of the tets: locate(p, filter, max_distance_m) as TissueModel::locate
// (the deepest admitted tet holding p at rest, else the nearest within max_distance_m; nullopt if none).
class PointLocator {
 public:
  virtual ~PointLocator() = default;
  virtual std::optional<Embedded> locate(const Eigen::Vector3d& rest_m, ElementFilter filter,
                                         double max_distance_m) const = 0;
};

// One tet for a TetLocator: its four nodes (positively oriented at rest), what a filter sees of it, and its
// key: of two tets a point lies equally deep in (or equally near), locate() gives the one with the smaller
// key (-1: its index in build()'s list), so that the answer does not depend on how the tets were entered.
struct LocatorTet {
  std::array<int, 4> nodes{-1, -1, -1, -1};
  ElementInfo element;
  std::int64_t key = -1;
};

// A locator over a plain list of tets at rest (a reader's copy of the tet cutter's mesh): a uniform grid
// (cells the tets' mean edge at the last build) in whose cells each tet is entered where its bounding box
// overlaps them. Build O(tets x cells a tet overlaps); update O(the tets removed and added x their cells);
// locate O(tets in the point's cell), or, when the point is in none, in the rings of cells around it out to
// its nearest tet (at most max_distance_m); the candidates in a per-thread scratch list. Tets flat at rest
// are left out. The same tets, built at once or reached by updates, give the same answers.
class TetLocator final : public PointLocator {
 public:
  TetLocator() : grid_(1.0) {}
  // Replaces what it holds: `rest_m` the node positions (indexed as the tets' nodes), `tets` the tets. When
  // `slots` is given, it receives each tet's slot (for update()), -1 for a tet left out.
  void build(std::span<const Eigen::Vector3d> rest_m, std::span<const LocatorTet> tets,
             std::vector<int>* slots = nullptr);
  // Removes the tets in `removed` (slots from build() or update(); -1 is skipped) and enters `added`, their
  // nodes in `rest_m`; `slots` receives each added tet's slot, -1 for one left out. The grid's cells stay.
  // Added tets carry their keys (one left at -1 keeps it and wins every tie).
  void update(std::span<const Eigen::Vector3d> rest_m, std::span<const int> removed, std::span<const LocatorTet> added,
              std::vector<int>& slots);
  std::optional<Embedded> locate(const Eigen::Vector3d& rest_m, ElementFilter filter,
                                 double max_distance_m) const override;
  std::size_t size() const noexcept { return tets_.size() - free_.size(); }

 private:
  struct Held {
    LocatorTet tet;
    Eigen::Matrix3d inverse_edges;       // [x1 - x0, x2 - x0, x3 - x0]^-1 at rest
    std::array<Eigen::Vector3d, 4> x_m;  // the nodes at rest
    Eigen::AlignedBox3d box() const {
      Eigen::AlignedBox3d b;
      for (const Eigen::Vector3d& p : x_m) b.extend(p);
      return b;
    }
  };
  static std::optional<Held> held(std::span<const Eigen::Vector3d> rest_m, const LocatorTet& t);
  // The integer coordinates of the first and last grid cells the tet's bounding box overlaps.
  Eigen::AlignedBox3d cellRange(const Held& h) const;
  // Calls visit(centre) for every grid cell the tet's bounding box overlaps: where it is entered or removed.
  template <typename Visit>
  void forCells(const Held& h, Visit&& visit) const;
  // Into `out` (cleared; ascending, no repeats): the tets entered in the cells `ring` cells (Chebyshev) from
  // the cell `index` (integer cell coordinates). O(cells in the ring + their entries).
  void ringCandidates(const Eigen::Array3d& index, int ring, std::vector<int>& out) const;
  void enter(int slot);  // the held tet in slot into the grid's cells
  mesh::VertexGrid grid_;
  std::vector<Held> tets_;     // by slot; a free slot's tet has nodes -1
  std::vector<int> free_;      // slots removed and not reused yet
  Eigen::AlignedBox3d cells_;  // the cell coordinates of every tet entered since the last build (grows only)
};

// How far towards its probe a vertex is nudged to find its own tet, and how far off that tet (rounding) it
// may be and still be embedded in it.
inline constexpr double kEmbedNudgeM = 1e-6;
inline constexpr double kEmbedOnFaceM = 1e-9;
// Vertices farther than this from every tet at rest are not embedded (they stay where they are).
inline constexpr double kEmbedReachM = 1e-3;

// A point just inside the surface beside a vertex at x: halfway to its neighbours' centroid, a quarter of
// their mean distance behind `area_normal` (the sum of its faces' cross products, (b - a) x (c - a)). On the
// vertex's own side of a cut through it (its neighbours are). `area_sum` is the sum of those cross
// products' lengths: where the faces' normals cancel (|area_normal| <= 1e-9 area_sum, its direction rounding
// noise: a fold, as the floor of a groove cut with no opening, where both walls meet) the point is a quarter
// of the spread past the vertex away from its neighbours' centroid (the tissue beyond the fold's tip).
// x itself without neighbours.
Eigen::Vector3d probeBeside(const Eigen::Vector3d& x_m, std::span<const Eigen::Vector3d> neighbours_m,
                            const Eigen::Vector3d& area_normal, double area_sum);

// The base tets the rule consulted for a vertex (-1: none found): the probe's, the nudged point's and the
// one the vertex is embedded in. While their pieces stay as they are, the vertex's embedding does too (pieces
// of one base tet do not overlap), so a reader keeping the embedding up to date re-embeds the vertex when one
// of them changed.
using EmbedBases = std::array<int, 3>;

// The vertex at x_m embedded by the rule above, with the probe beside_m (probeBeside); nullopt when no tet
// is within kEmbedReachM of it. `bases`, if given, gets the base tets consulted.
std::optional<Embedded> embedSurfaceVertex(const PointLocator& tets, const Eigen::Vector3d& x_m,
                                           const Eigen::Vector3d& beside_m, EmbedBases* bases = nullptr);

}  // namespace incise::physics
