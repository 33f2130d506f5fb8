// GeometryStream's tet part (geometry_stream.h): the tet cutter's working mesh, nodes and base tets' children,
// through their own dirty queues and sweep. Thread: the writer (the sim thread). Cost: O(journal entries) to
// mark, O(budget) to write. The tet cutter never renumbers its mesh after load (a new incision's rebase
// appends base tets and reports the ones it changed), so the reader follows every incision without a reset.
#include <algorithm>

#include "incise/sim/geometry_stream.h"
#include "incise/sim/world.h"
#include "incise/tets/tet_cutter.h"

namespace incise::sim {

void GeometryStream::takeTets(const World& world) noexcept {
  const tets::TetCutter* cutter = world.tets();
  if (!cutter) return;
  const tets::TetChanges& changes = cutter->changes();
  try {
    for (const int n : changes.nodes) tets_.nodes.mark(static_cast<std::size_t>(n), counters_.regrowths);
    for (const int t : changes.base_tets) tets_.bases.mark(static_cast<std::size_t>(t), counters_.regrowths);
  } catch (...) {  // out of memory growing the flags: a reader re-syncs everything
    requestReset();
  }
}

void GeometryStream::startTetReset(const World& world, std::int64_t frame) noexcept {
  const tets::TetCutter& cutter = *world.tets();
  const auto nodes = static_cast<std::uint32_t>(cutter.nodeCount());
  const auto bases = static_cast<std::uint32_t>(cutter.baseTetCount());
  GeometryRecord& r = next();
  r.type = GeometryRecordType::TetReset;
  r.index = 0;
  r.info = {frame, nodes, bases, 0, 0};
  for (std::uint8_t& f : tets_.nodes.flag) f &= static_cast<std::uint8_t>(~kSent);  // the reader starts over
  tets_.reset_pending = false;
  tets_.sweeping = true;
  tets_.swept = false;
  tets_.sweep_node = tets_.sweep_base = 0;
  tets_.sweep_nodes = nodes, tets_.sweep_bases = bases;
}

std::size_t GeometryStream::writeTetNodes(const World& world, std::size_t budget) noexcept {
  const tets::TetCutter& cutter = *world.tets();
  const auto emit = [&](std::uint32_t n) {
    if (n >= tets_.nodes.flag.size()) return;  // a swept node past the flags: cannot happen after attach()
    tets_.nodes.flag[n] |= kSent;
    const Eigen::Vector3d& x = cutter.nodePosition(static_cast<int>(n));
    GeometryRecord& r = next();
    r.type = GeometryRecordType::TetNode;
    r.kind = 0;
    r.index = n;
    r.position_m[0] = x[0], r.position_m[1] = x[1], r.position_m[2] = x[2];
  };
  std::size_t n = 0;
  for (; n < budget && !tets_.nodes.empty(); ++n) emit(tets_.nodes.pop());
  for (; n < budget && tets_.sweeping && tets_.sweep_node < tets_.sweep_nodes; ++n) emit(tets_.sweep_node++);
  return n;
}

// All of a base tet's children at once, if the budget holds them and the reader has their nodes; false
// (nothing written) otherwise.
bool GeometryStream::sendTets(const World& world, std::uint32_t base, std::size_t& budget) noexcept {
  const std::span<const tets::TetChild> children = world.tets()->children(static_cast<int>(base));
  if (std::max<std::size_t>(children.size(), 1) > budget) return false;
  for (const tets::TetChild& c : children)
    for (const int n : c.nodes)
      if (static_cast<std::size_t>(n) >= tets_.nodes.flag.size() ||
          !(tets_.nodes.flag[static_cast<std::size_t>(n)] & kSent))
        return false;
  for (std::size_t slot = 0; slot < children.size(); ++slot) {
    GeometryRecord& r = next();
    r.type = GeometryRecordType::Tet;
    r.kind = static_cast<std::uint8_t>(slot);
    r.index = base;
    for (int i = 0; i < 4; ++i) r.tet.nodes[i] = children[slot].nodes[static_cast<std::size_t>(i)];
    r.tet.count = static_cast<std::uint8_t>(children.size());
    r.tet.side = children[slot].side;
    r.tet.cut_faces = children[slot].cut_faces;
  }
  if (children.empty()) {  // no piece left: the reader drops the base tet's children
    GeometryRecord& r = next();
    r.type = GeometryRecordType::Tet;
    r.kind = 0;
    r.index = base;
    r.tet = {{-1, -1, -1, -1}, 0, 0, 0};
  }
  budget -= std::max<std::size_t>(children.size(), 1);
  return true;
}

// Nodes first (queued, then swept), then base tets (queued, then swept once the sweep's nodes have gone).
// A base tet that cannot go yet goes to the back of its queue; each one looked at costs one of the budget.
std::size_t GeometryStream::writeTets(const World& world, std::size_t budget) noexcept {
  if (!tets_.present || budget == 0) return 0;
  std::size_t left = budget - writeTetNodes(world, budget);
  for (std::size_t tries = std::min(tets_.bases.count, left); tries > 0 && left > 0; --tries) {
    const std::uint32_t base = tets_.bases.pop();
    if (!sendTets(world, base, left)) {
      tets_.bases.mark(base, counters_.regrowths);  // room for it: it was just popped
      --left;
    }
  }
  if (!tets_.sweeping || tets_.sweep_node < tets_.sweep_nodes) return budget - left;
  while (left > 0 && tets_.sweep_base < tets_.sweep_bases) {
    if (!sendTets(world, tets_.sweep_base, left)) {
      if (world.tets()->children(static_cast<int>(tets_.sweep_base)).size() > left) break;  // next frame
      tets_.bases.mark(tets_.sweep_base, counters_.regrowths);  // a node still queued: later
      --left;
    }
    ++tets_.sweep_base;
  }
  if (tets_.sweep_base == tets_.sweep_bases) tets_.sweeping = false, tets_.swept = true;
  return budget - left;
}

std::size_t GeometryStream::tetBacklog() const noexcept {
  if (!tets_.present) return 0;
  return tets_.nodes.count + tets_.bases.count + (tets_.reset_pending ? 1 : 0) +
         (tets_.sweeping ? (tets_.sweep_nodes - tets_.sweep_node) + (tets_.sweep_bases - tets_.sweep_base) : 0);
}

std::uint8_t GeometryStream::tetFlags() const noexcept {
  if (!tets_.present || !tets_.swept || tets_.reset_pending) return 0;
  return static_cast<std::uint8_t>(kFrameTetsComplete | (tetBacklog() == 0 ? kFrameTetsExact : 0));
}

}  // namespace incise::sim
