// The global DFFD's lattice (§3.1): its construction (the box, the knots at the discontinuities and at the
// obstacles' v-extremes), the conservative C-/C+ projection onto each obstacle, the kernel that spreads it,
// the Theorem 1 guard, map(), stitch(); and worstPenetration. The model split is in global_dffd_split.cpp,
// the openings in global_dffd_openings.cpp.
#include "incise/global_dffd/global_dffd.h"
#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "incise/bspline/fold_over.h"
#include "incise/bspline/knot_vector.h"
#include "incise/bspline/tensor_kernel.h"
#include "incise/mesh/surface_query.h"

namespace incise::global_dffd {

DffdError::DffdError(DffdErrorKind kind_, const std::string& message, std::string obstacle_,
                     std::string other_obstacle_, int controls_needed_)
    : std::runtime_error(message),
      kind(kind_),
      obstacle(std::move(obstacle_)),
      other_obstacle(std::move(other_obstacle_)),
      controls_needed(controls_needed_) {}

namespace {

struct Triangle {
  Eigen::Vector3d a, b, c;
  Eigen::AlignedBox3d box;
};

std::vector<Triangle> triangles(const mesh::TriMesh& mesh) {
  std::vector<Triangle> out;
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    Eigen::Vector3d p[3];
    int i = 0;
    for (auto v = mesh.cfv_iter(f); v.is_valid() && i < 3; ++v) p[i++] = mesh::toEigen(mesh.point(*v));
    Triangle t{p[0], p[1], p[2], {}};
    t.box.extend(p[0]).extend(p[1]).extend(p[2]);
    out.push_back(t);
  }
  return out;
}

// Centre of mass of the solid a closed, outward-oriented mesh bounds (signed tetrahedra from the origin).
Eigen::Vector3d centreOfMass(const std::vector<Triangle>& tris) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double volume = 0.0;
  for (const Triangle& t : tris) {
    const double v = t.a.dot(t.b.cross(t.c)) / 6.0;
    volume += v;
    sum += v * (t.a + t.b + t.c) / 4.0;
  }
  return std::abs(volume) > 0.0 ? Eigen::Vector3d(sum / volume) : Eigen::Vector3d::Zero();
}

// Smallest and largest x of the triangles' parts inside the slab y in [y0, y1], z in [z0, z1]
// (Sutherland-Hodgman against the four planes). False when nothing lies in the slab.
bool xRangeInSlab(const std::vector<Triangle>& tris, double y0, double y1, double z0, double z1, double& x_min,
                  double& x_max) {
  x_min = INFINITY, x_max = -INFINITY;
  for (const Triangle& t : tris) {
    if (t.box.max().y() < y0 || t.box.min().y() > y1 || t.box.max().z() < z0 || t.box.min().z() > z1) continue;
    if (t.box.min().x() >= x_min && t.box.max().x() <= x_max) continue;  // cannot widen the range
    Eigen::Vector3d poly[9], next[9];
    int n = 3;
    poly[0] = t.a, poly[1] = t.b, poly[2] = t.c;
    const struct {
      int axis;
      double value;
      double sign;
    } planes[4] = {{1, y0, 1}, {1, y1, -1}, {2, z0, 1}, {2, z1, -1}};
    for (const auto& pl : planes) {
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d& p = poly[i];
        const Eigen::Vector3d& q = poly[(i + 1) % n];
        const double dp = pl.sign * (p[pl.axis] - pl.value), dq = pl.sign * (q[pl.axis] - pl.value);
        if (dp >= 0) next[m++] = p;
        if ((dp >= 0) != (dq >= 0)) next[m++] = p + (q - p) * (dp / (dp - dq));
      }
      n = m;
      std::copy(next, next + n, poly);
      if (n == 0) break;
    }
    for (int i = 0; i < n; ++i) x_min = std::min(x_min, poly[i].x()), x_max = std::max(x_max, poly[i].x());
  }
  return x_min <= x_max;
}

// Crossings of the line {y = y0, z = z0} along x with the triangles, counting only those at x > x_from
// (strictly inside a triangle's yz-projection: a line through an edge or a vertex counts nothing there).
int rayCrossings(const std::vector<Triangle>& tris, double x_from, double y0, double z0) {
  int crossings = 0;
  for (const Triangle& t : tris) {
    if (t.box.max().x() < x_from || t.box.min().y() > y0 || t.box.max().y() < y0 || t.box.min().z() > z0 ||
        t.box.max().z() < z0)
      continue;
    const auto side = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
      return (q.y() - p.y()) * (z0 - p.z()) - (q.z() - p.z()) * (y0 - p.y());
    };
    const double s0 = side(t.a, t.b), s1 = side(t.b, t.c), s2 = side(t.c, t.a);
    if (!((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0))) continue;
    const double x = (s1 * t.a.x() + s2 * t.b.x() + s0 * t.c.x()) / (s0 + s1 + s2);  // barycentric
    if (x > x_from) ++crossings;
  }
  return crossings;
}

// How often the line {y = y0, z = z0} along x enters the solid (half its crossings with the surface).
int entries(const std::vector<Triangle>& tris, double y0, double z0) {
  return rayCrossings(tris, -INFINITY, y0, z0) / 2;
}

// Whether p lies inside the closed surface: parity of a ray along +x, moved off p by a hair (h) three
// ways so that a ray through an edge or a vertex (which counts wrong) is outvoted.
bool insideSolid(const std::vector<Triangle>& tris, const Eigen::Vector3d& p, double h) {
  const int votes = rayCrossings(tris, p.x(), p.y() + h * 0.7548776, p.z() + h * 0.5698403) % 2 +
                    rayCrossings(tris, p.x(), p.y() - h * 0.3183099, p.z() + h * 0.8862269) % 2 +
                    rayCrossings(tris, p.x(), p.y() + h * 0.1415926, p.z() - h * 0.6931472) % 2;
  return votes >= 2;
}

double kernelValue(DffdKernel kind, double d, double width) {
  if (d >= width) return 0.0;
  if (kind == DffdKernel::Gaussian) {
    const double sigma = width / 3.0;
    return std::exp(-d * d / (2.0 * sigma * sigma));
  }
  // The uniform quadratic B-spline N(t) (support |t| < 3/2), scaled to 1 at d = 0 and 0 at d = width.
  const double t = 1.5 * d / width;
  const double n = t <= 0.5 ? 0.75 - t * t : 0.5 * (t - 1.5) * (t - 1.5);
  return n / 0.75;
}

int multiplicity(const std::vector<double>& knots, double t) {
  return static_cast<int>(std::count(knots.begin(), knots.end(), t));
}

// Monotone in v: every line along u through the obstacle enters it once (sampled at the control rows and
// between them, slightly off the grid so that no line runs through a vertex or an edge); else DffdError.
void checkMonotone(const DffdObstacle& d, const std::vector<Triangle>& tris) {
  const Eigen::Vector3d extent = d.box.sizes();
  for (int sj = 1; sj < 64; ++sj)
    for (int sk = 1; sk < 64; ++sk) {
      const double y = d.box.min().y() + extent.y() * (sj + 0.1234567) / 64.0;
      const double z = d.box.min().z() + extent.z() * (sk + 0.3456789) / 64.0;
      const int n = entries(tris, y, z);
      if (n > 1)
        throw DffdError(DffdErrorKind::NotMonotone,
                        "obstacle '" + d.name + "' is not monotone in v: the line along u at v = " +
                            core::formatNumber(y) + ", w = " + core::formatNumber(z) + " enters it " +
                            std::to_string(n) + " times (the projection onto C-(v), C+(v) needs one)",
                        d.name);
    }
}

}  // namespace

GlobalDffd::GlobalDffd(const std::vector<Obstacle>& obstacles, const GlobalDffdOptions& options)
    : options_(options),
      volume_(bspline::BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
                                               {2, 2, 2}, {2, 2, 2})) {
  const GlobalDffdOptions& o = options;
  if (o.order < 2 || o.order > 8)
    throw std::invalid_argument("GlobalDffd: order = " + std::to_string(o.order) + " is outside [2, 8]");
  for (int a = 0; a < 3; ++a)
    if (o.controls[a] < o.order || o.controls[a] > 4096)
      throw std::invalid_argument("GlobalDffd: controls[" + std::to_string(a) + "] = " + std::to_string(o.controls[a]) +
                                  " must be in [order, 4096]");
  if (!(o.margin_m >= 0.0) || !std::isfinite(o.margin_m))
    throw std::invalid_argument("GlobalDffd: margin_m = " + core::formatNumber(o.margin_m) + " must be >= 0");
  if (!(o.kernel_width > 0.0) || !std::isfinite(o.kernel_width))
    throw std::invalid_argument("GlobalDffd: kernel_width = " + core::formatNumber(o.kernel_width) + " must be > 0");
  if (!(o.epsilon > 0.0 && o.epsilon < 1e-3))
    throw std::invalid_argument("GlobalDffd: epsilon = " + core::formatNumber(o.epsilon) + " must be in (0, 1e-3)");
  if (!(o.clearance_m >= 0.0) || !std::isfinite(o.clearance_m))
    throw std::invalid_argument("GlobalDffd: clearance_m = " + core::formatNumber(o.clearance_m) + " must be >= 0");
  if (obstacles.empty() && !o.box)
    throw DffdError(DffdErrorKind::NoExtent, "GlobalDffd: no obstacle and no box: the lattice has no extent");
  place(obstacles);
  wrap(obstacles);
  markMovedCells();
}

void GlobalDffd::place(const std::vector<Obstacle>& obstacles) {
  const int order = options_.order;
  Eigen::AlignedBox3d all;
  for (const Obstacle& ob : obstacles) {
    const mesh::ManifoldReport report = mesh::checkManifold(ob.mesh.mesh());
    if (!report.closed_two_manifold)
      throw DffdError(DffdErrorKind::ObstacleNotClosed,
                      "obstacle '" + ob.name + "': not a closed two-manifold: " + report.first_problem, ob.name);
    DffdObstacle d;
    d.name = ob.name;
    d.input_index = static_cast<int>(obstacles_.size());
    const std::vector<Triangle> tris = triangles(ob.mesh.mesh());
    for (const Triangle& t : tris) {
      if (!t.a.allFinite() || !t.b.allFinite() || !t.c.allFinite())
        throw DffdError(DffdErrorKind::ObstacleNotFinite, "obstacle '" + ob.name + "': a vertex is not finite",
                        ob.name);
      d.box.extend(t.box);
    }
    d.u = centreOfMass(tris).x();
    all.extend(d.box);
    obstacles_.push_back(d);
  }
  if (options_.box) {
    box_ = *options_.box;
    if (box_.isEmpty() || !box_.min().allFinite() || !box_.max().allFinite())
      throw std::invalid_argument("GlobalDffd: the lattice box is empty or not finite");
    for (const DffdObstacle& d : obstacles_)
      if (!box_.contains(d.box))
        throw DffdError(DffdErrorKind::ObstacleOutsideBox,
                        "obstacle '" + d.name + "' lies outside the lattice box (its box [" +
                            core::formatNumber(d.box.min().x()) + ", " + core::formatNumber(d.box.max().x()) + "] x [" +
                            core::formatNumber(d.box.min().y()) + ", " + core::formatNumber(d.box.max().y()) + "] x [" +
                            core::formatNumber(d.box.min().z()) + ", " + core::formatNumber(d.box.max().z()) + "])",
                        d.name);
  } else {
    box_ = all;
    box_.min().array() -= options_.margin_m;
    box_.max().array() += options_.margin_m;
  }
  std::sort(obstacles_.begin(), obstacles_.end(),
            [](const DffdObstacle& a, const DffdObstacle& b) { return a.u < b.u; });
  for (size_t i = 1; i < obstacles_.size(); ++i)
    if (!(obstacles_[i].u > obstacles_[i - 1].u))
      throw DffdError(
          DffdErrorKind::SameCentre,
          "obstacles '" + obstacles_[i - 1].name + "' and '" + obstacles_[i].name + "' have the same centre in u",
          obstacles_[i - 1].name, obstacles_[i].name);
  volume_ = bspline::BSplineVolume::identity(box_, {order, order, order}, options_.controls);
  for (const DffdObstacle& d : obstacles_) {
    const int have = multiplicity(volume_.knots(0), d.u);
    if (have < order) volume_.insertKnot(0, d.u, order - have);
  }
  if (options_.v_knots == VKnots::AtObstacleExtremes) {
    const auto domain = volume_.domain(1);
    for (const DffdObstacle& d : obstacles_)
      for (const double v : {d.box.min().y(), d.box.max().y()}) {
        if (!(v > domain[0] && v < domain[1])) continue;
        const int have = multiplicity(volume_.knots(1), v);
        if (have < order - 1) volume_.insertKnot(1, v, order - 1 - have);
      }
  }
  identity_controls_.assign(volume_.controls().begin(), volume_.controls().end());
  spacing_u_ = box_.sizes().x() / (options_.controls[0] - order + 1);
  rest_u_.clear();
  for (int q = 0; q < volume_.controlCounts()[0]; ++q) rest_u_.push_back(volume_.control(q, 0, 0).x());
  const std::vector<double>& knots = volume_.knots(0);
  for (DffdObstacle& d : obstacles_) {
    const int first = static_cast<int>(std::find(knots.begin(), knots.end(), d.u) - knots.begin());
    d.i_minus = first - 1;
    d.i_plus = first;
    d.kernel_width = options_.kernel_width;
  }
}

void GlobalDffd::spread(const DffdObstacle& o, int j, int k, double move_minus, double move_plus, double width) {
  // kappa of the control's distance from the discontinuity at rest, in original control spacings: the
  // planes next to the inserted knots crowd together (their Greville abscissae), so a kernel over plane
  // indices would move neighbours past each other where a kernel over distance keeps their order.
  const int count = volume_.controlCounts()[0];
  for (int q = o.i_minus; q >= 0; --q) {
    const double kappa = kernelValue(options_.kernel, (o.u - rest_u_[static_cast<size_t>(q)]) / spacing_u_, width);
    if (kappa == 0.0) break;
    Eigen::Vector3d p = volume_.control(q, j, k);
    p.x() += kappa * move_minus;
    volume_.setControl(q, j, k, p);
  }
  for (int q = o.i_plus; q < count; ++q) {
    const double kappa = kernelValue(options_.kernel, (rest_u_[static_cast<size_t>(q)] - o.u) / spacing_u_, width);
    if (kappa == 0.0) break;
    Eigen::Vector3d p = volume_.control(q, j, k);
    p.x() += kappa * move_plus;
    volume_.setControl(q, j, k, p);
  }
}

void GlobalDffd::wrap(const std::vector<Obstacle>& obstacles) {
  const int order = options_.order;
  const std::array<int, 3> counts = volume_.controlCounts();
  const std::vector<double>& kv = volume_.knots(1);
  const std::vector<double>& kw = volume_.knots(2);
  // Neighbouring obstacles: each one's kernels must fit between the discontinuities.
  for (size_t i = 1; i < obstacles_.size(); ++i) {
    const DffdObstacle& a = obstacles_[i - 1];
    const DffdObstacle& b = obstacles_[i];
    // Each side's kernel reaches kernel_width spacings; between the two reaches, order - 1 more spacings
    // keep any basis function from seeing both moves.
    const int needed = static_cast<int>(std::ceil(2.0 * options_.kernel_width)) + order - 1;
    const int have = static_cast<int>(std::floor((b.u - a.u) / spacing_u_));
    if (have < needed) {
      const int controls = static_cast<int>(std::ceil(double(options_.controls[0]) * needed / std::max(have, 1)));
      throw DffdError(DffdErrorKind::TooClose,
                      "obstacles '" + a.name + "' and '" + b.name + "' are too close for order " +
                          std::to_string(order) + " and kernel width " + core::formatNumber(options_.kernel_width) +
                          ": " + std::to_string(needed) +
                          " control spacings are needed between their discontinuities, there are " +
                          std::to_string(have) + " (raise controls[0] from " + std::to_string(options_.controls[0]) +
                          " to at least " + std::to_string(controls) + ")",
                      a.name, b.name, controls);
    }
  }
  // The conservative boundary curves and the moves, per obstacle and control row.
  struct Move {
    int obstacle, j, k;
    double minus, plus;
  };
  std::vector<Move> moves;
  for (size_t i = 0; i < obstacles_.size(); ++i) {
    DffdObstacle& d = obstacles_[i];
    const std::vector<Triangle> tris = triangles(obstacles[static_cast<size_t>(d.input_index)].mesh.mesh());
    checkMonotone(d, tris);
    for (int k = 0; k < counts[2]; ++k)
      for (int j = 0; j < counts[1]; ++j) {
        double x_min, x_max;
        if (!xRangeInSlab(tris, kv[static_cast<size_t>(j)], kv[static_cast<size_t>(j + order)],
                          kw[static_cast<size_t>(k)], kw[static_cast<size_t>(k + order)], x_min, x_max))
          continue;
        const double minus = std::min(0.0, x_min - options_.clearance_m - volume_.control(d.i_minus, j, k).x());
        const double plus = std::max(0.0, x_max + options_.clearance_m - volume_.control(d.i_plus, j, k).x());
        d.max_move_m = std::max({d.max_move_m, -minus, plus});
        moves.push_back({static_cast<int>(i), j, k, minus, plus});
      }
  }
  // Spread the moves; under FoldPolicy::Widen, widen every kernel by a plane until Theorem 1 holds.
  const std::vector<Eigen::Vector3d> rest(volume_.controls().begin(), volume_.controls().end());
  for (double width = options_.kernel_width;; width += 1.0) {
    for (const Move& m : moves) spread(obstacles_[static_cast<size_t>(m.obstacle)], m.j, m.k, m.minus, m.plus, width);
    const bspline::FoldReport fold = bspline::checkAxisOrder(volume_, 0);
    if (fold.ok) {
      for (DffdObstacle& d : obstacles_) d.kernel_width = width;
      return;
    }
    const auto nearest =
        std::min_element(obstacles_.begin(), obstacles_.end(), [&](const DffdObstacle& a, const DffdObstacle& b) {
          return std::abs(a.i_minus - fold.i) < std::abs(b.i_minus - fold.i);
        });
    if (options_.on_fold == FoldPolicy::Refuse || width + 1.0 > counts[0])
      throw DffdError(DffdErrorKind::Folds,
                      "obstacle '" + nearest->name + "': the kernel (width " + core::formatNumber(width) +
                          " planes) would fold the lattice (Theorem 1): " + fold.message +
                          "; widen kernel_width, add control planes in u or use FoldPolicy::Widen",
                      nearest->name);
    for (int k = 0; k < counts[2]; ++k)  // back to the unmoved controls
      for (int j = 0; j < counts[1]; ++j)
        for (int i = 0; i < counts[0]; ++i)
          volume_.setControl(i, j, k, rest[static_cast<size_t>(volume_.controlIndex(i, j, k))]);
  }
}

int GlobalDffd::cellOf(const Eigen::Vector3d& x, int side, double& u) const {
  std::array<int, 3> spans;
  return cellAndSpans(x, side, u, spans);
}

int GlobalDffd::cellAndSpans(const Eigen::Vector3d& x, int side, double& u, std::array<int, 3>& spans) const {
  const auto domain = volume_.domain(0);
  u = std::clamp(x.x() + side * options_.epsilon, domain[0], domain[1]);
  const std::array<int, 3> counts = volume_.controlCounts();
  const double t[3] = {u, x.y(), x.z()};
  for (int a = 0; a < 3; ++a)
    spans[static_cast<size_t>(a)] =
        bspline::findSpan(volume_.knots(a), options_.order, counts[static_cast<size_t>(a)], t[a]);
  return spans[0] + counts[0] * (spans[1] + counts[1] * spans[2]);
}

Eigen::Vector3d GlobalDffd::map(const Eigen::Vector3d& x, int side) const {
  if (!box_.contains(x)) return x;
  double u = 0.0;
  std::array<int, 3> spans;
  // Where no control of the support moved, F is the identity lattice's: x itself (not its rounding).
  if (!moved_cell_[static_cast<size_t>(cellAndSpans(x, side, u, spans))]) return x;
  // BSplineVolume::evaluateUnchecked with the spans already found (the same operations: the same bits).
  const int o = options_.order;
  const double t[3] = {u, x.y(), x.z()};
  double basis[3][bspline::kMaxOrder];
  int first[3];
#if INCISE_TENSOR_AVX2
  if (o == 4) {  // the three axes at once, the same bits
    const double* const knots[3] = {volume_.knots(0).data(), volume_.knots(1).data(), volume_.knots(2).data()};
    bspline::detail::basisFunctions4x3(knots, spans.data(), t, basis);
  } else
#endif
    for (int a = 0; a < 3; ++a)
      bspline::basisFunctions(volume_.knots(a), o, spans[static_cast<size_t>(a)], t[a], basis[a]);
  for (int a = 0; a < 3; ++a) first[a] = spans[static_cast<size_t>(a)] - (o - 1);
  const std::array<int, 3> counts = volume_.controlCounts();
  return bspline::detail::tensorSum(volume_.controls().data()->data(), counts[0], counts[1],
                                    volume_.controlIndex(first[0], first[1], first[2]), volume_.orders(), basis[0],
                                    basis[1], basis[2]);
}

void GlobalDffd::markMovedCells() {
  // Knot cell (su, sv, sw) (span indices, each < the control count) is moved when a control of its support
  // (i in su - o + 1 .. su, likewise j, k) is not where place() put it (the identity lattice's).
  const std::array<int, 3> counts = volume_.controlCounts();
  const int o = options_.order;
  moved_cell_.assign(static_cast<size_t>(counts[0]) * counts[1] * counts[2], 0);
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      for (int i = 0; i < counts[0]; ++i) {
        if (volume_.control(i, j, k) == identity_controls_[static_cast<size_t>(volume_.controlIndex(i, j, k))])
          continue;
        for (int c = k; c < std::min(counts[2], k + o); ++c)
          for (int b = j; b < std::min(counts[1], j + o); ++b)
            for (int a = i; a < std::min(counts[0], i + o); ++a)
              moved_cell_[static_cast<size_t>(a + counts[0] * (b + counts[1] * c))] = 1;
      }
}

double GlobalDffd::minJacobian(int samples_per_cell) const {
  return bspline::minJacobianDeterminant(volume_, samples_per_cell);
}

void GlobalDffd::stitch(int index, double w_s) {
  if (index < 0 || index >= static_cast<int>(obstacles_.size()))
    throw std::invalid_argument("GlobalDffd::stitch: obstacle index " + std::to_string(index) + " is out of range");
  if (!(w_s >= box_.min().z() && w_s <= box_.max().z()))
    throw std::invalid_argument("GlobalDffd::stitch: w_s = " + core::formatNumber(w_s) + " is outside the box");
  const DffdObstacle& d = obstacles_[static_cast<size_t>(index)];
  const std::array<int, 3> counts = volume_.controlCounts();
  for (int j = 0; j < counts[1]; ++j) {
    // Each plane's column j goes to one point (X, v_j, w_s), X its most extreme projected u over the column
    // (leftmost for F-, rightmost for F+): every w maps to the same seam point, which stays clear of the
    // obstacle. (The paper puts both planes at (u_i, v_j, w_s), joining the two sides through the obstacle.)
    double x_minus = INFINITY, x_plus = -INFINITY;
    for (int k = 0; k < counts[2]; ++k) {
      x_minus = std::min(x_minus, volume_.control(d.i_minus, j, k).x());
      x_plus = std::max(x_plus, volume_.control(d.i_plus, j, k).x());
    }
    for (int k = 0; k < counts[2]; ++k) {
      volume_.setControl(d.i_minus, j, k, Eigen::Vector3d(x_minus, volume_.control(d.i_minus, j, k).y(), w_s));
      volume_.setControl(d.i_plus, j, k, Eigen::Vector3d(x_plus, volume_.control(d.i_plus, j, k).y(), w_s));
    }
  }
  markMovedCells();
}

double worstPenetration(const mesh::TriMesh& mesh, const std::vector<Obstacle>& obstacles, std::string* which) {
  double worst = 0.0;
  for (const Obstacle& ob : obstacles) {
    const std::vector<Triangle> tris = triangles(ob.mesh.mesh());
    Eigen::AlignedBox3d box;
    for (const Triangle& t : tris) box.extend(t.box);
    for (const auto v : mesh.vertices()) {
      if (mesh.status(v).deleted()) continue;
      const Eigen::Vector3d p = mesh::toEigen(mesh.point(v));
      if (!box.contains(p)) continue;
      if (!insideSolid(tris, p, 1e-9 * box.sizes().maxCoeff())) continue;
      double depth = INFINITY;
      for (const Triangle& t : tris)
        depth = std::min(depth, (mesh::closestPointOnTriangle(p, t.a, t.b, t.c) - p).norm());
      if (depth > worst) {
        worst = depth;
        if (which) *which = ob.name;
      }
    }
  }
  return worst;
}

}  // namespace incise::global_dffd
