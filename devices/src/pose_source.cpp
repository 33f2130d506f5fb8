#include "incise/devices/pose_source.h"

namespace incise::devices {

// Out of line so that the vtable has one home.
PoseSource::~PoseSource() = default;
PoseSink::~PoseSink() = default;

std::optional<PoseSample> VectorPoseSource::next() {
  if (next_ >= samples_.size()) return std::nullopt;
  return samples_[next_++];
}

std::string VectorPoseSource::describe() const {
  return "in-memory samples (" + std::to_string(next_) + " of " + std::to_string(samples_.size()) + " read)";
}

}  // namespace incise::devices
