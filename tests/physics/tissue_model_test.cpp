// Tests for physics/src/tissue_model.cpp and the step's dynamics (tissue_model_step.cpp): what a model
// refuses at load (by the field or the tet), a prestretched bar reaching its natural length exactly, stepping
// to rest ending at the static solution, a crushed and inverted block pushing back to its rest shape without
// blowing up, the same steps giving the same bytes, and the contact's local model predicting the next step.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "physics_fixture.h"

namespace incise::physics {
namespace {

using testing::grid;
using testing::nodesAt;
using testing::plane;
using testing::refusal;

// Largest |x_i - y_i| over the nodes.
double maxDistance(std::span<const Eigen::Vector3d> x, std::span<const Eigen::Vector3d> y) {
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) d = std::max(d, (x[i] - y[i]).norm());
  return d;
}

TEST_CASE("tissue_model: a tissue with nothing held, a bad material or a bad tet is refused by name", "[physics]") {
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 0.01), Eigen::Vector3i(2, 2, 2));
  Boundary held;
  held.fixed_boxes = {plane(1, 0.0)};
  CHECK_NOTHROW(TissueModel(g.mesh, Material{}, held));
  CHECK(refusal([&] { TissueModel(g.mesh, Material{}, Boundary{}); }).find("no node is held") != std::string::npos);
  Boundary elsewhere;  // a box that holds none of the nodes
  elsewhere.fixed_boxes = {{Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(2, 2, 2)}};
  CHECK(refusal([&] { TissueModel(g.mesh, Material{}, elsewhere); }).find("no node is held") != std::string::npos);
  Material m;
  m.poisson_ratio = 0.5;
  CHECK(refusal([&] { TissueModel(g.mesh, m, held); }) == "Material: poisson_ratio = 0.5 is outside [0, 0.5)");
  m = Material{};
  m.youngs_modulus_Pa = -1.0;
  CHECK(refusal([&] { TissueModel(g.mesh, m, held); }).find("youngs_modulus_Pa = -1") != std::string::npos);
  m = Material{};
  m.density_kg_per_m3 = 0.0;
  CHECK(refusal([&] { TissueModel(g.mesh, m, held); }).find("density_kg_per_m3 = 0") != std::string::npos);
  tets::TetMesh inverted = g.mesh;
  std::swap(inverted.tets[5][1], inverted.tets[5][2]);
  CHECK(refusal([&] { TissueModel(inverted, Material{}, held); }) == "TissueModel: tet 5 is flat or inverted at rest");
  tets::TetMesh out_of_range = g.mesh;
  out_of_range.tets[3][0] = 1000;
  CHECK(refusal([&] { TissueModel(out_of_range, Material{}, held); }).find("tet 3 has node 1000") != std::string::npos);
}

TEST_CASE("tissue_model: masses are the density times the volume, a quarter of each tet to each node", "[physics]") {
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.03), Eigen::Vector3i(2, 1, 3));
  Boundary b;
  b.fixed_boxes = {plane(1, 0.0)};
  Material m;
  m.density_kg_per_m3 = 1100.0;
  const TissueModel model(g.mesh, m, b);
  CHECK(model.totalMass_kg() == Approx(1100.0 * 0.02 * 0.01 * 0.03).epsilon(1e-12));
  // A corner node of the Kuhn grid belongs to 1 or 6 tets of its cube (the main diagonal's ends).
  CHECK(model.mass_kg(0) == Approx(1100.0 * 1e-6 / 4.0).epsilon(1e-12));  // 6 tets of 1/6 cm^3: a quarter each
  CHECK(model.isHeld(0));
  CHECK_FALSE(model.isHeld(static_cast<int>(g.mesh.nodes_m.size()) - 1));
}

TEST_CASE("tissue_model: a bar prestretched along x and held at one end shrinks to its natural length exactly",
          "[physics]") {
  // The natural shape is the mesh with x divided by 1.25: held on x = 0 (where x / 1.25 = x) and free
  // elsewhere, the bar reaches it exactly (linear tets hold a homogeneous deformation).
  const double length = 0.05;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(length, 0.01, 0.01), Eigen::Vector3i(10, 2, 2));
  Material m;
  m.prestretch = Eigen::Vector3d(1.25, 1.0, 1.0);
  m.poisson_ratio = 0.3;
  Boundary b;
  b.fixed_boxes = {plane(0, 0.0)};
  b.gravity_m_per_s2.setZero();
  TissueModel model(g.mesh, m, b);
  const StaticResult r = model.solveStatic();
  REQUIRE(r.converged);
  double error = 0.0;
  for (int i = 0; i < model.nodeCount(); ++i) {
    const Eigen::Vector3d rest = model.restPositions_m()[static_cast<std::size_t>(i)];
    const Eigen::Vector3d natural(rest.x() / 1.25, rest.y(), rest.z());
    error = std::max(error, (model.positions_m()[static_cast<std::size_t>(i)] - natural).norm());
  }
  INFO("Newton " << r.newton_iterations << ", largest distance to the natural shape " << error << " m");
  CHECK(error < 1e-9);
}

// A column hanging under gravity from its top, the same tissue twice: one solved statically, one stepped.
TEST_CASE("tissue_model: stepping a hanging column from rest settles at the static solution", "[physics]") {
  const double length = 0.05;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, length, 0.01), Eigen::Vector3i(2, 10, 2));
  Material m;
  m.youngs_modulus_Pa = 2e4, m.poisson_ratio = 0.3;
  m.damping = {5.0, 0.01};
  Boundary b;
  b.fixed_boxes = {plane(1, length)};
  ModelOptions o;
  o.cg_tolerance = 1e-8, o.max_cg_iterations = 500;
  TissueModel statics(g.mesh, m, b, o), dynamics(g.mesh, m, b, o);
  REQUIRE(statics.solveStatic().converged);
  const double tip_m = -testing::meanDisplacement(statics, nodesAt(g.mesh, 1, 0.0), 1);
  REQUIRE(tip_m > 1e-4);  // it sags visibly
  int inverted = 0;
  for (int i = 0; i < 600; ++i) {  // 3 s at 200 Hz
    const StepStats s = dynamics.step(0.005);
    REQUIRE(s.status == StepStatus::Converged);
    inverted = std::max(inverted, s.inverted_elements);
  }
  const double distance = maxDistance(statics.positions_m(), dynamics.positions_m());
  INFO("static tip sag " << tip_m << " m, stepped vs static: " << distance << " m");
  CHECK(distance < 1e-3 * tip_m);
  CHECK(inverted == 0);
  double speed = 0.0;
  for (const Eigen::Vector3d& v : dynamics.velocities_m_per_s()) speed = std::max(speed, v.norm());
  CHECK(speed < 1e-4);
}

// A 1 cm cube held on its base, its top pressed below its base (every column inverted), then let go.
TEST_CASE("tissue_model: a crushed and inverted block pushes back to its rest shape and never blows up", "[physics]") {
  const double side = 0.01;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(side), Eigen::Vector3i(3, 3, 3));
  Material m;
  m.youngs_modulus_Pa = 3e4, m.poisson_ratio = 0.45;
  Boundary b;
  b.fixed_boxes = {plane(1, 0.0)};
  b.gravity_m_per_s2.setZero();
  TissueModel model(g.mesh, m, b);
  // Every node above the base goes through it: y -> -y / 2 (the block turned inside out).
  for (int i = 0; i < model.nodeCount(); ++i) {
    const Eigen::Vector3d rest = model.restPositions_m()[static_cast<std::size_t>(i)];
    if (!model.isHeld(i)) model.setPosition(i, Eigen::Vector3d(rest.x(), -0.5 * rest.y(), rest.z()));
  }
  const StepStats first = model.step(0.005);
  CHECK(first.inverted_elements == static_cast<int>(g.mesh.tets.size()));
  int steps = 1, inverted = first.inverted_elements;
  double largest_m = 0.0;
  for (; steps < 2000 && inverted > 0; ++steps) {
    const StepStats s = model.step(0.005);
    REQUIRE(s.status != StepStatus::NonFinite);
    inverted = s.inverted_elements;
    for (const Eigen::Vector3d& x : model.positions_m()) largest_m = std::max(largest_m, x.norm());
  }
  INFO("every tet upright again after " << steps << " steps; farthest node " << largest_m << " m from the origin");
  CHECK(inverted == 0);
  CHECK(largest_m < 4.0 * side);  // it pushes back: no node is thrown away
  for (int i = 0; i < 1000; ++i) REQUIRE(model.step(0.005).status != StepStatus::NonFinite);
  const double distance = maxDistance(model.positions_m(), model.restPositions_m());
  INFO("distance to the rest shape after 1000 more steps: " << distance << " m");
  CHECK(distance < 1e-3 * side);
}

TEST_CASE("tissue_model: a block squeezed flat by a held tool and released recovers", "[physics]") {
  const double side = 0.01;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(side), Eigen::Vector3i(3, 3, 3));
  Boundary b;
  b.fixed_boxes = {plane(1, 0.0)};
  TissueModel model(g.mesh, Material{}, b);
  const std::vector<int> top = nodesAt(g.mesh, 1, side);
  // The tool lowers the top to 2% of the height over 50 steps (and holds it there 50 steps).
  for (int i = 1; i <= 100; ++i) {
    const double height = side * (1.0 - 0.98 * std::min(1.0, i / 50.0));
    for (const int n : top) {
      const Eigen::Vector3d rest = model.restPositions_m()[static_cast<std::size_t>(n)];
      model.holdNode(n, Eigen::Vector3d(rest.x(), height, rest.z()));
    }
    REQUIRE(model.step(0.005).status != StepStatus::NonFinite);
  }
  for (const Eigen::Vector3d& x : model.positions_m()) REQUIRE(x.allFinite());
  for (const int n : top) model.releaseNode(n);
  for (int i = 0; i < 1000; ++i) REQUIRE(model.step(0.005).status != StepStatus::NonFinite);
  // Back to where gravity alone holds it: close to rest (E 30 kPa, 1 cm: a sag of a few micrometres).
  CHECK(maxDistance(model.positions_m(), model.restPositions_m()) < 2e-5);
  CHECK(model.step(0.005).inverted_elements == 0);
}

TEST_CASE("tissue_model: the same steps give the same bytes", "[physics]") {
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.01, 0.04), Eigen::Vector3i(2, 2, 8));
  Boundary b;
  b.fixed_boxes = {plane(2, 0.0)};
  const auto run = [&] {
    TissueModel model(g.mesh, Material{}, b);
    for (int i = 0; i < 40; ++i) {
      model.clearExternalForces();
      model.addNodeForce(model.nodeCount() - 1, Eigen::Vector3d(0.01 * std::sin(0.3 * i), 0.0, 0.0));
      model.step(0.005);
    }
    return std::vector<Eigen::Vector3d>(model.positions_m().begin(), model.positions_m().end());
  };
  const std::vector<Eigen::Vector3d> a = run(), c = run();
  REQUIRE(a.size() == c.size());
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof(Eigen::Vector3d)) == 0);
}

// A 20 x 10 x 20 mm slab of 4 x 2 x 4 cells held at its bottom (y = 0), no gravity, solved tightly.
struct HeldSlab {
  testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.01, 0.02), Eigen::Vector3i(4, 2, 4));
  Boundary b = held();
  ModelOptions o = tight();
  static Boundary held() {
    Boundary b;
    b.fixed_boxes = {plane(1, 0.0)};
    b.gravity_m_per_s2.setZero();
    return b;
  }
  static ModelOptions tight() {
    ModelOptions o;
    o.cg_tolerance = 1e-10, o.max_cg_iterations = 1000;
    return o;
  }
};

TEST_CASE("tissue_model: the contact model's stiffness predicts how far the next step moves a pushed point",
          "[physics]") {
  // At rest without gravity the next step's matrix is the last one's: a force f held at the point for one
  // step moves it by exactly K^-1 f (K the contact model's stiffness), up to CG's tolerance.
  const HeldSlab slab;
  const testing::Grid& g = slab.g;
  const Boundary& b = slab.b;
  const ModelOptions& o = slab.o;
  TissueModel model(g.mesh, Material{}, b, o);
  const Eigen::Vector3d at(0.0113, 0.0098, 0.0071);
  const std::optional<Embedded> point = model.locate(at);
  REQUIRE(point);
  CHECK(embeddedPosition(*point, model.restPositions_m()).isApprox(at, 1e-12));
  CHECK_FALSE(model.contactModel(*point, Eigen::Vector3d::UnitY()).valid);  // no step yet
  model.step(0.005);
  const ContactModel contact = model.contactModel(*point, Eigen::Vector3d::UnitY());
  REQUIRE(contact.valid);
  CHECK((contact.stiffness_N_per_m - contact.stiffness_N_per_m.transpose()).norm() <
        1e-9 * contact.stiffness_N_per_m.norm());
  const Eigen::Vector3d force_N(0.02, -0.05, 0.01);
  model.addPointForce(*point, force_N);
  model.step(0.005);
  const Eigen::Vector3d moved = embeddedPosition(*point, model.positions_m()) - at;
  const Eigen::Vector3d predicted = contact.stiffness_N_per_m.inverse() * force_N;
  INFO("moved " << moved.transpose() << " m, predicted " << predicted.transpose() << " m");
  CHECK((moved - predicted).norm() < 1e-6 * predicted.norm());
  // A tool below the surface is pushed back along the stiffness; one above it feels nothing.
  const Eigen::Vector3d tool = contact.point_m - 0.001 * contact.normal;
  CHECK(contact.reactionForce_N(tool).isApprox(contact.stiffness_N_per_m * (0.001 * contact.normal)));
  CHECK(contact.reactionForce_N(contact.point_m + 0.001 * contact.normal).isZero());
}

TEST_CASE("tissue_model: a tool pressing the skin dents it, its spring in series with the tissue", "[physics]") {
  // A tool 2 mm below the top of a held slab, on a spring of k = 400 N/m to the skin's point there: the
  // static dent is where the spring's force and the tissue's answer to that force as a point load agree
  // (two solves to rounding), the steps settle there, a spring a thousand times stiffer stays stable (the
  // press is implicit) and follows the tool, and a tool lifted off lets the tissue go back to rest.
  const HeldSlab slab;
  const testing::Grid& g = slab.g;
  const Boundary& b = slab.b;
  const ModelOptions& o = slab.o;
  const Eigen::Vector3d at(0.0113, 0.01, 0.0071), up = Eigen::Vector3d::UnitY(), tool = at - 0.002 * up;
  const double k_N_per_m = 400.0;
  TissueModel pressed(g.mesh, Material{}, b, o);
  const std::optional<Embedded> point = pressed.locate(at);
  REQUIRE(point);
  pressed.setToolPress(*point, up, tool, k_N_per_m);
  REQUIRE(pressed.solveStatic().converged);
  const Eigen::Vector3d dent_m = embeddedPosition(*point, pressed.positions_m());
  const double gap_m = (dent_m - tool).dot(up);
  const Eigen::Vector3d force_N = pressed.toolPressForce_N();
  INFO("dent " << (at - dent_m).transpose() * 1e3 << " mm, force " << force_N.transpose() << " N");
  CHECK(gap_m > 0.0002);
  CHECK(gap_m < 0.0018);  // the tissue gave
  CHECK(force_N.isApprox(-k_N_per_m * gap_m * up, 1e-12));

  TissueModel loaded(g.mesh, Material{}, b, o);
  loaded.addPointForce(*point, force_N);
  REQUIRE(loaded.solveStatic().converged);
  CHECK(maxDistance(loaded.positions_m(), pressed.positions_m()) < 1e-6 * (at - dent_m).norm());

  TissueModel stepped(g.mesh, Material{}, b, o);
  stepped.setToolPress(*point, up, tool, k_N_per_m);
  for (int i = 0; i < 400; ++i) REQUIRE(stepped.step(0.01).status == StepStatus::Converged);
  CHECK((embeddedPosition(*point, stepped.positions_m()) - dent_m).norm() < 0.01 * (at - dent_m).norm());

  TissueModel stiff(g.mesh, Material{}, b, o);
  stiff.setToolPress(*point, up, tool, 1000.0 * k_N_per_m);
  double largest_m = 0.0;
  for (int i = 0; i < 200; ++i) {
    REQUIRE(stiff.step(0.01).status == StepStatus::Converged);
    for (const Eigen::Vector3d& x : stiff.positions_m()) largest_m = std::max(largest_m, (x - at).norm());
  }
  CHECK(largest_m < 0.03);  // nothing flew off
  CHECK(std::abs((embeddedPosition(*point, stiff.positions_m()) - tool).dot(up)) < 0.0001);

  stepped.setToolPress(*point, up, at + 0.001 * up, k_N_per_m);  // lifted above the skin
  for (int i = 0; i < 400; ++i) stepped.step(0.01);
  CHECK(stepped.toolPressForce_N().isZero());
  CHECK(maxDistance(stepped.positions_m(), stepped.restPositions_m()) < 1e-6);
}

TEST_CASE("tissue_model: the rest map takes a deformed point back to the material point it carries", "[physics]") {
  // A column held at its top, its nodes moved by a smooth bend and shear (millimetres at the free end):
  // points inside it, at their deformed positions, map back to their rest positions (Newton on each tet's
  // affine deformation: to rounding).
  const double length = 0.05;
  const testing::Grid g = grid(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, length, 0.01), Eigen::Vector3i(2, 10, 2));
  Boundary b;
  b.fixed_boxes = {plane(1, length)};
  TissueModel model(g.mesh, Material{}, b);
  const RestMap at_rest = model.restMap(Eigen::Vector3d(0.004, 0.01, 0.006));
  CHECK(at_rest.located);
  CHECK(at_rest.toRest(Eigen::Vector3d(0.004, 0.01, 0.006)).isApprox(Eigen::Vector3d(0.004, 0.01, 0.006), 1e-14));
  const auto bent = [&](const Eigen::Vector3d& x) {
    const double free = (1.0 - x.y() / length) * (1.0 - x.y() / length);
    return Eigen::Vector3d(x + free * Eigen::Vector3d(0.004, -0.003, 0.002 + 0.3 * x.x()));
  };
  for (int n = 0; n < model.nodeCount(); ++n)
    if (!model.isHeld(n)) model.setPosition(n, bent(model.restPositions_m()[static_cast<std::size_t>(n)]));
  // A tool's path down the column, each map's guess the last one's (as the simulation follows the blade).
  double largest_move_m = 0.0, largest_error_m = 0.0;
  Eigen::Vector3d guess = Eigen::Vector3d(0.002, 0.049, 0.005);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d rest(0.002 + 0.006 * i / 50.0, 0.049 - 0.048 * i / 50.0, 0.005 + 0.002 * (i % 2));
    const std::optional<Embedded> e = model.locate(rest);
    REQUIRE(e);
    const Eigen::Vector3d world = embeddedPosition(*e, model.positions_m());
    const RestMap map = model.restMap(world, guess);
    REQUIRE(map.located);
    largest_move_m = std::max(largest_move_m, (world - rest).norm());
    largest_error_m = std::max(largest_error_m, (map.toRest(world) - rest).norm());
    // Near the point the map is the tet's inverse deformation gradient: a step in the world maps to a step at rest.
    const Eigen::Vector3d nudge(1e-5, -2e-5, 1e-5);
    CHECK(map.toRest(world + nudge).isApprox(map.toRest(world) + map.directionToRest(nudge), 1e-12));
    guess = map.toRest(world);
  }
  INFO("points moved up to " << largest_move_m * 1e3 << " mm; mapped back within " << largest_error_m << " m");
  CHECK(largest_move_m > 0.002);
  CHECK(largest_error_m < 1e-12);
  // Without the path's guess the free end is out of reach of where the point is in the world: the identity.
  const Eigen::Vector3d end_rest(0.009, 0.0005, 0.0095);
  const Eigen::Vector3d end_world = embeddedPosition(*model.locate(end_rest), model.positions_m());
  CHECK((end_world - end_rest).norm() > 0.004);
  CHECK_FALSE(model.restMap(end_world).located);
  CHECK((model.restMap(end_world, end_rest + Eigen::Vector3d(0.0005, 0.0, 0.0)).toRest(end_world) - end_rest).norm() <
        1e-12);
  // Far from the tissue (beyond the reach): the identity.
  const RestMap far = model.restMap(Eigen::Vector3d(0.05, 0.0, 0.0));
  CHECK_FALSE(far.located);
  CHECK(far.toRest(Eigen::Vector3d(0.05, 0.0, 0.0)) == Eigen::Vector3d(0.05, 0.0, 0.0));
  CHECK_FALSE(model.restMap(Eigen::Vector3d(NAN, 0.0, 0.0)).located);
}

}  // namespace
}  // namespace incise::physics
