#include "incise/physics/material.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "incise/core/format.h"

namespace incise::physics {
namespace {

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument(what); }

std::string number(double value) { return core::formatNumber(value); }

std::string vector(const Eigen::Vector3d& v) { return core::formatPoint(v); }

void requirePositive(double value, const char* field) {
  if (!(std::isfinite(value) && value > 0.0))
    refuse(std::string("Material: ") + field + " = " + number(value) + " must be finite and > 0");
}

void requireNonNegative(double value, const char* field) {
  if (!(std::isfinite(value) && value >= 0.0))
    refuse(std::string("Material: ") + field + " = " + number(value) + " must be finite and >= 0");
}

}  // namespace

Lame lame(const Material& m) noexcept {
  const double e = m.youngs_modulus_Pa, nu = m.poisson_ratio;
  return {e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))};
}

void validate(const Material& m) {
  requirePositive(m.youngs_modulus_Pa, "youngs_modulus_Pa");
  if (!(std::isfinite(m.poisson_ratio) && m.poisson_ratio >= 0.0 && m.poisson_ratio < 0.5))
    refuse("Material: poisson_ratio = " + number(m.poisson_ratio) + " is outside [0, 0.5)");
  requirePositive(m.density_kg_per_m3, "density_kg_per_m3");
  requireNonNegative(m.damping.mass_per_s, "damping.mass_per_s");
  requireNonNegative(m.damping.stiffness_s, "damping.stiffness_s");
  for (int i = 0; i < 3; ++i)
    if (!(std::isfinite(m.prestretch[i]) && m.prestretch[i] > 0.0))
      refuse("Material: prestretch = " + vector(m.prestretch) + " must be finite and > 0 on every axis");
}

void validate(const Boundary& b, int node_count) {
  if (!b.gravity_m_per_s2.allFinite())
    refuse("Boundary: gravity_m_per_s2 = " + vector(b.gravity_m_per_s2) + " must be finite");
  for (size_t i = 0; i < b.fixed_nodes.size(); ++i)
    if (b.fixed_nodes[i] < 0 || b.fixed_nodes[i] >= node_count)
      refuse("Boundary: fixed_nodes[" + std::to_string(i) + "] = " + std::to_string(b.fixed_nodes[i]) +
             " is outside [0, " + std::to_string(node_count) + ")");
  for (size_t i = 0; i < b.fixed_boxes.size(); ++i) {
    const Box& box = b.fixed_boxes[i];
    if (!box.min_m.allFinite() || !box.max_m.allFinite() || (box.min_m.array() > box.max_m.array()).any())
      refuse("Boundary: fixed_boxes[" + std::to_string(i) + "] from " + vector(box.min_m) + " to " + vector(box.max_m) +
             " must be finite with min <= max");
  }
}

bool insideFixedBox(const Boundary& boundary, const Eigen::Vector3d& rest_m) noexcept {
  for (const Box& box : boundary.fixed_boxes)
    if (box.contains(rest_m)) return true;
  return false;
}

}  // namespace incise::physics
