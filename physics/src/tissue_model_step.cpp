// TissueModel::step and solveStatic (tissue_model.h), and the assembly they share.
//
// Linearised backward Euler with Rayleigh damping D = alpha M + beta K (Baraff & Witkin 1998; SOFA's
// EulerImplicitSolver): with f = f_ext + M g + f_el(x0) and K the co-rotated stiffness at x0,
//   [(1 + h alpha) M + h (h + beta) K] v1 = M v0 + h f,   x1 = x0 + h v1,
// solved for v1 by CG from v0 + (v0 - v-1) while the tissue moves (ModelOptions::extrapolate_velocity).
// The static solve takes Newton steps K dx = f with the same K and f.
#include <algorithm>
#include <cmath>

#include "incise/physics/tissue_model.h"
#include "lanes.h"
#include "tissue_model_state.h"

namespace incise::physics {
namespace {

using detail::Element;

// The rotated shape gradients c_a = R beta_a, each padded to four lanes (the 4th 0).
struct alignas(32) Gradients {
  double c[4][4];
};

// block += K_ab = kl c_a c_b^T + km c_b c_a^T + km dot I (kl, km: the Lame coefficients times the volume and
// the stiffness coefficient), row r as (kl c_a[r]) c_b + (km c_b[r]) c_a, four lanes at a time: the scalar
// kl c_a[r] c_b[k] + km c_b[r] c_a[k] in the same order, so the same bits.
void addPair(detail::Block& block, const Gradients& g, int a, int b, double kl, double km, double dot) noexcept {
  using detail::Lanes;
  const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
  const Lanes ca = Lanes::load(g.c[ua]), cb = Lanes::load(g.c[ub]);
  for (int r = 0; r < 3; ++r) {
    double* row = block.c + 4 * r;
    const Lanes lr = Lanes::broadcast(kl * g.c[ua][r]), mr = Lanes::broadcast(km * g.c[ub][r]);
    (Lanes::load(row) + (lr * cb + mr * ca)).store(row);
  }
  const double km_dot = km * dot;
  block(0, 0) += km_dot, block(1, 1) += km_dot, block(2, 2) += km_dot;
}

// One element's elastic forces (into force) and its stiffness times k (into the matrix).
bool assembleElement(Element& e, TissueModel::State& s, double k) noexcept {
  const auto& x = s.x_m;
  const Eigen::Vector3d& x0 = x[static_cast<std::size_t>(e.nodes[0])];
  Eigen::Matrix3d ds;
  for (int i = 0; i < 3; ++i) ds.col(i) = x[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(i + 1)])] - x0;
  const Eigen::Matrix3d f = ds * e.bm;
  int iterations = 0;
  const Eigen::Matrix3d r =
      detail::rotation(f, e.q, s.options.rotation_tolerance, s.options.max_rotation_iterations, iterations);
  const Eigen::Matrix3d rf = r.transpose() * f;
  Eigen::Matrix3d strain = 0.5 * (rf + rf.transpose()) - Eigen::Matrix3d::Identity();
  const double lambda = s.lame.lambda_Pa, mu = s.lame.mu_Pa, volume = e.volume_m3;
  Eigen::Matrix3d stress = 2.0 * mu * strain;
  stress.diagonal().array() += lambda * strain.trace();
  // Forces on nodes 1..3 are the columns of -V R sigma bm^T; node 0 takes minus their sum.
  const Eigen::Matrix3d h = -volume * (r * (stress * e.bm.transpose()));
  for (int i = 0; i < 3; ++i) s.force_N[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(i + 1)])] += h.col(i);
  s.force_N[static_cast<std::size_t>(e.nodes[0])] -= h.col(0) + h.col(1) + h.col(2);
  const Eigen::Matrix3d c3 = r * e.bm.transpose();  // c_1..3 = R beta_1..3; c_0 = -(c_1 + c_2 + c_3)
  const double kl = k * lambda * volume, km = k * mu * volume;
  Gradients g;
  for (int d = 0; d < 3; ++d) {
    g.c[0][d] = -(c3(d, 0) + c3(d, 1) + c3(d, 2));
    for (int a = 1; a < 4; ++a) g.c[a][d] = c3(d, a - 1);
  }
  for (int a = 0; a < 4; ++a) g.c[a][3] = 0.0;
  for (int a = 0; a < 4; ++a)
    addPair(s.matrix.diagonal(e.nodes[static_cast<std::size_t>(a)]), g, a, a, kl, km,
            e.dots[static_cast<std::size_t>(a)]);
  for (std::size_t p = 0; p < 6; ++p) {
    int a = detail::kPairs[p][0], b = detail::kPairs[p][1];
    if (e.nodes[static_cast<std::size_t>(a)] > e.nodes[static_cast<std::size_t>(b)]) std::swap(a, b);
    addPair(s.matrix.upper(e.nodes[static_cast<std::size_t>(a)], e.pair[p]), g, a, b, kl, km, e.dots[4 + p]);
  }
  return f.determinant() <= 0.0;
}

// Asks the cache for the blocks e adds to (none if it is dead).
void prefetchBlocks(const Element& e, const detail::BlockMatrix& matrix) noexcept {
  if (!e.alive) return;
  for (const int node : e.nodes) matrix.prefetchDiagonal(node);
  for (std::size_t p = 0; p < 6; ++p) {
    const int a = e.nodes[static_cast<std::size_t>(detail::kPairs[p][0])];
    const int b = e.nodes[static_cast<std::size_t>(detail::kPairs[p][1])];
    matrix.prefetchUpper(std::min(a, b), e.pair[p]);
  }
}

}  // namespace

int TissueModel::State::assemble(double mass_coefficient, double stiffness_coefficient) noexcept {
  matrix.setZero();
  for (auto& f : force_N) f.setZero();
  int inverted = 0;
  // The blocks an element adds to are scattered over the matrix (a megabyte on the benchmark's grids): asking
  // for those of the element kPrefetchAhead later while this one computes hides part of their misses.
  constexpr std::size_t kPrefetchAhead = 2;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (i + kPrefetchAhead < elements.size()) prefetchBlocks(elements[i + kPrefetchAhead], matrix);
    if (elements[i].alive) inverted += assembleElement(elements[i], *this, stiffness_coefficient) ? 1 : 0;
  }
  for (std::size_t i = 0; i < mass_kg.size(); ++i) {
    detail::Block& d = matrix.diagonal(static_cast<int>(i));
    const double m = mass_coefficient * mass_kg[i];
    d(0, 0) += m, d(1, 1) += m, d(2, 2) += m;
  }
  return inverted;
}

namespace {

// CG's coarse level is used while the tissue is hard to solve (the last step took kCoarseOn iterations or
// more; off again at kCoarseOff or fewer) and only where it pays: when the first step with it takes more
// than kCoarseHelps of the iterations SSOR alone took the step before, it stays off for kCoarseRest steps.
// An iteration with it costs about 1.5 without (three passes over the blocks, not two) and its build a few
// more: the swinging beams' hard steps fall from 56-60 iterations to 24-31 with it, the 83k-tet bunny's
// only from 27 to 25 on average. Iteration counts decide, never the clock: the same steps either way.
// A tissue whose aggregates would hold more than kCoarseLargest free nodes each is not tried: where it pays
// they hold 100-260 (the benchmark's grids); on the 83k-tet bunny (15k free nodes, about 950 an aggregate)
// the modes cut 27 iterations to 25 on average, and a trial step (capped, at 1.5x) showed in its p99.
constexpr int kCoarseOn = 12, kCoarseOff = 4, kCoarseRest = 1000, kCoarseLargest = 512;
constexpr double kCoarseHelps = 0.7;

}  // namespace

bool TissueModel::State::useCoarse() noexcept {
  if (options.coarse_aggregates < 2) return false;
  if (coarse_rest_steps > 0) --coarse_rest_steps;
  if (!(last_step_dt_s > 0.0)) return coarse_on;  // no step since the start or a reset: unchanged
  const int last = last_step_cg_iterations;
  if (coarse_on) {
    if (coarse_trial && last > kCoarseHelps * ssor_iterations)
      coarse_on = false, coarse_rest_steps = kCoarseRest;
    else if (last <= kCoarseOff)
      coarse_on = false;
    coarse_trial = false;
  } else if (last >= kCoarseOn && coarse_rest_steps == 0) {
    const auto free_nodes = std::count(active.begin(), active.end(), std::uint8_t{1});
    if (free_nodes > static_cast<std::ptrdiff_t>(options.coarse_aggregates) * kCoarseLargest)
      coarse_rest_steps = kCoarseRest;
    else
      coarse_on = coarse_trial = true, ssor_iterations = last;
  }
  return coarse_on;
}

bool TissueModel::State::buildCoarse() noexcept {
  if (!useCoarse()) return false;
  if (structure != partitioned_structure) {
    coarse.partition(rest_m, active, options.coarse_aggregates, options.coarse_nodes_per_aggregate);
    partitioned_structure = structure;
  }
  return coarse.build(matrix, x_m, active);
}

void TissueModel::State::addToolPress(double stiffness_coefficient) noexcept {
  press_force_N.setZero();
  if (!press.on) return;
  const int n = static_cast<int>(x_m.size());
  for (const int node : press.anchor.nodes)
    if (node < 0 || node >= n) return;
  const Eigen::Vector3d& normal = press.normal;
  const double gap_m = (embeddedPosition(press.anchor, x_m) - press.tool_m).dot(normal);
  if (!(gap_m > 0.0)) return;
  press_force_N = -press.stiffness_N_per_m * gap_m * normal;
  // f_i = w_i f(p), p = sum_j w_j x_j: df_i / dx_j = -k w_i w_j n n^T, so K gains k w_i w_j n n^T.
  const Eigen::Matrix3d nn = (stiffness_coefficient * press.stiffness_N_per_m) * (normal * normal.transpose());
  const auto& nodes = press.anchor.nodes;
  const auto& w = press.anchor.weights;
  for (std::size_t a = 0; a < 4; ++a) {
    force_N[static_cast<std::size_t>(nodes[a])] += w[a] * press_force_N;
    detail::addTo(matrix.diagonal(nodes[a]), (w[a] * w[a]) * nn);
    for (std::size_t b = a + 1; b < 4; ++b) {
      const int lo = std::min(nodes[a], nodes[b]), hi = std::max(nodes[a], nodes[b]);
      const int local = lo == hi ? -1 : matrix.find(lo, hi);
      if (local >= 0) detail::addTo(matrix.upper(lo, local), (w[a] * w[b]) * nn);
    }
  }
}

StepStats TissueModel::step(double dt_s) noexcept {
  State& s = *s_;
  StepStats stats;
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) return stats.status = StepStatus::BadTimeStep, stats;
  const double h = dt_s, alpha = s.material.damping.mass_per_s, beta = s.material.damping.stiffness_s;
  s.moveHeldNodes();
  stats.inverted_elements = s.assemble(1.0 + h * alpha, h * (h + beta));
  s.addToolPress(h * h);
  s.coarse_current = s.buildCoarse();
  stats.coarse_level = s.coarse_current;
  // The last step's dv is this step's best guess while the tissue moves; once it has settled (the last
  // solve took at most 2 iterations) dv is mostly the solver's own error, and v alone is the better guess.
  const bool extrapolate = s.options.extrapolate_velocity && s.last_step_dt_s == h && s.last_step_cg_iterations > 2;
  s.last_dt_s = h, s.last_step_dt_s = 0.0;
  const Eigen::Vector3d& g = s.boundary.gravity_m_per_s2;
  for (std::size_t i = 0; i < s.x_m.size(); ++i) {
    s.rhs[i] =
        s.active[i]
            ? Eigen::Vector3d(s.mass_kg[i] * s.v_m_per_s[i] + h * (s.external_N[i] + s.mass_kg[i] * g + s.force_N[i]))
            : Eigen::Vector3d::Zero();
    s.v_next[i] = extrapolate ? Eigen::Vector3d(s.v_m_per_s[i] + s.dv_last_m_per_s[i]) : s.v_m_per_s[i];
  }
  // The floor: gravity's momentum over the step (a tissue at rest has b ~ 0, and a residual small next to
  // its own weight is small enough).
  for (std::size_t i = 0; i < s.x_m.size(); ++i) s.force_N[i] = (h * s.mass_kg[i]) * g;
  const detail::PcgResult cg =
      detail::solvePcg(s.matrix, s.active, s.rhs, s.v_next, s.options.cg_tolerance, s.options.max_cg_iterations,
                       s.options.ssor_relaxation, s.force_N, s.pcg, s.coarse_current ? &s.coarse : nullptr);
  stats.cg_iterations = cg.iterations;
  stats.relative_residual = cg.relative_residual;
  bool finite = cg.finite;
  for (std::size_t i = 0; i < s.x_m.size() && finite; ++i) finite = s.v_next[i].allFinite();
  if (!finite) {
    for (auto& v : s.v_m_per_s) v.setZero();
    for (auto& dv : s.dv_last_m_per_s) dv.setZero();
    stats.status = StepStatus::NonFinite;
    return stats;
  }
  for (std::size_t i = 0; i < s.x_m.size(); ++i) {
    if (!s.active[i]) {
      s.dv_last_m_per_s[i].setZero();
      continue;
    }
    s.dv_last_m_per_s[i] = s.v_next[i] - s.v_m_per_s[i];
    s.v_m_per_s[i] = s.v_next[i], s.x_m[i] += h * s.v_next[i];
  }
  ++s.steps;
  s.last_step_dt_s = h, s.last_step_cg_iterations = cg.iterations;
  stats.status = cg.converged ? StepStatus::Converged : StepStatus::IterationLimit;
  return stats;
}

StaticResult TissueModel::solveStatic(const StaticOptions& options) {
  State& s = *s_;
  StaticResult result;
  const ModelOptions kept = s.options;
  s.options.rotation_tolerance = options.rotation_tolerance;
  s.options.max_rotation_iterations = options.max_rotation_iterations;
  s.moveHeldNodes();
  for (auto& v : s.v_m_per_s) v.setZero();
  const Eigen::Vector3d& g = s.boundary.gravity_m_per_s2;
  double load = 0.0;
  for (std::size_t i = 0; i < s.x_m.size(); ++i)
    if (s.active[i]) load += (s.external_N[i] + s.mass_kg[i] * g).squaredNorm();
  load = std::sqrt(load);
  s.coarse_current = false;
  for (int it = 0; it <= options.max_newton_iterations; ++it) {
    s.assemble(0.0, 1.0);
    s.addToolPress(1.0);
    for (std::size_t i = 0; i < s.x_m.size(); ++i)
      s.rhs[i] =
          s.active[i] ? Eigen::Vector3d(s.external_N[i] + s.mass_kg[i] * g + s.force_N[i]) : Eigen::Vector3d::Zero();
    const double residual = std::sqrt(detail::dotActive(s.rhs, s.rhs, s.active));
    if (it == 0) load = std::max(load, residual);  // no load (a prestretch alone): the first residual's scale
    result.relative_force_residual = load > 0.0 ? residual / load : 0.0;
    if (residual <= options.force_tolerance * load || it == options.max_newton_iterations) {
      result.converged = residual <= options.force_tolerance * load;
      break;
    }
    for (auto& dx : s.v_next) dx.setZero();
    const detail::PcgResult cg = detail::solvePcg(s.matrix, s.active, s.rhs, s.v_next, options.cg_tolerance,
                                                  options.max_cg_iterations, s.options.ssor_relaxation, {}, s.pcg);
    result.cg_iterations += cg.iterations;
    if (!cg.finite) break;
    for (std::size_t i = 0; i < s.x_m.size(); ++i)
      if (s.active[i]) s.x_m[i] += s.v_next[i];
    ++result.newton_iterations;
  }
  s.options = kept;
  s.last_dt_s = 0.0;       // the matrix is K alone, not a step's
  s.last_step_dt_s = 0.0;  // and the velocities were zeroed
  return result;
}

}  // namespace incise::physics
