// A uniform-grid spatial hash over points (mesh vertices, by id) for local queries around a scalpel
// stroke: "which vertices lie in this box?" without touching the rest of the mesh.
//
// Shapes: ids are the caller's ints (typically VertexHandle::idx()); each (id, point) pair is one entry;
// inserting an id twice stores two entries. Cells are cubes of side cell_size; cell (i, j, k) holds the
// points p with floor(p / cell_size) = (i, j, k), each coordinate clamped to +-2^20 cells (points farther
// out share the outermost cells: still correct, only slower).
// Units: those of the points (metres in incise); cell_size in the same unit.
// Threads: const members may be called from any number of threads at once; mutators need exclusive access.
// Failure: std::invalid_argument for a non-positive or non-finite cell size, a non-finite point, or a
// move()/remove() of an entry that is not there (with the id); the grid is then unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/cutting/surface_mesh.h"

namespace incise::cutting {

class VertexGrid {
 public:
  explicit VertexGrid(double cell_size);

  // Adds the entry (id, p). O(1) amortised.
  void insert(int id, const Eigen::Vector3d& p);
  // Moves the entry (id, from) to `to`; `from` must be the position it was inserted or last moved to
  // (bit-exact, it selects the cell). O(entries in the cell) expected.
  void move(int id, const Eigen::Vector3d& from, const Eigen::Vector3d& to);
  // Removes the entry (id, p); same rule for p as move's `from`. O(entries in the cell) expected.
  void remove(int id, const Eigen::Vector3d& p);

  // Appends to `out` the ids of entries whose point lies in the closed box, in ascending id order (only the
  // appended part is sorted; the caller clears `out`). An empty or NaN box appends nothing. No allocation
  // when `out` has the capacity. Cost O(min(cells in box, occupied cells) + hits * log hits).
  void query(const Eigen::AlignedBox3d& box, std::vector<int>& out) const;

  std::size_t size() const noexcept { return size_; }
  double cellSize() const noexcept { return cell_size_; }
  void clear() noexcept;

 private:
  struct Entry {
    int id;
    Eigen::Vector3d p;
  };
  struct KeyHash {
    std::size_t operator()(std::int64_t key) const noexcept;
  };
  using Cell = std::vector<Entry>;
  using Map = std::unordered_map<std::int64_t, Cell, KeyHash>;
  struct Location {
    Map::iterator cell;
    Cell::iterator entry;
  };

  std::int64_t cellCoordinate(double x) const noexcept;
  static std::int64_t pack(std::int64_t i, std::int64_t j, std::int64_t k) noexcept;
  std::int64_t key(const Eigen::Vector3d& p) const noexcept;
  void checkPoint(const Eigen::Vector3d& p, int id, const char* who) const;
  Location locate(int id, const Eigen::Vector3d& p, const char* who);  // throws when absent
  void appendHits(const Cell& cell, const Eigen::AlignedBox3d& box, std::vector<int>& out) const;

  double cell_size_;
  std::size_t size_ = 0;
  Map cells_;
};

// 2 x the mean length of the mesh's non-deleted edges: a cell then holds a few vertices. Throws
// std::invalid_argument when the mesh has no edge of positive finite length. Cost O(E).
double suggestedCellSize(const TriMesh& mesh);

}  // namespace incise::cutting
