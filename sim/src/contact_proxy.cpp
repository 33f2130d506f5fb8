#include "incise/sim/contact_proxy.h"

#include <algorithm>
#include <span>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_query.h"

namespace incise::sim {

namespace {

Eigen::AlignedBox3d segmentBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double grow_m) {
  Eigen::AlignedBox3d box(a.cwiseMin(b), a.cwiseMax(b));
  box.min().array() -= grow_m;
  box.max().array() += grow_m;
  return box;
}

}  // namespace

ContactProxy::ContactProxy() : triangles_(kCapacity) {}
ContactProxy::~ContactProxy() = default;

void ContactProxy::refill(const incision::SurfaceCutter& cutter, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          double reach_m, int stamp) noexcept {
  if (!a.allFinite() || !b.allFinite() || !(reach_m > 0.0)) return;
  region_ = segmentBox(a, b, reach_m);
  reach_m_ = reach_m;
  stamp_ = stamp;
  int found = 0;
  try {
    found = cutter.skinNear(region_, std::span(triangles_));
  } catch (...) {  // the cutter's scratch grew and allocation failed: an empty proxy (no contact) this time
    found = 0;
  }
  count_ = std::min(found, kCapacity);
  largest_ = std::max(largest_, found);
  ++refills_;
  if (found > kCapacity) ++overflows_;
}

bool ContactProxy::refillDue(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int stamp) const noexcept {
  if (stamp != stamp_ || region_.isEmpty()) return true;
  return !region_.contains(segmentBox(a, b, 0.5 * reach_m_));
}

bool ContactProxy::covers(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept {
  return !region_.isEmpty() && region_.contains(a) && region_.contains(b);
}

std::optional<ProxyHit> ContactProxy::firstCrossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const noexcept {
  if (!a.allFinite() || !b.allFinite()) return std::nullopt;
  std::optional<ProxyHit> best;
  double best_t = 1.0;
  for (int i = 0; i < count_; ++i) {
    const mesh::SkinTriangle& tri = triangles_[static_cast<std::size_t>(i)];
    const auto t = mesh::segmentTriangle(a, b, tri.corners_m[0], tri.corners_m[1], tri.corners_m[2]);
    if (!t || *t > best_t) continue;
    best_t = *t;
    best = ProxyHit{a + *t * (b - a), tri.normal, *t};
  }
  return best;
}

}  // namespace incise::sim
