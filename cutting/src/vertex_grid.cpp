#include "incise/cutting/vertex_grid.h"

#include "incise/cutting/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace incise::cutting {

namespace {

constexpr std::int64_t kMaxCell = (std::int64_t{1} << 20) - 1;  // 21 bits per axis, signed
constexpr std::int64_t kMinCell = -(std::int64_t{1} << 20);

}  // namespace

VertexGrid::VertexGrid(double cell_size) : cell_size_(cell_size) {
  if (!std::isfinite(cell_size) || cell_size <= 0.0) {
    throw std::invalid_argument("VertexGrid: cell size must be finite and > 0, got " + formatNumber(cell_size));
  }
}

std::size_t VertexGrid::KeyHash::operator()(std::int64_t key) const noexcept {
  auto x = static_cast<std::uint64_t>(key);  // splitmix64 finaliser: packed keys are far from random
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<std::size_t>(x ^ (x >> 31));
}

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
    throw std::invalid_argument(std::string("VertexGrid::") + who + ": non-finite point " + formatPoint(p) +
                                " for id " + std::to_string(id));
}

void VertexGrid::insert(int id, const Eigen::Vector3d& p) {
  checkPoint(p, id, "insert");
  cells_[key(p)].push_back({id, p});
  ++size_;
}

VertexGrid::Location VertexGrid::locate(int id, const Eigen::Vector3d& p, const char* who) {
  if (const auto cell = cells_.find(key(p)); cell != cells_.end()) {
    const auto it =
        std::find_if(cell->second.begin(), cell->second.end(), [&](const Entry& e) { return e.id == id && e.p == p; });
    if (it != cell->second.end()) return {cell, it};
  }
  throw std::invalid_argument(std::string("VertexGrid::") + who + ": no entry for id " + std::to_string(id) + " at " +
                              formatPoint(p));
}

void VertexGrid::move(int id, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  checkPoint(to, id, "move");
  const Location at = locate(id, from, "move");
  if (key(from) == key(to)) {
    at.entry->p = to;
    return;
  }
  insert(id, to);  // first, so a failed allocation leaves the entry where it was
  remove(id, from);
}

void VertexGrid::remove(int id, const Eigen::Vector3d& p) {
  const auto [cell, it] = locate(id, p, "remove");
  *it = cell->second.back();
  cell->second.pop_back();
  if (cell->second.empty()) cells_.erase(cell);
  --size_;
}

void VertexGrid::clear() noexcept {
  cells_.clear();
  size_ = 0;
}

void VertexGrid::appendHits(const Cell& cell, const Eigen::AlignedBox3d& box, std::vector<int>& out) const {
  for (const Entry& e : cell)
    if (box.contains(e.p)) out.push_back(e.id);
}

void VertexGrid::query(const Eigen::AlignedBox3d& box, std::vector<int>& out) const {
  if (box.min().hasNaN() || box.max().hasNaN() || box.isEmpty()) return;
  const std::size_t first = out.size();
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  const std::int64_t i0 = cellCoordinate(lo.x()), j0 = cellCoordinate(lo.y()), k0 = cellCoordinate(lo.z());
  const std::int64_t i1 = cellCoordinate(hi.x()), j1 = cellCoordinate(hi.y()), k1 = cellCoordinate(hi.z());
  const double box_cells = double(i1 - i0 + 1) * double(j1 - j0 + 1) * double(k1 - k0 + 1);
  if (box_cells > static_cast<double>(cells_.size())) {  // sparse grid, big box: visit occupied cells
    for (const auto& [key, cell] : cells_) appendHits(cell, box, out);
  } else {
    for (std::int64_t k = k0; k <= k1; ++k)
      for (std::int64_t j = j0; j <= j1; ++j)
        for (std::int64_t i = i0; i <= i1; ++i)
          if (const auto cell = cells_.find(pack(i, j, k)); cell != cells_.end()) appendHits(cell->second, box, out);
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

}  // namespace incise::cutting
