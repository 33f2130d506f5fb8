// The pose queue: how poses travel from a device thread (HID, trace feeder) to the thread that consumes them
// (the sim thread, a recorder) — an SpscQueue of poses as plain values, and a devices::PoseSink, so a live
// source (devices::HidPoseSource) pushes into it directly.
//
// Threads: push from one producer thread, pop from one consumer thread (SpscQueue's rules). Cost: O(1), no
// allocation, no lock, never blocks. Failure: push returns false when full (the pose is dropped: the
// producer counts it); pop returns false when empty.
#pragma once

#include <cstddef>
#include <cstdint>

#include "incise/devices/pose_sample.h"
#include "incise/devices/pose_source.h"
#include "incise/sim/spsc_queue.h"

namespace incise::sim {

namespace detail {
// A pose as plain values: the queue's copies must not throw, and Eigen's assignments are not noexcept.
struct QueuedPose {
  double time_s = 0.0, tip[3] = {}, q[4] = {1.0, 0.0, 0.0, 0.0}, pressure = 0.0;
  std::uint32_t buttons = 0;
  bool has_pressure = false;
};

inline QueuedPose toQueued(const devices::PoseSample& pose) noexcept {
  QueuedPose q;
  q.time_s = pose.time_s;
  for (int a = 0; a < 3; ++a) q.tip[a] = pose.tip_m[a];
  q.q[0] = pose.orientation.w(), q.q[1] = pose.orientation.x(), q.q[2] = pose.orientation.y(),
  q.q[3] = pose.orientation.z();
  q.buttons = pose.buttons;
  q.has_pressure = pose.pressure.has_value();
  q.pressure = pose.pressure.value_or(0.0);
  return q;
}

inline devices::PoseSample fromQueued(const QueuedPose& q) noexcept {
  devices::PoseSample pose;
  pose.time_s = q.time_s;
  pose.tip_m = Eigen::Vector3d(q.tip[0], q.tip[1], q.tip[2]);
  pose.orientation = Eigen::Quaterniond(q.q[0], q.q[1], q.q[2], q.q[3]);
  pose.buttons = q.buttons;
  if (q.has_pressure) pose.pressure = q.pressure;
  return pose;
}
}  // namespace detail

template <std::size_t Capacity>
class PoseQueue final : public devices::PoseSink {
 public:
  bool push(const devices::PoseSample& pose) noexcept override { return queue_.tryPush(detail::toQueued(pose)); }
  bool pop(devices::PoseSample& out) noexcept {
    detail::QueuedPose q;
    if (!queue_.tryPop(q)) return false;
    out = detail::fromQueued(q);
    return true;
  }
  std::size_t sizeApprox() const noexcept { return queue_.sizeApprox(); }
  static constexpr std::size_t capacity() noexcept { return Capacity; }

 private:
  SpscQueue<detail::QueuedPose, Capacity> queue_;
};

}  // namespace incise::sim
