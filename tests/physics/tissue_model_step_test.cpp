// Tests for physics/src/tissue_model_step.cpp: the model against analytic solutions of linear elasticity
// (a column under its own weight, a bar in uniaxial tension with its Poisson contraction, a cantilever under
// its own weight against Euler-Bernoulli, the column's first longitudinal vibration), each on meshes refined
// twice with the error table printed and required to fall.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <catch2/catch.hpp>

#include "physics_fixture.h"
#include "tissue_model_state.h"

namespace incise::physics {
namespace {

using testing::grid;
using testing::meanDisplacement;
using testing::nodesAt;
using testing::plane;

constexpr double kG = 9.81;

// A column of side a and length L along y hanging from its top (y = L), nu = 0: the displacement along the
// axis at depth s below the top is u(s) = rho g (L s - s^2 / 2) / E, at the tip rho g L^2 / (2 E).
struct ColumnError {
  int tets;
  double tip_error, max_error;  // relative to the tip's analytic value
};

ColumnError column(int n) {
  const double a = 0.02, length = 0.1;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(a, length, a), Eigen::Vector3i(n, 5 * n, n));
  Material m;
  m.youngs_modulus_Pa = 1e5, m.poisson_ratio = 0.0;
  Boundary b;
  b.fixed_boxes = {plane(1, length)};
  b.gravity_m_per_s2 = Eigen::Vector3d(0, -kG, 0);
  TissueModel model(g.mesh, m, b);
  const StaticResult r = model.solveStatic();
  REQUIRE(r.converged);
  const double rho_g_over_e = m.density_kg_per_m3 * kG / m.youngs_modulus_Pa;
  const double tip = rho_g_over_e * length * length / 2.0;
  ColumnError e{static_cast<int>(g.mesh.tets.size()), 0.0, 0.0};
  for (int i = 0; i < model.nodeCount(); ++i) {
    const double s = length - model.restPositions_m()[static_cast<std::size_t>(i)].y();
    const double u = -(model.positions_m()[static_cast<std::size_t>(i)].y() -
                       model.restPositions_m()[static_cast<std::size_t>(i)].y());
    e.max_error = std::max(e.max_error, std::abs(u - rho_g_over_e * (length * s - s * s / 2.0)) / tip);
  }
  e.tip_error = std::abs(-meanDisplacement(model, nodesAt(g.mesh, 1, 0.0), 1) - tip) / tip;
  return e;
}

TEST_CASE("tissue_model: a column under its own weight sags as rho g (L z - z^2/2) / E", "[physics]") {
  std::printf("column under its own weight (E 100 kPa, nu 0, 2 x 2 x 10 cm): error / analytic tip %.4g mm\n",
              1e3 * 1000 * kG * 0.01 / 2e5);
  std::printf("  %8s %8s %12s %12s\n", "cells", "tets", "tip error", "max error");
  std::vector<ColumnError> errors;
  for (const int n : {1, 2, 4}) {
    errors.push_back(column(n));
    std::printf("  %3dx%dx%-2d %8d %12.3e %12.3e\n", n, 5 * n, n, errors.back().tets, errors.back().tip_error,
                errors.back().max_error);
  }
  // The tip (the bottom face's mean) converges as h^2, the worst node (linear tets cannot hold the
  // quadratic profile across the section) as h.
  for (std::size_t i = 1; i < errors.size(); ++i) {
    CHECK(errors[i].tip_error < 0.5 * errors[i - 1].tip_error);
    CHECK(errors[i].max_error < errors[i - 1].max_error);
  }
  CHECK(errors.back().tip_error < 1e-4);
  CHECK(errors.back().max_error < 0.02);
}

// A bar along x (length L, side a), clamped at x = 0, pulled by a uniform traction sigma on x = L, nu = 0.3:
// in its middle the axial strain is sigma / E and the lateral strain -nu sigma / E.
struct StretchError {
  int tets;
  double axial, lateral_y, lateral_z;  // relative errors
};

StretchError stretch(int n) {
  const double a = 0.02, length = 0.1, sigma_Pa = 1000.0;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(length, a, a), Eigen::Vector3i(5 * n, n, n));
  Material m;
  m.youngs_modulus_Pa = 1e5, m.poisson_ratio = 0.3;
  Boundary b;
  b.fixed_boxes = {plane(0, 0.0)};
  b.gravity_m_per_s2.setZero();
  TissueModel model(g.mesh, m, b);
  // The traction on each face cell spread equally over its four corners.
  const double cell_force_N = sigma_Pa * (a / n) * (a / n);
  for (const int node : nodesAt(g.mesh, 0, length)) {
    const Eigen::Vector3d& x = g.mesh.nodes_m[static_cast<std::size_t>(node)];
    const auto cornerShare = [&](double c) { return (std::abs(c) < 1e-9 || std::abs(c - a) < 1e-9) ? 1.0 : 2.0; };
    model.addNodeForce(node, Eigen::Vector3d(0.25 * cell_force_N * cornerShare(x.y()) * cornerShare(x.z()), 0, 0));
  }
  const StaticResult r = model.solveStatic();
  INFO("Newton " << r.newton_iterations << ", CG " << r.cg_iterations << ", residual " << r.relative_force_residual);
  REQUIRE(r.converged);
  const double strain = sigma_Pa / m.youngs_modulus_Pa;
  const double x0 = 0.4 * length, x1 = 0.6 * length;
  const double axial =
      (meanDisplacement(model, nodesAt(g.mesh, 0, x1), 0) - meanDisplacement(model, nodesAt(g.mesh, 0, x0), 0)) /
      (x1 - x0);
  const auto lateral = [&](int axis) {
    double sum = 0.0;
    for (const double x : {x0, x1}) {
      std::vector<int> low, high;
      for (const int node : nodesAt(g.mesh, 0, x)) {
        const double c = g.mesh.nodes_m[static_cast<std::size_t>(node)][axis];
        if (std::abs(c) < 1e-9) low.push_back(node);
        if (std::abs(c - a) < 1e-9) high.push_back(node);
      }
      sum += (meanDisplacement(model, high, axis) - meanDisplacement(model, low, axis)) / a;
    }
    return sum / 2.0;
  };
  const double nu = m.poisson_ratio;
  return {static_cast<int>(g.mesh.tets.size()), std::abs(axial - strain) / strain,
          std::abs(lateral(1) + nu * strain) / (nu * strain), std::abs(lateral(2) + nu * strain) / (nu * strain)};
}

TEST_CASE("tissue_model: a bar in uniaxial tension contracts laterally by -nu times its axial strain", "[physics]") {
  std::printf("bar in uniaxial tension (E 100 kPa, nu 0.3, sigma 1 kPa, 2 x 2 x 10 cm): relative errors mid-bar\n");
  std::printf("  %8s %8s %12s %12s %12s\n", "cells", "tets", "axial", "lateral y", "lateral z");
  std::vector<StretchError> errors;
  for (const int n : {1, 2, 4}) {
    errors.push_back(stretch(n));
    const StretchError& e = errors.back();
    std::printf("  %2dx%dx%-2d %8d %12.3e %12.3e %12.3e\n", 5 * n, n, n, e.tets, e.axial, e.lateral_y, e.lateral_z);
  }
  for (const StretchError& e : errors) {
    CHECK(e.axial < 0.03);
    CHECK(e.lateral_y < 0.05);
    CHECK(e.lateral_z < 0.05);
  }
  CHECK(errors.back().axial < errors.front().axial);
}

// A cantilever along x (length L, square section h), clamped at x = 0, under its own weight, nu = 0:
// Euler-Bernoulli's tip deflection q L^4 / (8 E I), q = rho g h^2, I = h^4 / 12.
struct CantileverError {
  int tets;
  double tip_m, error;
  int cg_iterations;
};

CantileverError cantilever(int n) {
  const double h = 0.01, length = 0.1;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(length, h, h), Eigen::Vector3i(10 * n, n, n));
  Material m;
  m.youngs_modulus_Pa = 1e7, m.poisson_ratio = 0.0;
  Boundary b;
  b.fixed_boxes = {plane(0, 0.0)};
  b.gravity_m_per_s2 = Eigen::Vector3d(0, -kG, 0);
  TissueModel model(g.mesh, m, b);
  const StaticResult r = model.solveStatic();
  INFO("Newton " << r.newton_iterations << ", CG " << r.cg_iterations << ", residual " << r.relative_force_residual);
  REQUIRE(r.converged);
  const double q = m.density_kg_per_m3 * kG * h * h, inertia = h * h * h * h / 12.0;
  const double analytic = q * std::pow(length, 4) / (8.0 * m.youngs_modulus_Pa * inertia);
  const double tip = -meanDisplacement(model, nodesAt(g.mesh, 0, length), 1);
  return {static_cast<int>(g.mesh.tets.size()), tip, std::abs(tip - analytic) / analytic, r.cg_iterations};
}

void cantileverTable(const std::vector<int>& refinements, std::vector<CantileverError>& errors) {
  const double analytic = 1000 * kG * 1e-4 * 1e-4 / (8.0 * 1e7 * 1e-8 / 12.0);
  std::printf("cantilever under its own weight (E 10 MPa, nu 0, 1 x 1 x 10 cm): Euler-Bernoulli tip %.4g mm\n",
              1e3 * analytic);
  std::printf("  %10s %8s %12s %12s %10s\n", "cells", "tets", "tip (mm)", "rel. error", "CG iter.");
  for (const int n : refinements) {
    errors.push_back(cantilever(n));
    const CantileverError& e = errors.back();
    std::printf("  %3dx%dx%-3d %8d %12.5f %12.3e %10d\n", 10 * n, n, n, e.tets, 1e3 * e.tip_m, e.error,
                e.cg_iterations);
  }
}

TEST_CASE("tissue_model: a cantilever's tip deflection converges to Euler-Bernoulli's q L^4 / (8 E I)", "[physics]") {
  std::vector<CantileverError> errors;
  cantileverTable({1, 2, 4}, errors);
  // Linear tets are too stiff in bending (shear locking): the error falls with every refinement.
  CHECK(errors[1].error < errors[0].error);
  CHECK(errors[2].error < errors[1].error);
  CHECK(errors[2].error < 0.25);
}

TEST_CASE("tissue_model: the cantilever refined to 30k tets comes within 10% of Euler-Bernoulli", "[physics][slow]") {
  std::vector<CantileverError> errors;
  cantileverTable({4, 8}, errors);
  CHECK(errors[1].error < errors[0].error);
  CHECK(errors[1].error < 0.10);
}

// The column above (2 x 2 x 10 cm, E 100 kPa, nu 0) held at its top and let go from its sag without gravity,
// undamped: it vibrates mostly in its first longitudinal mode, f1 = sqrt(E / rho) / (4 L) = 25 Hz. The tip's
// mean displacement is stepped at 10 kHz (implicit Euler's period error ~ (w h)^2 / 3 = 1e-4) and its period
// taken between its first and third zero crossings.
struct VibrationError {
  int tets;
  double frequency_Hz, error;
};

VibrationError vibration(int n) {
  const double a = 0.02, length = 0.1, dt_s = 1e-4;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(a, length, a), Eigen::Vector3i(n, 5 * n, n));
  Material m;
  m.youngs_modulus_Pa = 1e5, m.poisson_ratio = 0.0;
  m.damping = {0.0, 0.0};
  Boundary b;
  b.fixed_boxes = {plane(1, length)};
  b.gravity_m_per_s2 = Eigen::Vector3d(0, -kG, 0);
  TissueModel sagged(g.mesh, m, b);
  REQUIRE(sagged.solveStatic().converged);
  b.gravity_m_per_s2.setZero();
  ModelOptions o;
  o.cg_tolerance = 1e-9, o.max_cg_iterations = 2000;
  TissueModel model(g.mesh, m, b, o);
  for (int i = 0; i < model.nodeCount(); ++i) model.setPosition(i, sagged.positions_m()[static_cast<std::size_t>(i)]);
  const std::vector<int> tip = nodesAt(g.mesh, 1, 0.0);
  std::vector<double> crossings_s;
  double previous = meanDisplacement(model, tip, 1);
  for (int k = 1; k <= 1000 && crossings_s.size() < 3; ++k) {
    REQUIRE(model.step(dt_s).status == StepStatus::Converged);
    const double u = meanDisplacement(model, tip, 1);
    if ((previous < 0.0) != (u < 0.0)) crossings_s.push_back(dt_s * (k - 1 + previous / (previous - u)));
    previous = u;
  }
  REQUIRE(crossings_s.size() == 3);
  const double frequency_Hz = 1.0 / (crossings_s[2] - crossings_s[0]);
  const double analytic_Hz = std::sqrt(m.youngs_modulus_Pa / m.density_kg_per_m3) / (4.0 * length);
  return {static_cast<int>(g.mesh.tets.size()), frequency_Hz, std::abs(frequency_Hz - analytic_Hz) / analytic_Hz};
}

TEST_CASE("tissue_model: a column let go from its sag vibrates at its first frequency sqrt(E / rho) / (4 L)",
          "[physics]") {
  std::printf("column's free vibration (E 100 kPa, nu 0, 2 x 2 x 10 cm, undamped, 10 kHz): analytic 25 Hz\n");
  std::printf("  %8s %8s %14s %12s\n", "cells", "tets", "frequency Hz", "rel. error");
  std::vector<VibrationError> errors;
  for (const int n : {1, 2, 4}) {
    errors.push_back(vibration(n));
    const VibrationError& e = errors.back();
    std::printf("  %3dx%dx%-2d %8d %14.4f %12.3e\n", n, 5 * n, n, e.tets, e.frequency_Hz, e.error);
  }
  // Lumped masses make the frequency low by O(h^2): a quarter of the error at each halving of the cells.
  CHECK(errors[1].error < 0.4 * errors[0].error);
  CHECK(errors[2].error < 0.4 * errors[1].error);
  CHECK(errors[2].error < 1e-3);
}

// A beam of 2 mm cubes clamped at one end, let go under gravity (it swings, as the benchmark's grids do),
// stepped at 200 Hz with CG started from v or from v + the last step's dv: every step converged either way.
struct Swing {
  int iterations = 0;
  int coarse_steps = 0;  // steps whose CG used the coarse level
  std::vector<Eigen::Vector3d> x_m;
};

testing::Grid swingBeam() {
  return grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 0.04), Eigen::Vector3i(5, 5, 20));
}

Swing swing(bool extrapolate, int coarse_aggregates = ModelOptions{}.coarse_aggregates) {
  const testing::Grid g = swingBeam();
  Boundary b;
  b.fixed_boxes = {plane(2, 0.0)};
  b.gravity_m_per_s2 = Eigen::Vector3d(0, -kG, 0);
  ModelOptions o;
  o.max_cg_iterations = 1000, o.extrapolate_velocity = extrapolate, o.coarse_aggregates = coarse_aggregates;
  TissueModel model(g.mesh, Material{}, b, o);
  Swing out;
  for (int k = 0; k < 120; ++k) {
    const StepStats stats = model.step(0.005);
    REQUIRE(stats.status == StepStatus::Converged);
    out.iterations += stats.cg_iterations;
    out.coarse_steps += stats.coarse_level ? 1 : 0;
  }
  out.x_m.assign(model.positions_m().begin(), model.positions_m().end());
  return out;
}

// The two runs end in the same place: the beam swung (over 2 mm) and they differ by under 1% of that.
void checkSameMotion(const Swing& a, const Swing& b) {
  double largest_m = 0.0, differs_m = 0.0;
  const testing::Grid rest = swingBeam();
  for (std::size_t i = 0; i < a.x_m.size(); ++i) {
    largest_m = std::max(largest_m, (a.x_m[i] - rest.mesh.nodes_m[i]).norm());
    differs_m = std::max(differs_m, (a.x_m[i] - b.x_m[i]).norm());
  }
  INFO("largest displacement " << largest_m << " m, largest difference " << differs_m << " m");
  CHECK(largest_m > 0.002);
  CHECK(differs_m < 0.01 * largest_m);
}

TEST_CASE("tissue_model: CG started from the extrapolated velocity converges in fewer iterations, same motion",
          "[physics]") {
  const Swing from_v = swing(false), extrapolated = swing(true);
  INFO("CG iterations over 120 steps: from v " << from_v.iterations << ", extrapolated " << extrapolated.iterations);
  CHECK(extrapolated.iterations < 0.85 * from_v.iterations);
  checkSameMotion(from_v, extrapolated);
}

TEST_CASE("tissue_model: CG's coarse level (rigid modes per aggregate) cuts its iterations, same motion", "[physics]") {
  const Swing ssor = swing(true, 0), two_level = swing(true);
  INFO("CG iterations over 120 steps: SSOR " << ssor.iterations << ", with the coarse level " << two_level.iterations);
  CHECK(two_level.iterations < 0.6 * ssor.iterations);
  checkSameMotion(ssor, two_level);
  INFO("coarse steps " << two_level.coarse_steps << " of 120");
  CHECK(two_level.coarse_steps > 60);  // the beam swings all along
  CHECK(ssor.coarse_steps == 0);
}

TEST_CASE("tissue_model: the coarse level is used while CG needs many iterations and only where it cuts them",
          "[physics]") {
  TissueModel::State s(0.001);
  s.last_step_dt_s = 0.005;
  const auto after = [&](int iterations) {
    s.last_step_cg_iterations = iterations;
    return s.useCoarse();
  };
  CHECK_FALSE(after(3));  // easy: SSOR alone
  CHECK_FALSE(after(11));
  CHECK(after(30));  // hard: tried
  CHECK(after(12));  // the trial cut 30 to 12: kept
  CHECK(after(9));
  CHECK_FALSE(after(4));   // easy again
  CHECK(after(20));        // tried again
  CHECK_FALSE(after(16));  // 20 -> 16 does not pay for its cost: rested
  int resting = 0;
  while (!after(40) && resting < 5000) ++resting;
  CHECK(resting == 999);  // then tried again
  s.options.coarse_aggregates = 0;
  CHECK_FALSE(after(60));  // switched off
}

}  // namespace
}  // namespace incise::physics
