// Calibrating a pen mapping (hid_profile.h, PenMapping) from presses on the tablet, as `incise hid
// calibrate` asks for them: two presses at opposite corners of the part of the tablet that is to lie over the
// tissue, then one press as firm as a cut to half of max_depth_m.
//
// Units: tablet fractions, normalised pressure, metres. Threads: one owner. Cost: O(poses) (each press keeps
// its poses' fractions and pressures). Failure: calibratePen throws std::invalid_argument when the corner
// presses are less than 5% of the tablet apart in X or in Y ("press at opposite corners"), or when the firm
// press is no firmer than the dead band.
#pragma once

#include <optional>
#include <vector>

#include "incise/devices/hid_profile.h"
#include "incise/devices/pose_sample.h"

namespace incise::devices {

struct PenPress {
  double fx = 0.0, fy = 0.0;      // median position, tablet fractions
  std::vector<double> pressures;  // while down, in order (empty for a pen without pressure)
  double start_s = 0.0, end_s = 0.0;
};

// Presses. PenPressDetector reads the poses a pen profile makes with any mapping (the one it is given, to
// invert it with penReadingFor): a press runs from the first pose with the cut bit (button 0: the tip down)
// to the first pose without it; its position is the median of its poses' tablet fractions (fx, fy in 0..1,
// steady against the slide of a landing pen), its pressures the poses' normalised pressures.
class PenPressDetector {
 public:
  // `reading` is the mapping the profile that makes the poses uses.
  explicit PenPressDetector(const PenMapping& reading) : reading_(reading) {}
  // True when `pose` ends a press (press() holds it until the next one ends).
  bool add(const PoseSample& pose);
  const PenPress& press() const { return done_; }

 private:
  PenMapping reading_;
  bool down_ = false;
  std::vector<double> fx_, fy_;
  PenPress current_, done_;
};

struct PenCalibration {
  PenMapping mapping;                             // `target` with the area, dead_band and curve calibrated
  double x0 = 0.0, y0 = 0.0, x1 = 1.0, y1 = 1.0;  // the area on the tablet, fractions
  std::optional<double> firm_pressure;            // the pressure press's median (nullopt: none)
};

// `pressure` may be null (no third press, or a pen without pressure).
// The area. The two corner presses span [min fx, max fx] x [min fy, max fy] of the tablet (in either order:
// the tablet's X stays along x_edge_m, so up does not flip); calibratePen lays that onto the rectangle of
// `target` (the scenario's current origin_m, x_edge_m, y_edge_m): origin' = origin - x0/w * x_edge - y0/h *
// y_edge, x_edge' = x_edge / w, y_edge' = y_edge / h for the span's corner (x0, y0), width w and height h.
// The pressure. dead_band = the lightest pressure the pen reported while down (below it nothing cuts: the
// pen's activation force), firm = the median pressure of the press; curve is chosen so that firm gives half
// of max_depth_m: ((firm - dead_band) / (1 - dead_band))^curve = 0.5, clamped to the 0.1..10 a scenario allows.
// Without pressure (or without a pressure press) dead_band and curve are left as `target` has them.
PenCalibration calibratePen(const PenMapping& target, const PenPress& corner, const PenPress& opposite,
                            const PenPress* pressure);

}  // namespace incise::devices
