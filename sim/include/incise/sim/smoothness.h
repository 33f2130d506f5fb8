// Movement smoothness of a speed profile, the two measures of Balasubramanian, Melendez-Calderon,
// Roby-Brami and Burdet, "On the analysis of movement smoothness", J. NeuroEngineering and Rehabilitation
// 12:112 (2015); both are computed on the speed profile v(t), as in that paper and its reference code.
// The formulas are above logDimensionlessJerk and spectralArcLength.
//
// Units: metres, seconds; the measures are dimensionless. Threads: any. Cost: LDLJ O(n), SPARC O(N log N)
// with N the padded length. Failure: NaN for fewer than 4 samples, a non-positive dt or a speed that is
// zero throughout (no movement: nothing to be smooth about); never throws.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

namespace incise::sim {

struct SparcOptions {
  double max_cutoff_hz = 10.0;  // wc_max
  double threshold = 0.05;      // of the normalised spectrum
  int pad_level = 4;            // zero padding: 2^(ceil(log2 n) + pad_level) points
};

// The speed comes from positions sampled at a fixed interval dt_s (speedProfile: |p[k+1] - p[k]| / dt).
// Derivatives are finite differences: d^2v/dt^2 ~ (v[k+1] - 2 v[k] + v[k-1]) / dt^2, the integral a sum
// times dt. The FFT is Eigen's (unsupported/Eigen/FFT, kissfft inside), not hand-rolled.
std::vector<double> speedProfile(std::span<const Eigen::Vector3d> positions_m, double dt_s);
// Log dimensionless jerk: LDLJ = -ln( (t2 - t1)^3 / v_peak^2 * integral_t1^t2 |d^2 v / dt^2|^2 dt ) (the
// jerk of the path is the second derivative of the speed; the paper's Eq. for the dimensionless jerk,
// normalised by the peak speed). Smoother: higher (less negative).
double logDimensionlessJerk(std::span<const double> speed_m_per_s, double dt_s);
// Spectral arc length: SPARC = -integral_0^wc sqrt( (1 / wc)^2 + (dV^(w) / dw)^2 ) dw, with
//   V^(w) = |V(w)| / |V(0)| the Fourier magnitude spectrum of v normalised by its DC value,
//   wc = min(wc_max, max{w : V^(r) >= threshold for r <= w}) the adaptive cut-off (the paper's Eq. 5-6;
//   wc_max = 10 Hz, threshold 0.05, the spectrum zero-padded to 2^(ceil(log2 n) + 4) points, at most 2^22
//   unless n is larger).
// Smoother: closer to 0 (a single Gaussian bump gives about -1.4); jerky movements are more negative.
double spectralArcLength(std::span<const double> speed_m_per_s, double dt_s, const SparcOptions& options = {});

}  // namespace incise::sim
