#include "incise/cutting/global_dffd.h"
#include "incise/cutting/format.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "incise/cutting/clip_cap.h"
#include "incise/cutting/fold_over.h"
#include "incise/cutting/knot_vector.h"
#include "tensor_kernel.h"
#include "incise/cutting/surface_query.h"

namespace incise::cutting {
namespace {

struct Triangle {
  Eigen::Vector3d a, b, c;
  Eigen::AlignedBox3d box;
};

std::vector<Triangle> triangles(const TriMesh& mesh) {
  std::vector<Triangle> out;
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    Eigen::Vector3d p[3];
    int i = 0;
    for (auto v = mesh.cfv_iter(f); v.is_valid() && i < 3; ++v) p[i++] = toEigen(mesh.point(*v));
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
    const struct { int axis; double value; double sign; } planes[4] = {{1, y0, 1}, {1, y1, -1}, {2, z0, 1}, {2, z1, -1}};
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
int entries(const std::vector<Triangle>& tris, double y0, double z0) { return rayCrossings(tris, -INFINITY, y0, z0) / 2; }

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

}  // namespace

GlobalDffd::GlobalDffd(const std::vector<Obstacle>& obstacles, const GlobalDffdOptions& options)
    : options_(options),
      volume_(BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), {2, 2, 2},
                                      {2, 2, 2})) {
  const GlobalDffdOptions& o = options;
  if (o.order < 2 || o.order > 8) throw std::invalid_argument("GlobalDffd: order = " + std::to_string(o.order) + " is outside [2, 8]");
  for (int a = 0; a < 3; ++a)
    if (o.controls[a] < o.order || o.controls[a] > 4096)
      throw std::invalid_argument("GlobalDffd: controls[" + std::to_string(a) + "] = " + std::to_string(o.controls[a]) +
                                  " must be in [order, 4096]");
  if (!(o.margin_m >= 0.0) || !std::isfinite(o.margin_m)) throw std::invalid_argument("GlobalDffd: margin_m = " + formatNumber(o.margin_m) + " must be >= 0");
  if (!(o.kernel_width > 0.0) || !std::isfinite(o.kernel_width))
    throw std::invalid_argument("GlobalDffd: kernel_width = " + formatNumber(o.kernel_width) + " must be > 0");
  if (!(o.epsilon > 0.0 && o.epsilon < 1e-3)) throw std::invalid_argument("GlobalDffd: epsilon = " + formatNumber(o.epsilon) + " must be in (0, 1e-3)");
  if (!(o.clearance_m >= 0.0) || !std::isfinite(o.clearance_m))
    throw std::invalid_argument("GlobalDffd: clearance_m = " + formatNumber(o.clearance_m) + " must be >= 0");
  if (obstacles.empty() && !o.box) throw DffdError("GlobalDffd: no obstacle and no box: the lattice has no extent");
  place(obstacles);
  wrap(obstacles);
  markMovedCells();
}

void GlobalDffd::place(const std::vector<Obstacle>& obstacles) {
  const int order = options_.order;
  Eigen::AlignedBox3d all;
  for (const Obstacle& ob : obstacles) {
    const ManifoldReport report = checkManifold(ob.mesh.mesh());
    if (!report.closed_two_manifold)
      throw DffdError("obstacle '" + ob.name + "': not a closed two-manifold: " + report.first_problem);
    DffdObstacle d;
    d.name = ob.name;
    d.input_index = static_cast<int>(obstacles_.size());
    const std::vector<Triangle> tris = triangles(ob.mesh.mesh());
    for (const Triangle& t : tris) {
      if (!t.a.allFinite() || !t.b.allFinite() || !t.c.allFinite()) throw DffdError("obstacle '" + ob.name + "': a vertex is not finite");
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
        throw DffdError("obstacle '" + d.name + "' lies outside the lattice box (its box [" + formatNumber(d.box.min().x()) + ", " +
                        formatNumber(d.box.max().x()) + "] x [" + formatNumber(d.box.min().y()) + ", " + formatNumber(d.box.max().y()) + "] x [" +
                        formatNumber(d.box.min().z()) + ", " + formatNumber(d.box.max().z()) + "])");
  } else {
    box_ = all;
    box_.min().array() -= options_.margin_m;
    box_.max().array() += options_.margin_m;
  }
  std::sort(obstacles_.begin(), obstacles_.end(), [](const DffdObstacle& a, const DffdObstacle& b) { return a.u < b.u; });
  for (size_t i = 1; i < obstacles_.size(); ++i)
    if (!(obstacles_[i].u > obstacles_[i - 1].u))
      throw DffdError("obstacles '" + obstacles_[i - 1].name + "' and '" + obstacles_[i].name + "' have the same centre in u");
  volume_ = BSplineVolume::identity(box_, {order, order, order}, options_.controls);
  for (const DffdObstacle& d : obstacles_) {
    const int have = multiplicity(volume_.knots(0), d.u);
    if (have < order) volume_.insertKnot(0, d.u, order - have);
  }
  if (options_.v_knots) {
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
    if (have < needed)
      throw DffdError("obstacles '" + a.name + "' and '" + b.name + "' are too close for order " + std::to_string(order) +
                      " and kernel width " + formatNumber(options_.kernel_width) + ": " + std::to_string(needed) +
                      " control spacings are needed between their discontinuities, there are " + std::to_string(have) +
                      " (raise controls[0] from " + std::to_string(options_.controls[0]) + " to at least " +
                      std::to_string(static_cast<int>(std::ceil(double(options_.controls[0]) * needed / std::max(have, 1)))) + ")");
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
    // Monotone in v: every line along u through the obstacle enters it once (sampled at the control rows
    // and between them, slightly off the grid so that no line runs through a vertex or an edge).
    const Eigen::Vector3d extent = d.box.sizes();
    for (int sj = 1; sj < 64; ++sj)
      for (int sk = 1; sk < 64; ++sk) {
        const double y = d.box.min().y() + extent.y() * (sj + 0.1234567) / 64.0;
        const double z = d.box.min().z() + extent.z() * (sk + 0.3456789) / 64.0;
        const int n = entries(tris, y, z);
        if (n > 1)
          throw DffdError("obstacle '" + d.name + "' is not monotone in v: the line along u at v = " + formatNumber(y) + ", w = " + formatNumber(z) +
                          " enters it " + std::to_string(n) + " times (the projection onto C-(v), C+(v) needs one)");
      }
    for (int k = 0; k < counts[2]; ++k)
      for (int j = 0; j < counts[1]; ++j) {
        double x_min, x_max;
        if (!xRangeInSlab(tris, kv[static_cast<size_t>(j)], kv[static_cast<size_t>(j + order)], kw[static_cast<size_t>(k)],
                          kw[static_cast<size_t>(k + order)], x_min, x_max))
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
    const FoldReport fold = checkAxisOrder(volume_, 0);
    if (fold.ok) {
      for (DffdObstacle& d : obstacles_) d.kernel_width = width;
      return;
    }
    const auto nearest = std::min_element(obstacles_.begin(), obstacles_.end(), [&](const DffdObstacle& a, const DffdObstacle& b) {
      return std::abs(a.i_minus - fold.i) < std::abs(b.i_minus - fold.i);
    });
    if (options_.on_fold == FoldPolicy::Refuse || width + 1.0 > counts[0])
      throw DffdError("obstacle '" + nearest->name + "': the kernel (width " + formatNumber(width) + " planes) would fold the lattice (Theorem 1): " +
                      fold.message + "; widen kernel_width, add control planes in u or use FoldPolicy::Widen");
    for (int k = 0; k < counts[2]; ++k)  // back to the unmoved controls
      for (int j = 0; j < counts[1]; ++j)
        for (int i = 0; i < counts[0]; ++i) volume_.setControl(i, j, k, rest[static_cast<size_t>(volume_.controlIndex(i, j, k))]);
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
  for (int a = 0; a < 3; ++a) spans[static_cast<size_t>(a)] = findSpan(volume_.knots(a), options_.order, counts[static_cast<size_t>(a)], t[a]);
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
  double basis[3][kMaxOrder];
  int first[3];
  for (int a = 0; a < 3; ++a) {
    basisFunctions(volume_.knots(a), o, spans[static_cast<size_t>(a)], t[a], basis[a]);
    first[a] = spans[static_cast<size_t>(a)] - (o - 1);
  }
  const std::array<int, 3> counts = volume_.controlCounts();
  return detail::tensorSum(volume_.controls().data()->data(), counts[0], counts[1],
                           volume_.controlIndex(first[0], first[1], first[2]), volume_.orders(), basis[0], basis[1], basis[2]);
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
        if (volume_.control(i, j, k) == identity_controls_[static_cast<size_t>(volume_.controlIndex(i, j, k))]) continue;
        for (int c = k; c < std::min(counts[2], k + o); ++c)
          for (int b = j; b < std::min(counts[1], j + o); ++b)
            for (int a = i; a < std::min(counts[0], i + o); ++a) moved_cell_[static_cast<size_t>(a + counts[0] * (b + counts[1] * c))] = 1;
      }
}

double GlobalDffd::minJacobian(int samples_per_cell) const { return minJacobianDeterminant(volume_, samples_per_cell); }

void GlobalDffd::stitch(int index, double w_s) {
  if (index < 0 || index >= static_cast<int>(obstacles_.size()))
    throw std::invalid_argument("GlobalDffd::stitch: obstacle index " + std::to_string(index) + " is out of range");
  if (!(w_s >= box_.min().z() && w_s <= box_.max().z()))
    throw std::invalid_argument("GlobalDffd::stitch: w_s = " + formatNumber(w_s) + " is outside the box");
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

// ---------------------------------------------------------------------------------------------------------
// Splitting the model.

namespace {

struct Soup {
  std::vector<Eigen::Vector3d> x;
  std::vector<int> source;
  std::vector<std::array<int, 2>> edge;
  std::vector<std::int8_t> side;
  std::vector<int> plane;
  std::vector<std::array<int, 3>> faces;
  std::vector<int> remap;                      // compaction
  std::vector<int> touching;                   // splitAt: faces with a vertex on its plane

  int add(const Eigen::Vector3d& p, int src, std::array<int, 2> e, int on_plane) {
    x.push_back(p);
    source.push_back(src);
    edge.push_back(e);
    side.push_back(0);
    plane.push_back(on_plane);
    return static_cast<int>(x.size()) - 1;
  }
};

Soup soupOf(const TriMesh& mesh) {
  Soup s;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (const auto v : mesh.vertices())
    if (!mesh.status(v).deleted()) index[static_cast<size_t>(v.idx())] = s.add(toEigen(mesh.point(v)), v.idx(), {-1, -1}, -1);
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    std::array<int, 3> t{};
    int i = 0;
    for (auto v = mesh.cfv_ccwiter(f); v.is_valid() && i < 3; ++v) t[static_cast<size_t>(i++)] = index[static_cast<size_t>(v->idx())];
    s.faces.push_back(t);
  }
  return s;
}

void soupOf(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces, Soup& s) {
  s.x.assign(positions.begin(), positions.end());
  s.source.resize(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) s.source[v] = static_cast<int>(v);
  s.edge.assign(positions.size(), {-1, -1});
  s.side.assign(positions.size(), 0);
  s.plane.assign(positions.size(), -1);
  s.faces.assign(faces.begin(), faces.end());
  for (const auto& f : s.faces)
    for (const int v : f)
      if (v < 0 || static_cast<size_t>(v) >= positions.size())
        throw DffdError("splitAtDiscontinuities: a face refers to vertex " + std::to_string(v) + " of " +
                        std::to_string(positions.size()));
}

// Splits every face crossing the plane x = u and marks the vertices on it. The whole section is split,
// also where the model reaches beyond the box: F is the identity there, so both lips stay together, and
// each closed section curve gives exactly two lips (boundary loops) whatever the model's position.
void splitAt(Soup& s, double u, int plane, const Eigen::AlignedBox3d& box) {
  std::map<std::pair<int, int>, int> points;
  const auto sgn = [&](int v) { return s.x[static_cast<size_t>(v)].x() < u ? -1 : s.x[static_cast<size_t>(v)].x() > u ? 1 : 0; };
  // Vertices within a hair of the plane are put on it: splitting an edge there would make a sliver.
  const double snap = 1e-9 * box.sizes().maxCoeff();
  bool snapped = false;
  for (size_t v = 0; v < s.x.size(); ++v) {
    if (std::abs(s.x[v].x() - u) > snap) continue;
    s.x[v].x() = u;
    s.plane[v] = plane;
    snapped = true;
  }
  const auto point = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    if (const auto it = points.find(key); it != points.end()) return it->second;
    const Eigen::Vector3d& pa = s.x[static_cast<size_t>(key.first)];
    const Eigen::Vector3d& pb = s.x[static_cast<size_t>(key.second)];
    const double t = (u - pa.x()) / (pb.x() - pa.x());
    Eigen::Vector3d p = pa + t * (pb - pa);
    p.x() = u;
    const int src_a = s.source[static_cast<size_t>(key.first)], src_b = s.source[static_cast<size_t>(key.second)];
    const int id = s.add(p, -1, {src_a, src_b}, plane);
    points.emplace(key, id);
    return id;
  };
  // In place: a crossing face becomes its first piece, the others go to the end; every piece touches the
  // plane (separate()'s candidates, with the faces of snapped vertices).
  s.touching.clear();
  const size_t count = s.faces.size();
  const auto piece = [&](size_t f, bool first, std::array<int, 3> t) {
    if (first) {
      s.faces[f] = t;
      s.touching.push_back(static_cast<int>(f));
    } else {
      s.touching.push_back(static_cast<int>(s.faces.size()));
      s.faces.push_back(t);
    }
  };
  for (size_t i = 0; i < count; ++i) {
    const std::array<int, 3> f = s.faces[i];
    const int sa = sgn(f[0]), sb = sgn(f[1]), sc = sgn(f[2]);
    if (!((sa * sb < 0) || (sb * sc < 0) || (sc * sa < 0))) continue;
    // Rotate so that a is the vertex alone on its side (or on the plane).
    int r = 0;
    const int sg[3] = {sa, sb, sc};
    for (int k = 0; k < 3; ++k)
      if (sg[k] != 0 && sg[(k + 1) % 3] != sg[k] && sg[(k + 2) % 3] != sg[k]) r = k;
    const int a = f[static_cast<size_t>(r)], b = f[static_cast<size_t>((r + 1) % 3)], c = f[static_cast<size_t>((r + 2) % 3)];
    const int s_b = sg[(r + 1) % 3], s_c = sg[(r + 2) % 3];
    if (s_b == 0) {  // b on the plane: the crossing is on c-a
      const int p = point(c, a);
      piece(i, true, {a, b, p});
      piece(i, false, {b, c, p});
    } else if (s_c == 0) {  // c on the plane: the crossing is on a-b
      const int p = point(a, b);
      piece(i, true, {a, p, c});
      piece(i, false, {p, b, c});
    } else {  // a alone: crossings on a-b and c-a
      const int p = point(a, b), q = point(c, a);
      piece(i, true, {a, p, q});
      piece(i, false, {p, b, c});
      piece(i, false, {p, c, q});
    }
  }
  if (snapped) {  // faces around vertices put on the plane: a full pass (rare)
    s.touching.clear();
    for (size_t f = 0; f < s.faces.size(); ++f)
      for (const int v : s.faces[f])
        if (s.plane[static_cast<size_t>(v)] == plane) {
          s.touching.push_back(static_cast<int>(f));
          break;
        }
  }
}

// Duplicates every vertex on `plane` whose faces lie on both sides (and none across): the + faces get a copy.
void separate(Soup& s, int plane, double u) {
  // (vertex on the plane, face around it), sorted by vertex.
  std::vector<std::pair<int, int>> around;
  for (const int f : s.touching)
    for (const int v : s.faces[static_cast<size_t>(f)])
      if (s.plane[static_cast<size_t>(v)] == plane) around.emplace_back(v, f);
  std::sort(around.begin(), around.end());
  std::vector<int> face_side;
  for (size_t begin = 0; begin < around.size();) {
    const int v = around[begin].first;
    size_t end = begin;
    while (end < around.size() && around[end].first == v) ++end;
    bool minus = false, plus = false, across = false;
    face_side.assign(end - begin, 0);
    for (size_t i = begin; i < end; ++i) {
      int side = 0;
      for (const int w : s.faces[static_cast<size_t>(around[i].second)]) {
        const double x = s.x[static_cast<size_t>(w)].x();
        const int sw = x < u ? -1 : x > u ? 1 : 0;
        if (sw != 0 && side != 0 && sw != side) across = true;
        if (sw != 0) side = sw;
      }
      face_side[i - begin] = side;
      minus = minus || side < 0;
      plus = plus || side > 0;
    }
    if (!across && minus && plus) {  // else the split's end, or a vertex touching the plane from one side
      s.side[static_cast<size_t>(v)] = -1;
      const int copy = s.add(s.x[static_cast<size_t>(v)], s.source[static_cast<size_t>(v)], s.edge[static_cast<size_t>(v)], plane);
      s.side[static_cast<size_t>(copy)] = 1;
      for (size_t i = begin; i < end; ++i)
        if (face_side[i - begin] > 0)
          for (int& w : s.faces[static_cast<size_t>(around[i].second)])
            if (w == v) w = copy;
    }
    begin = end;
  }
}

// Closes each opening left by separate(): a loop of boundary edges whose vertices all lie on `plane` on
// one side. Its two halves, from its lowest-v vertex to its highest, are given the same v-values (each
// half's edges split where the other half has a vertex) and welded vertex to vertex: once F is stitched
// both halves map onto the same seam, so the weld closes the surface without a flat face. A half that is
// not strictly monotone in v leaves that loop open (returned count).
int zipOpenings(Soup& s, int plane, const Eigen::AlignedBox3d& box) {
  std::map<std::pair<int, int>, int> face_of;  // directed edge -> face
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) face_of[{s.faces[f][static_cast<size_t>(i)], s.faces[f][static_cast<size_t>((i + 1) % 3)]}] = static_cast<int>(f);
  std::map<int, int> next;  // boundary: a -> b with no b -> a, both on the plane with the same side
  for (const auto& [e, f] : face_of) {
    (void)f;
    const auto [a, b] = e;
    if (face_of.count({b, a})) continue;
    if (s.plane[static_cast<size_t>(a)] != plane || s.plane[static_cast<size_t>(b)] != plane) continue;
    if (s.side[static_cast<size_t>(a)] == 0 || s.side[static_cast<size_t>(a)] != s.side[static_cast<size_t>(b)]) continue;
    next[a] = b;
  }
  const auto vOf = [&](int id) { return s.x[static_cast<size_t>(id)].y(); };
  std::map<int, char> used;
  int left_open = 0;
  for (const auto& entry : next) {
    const int start = entry.first;
    if (used.count(start)) continue;
    std::vector<int> loop;
    int v = start;
    while (!used.count(v) && next.count(v)) {
      used[v] = 1;
      loop.push_back(v);
      v = next[v];
    }
    if (v != start || loop.size() < 3) continue;
    const int n = static_cast<int>(loop.size());
    int lo = 0, hi = 0;
    for (int i = 1; i < n; ++i) {
      if (vOf(loop[static_cast<size_t>(i)]) < vOf(loop[static_cast<size_t>(lo)])) lo = i;
      if (vOf(loop[static_cast<size_t>(i)]) > vOf(loop[static_cast<size_t>(hi)])) hi = i;
    }
    std::vector<int> a, b;  // a: forward along the loop (its edges a[i] -> a[i+1]); b: backward
    for (int i = lo;; i = (i + 1) % n) {
      a.push_back(loop[static_cast<size_t>(i)]);
      if (i == hi) break;
    }
    for (int i = lo;; i = (i + n - 1) % n) {
      b.push_back(loop[static_cast<size_t>(i)]);
      if (i == hi) break;
    }
    const auto monotone = [&](const std::vector<int>& c) {
      for (size_t i = 1; i < c.size(); ++i)
        if (!(vOf(c[i]) > vOf(c[i - 1]))) return false;
      return true;
    };
    // Only an opening inside the box is stitched (beyond it F is the identity: nothing maps its halves
    // together), and only when no face already joins its two halves (welding would fold it flat).
    bool weldable = monotone(a) && monotone(b);
    for (const int id : loop) weldable = weldable && box.contains(s.x[static_cast<size_t>(id)]);
    if (weldable) {
      std::map<int, int> half;
      for (size_t i = 1; i + 1 < a.size(); ++i) half[a[i]] = 1;
      for (size_t i = 1; i + 1 < b.size(); ++i) half[b[i]] = 2;
      for (const auto& f : s.faces) {
        int mask = 0;
        for (const int id : f)
          if (const auto it = half.find(id); it != half.end()) mask |= it->second;
        if (mask == 3) weldable = false;
      }
    }
    // The fallback: a strip of triangles zipped between the two halves in order of v (each triangle takes
    // two consecutive vertices of one half and one of the other, the loop's edges reversed). Once stitched
    // both halves lie on the seam, so the strip is thin; it is kept only if the result is a two-manifold.
    const auto ladder = [&] {
      std::vector<std::array<int, 3>> strip;
      size_t ia = 0, ib = 0;
      while (ia + 1 < a.size() || ib + 1 < b.size()) {
        const bool advance_a = ib + 1 >= b.size() || (ia + 1 < a.size() && vOf(a[ia + 1]) <= vOf(b[ib + 1]));
        const std::array<int, 3> f = advance_a ? std::array<int, 3>{a[ia + 1], a[ia], b[ib]} : std::array<int, 3>{b[ib], b[ib + 1], a[ia]};
        advance_a ? ++ia : ++ib;
        if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) strip.push_back(f);
      }
      std::map<std::pair<int, int>, int> uses;
      bool manifold = true;
      for (const auto* faces : {&s.faces, &strip})
        for (const auto& f : *faces)
          for (int i = 0; i < 3 && manifold; ++i)
            manifold = ++uses[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] == 1;
      if (!manifold) return false;
      for (const auto& f : strip) {
        s.faces.push_back(f);
        for (int i = 0; i < 3; ++i) face_of[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] = static_cast<int>(s.faces.size()) - 1;
      }
      return true;
    };
    if (!weldable) {
      if (!ladder()) ++left_open;
      continue;
    }
    // Splits the chain edge p -> q (loop direction) of face f at the given points (ordered from p to q).
    const auto splitEdge = [&](int p, int q, const std::vector<int>& points) {
      const int f = face_of.at({p, q});
      auto t = s.faces[static_cast<size_t>(f)];
      while (t[0] != p) std::rotate(t.begin(), t.begin() + 1, t.end());
      const int r = t[2];
      std::vector<int> chain{p};
      chain.insert(chain.end(), points.begin(), points.end());
      chain.push_back(q);
      const auto record = [&](int face) {
        const auto& g = s.faces[static_cast<size_t>(face)];
        for (int i = 0; i < 3; ++i) face_of[{g[static_cast<size_t>(i)], g[static_cast<size_t>((i + 1) % 3)]}] = face;
      };
      face_of.erase({p, q});
      s.faces[static_cast<size_t>(f)] = {chain[0], chain[1], r};
      record(f);
      for (size_t i = 1; i + 1 < chain.size(); ++i) {
        s.faces.push_back({chain[i], chain[i + 1], r});
        record(static_cast<int>(s.faces.size()) - 1);
      }
    };
    // The merged v-sequence: each half gets a point where the other has a vertex.
    const auto insertInto = [&](const std::vector<int>& chain, const std::vector<int>& other, bool forward) {
      std::vector<int> out{chain[0]};
      size_t k = 1;
      for (size_t i = 1; i < chain.size(); ++i) {
        const int p = chain[i - 1], q = chain[i];
        std::vector<int> points;
        for (; k + 1 < other.size() && vOf(other[k]) < vOf(q); ++k) {
          if (vOf(other[k]) <= vOf(p)) continue;
          const double t = (vOf(other[k]) - vOf(p)) / (vOf(q) - vOf(p));
          Eigen::Vector3d x = s.x[static_cast<size_t>(p)] + t * (s.x[static_cast<size_t>(q)] - s.x[static_cast<size_t>(p)]);
          x.y() = vOf(other[k]);
          const int m = s.add(x, -1, {-1, -1}, plane);
          s.side[static_cast<size_t>(m)] = s.side[static_cast<size_t>(p)];
          points.push_back(m);
        }
        if (vOf(other[k]) == vOf(q) && k + 1 < other.size()) ++k;
        if (!points.empty()) {
          if (forward) {
            splitEdge(p, q, points);
          } else {
            std::vector<int> reversed(points.rbegin(), points.rend());
            splitEdge(q, p, reversed);
          }
        }
        out.insert(out.end(), points.begin(), points.end());
        out.push_back(q);
      }
      return out;
    };
    const std::vector<std::array<int, 3>> before = s.faces;
    const auto face_of_before = face_of;
    const std::vector<int> a2 = insertInto(a, b, true);
    const std::vector<int> b2 = insertInto(b, a, false);
    std::map<int, int> to;
    for (size_t i = 1; i + 1 < a2.size() && a2.size() == b2.size(); ++i) to[b2[i]] = a2[i];
    std::vector<std::array<int, 3>> welded = s.faces;
    for (auto& f : welded)
      for (int& id : f)
        if (const auto it = to.find(id); it != to.end()) id = it->second;
    // The weld must leave a two-manifold: no face folded flat, no directed edge used twice.
    std::map<std::pair<int, int>, int> uses;
    bool manifold = a2.size() == b2.size();
    for (const auto& f : welded) {
      manifold = manifold && f[0] != f[1] && f[1] != f[2] && f[0] != f[2];
      for (int i = 0; i < 3 && manifold; ++i)
        manifold = ++uses[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] == 1;
    }
    if (!manifold) {  // undo, then the strip
      s.faces = before;
      face_of = face_of_before;
      if (!ladder()) ++left_open;
      continue;
    }
    s.faces = std::move(welded);
  }
  return left_open;
}

SurfaceMesh meshOf(const std::vector<Eigen::Vector3d>& x, const std::vector<std::array<int, 3>>& faces) {
  SurfaceMesh mesh;
  TriMesh& m = mesh.mesh();
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(x.size());
  for (const auto& p : x) handles.push_back(m.add_vertex(toOpenMesh(p)));
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    if (!m.add_face(handles[static_cast<size_t>(t[0])], handles[static_cast<size_t>(t[1])], handles[static_cast<size_t>(t[2])]).is_valid())
      throw DffdError("splitting the model: face " + std::to_string(f) + " cannot be added (the model is not a two-manifold there)");
  }
  return mesh;
}

}  // namespace

namespace {

void splitSoup(Soup& s, const GlobalDffd& dffd, bool close_openings, DffdSplit& split) {
  for (size_t i = 0; i < dffd.obstacles().size(); ++i) {
    splitAt(s, dffd.obstacles()[i].u, static_cast<int>(i), dffd.box());
    separate(s, static_cast<int>(i), dffd.obstacles()[i].u);
  }
  split.left_open = 0;
  if (!close_openings) {  // nothing welded, every vertex used: hand the buffers over (swapped, both reused)
    std::swap(split.rest_m, s.x);
    std::swap(split.source_vertex, s.source);
    std::swap(split.source_edge, s.edge);
    std::swap(split.side, s.side);
    std::swap(split.plane, s.plane);
    std::swap(split.faces, s.faces);
    return;
  }
  for (size_t i = 0; i < dffd.obstacles().size(); ++i) split.left_open += zipOpenings(s, static_cast<int>(i), dffd.box());
  // Compact: vertices no face uses any more (welded away) are dropped. split's buffers keep their capacity.
  s.remap.assign(s.x.size(), -1);
  for (const auto& f : s.faces)
    for (const int v : f) s.remap[static_cast<size_t>(v)] = 0;
  split.rest_m.clear();
  split.source_vertex.clear();
  split.source_edge.clear();
  split.side.clear();
  split.plane.clear();
  for (size_t v = 0; v < s.x.size(); ++v) {
    if (s.remap[v] < 0) continue;
    s.remap[v] = static_cast<int>(split.rest_m.size());
    split.rest_m.push_back(s.x[v]);
    split.source_vertex.push_back(s.source[v]);
    split.source_edge.push_back(s.edge[v]);
    split.side.push_back(s.side[v]);
    split.plane.push_back(s.plane[v]);
  }
  split.faces.resize(s.faces.size());
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) split.faces[f][static_cast<size_t>(i)] = s.remap[static_cast<size_t>(s.faces[f][static_cast<size_t>(i)])];
}

// The working buffers of the splits made on this thread, kept so that a model split frame after frame does
// not map fresh pages every frame (about a third of the frame time on the robot otherwise).
Soup& scratchSoup() {
  thread_local Soup soup;
  return soup;
}

}  // namespace

DffdSplit splitAtDiscontinuities(const SurfaceMesh& model, const GlobalDffd& dffd, bool close_openings) {
  Soup soup = soupOf(model.mesh());
  DffdSplit split;
  splitSoup(soup, dffd, close_openings, split);
  return split;
}

DffdSplit splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces,
                                 const GlobalDffd& dffd, bool close_openings) {
  DffdSplit split;
  splitAtDiscontinuities(positions, faces, dffd, close_openings, split);
  return split;
}

void splitAtDiscontinuities(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces,
                            const GlobalDffd& dffd, bool close_openings, DffdSplit& out) {
  Soup& soup = scratchSoup();
  soupOf(positions, faces, soup);
  splitSoup(soup, dffd, close_openings, out);
}

SurfaceMesh DffdSplit::surface(std::span<const Eigen::Vector3d> positions) const {
  if (!positions.empty() && positions.size() != rest_m.size())
    throw DffdError("DffdSplit::surface: " + std::to_string(positions.size()) + " positions for " + std::to_string(rest_m.size()) +
                    " vertices");
  return meshOf(positions.empty() ? rest_m : std::vector<Eigen::Vector3d>(positions.begin(), positions.end()), faces);
}

void deformSplit(const DffdSplit& split, const GlobalDffd& dffd, std::span<Eigen::Vector3d> out) {
  if (out.size() != split.rest_m.size())
    throw DffdError("deformSplit: " + std::to_string(out.size()) + " output positions for " + std::to_string(split.rest_m.size()) +
                    " split vertices");
  for (size_t v = 0; v < out.size(); ++v) out[v] = dffd.map(split.rest_m[v], split.side[v]);
}

SurfaceMesh deformSplit(const DffdSplit& split, const GlobalDffd& dffd) {
  std::vector<Eigen::Vector3d> positions(split.rest_m.size());
  deformSplit(split, dffd, positions);
  return split.surface(positions);
}

namespace {

std::vector<Eigen::Vector3d> restOf(const DffdSplit& split) {
  if (split.side.size() != split.rest_m.size())
    throw DffdError("DffdBinding: the split has " + std::to_string(split.rest_m.size()) + " vertices but " +
                    std::to_string(split.side.size()) + " sides");
  return split.rest_m;
}

std::vector<int> insideOf(const std::vector<Eigen::Vector3d>& rest, const Eigen::AlignedBox3d& box) {
  std::vector<int> inside;
  for (size_t v = 0; v < rest.size(); ++v)
    if (box.contains(rest[v])) inside.push_back(static_cast<int>(v));
  return inside;
}

// The parameters map() evaluates F at: u shifted by side * epsilon and clamped to the domain.
std::vector<Eigen::Vector3d> boundParameters(const std::vector<Eigen::Vector3d>& rest, const std::vector<int>& inside,
                                             const DffdSplit& split, const GlobalDffd& dffd) {
  const auto domain = dffd.volume().domain(0);
  std::vector<Eigen::Vector3d> parameters;
  parameters.reserve(inside.size());
  for (const int v : inside) {
    const Eigen::Vector3d& x = rest[static_cast<size_t>(v)];
    const double u = std::clamp(x.x() + split.side[static_cast<size_t>(v)] * dffd.options().epsilon, domain[0], domain[1]);
    parameters.emplace_back(u, x.y(), x.z());
  }
  return parameters;
}

}  // namespace

DffdBinding::DffdBinding(const DffdSplit& split, const GlobalDffd& dffd)
    : rest_(restOf(split)), inside_(insideOf(rest_, dffd.box())), binding_(dffd.volume(), boundParameters(rest_, inside_, split, dffd)) {
  cells_.reserve(inside_.size());
  for (const int v : inside_) {
    double u = 0.0;
    cells_.push_back(dffd.cellOf(rest_[static_cast<size_t>(v)], split.side[static_cast<size_t>(v)], u));
  }
}

void DffdBinding::deform(const GlobalDffd& dffd, std::span<Eigen::Vector3d> out) const {
  if (out.size() != rest_.size())
    throw DffdError("DffdBinding::deform: " + std::to_string(out.size()) + " output positions for " + std::to_string(rest_.size()) +
                    " split vertices");
  const size_t n = inside_.size();
  // The bound vertices' positions go to out[0, n) first, then each to its own slot, last first: inside_ is
  // increasing with inside_[b] >= b, so a move never overwrites a position still to be moved.
  if (!binding_.deformAll(dffd.volume(), out.first(n)))
    throw DffdError("DffdBinding::deform: the GlobalDffd's lattice (orders or knots) is not the one the split was bound to");
  // As map(): a vertex in a cell where no control moved is its rest position exactly.
  for (size_t b = n; b-- > 0;)
    out[static_cast<size_t>(inside_[b])] = dffd.identityCell(cells_[b]) ? rest_[static_cast<size_t>(inside_[b])] : out[b];
  size_t next = 0;  // the vertices outside the box keep their rest position
  for (size_t v = 0; v < rest_.size(); ++v) {
    if (next < n && static_cast<size_t>(inside_[next]) == v) {
      ++next;
      continue;
    }
    out[v] = rest_[v];
  }
}

void validateModel(const SurfaceMesh& model, bool closed) {
  const ManifoldReport report = checkManifold(model.mesh());
  if (report.closed_two_manifold) return;
  const bool only_open = report.degenerate_faces == 0 && report.non_manifold_edges == 0 && report.non_manifold_vertices == 0;
  if (only_open && !closed && model.mesh().n_faces() > 0) return;  // a two-manifold with boundary
  throw DffdError("the model is not " + std::string(closed ? "a closed two-manifold" : "a two-manifold without degenerate faces") +
                  ": " + report.first_problem);
}

double stitchLevel(const DffdSplit& split, const GlobalDffd& dffd, int index) {
  double sum = 0.0;
  int count = 0;
  for (size_t v = 0; v < split.rest_m.size(); ++v)
    if (split.plane[v] == index) sum += split.rest_m[v].z(), ++count;
  return count > 0 ? sum / count : dffd.box().center().z();
}

SurfaceMesh cappedDeform(const SurfaceMesh& model, const GlobalDffd& dffd) {
  // Pieces between consecutive planes: below the first, between each pair, above the last.
  std::vector<SurfaceMesh> pieces;
  SurfaceMesh rest = model;
  for (const DffdObstacle& o : dffd.obstacles()) {
    pieces.push_back(clipAndCap(rest, 0, o.u, KeepSide::Below));
    rest = clipAndCap(rest, 0, o.u, KeepSide::Above);
  }
  pieces.push_back(std::move(rest));
  SurfaceMesh out;
  TriMesh& m = out.mesh();
  for (size_t p = 0; p < pieces.size(); ++p) {
    const TriMesh& piece = pieces[p].mesh();
    std::vector<TriMesh::VertexHandle> handles(piece.n_vertices());
    for (const auto v : piece.vertices()) {
      if (piece.status(v).deleted()) continue;
      const Eigen::Vector3d x = toEigen(piece.point(v));
      int side = 0;  // a cap vertex on the plane below this piece (+ side) or above it (- side)
      if (p > 0 && x.x() == dffd.obstacles()[p - 1].u) side = 1;
      if (p < dffd.obstacles().size() && x.x() == dffd.obstacles()[p].u) side = -1;
      handles[static_cast<size_t>(v.idx())] = m.add_vertex(toOpenMesh(dffd.map(x, side)));
    }
    for (const auto f : piece.faces()) {
      if (piece.status(f).deleted()) continue;
      std::array<TriMesh::VertexHandle, 3> t;
      int i = 0;
      for (auto v = piece.cfv_ccwiter(f); v.is_valid() && i < 3; ++v) t[static_cast<size_t>(i++)] = handles[static_cast<size_t>(v->idx())];
      m.add_face(t[0], t[1], t[2]);
    }
  }
  return out;
}

double worstPenetration(const TriMesh& mesh, const std::vector<Obstacle>& obstacles, std::string* which) {
  double worst = 0.0;
  for (const Obstacle& ob : obstacles) {
    const std::vector<Triangle> tris = triangles(ob.mesh.mesh());
    Eigen::AlignedBox3d box;
    for (const Triangle& t : tris) box.extend(t.box);
    for (const auto v : mesh.vertices()) {
      if (mesh.status(v).deleted()) continue;
      const Eigen::Vector3d p = toEigen(mesh.point(v));
      if (!box.contains(p)) continue;
      if (!insideSolid(tris, p, 1e-9 * box.sizes().maxCoeff())) continue;
      double depth = INFINITY;
      for (const Triangle& t : tris) depth = std::min(depth, (closestPointOnTriangle(p, t.a, t.b, t.c) - p).norm());
      if (depth > worst) {
        worst = depth;
        if (which) *which = ob.name;
      }
    }
  }
  return worst;
}

int boundaryLoops(const TriMesh& mesh) {
  std::vector<char> seen(mesh.n_halfedges(), 0);
  int loops = 0;
  for (const auto h : mesh.halfedges()) {
    if (mesh.status(h).deleted() || !mesh.is_boundary(h) || seen[static_cast<size_t>(h.idx())]) continue;
    ++loops;
    for (auto g = h; !seen[static_cast<size_t>(g.idx())]; g = mesh.next_halfedge_handle(g)) seen[static_cast<size_t>(g.idx())] = 1;
  }
  return loops;
}

}  // namespace incise::cutting
