// Where poses come from: a device, a recorded trace, a test's vector. The simulation pulls samples from a
// PoseSource on a device thread and hands them to the sim thread through a queue; it never sees the
// concrete source.
//
// Threads: next() is called from one thread (the device/reader thread), never concurrently;
// describe() from that thread too, or while no thread calls next(). Implementations need no locks.
// Failure: next() throws when the source is broken in a way it cannot skip (a trace's bad line throws
// devices::TraceError); the caller reports describe() with the error and stops reading.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "incise/devices/pose_sample.h"

namespace incise::devices {

class PoseSource {
 public:
  virtual ~PoseSource();

  // The next sample, or std::nullopt at the end (and on every call after that). A live device blocks
  // until its next reading; a trace returns immediately (pacing is the caller's business).
  virtual std::optional<PoseSample> next() = 0;
  // For logs and error messages: what the source is and where it stands ("trace 'a.csv' (line 17)").
  virtual std::string describe() const = 0;

 protected:
  PoseSource() = default;
  PoseSource(const PoseSource&) = default;
  PoseSource(PoseSource&&) = default;
  PoseSource& operator=(const PoseSource&) = default;
  PoseSource& operator=(PoseSource&&) = default;
};

// Where a live source (a device thread) puts its samples: the simulation's pose queue, a recorder's.
// push is called on the device thread for every sample and must not block or allocate (a queue); false
// means the sample was dropped (queue full), which the source counts.
class PoseSink {
 public:
  virtual ~PoseSink();
  virtual bool push(const PoseSample& sample) noexcept = 0;

 protected:
  PoseSink() = default;
  PoseSink(const PoseSink&) = default;
  PoseSink& operator=(const PoseSink&) = default;
};

// Samples held in memory, returned in order, as given (no validation). For tests and for scripted input.
// Cost O(1) per sample (a copy).
class VectorPoseSource final : public PoseSource {
 public:
  explicit VectorPoseSource(std::vector<PoseSample> samples) : samples_(std::move(samples)) {}

  std::optional<PoseSample> next() override;
  std::string describe() const override;

  // How many samples next() has returned so far.
  std::size_t consumed() const { return next_; }

 private:
  std::vector<PoseSample> samples_;
  std::size_t next_ = 0;
};

}  // namespace incise::devices
