#include "incise/viewer/tool_mesh.h"

#include <array>

namespace incise::viewer {

namespace {

using Vec = Eigen::Vector3d;

struct Builder {
  std::vector<float> out;
  void triangle(const Vec& a, const Vec& b, const Vec& c, const Vec& rgb) {
    Vec n = (b - a).cross(c - a);
    n = n.norm() > 0.0 ? Vec(n.normalized()) : Vec::UnitZ();
    for (const Vec* p : {&a, &b, &c}) {
      for (int i = 0; i < 3; ++i) out.push_back(static_cast<float>((*p)[i]));
      for (int i = 0; i < 3; ++i) out.push_back(static_cast<float>(n[i]));
      for (int i = 0; i < 3; ++i) out.push_back(static_cast<float>(rgb[i]));
    }
  }
  // A box from `from` to `to` with a cross-section of half-sizes (a along u, b along v).
  void bar(const Vec& from, const Vec& to, const Vec& u, const Vec& v, double a, double b, const Vec& rgb) {
    std::array<Vec, 8> c;
    for (int i = 0; i < 8; ++i)
      c[static_cast<std::size_t>(i)] = ((i & 4) ? to : from) + ((i & 1) ? a : -a) * u + ((i & 2) ? b : -b) * v;
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
      const auto& [p0, p1, p2, p3] = std::array<Vec, 4>{c[q[0]], c[q[1]], c[q[2]], c[q[3]]};
      triangle(p0, p1, p2, rgb);
      triangle(p0, p2, p3, rgb);
    }
  }
  void octahedron(const Vec& centre, double r, const Vec& rgb) {
    const std::array<Vec, 6> d = {Vec::UnitX(),  -Vec::UnitX(), Vec::UnitY(),
                                  -Vec::UnitY(), Vec::UnitZ(),  -Vec::UnitZ()};
    for (int x = 0; x < 2; ++x)
      for (int y = 2; y < 4; ++y)
        for (int z = 4; z < 6; ++z) {
          const Vec a = centre + r * d[x], b = centre + r * d[y], c = centre + r * d[z];
          // Outward winding: flip when the three axes' signs make an odd permutation.
          if (((x == 1) + (y == 3) + (z == 5)) % 2 == 0)
            triangle(a, b, c, rgb);
          else
            triangle(a, c, b, rgb);
        }
  }
};

}  // namespace

std::vector<float> toolTriangles(const ToolView& tool) {
  Builder b;
  if (!tool.show) return {};
  const Eigen::Matrix3d r = tool.orientation.normalized().toRotationMatrix();
  const Vec x = r.col(0), y = r.col(1), z = r.col(2);  // z: from the tip towards the handle
  const double blade_m = tool.blade_length_m / 3.0;
  const Vec tip = tool.tip_m, heel = tip + blade_m * z;
  const Vec steel(0.78, 0.80, 0.84), handle(0.30, 0.34, 0.40);
  // The blade: a curved edge approximated by two triangles, on both faces.
  const Vec belly = tip + 0.45 * blade_m * z + 0.0015 * x, back = heel - 0.0015 * x, edge_heel = heel + 0.0015 * x;
  for (const bool front : {true, false}) {
    const auto tri = [&](const Vec& p, const Vec& q, const Vec& s) {
      front ? b.triangle(p, q, s, steel) : b.triangle(p, s, q, steel);
    };
    tri(tip, belly, back);
    tri(belly, edge_heel, back);
  }
  b.bar(heel, tip + tool.blade_length_m * z, x, y, 0.002, 0.00075, handle);
  if (tool.contact) {
    b.octahedron(tool.contact_m, 0.0006, Vec(1.0, 0.85, 0.1));
    const Vec f = tool.force_N * tool.metres_per_newton;
    if (f.norm() > 1e-5) {
      const Vec dir = f.normalized(), u = dir.unitOrthogonal(), v = dir.cross(u);
      b.bar(tool.contact_m, tool.contact_m + f, u, v, 0.000125, 0.000125, Vec(0.2, 0.9, 0.3));
      b.octahedron(tool.contact_m + f, 0.0005, Vec(0.2, 0.9, 0.3));
    }
  }
  return std::move(b.out);
}

}  // namespace incise::viewer
