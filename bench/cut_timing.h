// The incision benchmarks' timed loop: a stroke cut sample by sample as the simulation would, the time of
// begin() and of every extend() in microseconds (steady clock). One definition for the incision and
// refinement benchmarks. Allocates the result (outside the timed calls).
#pragma once

#include <chrono>
#include <vector>

#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"

namespace incise::bench {

inline std::vector<double> timeSamples(incision::SurfaceCutter& cutter, const incision::Stroke& stroke) {
  using Clock = std::chrono::steady_clock;
  std::vector<double> sample_us;
  sample_us.reserve(stroke.samples.size() + 1);
  auto start = Clock::now();
  cutter.begin(stroke.first, stroke.blade_direction);
  sample_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  for (const incision::StrokeSample& sample : stroke.samples) {
    start = Clock::now();
    cutter.extend(sample);
    sample_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  return sample_us;
}

}  // namespace incise::bench
