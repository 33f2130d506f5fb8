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
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

class VertexGrid {
 public:
  explicit VertexGrid(double cell_size);

  // Room for `entries` more entries (and as many new cells) than there are now: until they are used,
  // insert() and move() allocate nothing (the sim thread's cutters reserve their headroom at load). Also
  // stores each cell's entries together (what queries read). Allocates, O(size + table).
  void reserve(std::size_t entries);
  // Adds the entry (id, p). O(1) amortised.
  void insert(int id, const Eigen::Vector3d& p);
  // Moves the entry (id, from) to `to`; `from` must be the position it was inserted or last moved to
  // (bit-exact, it selects the cell). O(entries in the cell) expected.
  void move(int id, const Eigen::Vector3d& from, const Eigen::Vector3d& to);
  // Removes the entry (id, p); same rule for p as move's `from`. O(entries in the cell) expected.
  void remove(int id, const Eigen::Vector3d& p);

  // Appends to `out` the ids of entries whose point lies in the closed box, in ascending id order (only the
  // appended part is sorted; the caller clears `out`). An empty or NaN box appends nothing. No allocation
  // when `out` has the capacity. Cost O(min(cells in box, table slots) + hits * log hits).
  void query(const Eigen::AlignedBox3d& box, std::vector<int>& out) const;

  std::size_t size() const noexcept { return size_; }
  double cellSize() const noexcept { return cell_size_; }
  void clear() noexcept;

 private:
  // Entries live in one pool, each cell's a singly linked list (freed entries on a free list); cells in an
  // open-addressing table (linear probing, never removed: an emptied cell keeps its slot for the next
  // vertex that comes back, as cut vertices do), at most half full.
  struct Entry {
    Eigen::Vector3d p;
    int id;
    int next;  // the next entry of the same cell (or of the free list), -1 at the end
  };
  struct Slot {
    std::int64_t key;  // kEmptyKey: unused
    int head;          // first entry, -1 when the cell is empty
  };

  std::int64_t cellCoordinate(double x) const noexcept;
  static std::int64_t pack(std::int64_t i, std::int64_t j, std::int64_t k) noexcept;
  std::int64_t key(const Eigen::Vector3d& p) const noexcept;
  void checkPoint(const Eigen::Vector3d& p, int id, const char* who) const;
  std::size_t slotOf(std::int64_t key) const noexcept;  // the key's slot, or the empty one it would take
  int cellHead(std::int64_t key) const noexcept;        // -1 when the cell has no entry
  Slot& cellSlot(std::int64_t key);                     // created if absent (may grow the table)
  void rehash(std::size_t slots);
  void compact();
  int newEntry(int id, const Eigen::Vector3d& p);
  int locate(int id, const Eigen::Vector3d& p, const char* who) const;  // entry index; throws when absent
  void appendHits(int head, const Eigen::AlignedBox3d& box, std::vector<int>& out) const;

  double cell_size_;
  std::size_t size_ = 0;
  std::vector<Entry> entries_;
  int free_ = -1;
  std::vector<Slot> slots_;  // a power of two in size
  std::size_t cells_ = 0;    // slots in use
};

// 2 x the mean length of the mesh's non-deleted edges: a cell then holds a few vertices. Throws
// std::invalid_argument when the mesh has no edge of positive finite length. Cost O(E).
double suggestedCellSize(const TriMesh& mesh);

}  // namespace incise::mesh
