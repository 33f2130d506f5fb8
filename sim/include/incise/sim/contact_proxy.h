// The haptic part's own copy of the skin around the scalpel (ARCHITECTURE.md, "One frame"): the
// cut phase copies the skin faces near the blade's probe out of the tissue (SurfaceCutter::skinNear: at
// rest for the current incision, walls left out, as SurfaceCutter::intersect sees it) into a fixed array,
// and the next frame's haptic part finds its contact there alone: no grid query, no mesh, nothing the cut
// is changing. The copy covers a region (the probe's box grown by `reach_m`, the distance the blade may move
// before the cut phase refills it); a probe outside it finds nothing (counted as a miss: the tool jumped).
//
// Shapes: metres; triangles counter-clockwise with outward unit normals. Capacity kCapacity triangles:
// a refill that finds more keeps the first kCapacity and counts the overflow (on the shipped 235k and 940k
// bunnies a 4 mm reach held about 150 and 600 faces; World sets it from the frame period: 2 mm at 1 kHz).
// Cost: refill O(vertices in the grown box + their faces) (cut phase); firstCrossing O(triangles) (haptic
// part: one Moller-Trumbore test each, about 5 ns). Allocation: the array at construction only.
// Threads: one owner, the sim thread. Never throws after construction.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

// OpenMesh stays out of sim's public headers: the triangles' type is complete in contact_proxy.cpp only.
namespace incise::mesh {
struct SkinTriangle;
}
namespace incise::incision {
class SurfaceCutter;
}

namespace incise::sim {

struct ProxyHit {
  Eigen::Vector3d point_m;
  Eigen::Vector3d normal;  // outward
  double t = 0.0;          // along the segment, in [0, 1]
};

class ContactProxy {
 public:
  static constexpr int kCapacity = 2048;

  ContactProxy();
  ~ContactProxy();
  ContactProxy(const ContactProxy&) = delete;
  ContactProxy& operator=(const ContactProxy&) = delete;

  // Cut phase: the skin within `reach_m` of the box around segment a-b (the blade's probe), from `cutter`.
  // `stamp` names the surface it was taken from (World: the incision count); refills() asks whether a new
  // one is due.
  void refill(const incision::SurfaceCutter& cutter, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double reach_m,
              int stamp) noexcept;
  // Due when segment a-b is not within the region shrunk by half the reach (the blade got close to its
  // edge) or the surface is another one.
  bool refillDue(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int stamp) const noexcept;
  // Both ends of a-b within the region: a crossing, if any, is among the triangles held.
  bool covers(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept;
  // The crossing of a -> b nearest a among the triangles held (nullopt: none, or a non-finite segment).
  std::optional<ProxyHit> firstCrossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept;

  int size() const noexcept { return count_; }
  std::int64_t refills() const noexcept { return refills_; }
  std::int64_t overflows() const noexcept { return overflows_; }  // refills that found more than kCapacity
  int largest() const noexcept { return largest_; }               // the most faces a refill found

 private:
  std::vector<mesh::SkinTriangle> triangles_;  // kCapacity, filled to count_
  int count_ = 0;
  Eigen::AlignedBox3d region_;  // empty until the first refill
  double reach_m_ = 0.0;
  int stamp_ = -1;
  std::int64_t refills_ = 0, overflows_ = 0;
  int largest_ = 0;
};

}  // namespace incise::sim
