// Tests for cutting/core/src/format.cpp: formatNumber writes the shortest text that reads back to the same
// double, and formatPoint and formatIndices build their text from it.
#include "incise/core/format.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace incise::core {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

double fromBits(std::uint64_t b) {
  double x = 0.0;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// The double std::strtod reads from formatNumber(x); fails the test unless all of the text is read.
double readBack(double x) {
  const std::string text = formatNumber(x);
  char* end = nullptr;
  const double y = std::strtod(text.c_str(), &end);
  INFO("formatNumber gave '" << text << "'");
  REQUIRE(end == text.c_str() + text.size());
  return y;
}

}  // namespace

TEST_CASE("format: formatNumber round-trips random doubles exactly via std::strtod", "[cutting]") {
  std::mt19937_64 random(20261201);
  std::uniform_real_distribution<double> metres(-1.0, 1.0);
  std::vector<double> values = {0.0,
                                -0.0,
                                0.1,
                                1.0 / 3.0,
                                -2.5,
                                1e-300,
                                6.02214076e23,
                                std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::lowest(),
                                std::numeric_limits<double>::epsilon()};
  for (int i = 0; i < 20'000; ++i) {
    values.push_back(metres(random));       // coordinates as the meshes have them
    const double any = fromBits(random());  // any bit pattern: every exponent
    if (std::isfinite(any)) values.push_back(any);
  }
  for (const double x : values) {
    INFO("x bits " << bits(x));
    REQUIRE(bits(readBack(x)) == bits(x));
  }
  REQUIRE(formatNumber(0.1) == "0.1");
  REQUIRE(formatNumber(-2.0) == "-2");
  REQUIRE(formatNumber(1e-300) == "1e-300");
  REQUIRE(formatNumber(5e6) == "5e+06");  // the shorter of the fixed and the scientific form
}

TEST_CASE("format: formatPoint and formatIndices text", "[cutting]") {
  REQUIRE(formatPoint(Eigen::Vector3d(0.1, -2.0, 1e-300)) == "(0.1, -2, 1e-300)");
  REQUIRE(formatPoint(Eigen::Vector3d(1.0 / 3.0, 0.0, 1234.5)) == "(0.3333333333333333, 0, 1234.5)");
  REQUIRE(formatPoint(Eigen::Vector2d(1.5, -0.25)) == "(1.5, -0.25)");
  REQUIRE(formatIndices({1, -2, 30}) == "(1, -2, 30)");
  REQUIRE(formatIndices({0, 0, 0}) == "(0, 0, 0)");
}

}  // namespace incise::core
