// A reader's copy of the tet cutter's working mesh, rebuilt from a GeometryStream's tet records
// (geometry_stream.h; GeometryMirror forwards them here), and the tet mesh's boundary kept up to date as
// tets change: every triangle that belongs to exactly one tet, oriented outwards. A viewer draws
// boundary(); a test compares it with tets::boundaryFaces of the cutter's view().
//
// Shapes: positions_m()[n] (metres, the cutter's deformed doubles bit for bit), indexed as the cutter's
// nodes (some unused); children(b) the pieces of base tet b (nodes in the cutter's order, positively
// oriented). boundary(): triangles of node indices, counter-clockwise seen from outside
// (tets::faceOpposite's convention; each starts at its smallest index). Threads: the reader's (the one that pulls the GeometryMirror).
// Cost: O(1) per node record, O(children) per tet record (a hash map of faces, updated as tets come and
// go); boundary() O(faces). Failure: nothing throws but std::bad_alloc.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "incise/sim/geometry_stream.h"

namespace incise::sim {

class TetMirror {
 public:
  // A TetReset, TetNode or Tet record; Frame records go to frame().
  void apply(const GeometryRecord& record);
  void frame(std::uint8_t flags) noexcept { flags_ = flags; }

  // The tet part arrived whole since its last TetReset (and nothing is waiting either): the stream's
  // kFrameTetsComplete / kFrameTetsExact at the last Frame record. Never before a tet tissue's first one.
  bool complete() const noexcept { return (flags_ & kFrameTetsComplete) != 0; }
  bool exact() const noexcept { return (flags_ & kFrameTetsExact) != 0; }
  bool present() const noexcept { return resets_ > 0; }
  std::int64_t resets() const noexcept { return resets_; }
  // Bumped by every record applied: a reader redraws when it differs from the one it drew.
  std::uint64_t version() const noexcept { return version_; }

  const std::vector<std::array<double, 3>>& positions_m() const noexcept { return positions_m_; }
  std::size_t tetCount() const noexcept { return tets_; }
  // The boundary's triangles and, when `on_cut` is given, 1 for each that lies on a cut (a wound's wall), 0
  // for the original surface's; sorted by their nodes.
  std::vector<std::array<std::int32_t, 3>> boundary(std::vector<std::uint8_t>* on_cut = nullptr) const;

  // One piece of a base tet: its nodes (positively oriented), its side of the cut (-1 / +1; 0: not cut) and
  // which of its faces lie on the cut (bit i: the face opposite node i).
  struct Child {
    std::array<std::int32_t, 4> nodes;
    std::int8_t side;
    std::uint8_t cut_faces;
  };
  std::size_t baseTetCount() const noexcept { return children_.size(); }
  // The pieces of base tet `base` now (empty for a base tet past baseTetCount()).
  std::span<const Child> children(std::size_t base) const noexcept {
    return base < children_.size() ? std::span<const Child>(children_[base]) : std::span<const Child>();
  }

 private:
  struct FaceKey {
    std::int32_t a, b, c;  // sorted
    bool operator==(const FaceKey&) const = default;
  };
  struct FaceHash {
    std::size_t operator()(const FaceKey& k) const noexcept;
  };
  struct FaceUse {
    int count = 0;     // tets holding the face
    int parity = 0;    // the sum over them of +1 when the face's outward triple is a rotation of the sorted
                       // key, else -1 (two tets on opposite sides cancel; one alone gives its orientation)
    bool cut = false;  // on the cut (as the tet that added it last says)
  };
  void reset(std::uint32_t nodes, std::uint32_t bases);
  void setChildren(std::uint32_t base, const GeometryRecord& record);
  void addFaces(const Child& child, int sign);

  std::vector<std::array<double, 3>> positions_m_;
  std::vector<std::vector<Child>> children_;  // per base tet
  std::unordered_map<FaceKey, FaceUse, FaceHash> faces_;
  std::size_t tets_ = 0;
  std::int64_t resets_ = 0;
  std::uint64_t version_ = 0;
  std::uint8_t flags_ = 0;
};

}  // namespace incise::sim
