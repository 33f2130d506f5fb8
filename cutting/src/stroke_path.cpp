#include "incise/cutting/stroke_path.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "incise/cutting/surface_query.h"
#include "incise/cutting/vertex_grid.h"

namespace incise::cutting {

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("strokeAlongPath: " + what);
}

}  // namespace

Stroke strokeAlongPath(const SurfaceMesh& surface, const StrokePathOptions& o) {
  check(o.start_m.allFinite(), "start_m is not finite");
  check(o.direction.allFinite() && o.direction.norm() > 0.0, "direction must be finite and non-zero");
  check(o.down.allFinite() && o.down.norm() > 0.0, "down must be finite and non-zero");
  check(std::isfinite(o.length_m) && o.length_m > 0.0, "length_m = " + std::to_string(o.length_m) + " must be > 0");
  check(std::isfinite(o.speed_m_per_s) && o.speed_m_per_s > 0.0, "speed_m_per_s must be > 0");
  check(std::isfinite(o.rate_hz) && o.rate_hz > 0.0, "rate_hz must be > 0");
  check(std::isfinite(o.bend_m) && std::isfinite(o.height_m) && o.height_m > 0.0, "bend_m / height_m");

  const TriMesh& mesh = surface.mesh();
  double longest_m = 0.0, mean_m = 0.0;
  for (const auto e : mesh.edges()) {
    const double l = mesh.calc_edge_length(e);
    longest_m = std::max(longest_m, l);
    mean_m += l;
  }
  mean_m /= std::max<double>(1.0, static_cast<double>(mesh.n_edges()));
  // Coarse cells: every ray spans 2 * height_m, and a fine grid would probe thousands of empty cells.
  VertexGrid grid(std::max({2.0 * mean_m, 0.05 * o.height_m, 1e-9}));
  for (const auto v : mesh.vertices()) grid.insert(v.idx(), toEigen(mesh.point(v)));

  const Eigen::Vector3d down = o.down.normalized();
  const Eigen::Vector3d dir = (o.direction - o.direction.dot(down) * down).normalized();
  const Eigen::Vector3d side = dir.cross(down);
  const double dt_s = 1.0 / o.rate_hz;
  const int count = static_cast<int>(std::floor(o.length_m / (o.speed_m_per_s * dt_s)));
  Stroke stroke;
  stroke.blade_direction = dir;
  for (int k = 0; k <= count; ++k) {
    const double along_m = o.speed_m_per_s * dt_s * k;
    const double x = along_m / o.length_m;  // 0 .. 1
    const Eigen::Vector3d path = o.start_m + along_m * dir + (4.0 * o.bend_m * x * (1.0 - x)) * side;
    const Eigen::Vector3d above = path - o.height_m * down;
    const auto hit = intersectSegment(mesh, grid, above, above + 2.0 * o.height_m * down, longest_m);
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

}  // namespace incise::cutting
