#include "incise/incision/stroke_path.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "incise/core/format.h"
#include "incise/mesh/surface_query.h"
#include "incise/mesh/vertex_grid.h"

namespace incise::incision {

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("strokeAlongPath: " + what);
}

void checkPositive(double value, const char* name) {
  check(std::isfinite(value) && value > 0.0,
        std::string(name) + " = " + core::formatNumber(value) + " must be finite and > 0");
}

}  // namespace

Stroke strokeAlongPath(const mesh::SurfaceMesh& surface, const StrokePathOptions& o) {
  check(o.start_m.allFinite(), "start_m is not finite");
  check(o.direction.allFinite() && o.direction.norm() > 0.0, "direction must be finite and non-zero");
  check(o.down.allFinite() && o.down.norm() > 0.0, "down must be finite and non-zero");
  checkPositive(o.length_m, "length_m");
  checkPositive(o.speed_m_per_s, "speed_m_per_s");
  checkPositive(o.rate_hz, "rate_hz");
  checkPositive(o.height_m, "height_m");
  check(std::isfinite(o.bend_m), "bend_m = " + core::formatNumber(o.bend_m) + " is not finite");
  check(std::isfinite(o.wave_m), "wave_m = " + core::formatNumber(o.wave_m) + " is not finite");

  const mesh::TriMesh& mesh = surface.mesh();
  double longest_m = 0.0, mean_m = 0.0;
  for (const auto e : mesh.edges()) {
    const double l = mesh.calc_edge_length(e);
    longest_m = std::max(longest_m, l);
    mean_m += l;
  }
  mean_m /= std::max<double>(1.0, static_cast<double>(mesh.n_edges()));
  // Coarse cells: every ray spans 2 * height_m, and a fine grid would probe thousands of empty cells.
  mesh::VertexGrid grid(std::max({2.0 * mean_m, 0.05 * o.height_m, 1e-9}));
  for (const auto v : mesh.vertices()) grid.insert(v.idx(), mesh::toEigen(mesh.point(v)));

  const Eigen::Vector3d down = o.down.normalized();
  const Eigen::Vector3d across = o.direction - o.direction.dot(down) * down;  // the direction's part across the rays
  check(across.norm() > 1e-9 * o.direction.norm(), "direction " + core::formatPoint(o.direction) +
                                                       " is along the rays (down " + core::formatPoint(o.down) +
                                                       "): the stroke would not move across the surface");
  const Eigen::Vector3d dir = across.normalized();
  const Eigen::Vector3d side = dir.cross(down);
  const double dt_s = 1.0 / o.rate_hz;
  const int count = static_cast<int>(std::floor(o.length_m / (o.speed_m_per_s * dt_s)));
  Stroke stroke;
  stroke.blade_direction = dir;
  for (int k = 0; k <= count; ++k) {
    const double along_m = o.speed_m_per_s * dt_s * k;
    const double x = along_m / o.length_m;  // 0 .. 1
    const double sideways_m = 4.0 * o.bend_m * x * (1.0 - x) + o.wave_m * std::sin(2.0 * std::numbers::pi * x);
    const Eigen::Vector3d path = o.start_m + along_m * dir + sideways_m * side;
    const Eigen::Vector3d above = path - o.height_m * down;
    const auto hit = mesh::intersectSegment(mesh, grid, above, above + 2.0 * o.height_m * down, longest_m);
    if (!hit) {
      check(k > 0, "the first ray misses the surface");
      break;
    }
    const StrokeSample sample{hit->point_m, hit->normal, o.start_time_s + dt_s * k};
    if (k == 0) {
      stroke.first = sample;
    } else {
      stroke.samples.push_back(sample);
    }
  }
  return stroke;
}

}  // namespace incise::incision
