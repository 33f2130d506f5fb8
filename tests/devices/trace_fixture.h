// Shared by the devices tests: unique temporary files, random valid samples, bit-exact comparison.
#pragma once

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/devices/pose_sample.h"

namespace incise::devices::testing {

// A path under the system temp directory, unique per process and call; removed on destruction.
class TempPath {
 public:
  explicit TempPath(const std::string& stem) {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("incise_devices_" + stem + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".csv");
    std::filesystem::remove(path_);
  }
  ~TempPath() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TempPath(const TempPath&) = delete;
  TempPath& operator=(const TempPath&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string string() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::uint64_t bits(double value) {
  std::uint64_t result;
  std::memcpy(&result, &value, sizeof result);
  return result;
}

inline bool sameBits(const std::optional<double>& a, const std::optional<double>& b) {
  return a.has_value() == b.has_value() && (!a || bits(*a) == bits(*b));
}

// Every double identical bit for bit (so -0.0 differs from 0.0), everything else equal.
inline bool bitExact(const PoseSample& a, const PoseSample& b) {
  bool same = bits(a.time_s) == bits(b.time_s) && a.buttons == b.buttons && sameBits(a.pressure, b.pressure);
  for (int i = 0; i < 3; ++i) same = same && bits(a.tip_m[i]) == bits(b.tip_m[i]);
  for (int i = 0; i < 4; ++i) same = same && bits(a.orientation.coeffs()[i]) == bits(b.orientation.coeffs()[i]);
  return same;
}

enum class Pressure { Always, Never, Sometimes };

// `count` valid samples with strictly increasing times, random tips over many magnitudes (including
// -0.0 and subnormals), random unit quaternions, any button mask, pressure per `pressure`.
inline std::vector<PoseSample> randomSamples(std::uint32_t seed, int count, Pressure pressure) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> step(1e-6, 1e-2);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  std::uniform_int_distribution<int> exponent(-320, 300);
  std::uniform_int_distribution<std::uint32_t> mask(0, 0xFFFFFFFFu);
  std::vector<PoseSample> samples;
  double time_s = -1.0 + unit(rng);
  for (int n = 0; n < count; ++n) {
    PoseSample s;
    time_s += step(rng);
    s.time_s = time_s;
    for (int i = 0; i < 3; ++i) {
      switch (n % 7) {
        case 0:
          s.tip_m[i] = std::ldexp(unit(rng), exponent(rng));
          break;
        case 1:
          s.tip_m[i] = -0.0;
          break;
        case 2:
          s.tip_m[i] = 4.9406564584124654e-324 * (1 + i);
          break;  // subnormals
        default:
          s.tip_m[i] = 0.2 * unit(rng);
      }
    }
    s.orientation = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
    s.buttons = n % 5 == 0 ? 0xFFFFFFFFu : mask(rng);
    const bool with_pressure = pressure == Pressure::Always || (pressure == Pressure::Sometimes && n % 2 == 0);
    if (with_pressure) s.pressure = n % 11 == 0 ? 0.0 : n % 13 == 0 ? 1.0 : fraction(rng);
    samples.push_back(s);
  }
  return samples;
}

}  // namespace incise::devices::testing

namespace Catch {
template <>
struct StringMaker<incise::devices::PoseSample> {
  static std::string convert(const incise::devices::PoseSample& s) {
    std::ostringstream out;
    out.precision(17);
    out << "{t " << s.time_s << " s, tip (" << s.tip_m.x() << ", " << s.tip_m.y() << ", " << s.tip_m.z() << ") m, q ("
        << s.orientation.w() << ", " << s.orientation.x() << ", " << s.orientation.y() << ", " << s.orientation.z()
        << "), buttons " << s.buttons << ", pressure ";
    if (s.pressure)
      out << *s.pressure;
    else
      out << "none";
    out << "}";
    return out.str();
  }
};
}  // namespace Catch
