// A tetrahedral mesh of the tissue volume: node positions, positively oriented tets and face adjacency.
// Plus queries (boundary, volume, dihedral angles), a conformity check and VTU / TetGen .node/.ele output.
// No cutting or splitting of tets here.
//
// Shapes: nodes_m #N positions in metres; tets #T x 4 0-based node indices; neighbours #T x 4 tet indices
// (neighbours[t][i] is the tet across the face opposite node i of t, -1 on the boundary), filled by
// buildAdjacency.
// Face convention: for a positively oriented tet (a, b, c, d) the outward faces are, opposite node
// 0: (b, c, d), 1: (a, d, c), 2: (a, b, d), 3: (a, c, b) (counter-clockwise seen from outside).
// Threads: free functions on distinct or const meshes may run concurrently. Everything here allocates: not
// for the sim thread.
// Failure: std::invalid_argument for out-of-range node indices or mismatched field sizes (with the index);
// MeshError naming the path for I/O failures.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace incise::tets {

struct TetMesh {
  std::vector<Eigen::Vector3d> nodes_m;
  std::vector<std::array<int, 4>> tets;        // positively oriented: det(b - a, c - a, d - a) > 0
  std::vector<std::array<int, 4>> neighbours;  // across the face opposite node i, -1 on the boundary
};

// The three nodes of the face of `tet` opposite its node `i` (0..3), ordered counter-clockwise seen from
// outside the tet (when the tet is positively oriented). O(1).
std::array<int, 3> faceOpposite(const std::array<int, 4>& tet, int i);

// Fills mesh.neighbours by sorting the 4T faces by their sorted node triple. A face shared by more than
// two tets (not conforming) leaves -1 on all of its sides. Throws std::invalid_argument for a node index
// out of range. Cost O(T log T).
void buildAdjacency(TetMesh& mesh);

// The faces that belong to one tet only, oriented outward (counter-clockwise seen from outside), in
// (tet, local face) order. Uses the faces themselves, not mesh.neighbours. Cost O(T log T).
std::vector<std::array<int, 3>> boundaryFaces(const TetMesh& mesh);

// Signed volume of one tet (m^3) and its smallest interior dihedral angle (degrees; 0 for a flat tet).
// std::out_of_range for a bad tet index; node indices are not checked. O(1).
double tetVolume(const TetMesh& mesh, int tet);
double tetMinDihedralAngleDeg(const TetMesh& mesh, int tet);

// Sum of the signed tet volumes (m^3). O(T).
double volume(const TetMesh& mesh);

// The volumes (m^3) of the mesh's pieces (tets joined through shared nodes), largest first: a tissue cut
// through falls into several. O(T).
std::vector<double> pieceVolumes(const TetMesh& mesh);

// Smallest interior dihedral angle over all tets, in degrees (180 for an empty mesh; 0 for a flat tet).
// O(T).
double minDihedralAngleDeg(const TetMesh& mesh);

struct TetCheck {
  bool conforming;            // no problem of any kind below
  int interior_faces;         // faces shared by exactly two tets, with opposite orientations
  int boundary_faces;         // faces of exactly one tet
  int non_manifold_faces;     // faces of three or more tets, or shared by two tets on the same side
  int inverted_tets;          // det(b - a, c - a, d - a) <= 0
  int bad_tets;               // node index out of range or repeated
  std::string first_problem;  // the first problem found, with 0-based tet / node indices; empty if none
};

// Every interior face shared by exactly two tets lying on opposite sides of it, boundary faces by one,
// no inverted tet, valid node indices; when mesh.neighbours has one entry per tet it must also match the
// adjacency the faces imply. Cost O(T log T).
TetCheck checkConforming(const TetMesh& mesh);

// ASCII VTK XML UnstructuredGrid (ParaView): Float64 points, tets as cell type 10, and one Int32 cell-data
// array per entry of `cell_fields` (each with one value per tet, else std::invalid_argument naming it;
// names must be non-empty without '"', '<', '>', '&'). Numbers with 17 significant digits, locale-
// independent. Writes path + ".tmp" and renames it to path; the .tmp is removed on failure. Cost O(N + T).
void saveVtu(const TetMesh& mesh, const std::filesystem::path& path,
             const std::map<std::string, std::vector<int>>& cell_fields = {});

// TetGen's stem.node ("N 3 0 0", then "i x y z") and stem.ele ("T 4 A", then "i a b c d" and one
// attribute per entry of `cell_fields`, in name order, named by a "# attributes:" comment line), 0-based.
// Both are written to .tmp files first, then renamed. Failure as saveVtu. Cost O(N + T).
void saveNodeEle(const TetMesh& mesh, const std::filesystem::path& stem,
                 const std::map<std::string, std::vector<int>>& cell_fields = {});

}  // namespace incise::tets
