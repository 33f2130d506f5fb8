#include "incise/sim/tet_mirror.h"

#include <algorithm>

#include "incise/tets/tet_mesh.h"

namespace incise::sim {

std::size_t TetMirror::FaceHash::operator()(const FaceKey& k) const noexcept {
  std::uint64_t h = static_cast<std::uint32_t>(k.a);
  h = h * 0x9e3779b97f4a7c15ULL ^ static_cast<std::uint32_t>(k.b);
  h = h * 0x9e3779b97f4a7c15ULL ^ static_cast<std::uint32_t>(k.c);
  return static_cast<std::size_t>(h ^ (h >> 29));
}

void TetMirror::reset(std::uint32_t nodes, std::uint32_t bases) {
  positions_m_.assign(nodes, {0.0, 0.0, 0.0});
  children_.assign(bases, {});
  faces_.clear();
  faces_.reserve(static_cast<std::size_t>(bases) * 3);
  tets_ = 0;
  flags_ = 0;
  ++resets_;
}

// +1: the child's four faces are added; -1: removed (a face whose count drops to 0 is forgotten).
void TetMirror::addFaces(const Child& child, int sign) {
  const std::array<int, 4> t = {child.nodes[0], child.nodes[1], child.nodes[2], child.nodes[3]};
  for (int i = 0; i < 4; ++i) {
    const std::array<int, 3> f = tets::faceOpposite(t, i);
    std::array<std::int32_t, 3> s = {f[0], f[1], f[2]};
    std::sort(s.begin(), s.end());
    const FaceKey key{s[0], s[1], s[2]};
    // f is a rotation of s (even) or of s with its last two swapped (odd).
    const bool even =
        (f[0] == s[0] && f[1] == s[1]) || (f[1] == s[0] && f[2] == s[1]) || (f[2] == s[0] && f[0] == s[1]);
    if (sign > 0) {
      FaceUse& use = faces_[key];
      ++use.count;
      use.parity += even ? 1 : -1;
      use.cut = (child.cut_faces >> i & 1u) != 0;
    } else if (const auto it = faces_.find(key); it != faces_.end()) {
      it->second.parity -= even ? 1 : -1;
      if (--it->second.count <= 0) faces_.erase(it);
    }
  }
}

// Slot 0 replaces the base tet's children (its old ones' faces removed); each slot adds its child.
void TetMirror::setChildren(std::uint32_t base, const GeometryRecord& r) {
  if (base >= children_.size()) children_.resize(base + 1);
  std::vector<Child>& children = children_[base];
  if (r.kind == 0) {
    for (const Child& c : children) addFaces(c, -1);
    tets_ -= children.size();
    children.clear();
  }
  if (r.tet.count == 0) return;
  const Child child{{r.tet.nodes[0], r.tet.nodes[1], r.tet.nodes[2], r.tet.nodes[3]}, r.tet.side, r.tet.cut_faces};
  for (const std::int32_t n : child.nodes)
    if (n < 0 || static_cast<std::size_t>(n) >= positions_m_.size()) return;  // never sent so: ignore
  children.push_back(child);
  ++tets_;
  addFaces(child, +1);
}

void TetMirror::apply(const GeometryRecord& r) {
  switch (r.type) {
    case GeometryRecordType::TetReset:
      reset(r.info.vertices, r.info.faces);
      break;
    case GeometryRecordType::TetNode:
      if (!present()) return;
      if (r.index >= positions_m_.size()) positions_m_.resize(r.index + 1, {0.0, 0.0, 0.0});
      positions_m_[r.index] = {r.position_m[0], r.position_m[1], r.position_m[2]};
      break;
    case GeometryRecordType::Tet:
      if (!present()) return;
      setChildren(r.index, r);
      break;
    default:
      return;
  }
  ++version_;
}

std::vector<std::array<std::int32_t, 3>> TetMirror::boundary(std::vector<std::uint8_t>* on_cut) const {
  std::vector<std::pair<std::array<std::int32_t, 3>, bool>> found;
  for (const auto& [key, use] : faces_)
    if (use.count == 1)
      found.push_back({use.parity > 0 ? std::array<std::int32_t, 3>{key.a, key.b, key.c}
                                      : std::array<std::int32_t, 3>{key.a, key.c, key.b},
                       use.cut});
  std::sort(found.begin(), found.end());  // a stable order (the map's is not)
  std::vector<std::array<std::int32_t, 3>> out;
  out.reserve(found.size());
  if (on_cut) on_cut->clear();
  for (const auto& [face, cut] : found) {
    out.push_back(face);
    if (on_cut) on_cut->push_back(cut ? 1 : 0);
  }
  return out;
}

}  // namespace incise::sim
