// Tests for physics/src/material.cpp: Lame's parameters, and the validation of materials and boundaries
// (each refusal names the field and its value).
#include "incise/physics/material.h"

#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

#include "physics_fixture.h"

namespace incise::physics {
namespace {

using testing::refusal;

TEST_CASE("material: Lame's parameters of E and nu", "[physics]") {
  Material m;
  m.youngs_modulus_Pa = 2.6e5;
  m.poisson_ratio = 0.3;
  const Lame l = lame(m);
  CHECK(l.mu_Pa == Approx(1e5));
  CHECK(l.lambda_Pa == Approx(2.6e5 * 0.3 / (1.3 * 0.4)));
  m.poisson_ratio = 0.0;
  CHECK(lame(m).lambda_Pa == 0.0);
}

TEST_CASE("material: E <= 0, nu below 0 or from 0.5 up, density <= 0 and a bad prestretch are refused by name",
          "[physics]") {
  CHECK_NOTHROW(validate(Material{}));
  const auto with = [](auto change) {
    Material m;
    change(m);
    return refusal([&] { validate(m); });
  };
  CHECK(with([](Material& m) { m.youngs_modulus_Pa = 0; }) == "Material: youngs_modulus_Pa = 0 must be finite and > 0");
  CHECK(with([](Material& m) { m.youngs_modulus_Pa = -5; }).find("youngs_modulus_Pa = -5") != std::string::npos);
  CHECK(with([](Material& m) { m.poisson_ratio = 0.5; }) == "Material: poisson_ratio = 0.5 is outside [0, 0.5)");
  CHECK(with([](Material& m) { m.poisson_ratio = -0.1; }) == "Material: poisson_ratio = -0.1 is outside [0, 0.5)");
  CHECK(with([](Material& m) { m.density_kg_per_m3 = 0; }) == "Material: density_kg_per_m3 = 0 must be finite and > 0");
  CHECK(with([](Material& m) { m.damping.mass_per_s = -1; }).find("damping.mass_per_s = -1") != std::string::npos);
  CHECK(with([](Material& m) { m.damping.stiffness_s = std::nan(""); }).find("damping.stiffness_s") !=
        std::string::npos);
  CHECK(with([](Material& m) { m.prestretch.y() = 0; }) ==
        "Material: prestretch = (1, 0, 1) must be finite and > 0 on every axis");
}

TEST_CASE("material: a boundary's bad node, box or gravity is refused with its entry", "[physics]") {
  Boundary b;
  b.fixed_nodes = {0, 7, 12};
  CHECK(refusal([&] { validate(b, 12); }) == "Boundary: fixed_nodes[2] = 12 is outside [0, 12)");
  CHECK_NOTHROW(validate(b, 13));
  b.fixed_boxes = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)},
                   {Eigen::Vector3d(0, 2, 0), Eigen::Vector3d(1, 1, 1)}};
  CHECK(refusal([&] { validate(b, 13); }) ==
        "Boundary: fixed_boxes[1] from (0, 2, 0) to (1, 1, 1) must be finite with min <= max");
  b.fixed_boxes.pop_back();
  b.gravity_m_per_s2.x() = INFINITY;
  CHECK(refusal([&] { validate(b, 13); }).find("gravity_m_per_s2") != std::string::npos);
}

TEST_CASE("material: a fixed box holds the points inside it, its faces included", "[physics]") {
  Boundary b;
  b.fixed_boxes = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)}};
  CHECK(insideFixedBox(b, Eigen::Vector3d(0.5, 0.5, 0.5)));
  CHECK(insideFixedBox(b, Eigen::Vector3d(1, 0, 1)));
  CHECK_FALSE(insideFixedBox(b, Eigen::Vector3d(1.0000001, 0.5, 0.5)));
  CHECK_FALSE(insideFixedBox(Boundary{}, Eigen::Vector3d::Zero()));
}

}  // namespace
}  // namespace incise::physics
