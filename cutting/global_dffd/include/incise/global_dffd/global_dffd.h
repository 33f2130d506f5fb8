// The global DFFD (Schein & Elber, "Discontinuous Free Form Deformations", §3): a deformable model moving
// through static obstacles splits open around each of them and re-forms behind it. GlobalDffd is the map F
// (§3.1: a trivariate B-spline over the obstacles' box, two discontinuity planes per obstacle projected onto
// it); the model is split along the planes (splitAtDiscontinuities, DffdSplitter, §3.2), deformed
// (deformSplit, DffdBinding) and its openings left open, stitched (GlobalDffd::stitch) or capped.
//
// Units: metres. Threads: const members from any thread. Cost: construction O(#controls * faces of the
// obstacles) (the conservative boundary), allocation at load only; map() O(order^3).
// Failure: DffdError naming the obstacle (or element) and the reason: an obstacle that is not a closed
// two-manifold, outside the lattice box, not monotone in v (a line along u at some (v, w) enters it more
// than once — the paper's stated limit), two obstacles too close for the order and the kernel (with the
// number of control planes that would be needed), a kernel that would fold F under FoldPolicy::Refuse;
// its fields (kind, obstacle, controls_needed) say the same for code. std::invalid_argument for bad options.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "incise/bspline/bspline_volume.h"
#include "incise/bspline/volume_binding.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::global_dffd {

// What a DffdError is about, for a caller that reacts to it (the benchmark raises controls[0] when told
// TooClose); what() says it in words.
enum class DffdErrorKind : std::uint8_t {
  NoExtent,            // no obstacle and no box
  ObstacleNotClosed,   // an obstacle is not a closed two-manifold
  ObstacleNotFinite,   // an obstacle's vertex is not finite
  ObstacleOutsideBox,  // an obstacle lies outside the given lattice box
  SameCentre,          // two obstacles have the same centre in u
  TooClose,            // two obstacles are too close for the order and the kernel (controls_needed)
  NotMonotone,         // a line along u enters an obstacle more than once
  Folds,               // the kernel would fold F (Theorem 1)
  BadModel,            // validateModel refused the model
  NotTwoManifold,      // the split model cannot be rebuilt as a two-manifold
  BadInput,            // counts that do not match: positions, faces' vertex indices
  OtherLattice,        // DffdBinding::deform with a lattice other than the one bound
};

struct DffdError : std::runtime_error {
  DffdError(DffdErrorKind kind, const std::string& message, std::string obstacle = {}, std::string other_obstacle = {},
            int controls_needed = 0);

  DffdErrorKind kind;
  std::string obstacle;        // the obstacle at fault (the first of two), "" when the error is not about one
  std::string other_obstacle;  // SameCentre, TooClose: the second obstacle
  int controls_needed = 0;     // TooClose: controls[0] must be raised to at least this
};

enum class DffdKernel : std::uint8_t { Gaussian, QuadraticBSpline };
enum class FoldPolicy : std::uint8_t { Refuse, Widen };
// Whether order - 1 knots go in v at each obstacle's v-extremes (Figure 4: the lips close sooner behind it).
enum class VKnots : std::uint8_t { None, AtObstacleExtremes };
// What becomes of the openings the split leaves (§3.2): left open (splitAtDiscontinuities with
// Openings::Leave, deformSplit), stitched (Openings::Close, GlobalDffd::stitch at stitchLevel, deformSplit)
// or capped (cappedDeform; the model must be closed).
enum class OpeningTreatment : std::uint8_t { Open, Stitched, Capped };
// splitAtDiscontinuities: leave the openings, or close them (welded, else a strip) for stitching.
enum class Openings : std::uint8_t { Leave, Close };
// validateModel: whether the model may have a boundary or must be closed.
enum class ModelClosure : std::uint8_t { MayBeOpen, Closed };

struct GlobalDffdOptions {
  int order = 4;                           // o, in u, v and w
  std::array<int, 3> controls{16, 12, 8};  // l, m, n before any knot insertion (>= order)
  double margin_m = 0.01;                  // the lattice box is the obstacles' box grown by this
  std::optional<Eigen::AlignedBox3d> box;  // or this box, which must hold every obstacle
  DffdKernel kernel = DffdKernel::QuadraticBSpline;
  double kernel_width = 3.0;                    // kappa falls from 1 to 0 over this many control spacings of
                                                // the uniform lattice (distance in u from the discontinuity)
  double epsilon = 1e-9;                        // split vertices are mapped at u_i -/+ epsilon
  double clearance_m = 0.0;                     // extra gap left between the wrapped model and the obstacle
  VKnots v_knots = VKnots::AtObstacleExtremes;  // order - 1 knots in v at each obstacle's v-extremes
  FoldPolicy on_fold = FoldPolicy::Refuse;
};

struct Obstacle {
  std::string name;
  mesh::SurfaceMesh mesh;  // closed two-manifold
};

struct DffdObstacle {
  std::string name;
  int input_index = 0;          // its index in the constructor's list (obstacles() is sorted by u)
  double u = 0.0;               // centre of mass along u: the discontinuity
  int i_minus = 0, i_plus = 0;  // control planes of F- and F+
  Eigen::AlignedBox3d box;      // the obstacle's bounding box
  double kernel_width = 0.0;    // the width used, in spacings (wider than asked under FoldPolicy::Widen)
  double max_move_m = 0.0;      // the largest move of a discontinuity control
};

class GlobalDffd {
 public:
  // Construction (§3.1): a trivariate B-spline F over the obstacles' axis-aligned bounding box plus a margin,
  // the identity at first (clamped uniform knots, controls at the Greville abscissae: the parameter domain
  // is the box, so a point's parameters are its coordinates). Axes: u = x (across: the split direction),
  // v = y (the model's motion), w = z (the slicing direction). Per obstacle, `order` knots at its centre of
  // mass in u give the two discontinuity planes F- and F+ (Definition 2); optionally order - 1 knots in v at
  // its v-extremes (Figure 4). For every control row (j, k) the planes' controls are projected along u onto
  // the obstacle's boundary: C-(v) / C+(v) in the plane w = w_k (Figure 1), taken conservatively as the
  // obstacle's smallest / largest x over the v- and w-support of that control, so that F's image of the
  // - side stays at or left of the obstacle and the + side at or right of it. The move spreads along u to
  // the neighbouring planes on the same side through a kernel kappa (a truncated Gaussian or a quadratic
  // B-spline) that decays from 1 to 0 over `kernel_width` planes. Controls move along u only, so Theorem 1
  // applies: F is fold-free while every row keeps its u-order (checkAxisOrder); a kernel that would break it
  // is refused, or widened until it does not (FoldPolicy).
  GlobalDffd(const std::vector<Obstacle>& obstacles, const GlobalDffdOptions& options = {});

  const bspline::BSplineVolume& volume() const noexcept { return volume_; }
  const std::vector<DffdObstacle>& obstacles() const noexcept { return obstacles_; }
  const Eigen::AlignedBox3d& box() const noexcept { return box_; }
  const GlobalDffdOptions& options() const noexcept { return options_; }

  // F(x): the identity outside the box and in knot cells where no control of the support moved (x itself,
  // exactly); at u == u_i exactly, side -1 / +1 evaluates F- / F+ (u_i -/+ epsilon), side 0 the right-hand
  // value. O(order^3) where it evaluates, O(log controls) elsewhere.
  Eigen::Vector3d map(const Eigen::Vector3d& x_m, int side = 0) const;
  // The knot cell (span indices, i-fastest) holding x (u shifted by side * epsilon and clamped, written to
  // u), and whether F is the identity there (no control of its support moved). x must lie in the box.
  // The cells stay the same when F's controls change (its knots do not). O(log controls) / O(1).
  int cellOf(const Eigen::Vector3d& x_m, int side, double& u) const;
  bool identityCell(int cell) const noexcept { return !moved_cell_[static_cast<size_t>(cell)]; }
  // Sampled minimum of det J over the lattice (fold_over.h). O(#cells * samples^3 * o^3).
  double minJacobian(int samples_per_cell = 2) const;
  // §3.2 stitching at the level w_s: every control of column j of F- moves to (X-_j, v_j, w_s), X-_j the
  // column's leftmost projected u, and of F+ to (X+_j, v_j, w_s), the rightmost: each side's opening maps
  // onto one seam curve, clear of the obstacle. (The paper's (u_i, v_j, w_s) would join both sides through
  // the obstacle.) Fold-free like the projection: each plane stays beyond its neighbours' u-order.
  void stitch(int index, double w_s_m);

 private:
  void place(const std::vector<Obstacle>& obstacles);
  void wrap(const std::vector<Obstacle>& obstacles);
  void spread(const DffdObstacle& o, int j, int k, double move_minus, double move_plus, double width);
  void markMovedCells();
  int cellAndSpans(const Eigen::Vector3d& x, int side, double& u, std::array<int, 3>& spans) const;

  GlobalDffdOptions options_;
  Eigen::AlignedBox3d box_;
  bspline::BSplineVolume volume_;
  std::vector<DffdObstacle> obstacles_;
  double spacing_u_ = 1.0;                          // the uniform control spacing in u before any insertion
  std::vector<double> rest_u_;                      // u of every control plane before the moves (Greville abscissae)
  std::vector<Eigen::Vector3d> identity_controls_;  // the controls place() set (the identity lattice's)
  std::vector<std::uint8_t> moved_cell_;  // per knot cell (span indices, i-fastest): a control of its support moved
};

// Checks a model before it is split: a two-manifold (it may be open unless ModelClosure::Closed is asked:
// the capped treatment needs it closed) with no degenerate face (a repeated vertex or no area: its crossing
// would be undefined). Throws DffdError naming the first face, edge or vertex at fault (0-based).
// O(V + E log E + F).
void validateModel(const mesh::SurfaceMesh& model, ModelClosure closure);

// The model split at every discontinuity (§3.2): each edge crossing u = u_i is split there (the whole
// section, also beyond the box, where F is the identity and the lips stay together), vertices within
// 1e-9 of the box's size from the plane are put on it, and each vertex on the plane between faces of both
// sides is duplicated: the - faces keep it (mapped at u_i - epsilon), the + faces get the copy (+ epsilon).
struct DffdSplit {
  std::vector<Eigen::Vector3d> rest_m;    // the split model's vertices, at rest
  std::vector<std::array<int, 3>> faces;  // its triangles (outward, counter-clockwise), vertex indices
  // The split model as a mesh: at rest, or with the given positions (one per vertex, e.g. deformSplit's).
  // Builds an OpenMesh mesh: O(V + F), for output and checks (about half a frame's time on the robot).
  mesh::SurfaceMesh surface(std::span<const Eigen::Vector3d> positions_m = {}) const;
  std::vector<int> source_vertex;               // per vertex: the model's vertex, or -1 for a split point
  std::vector<std::array<int, 2>> source_edge;  // per split point: the model edge's ends; {-1, -1} otherwise
  std::vector<std::int8_t> side;                // per vertex: -1 / +1 on a discontinuity, 0 elsewhere
  std::vector<int> plane;                       // per vertex: index of the obstacle whose plane it lies on, or -1
  int left_open = 0;                            // openings Openings::Close could not close (see below)
  // A model with texture coordinates or materials (the SurfaceMesh overload) gives them to the split: per
  // face, its corners' coordinates (a split point's interpolated along its edge in each face, so texture
  // seams are kept; a stitching strip's from the faces beside it) and its material, an index into
  // `materials`; empty otherwise. surface() and weldClosedLips() put them on the meshes they make.
  std::vector<std::array<Eigen::Vector2d, 3>> face_uv;
  std::vector<int> face_material;
  std::vector<mesh::Material> materials;
  bool operator==(const DffdSplit&) const = default;  // every field, bit for bit
};
// With Openings::Close, every opening the split leaves (a loop of duplicated vertices on one side of one
// plane) is closed: its two halves, from its lowest-v vertex to its highest, get the same v-values (edges
// split where the other half has a vertex) and are welded vertex to vertex. Once F is stitched
// (GlobalDffd::stitch) both halves map onto the same seam, so the output is closed with no flat face. An
// opening that cannot be welded (it reaches beyond the box, its halves are not monotone in v, or a face
// already spans from half to half) is closed by a strip of thin triangles zipped between its halves in
// order of v instead, if that leaves a two-manifold; else it stays open (counted in left_open).
// Cost O((V + F) log F) (plus O(F) per welded vertex). Failure: DffdError if the split model cannot be
// rebuilt as a two-manifold.
DffdSplit splitAtDiscontinuities(const mesh::SurfaceMesh& model, const GlobalDffd& dffd,
                                 Openings openings = Openings::Leave);
// The same from the model's vertex positions and triangles (a moving model: its triangles never change).
DffdSplit splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions_m,
                                 std::span<const std::array<int, 3>> faces, const GlobalDffd& dffd,
                                 Openings openings = Openings::Leave);
// The same into `out`, reusing its buffers (and per-thread working buffers): frame after frame, almost no
// allocation once warmed up. Threads: one call at a time per thread.
void splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions_m, std::span<const std::array<int, 3>> faces,
                            const GlobalDffd& dffd, Openings openings, DffdSplit& out);

// A model as the array forms of the split take it: its vertex positions (those OpenMesh has not deleted,
// in index order) and its triangles by position index. O(V + F).
struct ModelArrays {
  std::vector<Eigen::Vector3d> positions_m;
  std::vector<std::array<int, 3>> triangles;
};
ModelArrays modelArrays(const mesh::SurfaceMesh& model);

// The split of a model that moves frame after frame, its triangles fixed (the global DFFD's frame: split
// only what changed). The split's connectivity depends only on which side of each plane x = u_i every
// vertex lies, or whether it is put on the plane (within snapDistance), and on which diagonal splits each
// crossing face's four-sided piece (the clearly shorter one, else the first). When none of that changed
// since the previous call, with the same triangles, planes and box, the previous connectivity is kept and
// only the positions are recomputed: the previous split's constructions (vertices put on a plane, edge
// crossings, duplicated vertices, the diagonals' choices checked) are replayed in their order on the new
// positions, which gives the bits a full split gives (tests/cutting/global_dffd/global_dffd_splitter_test.cpp).
// Otherwise, and always with Openings::Close (whose welding depends on the vertices' order in v), it is
// splitAtDiscontinuities.
// Cost: O(V * planes) to compare the sides and O(V') to replay (V' split vertices; about 0.2 ms for the
// 35k-vertex split robot), else a full split's. No allocation once warmed up on one model.
// Threads: one call at a time per splitter. Failure: as splitAtDiscontinuities; the splitter then splits
// in full at its next call.
class DffdSplitter {
 public:
  DffdSplitter();
  ~DffdSplitter();
  DffdSplitter(DffdSplitter&&) noexcept;
  DffdSplitter& operator=(DffdSplitter&&) noexcept;

  // The split of the model at `positions_m` (one per model vertex), valid until the next call.
  const DffdSplit& split(std::span<const Eigen::Vector3d> positions_m, std::span<const std::array<int, 3>> faces,
                         const GlobalDffd& dffd, Openings openings = Openings::Leave);
  // Whether the last split() kept the previous connectivity (false after a full split).
  bool keptConnectivity() const noexcept;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// §3.2's stitching level for obstacle `index`: the mean w of the split's vertices on its plane (the box's
// centre in w if there are none). O(V).
double stitchLevel(const DffdSplit& split, const GlobalDffd& dffd, int index);

// §3.2's first method, for a closed two-manifold model: the model split at every plane u = u_i, mapped
// through F (each vertex from its own side), its lips welded where F leaves the two sides together, and each
// opening closed by two caps: the model's section at the plane, restricted to the knot cells (v, w) in which
// F separates the sides, triangulated at rest (CGAL's constrained Delaunay triangulation, with points inside
// so that the caps bend with F) and mapped through F- (the - side's cap) and F+ (the + side's). The caps meet
// the welded lips along the cells' boundary, so the result is closed and no two caps lie face to face. Cap
// faces are walls (material 0, planar texture coordinates at rest). Cost: O(V * order^3) for the mapping plus
// a CDT of each plane's section (O(S log S) in its lip edges and inner points). Failure: DffdError
// (BadModel) from validateModel for a model that is not closed or has a degenerate face; DffdError
// (NotTwoManifold) naming the plane when its section cannot be capped (its edges cross).
mesh::SurfaceMesh cappedDeform(const mesh::SurfaceMesh& model, const GlobalDffd& dffd);

// Every vertex of `split` mapped through F (its side on a discontinuity), into out_m (one per vertex; else
// DffdError). O(V * order^3), spread over the machine's cores by oneTBB (blocks of 2,048 vertices; the same
// bits with any number of threads). Not for a real-time thread: it waits for the blocks.
void deformSplit(const DffdSplit& split, const GlobalDffd& dffd, std::span<Eigen::Vector3d> out_m);
// The same as a mesh (split.surface() of the deformed positions): the deformed model, same connectivity.
mesh::SurfaceMesh deformSplit(const DffdSplit& split, const GlobalDffd& dffd);

// The open treatment's output: the split's surface at `positions_m` (deformSplit's: one per split vertex)
// with the lips F leaves together welded. A vertex duplicated on a plane whose image is bit for bit its
// twin's (beyond the box, or where no control of F's support moved: F- = F+ there) is merged with it when an
// edge of the opening at it welds too (both ends together); a lone such vertex between separated lips stays
// split (welding it alone would join the surface at a point). The opening is then only where F separates the
// lips: no zero-width crack whose faces touch each other (a self-intersection). Meant for splits with
// Openings::Leave. Vertices: the split's in index order, less the merged copies. O(V log V + F).
// Failure: DffdError when positions_m does not have one position per split vertex, or the welded surface
// cannot be built as a two-manifold.
mesh::SurfaceMesh weldClosedLips(const DffdSplit& split, std::span<const Eigen::Vector3d> positions_m);

// A split bound to F's lattice, for re-deforming it without a new split (F changed, the model did not:
// after stitch(), or another GlobalDffd with the same lattice). The parameters of the split's vertices
// inside the box (x with u shifted by side * epsilon and clamped to the domain, as map() does) are bound
// once with a VolumeBinding (spans and basis values computed once); deform() is then a weighted sum of
// o^3 controls per such vertex, bit-identical to deformSplit's positions. Vertices outside the box keep
// their rest position (F is the identity there).
// Shapes: one output position per vertex of split.mesh (vertex index order), metres.
// Cost: construction O(V * o^2 + #controls); deform O(V_inside * o^3 + V), no allocation. Memory about
// (3 * o + 1) doubles and 2 ints per vertex inside the box plus a cell index over the controls.
// Threads: deform is const and may run concurrently (each caller with its own output).
// Failure: DffdError from deform if `dffd`'s lattice (orders, knots: the box) is not the one bound, or if
// out_m does not have one position per split vertex; nothing is written then.
class DffdBinding {
 public:
  DffdBinding(const DffdSplit& split, const GlobalDffd& dffd);

  std::size_t size() const noexcept { return rest_.size(); }     // split vertices
  std::size_t bound() const noexcept { return inside_.size(); }  // of them inside the box

  void deform(const GlobalDffd& dffd, std::span<Eigen::Vector3d> out_m) const;

 private:
  std::vector<Eigen::Vector3d> rest_;  // per split vertex: its rest position
  std::vector<int> inside_;            // the vertices inside the box, increasing: binding point b is inside_[b]
  std::vector<int> cells_;             // binding point b's knot cell (GlobalDffd::cellOf)
  bspline::VolumeBinding binding_;
};

// How deep the deepest vertex of `mesh` lies inside any obstacle (metres; 0 when none is inside): inside
// by the parity of a ray along +x, depth the distance to the obstacle's closest triangle. The name of the
// obstacle is written to `which` when given. Cost O(vertices in an obstacle's box * its faces).
double worstPenetration(const mesh::TriMesh& mesh, const std::vector<Obstacle>& obstacles,
                        std::string* which = nullptr);

// Boundary loops of a mesh (closed chains of boundary edges). O(V + E).
int boundaryLoops(const mesh::TriMesh& mesh);

}  // namespace incise::global_dffd
