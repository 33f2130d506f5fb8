#include "incise/devices/hid_pen_calibration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::devices {
namespace {

constexpr double kMinSpan = 0.05;  // of the tablet, between the corner presses in X and in Y

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

std::string percent(double fraction) { return std::to_string(std::lround(fraction * 100.0)) + "%"; }

}  // namespace

bool PenPressDetector::add(const PoseSample& pose) {
  const bool down = (pose.buttons & 1u) != 0;
  if (down) {
    if (!down_) {
      current_ = PenPress{};
      current_.start_s = pose.time_s;
      fx_.clear();
      fy_.clear();
    }
    const PenReading r = penReadingFor(reading_, pose);
    fx_.push_back(r.fx);
    fy_.push_back(r.fy);
    if (pose.pressure) current_.pressures.push_back(*pose.pressure);
    current_.end_s = pose.time_s;
    down_ = true;
    return false;
  }
  if (!down_) return false;
  down_ = false;
  current_.fx = median(fx_);
  current_.fy = median(fy_);
  done_ = current_;
  return true;
}

PenCalibration calibratePen(const PenMapping& target, const PenPress& corner, const PenPress& opposite,
                            const PenPress* pressure) {
  PenCalibration c;
  c.x0 = std::min(corner.fx, opposite.fx), c.x1 = std::max(corner.fx, opposite.fx);
  c.y0 = std::min(corner.fy, opposite.fy), c.y1 = std::max(corner.fy, opposite.fy);
  const double w = c.x1 - c.x0, h = c.y1 - c.y0;
  if (!(w >= kMinSpan && h >= kMinSpan))
    throw std::invalid_argument("the two corner presses are " + percent(w) + " of the tablet apart in X and " +
                                percent(h) + " in Y: press at opposite corners of the area (at least " +
                                percent(kMinSpan) + " apart in each)");
  c.mapping = target;
  c.mapping.origin_m = target.origin_m - (c.x0 / w) * target.x_edge_m - (c.y0 / h) * target.y_edge_m;
  c.mapping.x_edge_m = target.x_edge_m / w;
  c.mapping.y_edge_m = target.y_edge_m / h;
  if (pressure == nullptr || pressure->pressures.empty()) return c;
  const double dead_band = *std::min_element(pressure->pressures.begin(), pressure->pressures.end());
  const double firm = median(pressure->pressures);
  c.firm_pressure = firm;
  if (!(firm > dead_band && dead_band < 0.99))
    throw std::invalid_argument("the pressure press held no firmer than its lightest reading (" + std::to_string(firm) +
                                "): press once, firmly, and hold a moment");
  c.mapping.dead_band = dead_band;
  const double t = (firm - dead_band) / (1.0 - dead_band);
  c.mapping.curve = std::clamp(std::log(0.5) / std::log(t), 0.1, 10.0);
  return c;
}

}  // namespace incise::devices
