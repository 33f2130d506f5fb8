// Closed triangle meshes made by the program: boxes, cylinders, icospheres, extruded polygons (prisms), a
// face-profile outline, their disjoint union and a humanoid "robot" of boxes and cylinders. They are the
// obstacles and models of the global-DFFD scenes (a robot walking through bars, a sphere squashed
// around a cylinder, a part molded around a non-convex silhouette), shared by tests, the CLI and the
// benchmarks.
//
// Shapes: every mesh function returns a closed, consistently outward-oriented (counter-clockwise seen from
// outside, positive signed volume) two-manifold SurfaceMesh of triangles, genus 0 per connected component,
// no deleted elements, every kind Original (merge keeps the parts' kinds), normals computed. Vertex and face
// order is fixed by the arguments: the same call gives the same mesh.
// Units: metres (positions, sizes, radii, heights).
// Threads: any thread; the functions share no state. They allocate: not for the sim thread.
// Failure: std::invalid_argument naming the function, the argument and its value for bad input (non-finite
// coordinates, non-positive sizes, too few segments or points, a self-intersecting outline, or a mesh that
// would have more than kMaxShapeFaces faces).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

// Upper bound on the faces of one generated mesh (about 5 GB as an OpenMesh TriMesh): larger requests throw
// std::invalid_argument instead of exhausting memory or overflowing OpenMesh's int handles.
inline constexpr long long kMaxShapeFaces = 50'000'000;

// The surface of `box` (min and max corners finite, size > 0 along every axis). Each of the 6 faces is a
// divisions x divisions grid of equal quads, each split into two triangles; vertices on the box's edges and
// corners are shared, so the mesh is watertight: 6n^2 + 2 vertices and 12n^2 faces for n = divisions
// (>= 1). Its signed volume is the box's volume. Cost O(n^2).
SurfaceMesh makeBox(const Eigen::AlignedBox3d& box, int divisions = 1);

// The same with its own number of divisions along each axis (each >= 1): the faces normal to axis a are
// divisions[b] x divisions[c] grids (b, c the other two axes); makeBox(box, n) is makeBox(box, (n, n, n)),
// the same mesh. 4 (nx ny + ny nz + nz nx) faces. Cost O(faces).
SurfaceMesh makeBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3i& divisions);

// A skin pad, the silicone block surgeons practise incisions on: a box of size_m (x width, y thickness, z
// depth; each finite and > 0) whose top face is the plane y = 0 (normal +y, the stroke generator's rays come
// down -y onto it), centred on x = z = 0, its bottom at y = -size_m.y. The top (and bottom) is a regular grid
// of cells at most grid_m (finite, > 0) on a side: ceil(size_m.x / grid_m) x ceil(size_m.z / grid_m) quads,
// two triangles each; the sides have ceil(size_m.y / (4 grid_m)) layers. The shipped pad: size (0.1, 0.02,
// 0.1), grid 0.001 -> 100 x 100 cells on top, 5 layers on the sides, 44,000 faces. Throws as makeBox, or for more than 1e6 cells
// along a side. Cost O(faces).
SurfaceMesh makeSkinPad(const Eigen::Vector3d& size_m, double grid_m);

// A closed cylinder from the disc centred at base_centre_m to the one at base_centre_m + axis_m (axis_m:
// direction and height, finite, length > 0), radius radius_m (finite, > 0). The circles are regular polygons
// of `segments` (>= 3) vertices inscribed in the circle, the first one in the direction u, where u is the
// unit vector perpendicular to the axis closest to the coordinate axis least aligned with it (x for an axis
// along z; then v = axis x u, so for an axis along +z the segments go from +x towards +y). The side is split
// into `rings` (>= 1) equal layers along the axis; each cap is a fan around its centre vertex plus
// cap_rings - 1 (cap_rings >= 1) concentric polygons at radii radius_m * k / cap_rings.
// segments * (rings + 1 + 2 * (cap_rings - 1)) + 2 vertices, 2 * segments * (rings + 2 * cap_rings - 1)
// faces. The mesh is exactly the prism over the inscribed polygon: volume
// segments / 2 * radius^2 * sin(2 pi / segments) * |axis|. Cost O(segments * (rings + cap_rings)).
SurfaceMesh makeCylinder(const Eigen::Vector3d& base_centre_m, const Eigen::Vector3d& axis_m, double radius_m,
                         int segments, int rings = 1, int cap_rings = 1);

// An icosphere: the regular icosahedron inscribed in the sphere (centre_m finite, radius_m finite and > 0),
// each triangle split into 4 at its edge midpoints `subdivisions` times (0..10), every new vertex projected
// onto the sphere. 10 * 4^s + 2 vertices, 20 * 4^s faces; all vertices on the sphere (to rounding), so the
// volume is below the ball's and above that of the ball of radius (smallest distance from the centre to a
// face plane). Cost O(4^s).
SurfaceMesh makeSphere(const Eigen::Vector3d& centre_m, double radius_m, int subdivisions);

// The simple polygon `outline_m` (points in the xy-plane, >= 3, finite; counter-clockwise or clockwise,
// normalised to counter-clockwise; may be non-convex; consecutive points distinct; edge i joins point i to
// point (i + 1) mod n) extruded from z = z0_m to z = z1_m (finite, z1_m > z0_m). The side is split into
// `rings` (>= 1) equal layers: n * (rings + 1) vertices, the outline's points only (layer k at
// z0 + (z1 - z0) * k / rings, from z0 up; each layer in the outline's normalised order). The two caps are
// CGAL's constrained Delaunay triangulation of the polygon (Exact_predicates_inexact_constructions_kernel,
// faces outside the polygon dropped by nesting level), with no added points: n - 2 triangles each; faces
// 2 * n * rings + 2 * (n - 2). Volume: the polygon's area times (z1 - z0).
// The outline is checked first: two edges that cross or touch other than at the point shared by consecutive
// edges (or consecutive edges that fold back onto each other) throw std::invalid_argument naming the two
// edges, lowest pair first ("outline edges 0 (points 0 - 1) and 2 (points 2 - 3) cross or touch"), with
// CGAL's exact predicates; also repeated consecutive points and zero area.
// Cost O(n log n + pairs of edges whose x-extents overlap) for the check, O(n log n) expected for the
// triangulation, O(n * rings) for the side.
SurfaceMesh makePrism(const std::vector<Eigen::Vector2d>& outline_m, double z0_m, double z1_m, int rings = 1);

// A human head and neck in profile as a closed polygon in the xy-plane, counter-clockwise: the face looks
// towards +x (neck front, chin, lips, nose, brow, forehead going up the +x side), the back of the head on the
// -x side, a horizontal cut through the neck at the bottom. y spans exactly [-height_m / 2, height_m / 2];
// x spans about [-0.36, 0.45] * height_m, with 0 at the neck's centre. Non-convex (dents under the lips and
// between nose and brow) and monotone in y: walking the outline from the neck cut's +x end, y rises strictly
// to the top vertex, then falls strictly to the neck cut's -x end, so every line y = c with
// -height_m / 2 < c < height_m / 2 meets it exactly twice. `points` (25..1,000,000; 25 is the landmark
// outline) vertices exactly: the extra points are spread along the outline's edges by length (none on the
// neck cut). height_m finite and > 0. Cost O(points).
std::vector<Eigen::Vector2d> faceSilhouette(double height_m, int points);

// The disjoint union of `parts`: every part's non-deleted vertices and faces, vertices renumbered in part
// order (part 0's first, each part's in handle order), faces likewise, kinds kept. Closed, oriented and
// manifold when every part is; parts that overlap in space are not detected here (findSelfIntersection in
// tetrahedralize.h does that). An empty list gives an empty mesh. Throws MeshError if a part's face cannot be
// added (a non-manifold part). Cost O(total V + F).
SurfaceMesh merge(const std::vector<SurfaceMesh>& parts);

// A humanoid robot of 7 separate closed components (the mesh merge() makes of them, built in one pass without
// the parts' own meshes), standing on z = 0 with its height
// height_m along z (finite, > 0; the head's top at z = height_m), facing +y, its width along x, centred on
// x = y = 0. Parts (h = height_m, in merge order): legs, cylinders of radius 0.07h at x = -/+0.10h from
// z = 0 to 0.45h; torso box [-0.20h, 0.20h] x [-0.10h, 0.10h] x [0.46h, 0.80h]; arms, cylinders of radius
// 0.05h at x = -/+0.27h from z = 0.42h to 0.78h; neck cylinder of radius 0.04h from z = 0.81h to 0.85h;
// head box [-0.09h, 0.09h] x [-0.09h, 0.09h] x [0.86h, h]. Gaps of at least 0.01h between parts, so they do
// not intersect.
// detail (1..200) scales the resolution: with d = detail, torso box 4d divisions, head box 2d, cylinders 12d
// segments and d cap rings, legs 6d rings, arms 5d, neck d: 516 d^2 - 60 d + 14 vertices and
// 1032 d^2 - 120 d faces. Detail 1 -> 470 vertices (912 faces); detail 8 -> 32,558 vertices (65,088 faces),
// the smallest detail with >= 30,000 vertices (the benchmarks' robot, kRobotDetail30k). Cost O(d^2).
SurfaceMesh makeRobot(double height_m, int detail);

// The detail of makeRobot that gives the benchmarks' robot (>= 30,000 vertices).
inline constexpr int kRobotDetail30k = 8;

}  // namespace incise::mesh
