#include "incise/sim/smoothness.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <unsupported/Eigen/FFT>

namespace incise::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool usable(std::span<const double> speed, double dt_s) {
  if (speed.size() < 4 || !(dt_s > 0.0)) return false;
  return std::any_of(speed.begin(), speed.end(), [](double v) { return v > 0.0; });
}

}  // namespace

std::vector<double> speedProfile(std::span<const Eigen::Vector3d> positions_m, double dt_s) {
  std::vector<double> speed;
  if (positions_m.size() < 2 || !(dt_s > 0.0)) return speed;
  speed.reserve(positions_m.size() - 1);
  for (std::size_t k = 0; k + 1 < positions_m.size(); ++k)
    speed.push_back((positions_m[k + 1] - positions_m[k]).norm() / dt_s);
  return speed;
}

// LDLJ = -ln( T^3 / v_peak^2 * sum_k (v[k+1] - 2 v[k] + v[k-1])^2 / dt^4 * dt ), T = n dt (Balasubramanian
// et al. 2015, the dimensionless jerk of the speed profile, "max" normalisation).
double logDimensionlessJerk(std::span<const double> speed, double dt_s) {
  if (!usable(speed, dt_s)) return kNaN;
  const double peak = *std::max_element(speed.begin(), speed.end());
  double integral = 0.0;
  for (std::size_t k = 1; k + 1 < speed.size(); ++k) {
    const double second = (speed[k + 1] - 2.0 * speed[k] + speed[k - 1]) / (dt_s * dt_s);
    integral += second * second * dt_s;
  }
  const double duration_s = static_cast<double>(speed.size()) * dt_s;
  const double dimensionless = std::pow(duration_s, 3) / (peak * peak) * integral;
  // A perfectly constant speed has no jerk at all: the smoothest possible, +infinity; capped so that the
  // figure stays a number in JSON (e^-50: far beyond any measured movement).
  return -std::log(std::max(dimensionless, std::exp(-50.0)));
}

// SPARC: the arc length of the normalised magnitude spectrum up to the adaptive cut-off, the frequency axis
// normalised by that cut-off (Balasubramanian et al. 2015, Eq. 5-6).
double spectralArcLength(std::span<const double> speed, double dt_s, const SparcOptions& o) {
  if (!usable(speed, dt_s)) return kNaN;
  // Padded to 2^(ceil(log2 n) + pad_level) points, at most 2^22 (64 MiB of spectrum: a 70 minute session at
  // 1 kHz pads less), never fewer than the samples.
  const int need = static_cast<int>(std::ceil(std::log2(static_cast<double>(speed.size()))));
  const std::size_t n = std::size_t{1} << std::max(need, std::clamp(need + o.pad_level, 4, 22));
  std::vector<double> padded(n, 0.0);
  std::copy(speed.begin(), speed.end(), padded.begin());
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, padded);
  const double df_hz = 1.0 / (static_cast<double>(n) * dt_s);
  const std::size_t last = std::min(n / 2, static_cast<std::size_t>(std::floor(o.max_cutoff_hz / df_hz)));
  std::vector<double> magnitude(last + 1);
  double peak = 0.0;
  for (std::size_t k = 0; k <= last; ++k) peak = std::max(peak, magnitude[k] = std::abs(spectrum[k]));
  if (!(peak > 0.0)) return kNaN;
  for (double& m : magnitude) m /= peak;
  std::size_t first_kept = 0, last_kept = 0;
  bool any = false;
  for (std::size_t k = 0; k <= last; ++k) {
    if (magnitude[k] < o.threshold) continue;
    if (!any) first_kept = k;
    last_kept = k;
    any = true;
  }
  if (!any || last_kept == first_kept) return 0.0;  // a spectrum with one bin above the threshold: a flat line
  const double span_hz = static_cast<double>(last_kept - first_kept) * df_hz;
  double length = 0.0;
  for (std::size_t k = first_kept; k < last_kept; ++k) {
    const double dm = magnitude[k + 1] - magnitude[k];
    length += std::sqrt((df_hz / span_hz) * (df_hz / span_hz) + dm * dm);
  }
  return -length;
}

}  // namespace incise::sim
