#include "incise/mesh/vertex_grid.h"

#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace incise::mesh {

namespace {

constexpr std::int64_t kMaxCell = (std::int64_t{1} << 20) - 1;  // 21 bits per axis, signed
constexpr std::int64_t kMinCell = -(std::int64_t{1} << 20);

}  // namespace

VertexGrid::VertexGrid(double cell_size) : cell_size_(cell_size) {
  if (!std::isfinite(cell_size) || cell_size <= 0.0) {
    throw std::invalid_argument("VertexGrid: cell size must be finite and > 0, got " + core::formatNumber(cell_size));
  }
}

namespace {

constexpr std::int64_t kEmptyKey = -1;  // pack() gives keys in [0, 2^63)

std::size_t hashKey(std::int64_t key) noexcept {
  auto x = static_cast<std::uint64_t>(key);  // splitmix64 finaliser: packed keys are far from random
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<std::size_t>(x ^ (x >> 31));
}

std::size_t powerOfTwoAtLeast(std::size_t n) {
  std::size_t p = 16;
  while (p < n) p *= 2;
  return p;
}

}  // namespace

std::int64_t VertexGrid::cellCoordinate(double x) const noexcept {
  const double c = std::floor(x / cell_size_);
  if (!(c >= static_cast<double>(kMinCell))) return kMinCell;  // also NaN, which callers exclude
  if (c >= static_cast<double>(kMaxCell)) return kMaxCell;
  return static_cast<std::int64_t>(c);
}

std::int64_t VertexGrid::pack(std::int64_t i, std::int64_t j, std::int64_t k) noexcept {
  constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  const auto u = [](std::int64_t c) { return static_cast<std::uint64_t>(c - kMinCell) & mask; };
  return static_cast<std::int64_t>(u(i) | u(j) << 21 | u(k) << 42);
}

std::int64_t VertexGrid::key(const Eigen::Vector3d& p) const noexcept {
  return pack(cellCoordinate(p.x()), cellCoordinate(p.y()), cellCoordinate(p.z()));
}

void VertexGrid::checkPoint(const Eigen::Vector3d& p, int id, const char* who) const {
  if (!p.allFinite())
    throw std::invalid_argument(std::string("VertexGrid::") + who + ": non-finite point " + core::formatPoint(p) +
                                " for id " + std::to_string(id));
}

std::size_t VertexGrid::slotOf(std::int64_t key) const noexcept {
  const std::size_t mask = slots_.size() - 1;
  std::size_t s = hashKey(key) & mask;
  while (slots_[s].key != key && slots_[s].key != kEmptyKey) s = (s + 1) & mask;
  return s;
}

int VertexGrid::cellHead(std::int64_t key) const noexcept {
  if (slots_.empty()) return -1;
  const Slot& slot = slots_[slotOf(key)];
  return slot.key == key ? slot.head : -1;
}

void VertexGrid::rehash(std::size_t slots) {
  std::vector<Slot> old(slots, Slot{kEmptyKey, -1});
  old.swap(slots_);
  for (const Slot& slot : old)
    if (slot.key != kEmptyKey) slots_[slotOf(slot.key)] = slot;
}

VertexGrid::Slot& VertexGrid::cellSlot(std::int64_t key) {
  if (2 * (cells_ + 1) > slots_.size()) rehash(powerOfTwoAtLeast(4 * (cells_ + 1)));
  Slot& slot = slots_[slotOf(key)];
  if (slot.key == kEmptyKey) {
    slot = {key, -1};
    ++cells_;
  }
  return slot;
}

void VertexGrid::reserve(std::size_t entries) {
  compact();
  entries_.reserve(size_ + entries);
  const std::size_t slots = powerOfTwoAtLeast(2 * (cells_ + entries + 1));
  if (slots > slots_.size()) rehash(slots);
}

void VertexGrid::compact() {
  // Each cell's entries made consecutive (in slot order, each list's order kept), the free list dropped: a
  // query then reads a cell's entries from one place, as a grid of per-cell arrays would.
  std::vector<Entry> packed;
  packed.reserve(std::max(entries_.capacity(), size_));
  for (Slot& slot : slots_) {
    if (slot.key == kEmptyKey || slot.head < 0) continue;
    const int head = static_cast<int>(packed.size());
    for (int e = slot.head; e >= 0; e = entries_[static_cast<std::size_t>(e)].next) {
      packed.push_back(entries_[static_cast<std::size_t>(e)]);
      packed.back().next = static_cast<int>(packed.size());
    }
    packed.back().next = -1;
    slot.head = head;
  }
  entries_ = std::move(packed);
  free_ = -1;
}

int VertexGrid::newEntry(int id, const Eigen::Vector3d& p) {
  if (free_ >= 0) {
    const int e = free_;
    free_ = entries_[static_cast<std::size_t>(e)].next;
    entries_[static_cast<std::size_t>(e)] = {p, id, -1};
    return e;
  }
  entries_.push_back({p, id, -1});
  return static_cast<int>(entries_.size()) - 1;
}

void VertexGrid::insert(int id, const Eigen::Vector3d& p) {
  checkPoint(p, id, "insert");
  Slot& slot = cellSlot(key(p));  // may grow the table: before the entry, so a failure leaves the grid as it was
  const int e = newEntry(id, p);
  entries_[static_cast<std::size_t>(e)].next = slot.head;
  slot.head = e;
  ++size_;
}

int VertexGrid::locate(int id, const Eigen::Vector3d& p, const char* who) const {
  for (int e = cellHead(key(p)); e >= 0; e = entries_[static_cast<std::size_t>(e)].next) {
    const Entry& entry = entries_[static_cast<std::size_t>(e)];
    if (entry.id == id && entry.p == p) return e;
  }
  throw std::invalid_argument(std::string("VertexGrid::") + who + ": no entry for id " + std::to_string(id) + " at " +
                              core::formatPoint(p));
}

void VertexGrid::move(int id, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  checkPoint(to, id, "move");
  const int e = locate(id, from, "move");
  if (key(from) == key(to)) {
    entries_[static_cast<std::size_t>(e)].p = to;
    return;
  }
  insert(id, to);  // first, so a failed allocation leaves the entry where it was
  remove(id, from);
}

void VertexGrid::remove(int id, const Eigen::Vector3d& p) {
  const int e = locate(id, p, "remove");
  Slot& slot = slots_[slotOf(key(p))];
  if (slot.head == e) {
    slot.head = entries_[static_cast<std::size_t>(e)].next;
  } else {
    int before = slot.head;
    while (entries_[static_cast<std::size_t>(before)].next != e)
      before = entries_[static_cast<std::size_t>(before)].next;
    entries_[static_cast<std::size_t>(before)].next = entries_[static_cast<std::size_t>(e)].next;
  }
  entries_[static_cast<std::size_t>(e)].next = free_;
  free_ = e;
  --size_;
}

void VertexGrid::clear() noexcept {
  entries_.clear();
  free_ = -1;
  std::fill(slots_.begin(), slots_.end(), Slot{kEmptyKey, -1});
  cells_ = 0;
  size_ = 0;
}

void VertexGrid::appendHits(int head, const Eigen::AlignedBox3d& box, std::vector<int>& out) const {
  for (int e = head; e >= 0; e = entries_[static_cast<std::size_t>(e)].next)
    if (box.contains(entries_[static_cast<std::size_t>(e)].p)) out.push_back(entries_[static_cast<std::size_t>(e)].id);
}

void VertexGrid::query(const Eigen::AlignedBox3d& box, std::vector<int>& out) const {
  if (box.min().hasNaN() || box.max().hasNaN() || box.isEmpty() || size_ == 0) return;
  const std::size_t first = out.size();
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  const std::int64_t i0 = cellCoordinate(lo.x()), j0 = cellCoordinate(lo.y()), k0 = cellCoordinate(lo.z());
  const std::int64_t i1 = cellCoordinate(hi.x()), j1 = cellCoordinate(hi.y()), k1 = cellCoordinate(hi.z());
  const double box_cells = double(i1 - i0 + 1) * double(j1 - j0 + 1) * double(k1 - k0 + 1);
  if (box_cells > static_cast<double>(slots_.size())) {  // sparse grid, big box: visit every cell
    for (const Slot& slot : slots_)
      if (slot.key != kEmptyKey) appendHits(slot.head, box, out);
  } else {
    for (std::int64_t k = k0; k <= k1; ++k)
      for (std::int64_t j = j0; j <= j1; ++j)
        for (std::int64_t i = i0; i <= i1; ++i) appendHits(cellHead(pack(i, j, k)), box, out);
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

double suggestedCellSize(const TriMesh& mesh) {
  double total = 0.0;
  std::size_t count = 0;
  for (const auto e : mesh.edges()) {
    const double length = mesh.calc_edge_length(e);
    if (std::isfinite(length)) {
      total += length;
      ++count;
    }
  }
  if (count == 0 || !(total > 0.0) || !std::isfinite(total))
    throw std::invalid_argument("suggestedCellSize: the mesh has no edge of positive finite length (" +
                                std::to_string(count) + " finite edges)");
  return 2.0 * total / static_cast<double>(count);
}

}  // namespace incise::mesh
