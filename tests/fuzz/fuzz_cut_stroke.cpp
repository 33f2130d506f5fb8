// libFuzzer harness: the surface cutter's outputs (incision/surface_cutter.h). The input is decoded into a
// stroke over a small tissue: which tissue (the shipped bunny, 10 cm, as shipped: coarse, cut through local
// refinement; a coarse 2 cm icosphere, refined too; a 3 cm skin pad at 1 mm; a 3 mm thin slab), the start over its top, the direction, length and bend (curvature), the
// blade's depth, and the tip's depth at both ends (a ramp, or none: the blade's depth). The stroke is cut
// (begin, extend, finish, fully opened) and the result must be a closed two-manifold with no two faces
// crossing other than along what they share (mesh::findSelfIntersections) and no failure the cutter reports;
// else the harness traps (a finding, the input saved by libFuzzer). An exception, a crash, a hang or a
// sanitizer report is a finding too. Cost per input: one cut and CGAL's check of the whole tissue (a few
// thousand faces: the tissues are small so that the fuzz build makes several executions a second).
// Threads: libFuzzer calls it from one thread; the tissues are built once.
#include <fuzzer/FuzzedDataProvider.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/self_intersection.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_mesh.h"

namespace {

using namespace incise;

struct Tissue {
  const char* name;
  mesh::SurfaceMesh mesh;
  double centre_x_m, centre_z_m, radius_m;  // where strokes start (over the top, y rays down)
};

const std::array<Tissue, 4>& tissues() {
  static const std::array<Tissue, 4> t = {
      Tissue{"bunny", mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01), -0.005, 0.015, 0.008},
      Tissue{"icosphere", mesh::makeSphere(Eigen::Vector3d::Zero(), 0.02, 3), 0.0, 0.0, 0.006},
      Tissue{"pad", mesh::makeSkinPad(Eigen::Vector3d(0.03, 0.01, 0.03), 0.001), 0.0, 0.0, 0.006},
      Tissue{"slab", mesh::makeSkinPad(Eigen::Vector3d(0.03, 0.003, 0.03), 0.001), 0.0, 0.0, 0.006},
  };
  return t;
}

// The faces of `cut` that may cross a face the cut changed: the changed faces (new, or with a vertex moved
// or made by the cut) and every face whose box overlaps their box. The rest of the tissue is as it was, and the
// tissues have no two faces crossing, so a crossing pair has a face here. Checking this part alone keeps
// CGAL's check (most of an execution's time on the whole tissue) to the cut's neighbourhood. As a mesh
// (faces OpenMesh cannot add, at a vertex where two fans of the part meet, make it return the whole cut).
mesh::SurfaceMesh neighbourhood(const mesh::SurfaceMesh& cut, const mesh::SurfaceMesh& tissue) {
  const mesh::TriMesh& m = cut.mesh();
  const mesh::TriMesh& t = tissue.mesh();
  const auto changed = [&](mesh::TriMesh::VertexHandle v) {
    return static_cast<std::size_t>(v.idx()) >= t.n_vertices() || m.point(v) != t.point(v);
  };
  // A face is new unless the tissue's face of the same index has the same corners in the same order.
  const auto same_face = [&](mesh::TriMesh::FaceHandle f) {
    if (static_cast<std::size_t>(f.idx()) >= t.n_faces() || t.status(f).deleted()) return false;
    auto a = m.cfv_iter(f);
    auto b = t.cfv_iter(f);
    for (int i = 0; i < 3; ++i, ++a, ++b)
      if (*a != *b) return false;
    return true;
  };
  Eigen::AlignedBox3d region;
  for (const auto f : m.faces()) {
    bool c = !same_face(f);
    for (const auto v : m.fv_range(f)) c = c || changed(v);
    if (c)
      for (const auto v : m.fv_range(f)) region.extend(mesh::toEigen(m.point(v)));
  }
  mesh::SurfaceMesh part;
  if (region.isEmpty()) return part;
  std::vector<mesh::TriMesh::VertexHandle> handle(m.n_vertices());
  for (const auto f : m.faces()) {
    Eigen::AlignedBox3d box;
    for (const auto v : m.fv_range(f)) box.extend(mesh::toEigen(m.point(v)));
    if (!box.intersects(region)) continue;
    std::array<mesh::TriMesh::VertexHandle, 3> corners;
    int i = 0;
    for (const auto v : m.fv_range(f)) {
      auto& h = handle[static_cast<std::size_t>(v.idx())];
      if (!h.is_valid()) h = part.mesh().add_vertex(m.point(v));
      corners[static_cast<std::size_t>(i++)] = h;
    }
    if (!part.mesh().add_face(corners[0], corners[1], corners[2]).is_valid()) return cut;
  }
  return part;
}

// A double in [lo, hi] from 16 bits of the input.
double between(FuzzedDataProvider& in, double lo, double hi) {
  return lo + (hi - lo) * in.ConsumeIntegral<std::uint16_t>() / 65535.0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Tissue& tissue = tissues()[in.ConsumeIntegralInRange<std::size_t>(0, tissues().size() - 1)];
  incision::StrokePathOptions path;
  const double x = tissue.centre_x_m + between(in, -1.0, 1.0) * tissue.radius_m;
  const double z = tissue.centre_z_m + between(in, -1.0, 1.0) * tissue.radius_m;
  path.start_m = Eigen::Vector3d(x, 0.05, z);
  const double angle = between(in, 0.0, 2.0 * M_PI);
  path.direction = Eigen::Vector3d(std::cos(angle), 0.0, std::sin(angle));
  path.length_m = between(in, 0.002, 0.015);
  path.bend_m = between(in, -0.25, 0.25) * path.length_m;
  incision::CutterOptions options;
  options.incision.depth_m = between(in, 0.001, 0.0045);  // the default lattice reaches 4.8 mm down
  const bool ramp = in.ConsumeBool();
  const double tip0_m = between(in, 0.0003, 0.006), tip1_m = between(in, 0.0003, 0.006);

  mesh::SurfaceMesh cut = tissue.mesh;
  incision::Stroke stroke = incision::strokeAlongPath(cut, path);
  if (ramp) {
    const std::size_t n = stroke.samples.size();
    stroke.first.depth_m = tip0_m;
    for (std::size_t k = 0; k < n; ++k)
      stroke.samples[k].depth_m = tip0_m + (tip1_m - tip0_m) * double(k + 1) / double(n);
  }
  incision::SurfaceCutter cutter(cut, options);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const incision::StrokeSample& s : stroke.samples) cutter.extend(s);
  cutter.finish();
  cutter.advance(stroke.samples.empty() ? 1.0 : stroke.samples.back().time_s + 1.0);  // fully opened

  // What was cut, for a finding's report (the stroke to rebuild in a regression test).
  const auto describe = [&] {
    std::fprintf(stderr,
                 "fuzz_cut_stroke: %s, start (%.17g, %.17g), direction (%.17g, %.17g), length %.17g, bend %.17g, "
                 "depth %.17g, tip %.17g to %.17g\n",
                 tissue.name, x, z, path.direction.x(), path.direction.z(), path.length_m, path.bend_m,
                 options.incision.depth_m, ramp ? tip0_m : -1.0, ramp ? tip1_m : -1.0);
  };
  const mesh::ManifoldReport report = mesh::checkManifold(cut.mesh());
  if (!cutter.stats().failure.empty() || !report.closed_two_manifold) {
    std::fprintf(stderr, "fuzz_cut_stroke: %s: %s%s\n", tissue.name, cutter.stats().failure.c_str(),
                 report.first_problem.c_str());
    describe();
    __builtin_trap();
  }
  const auto crossing = mesh::findSelfIntersections(neighbourhood(cut, tissue.mesh).mesh());
  if (!crossing.empty()) {
    std::fprintf(stderr, "fuzz_cut_stroke: %s: %zu pairs of faces cross, the first %d and %d\n", tissue.name,
                 crossing.size(), crossing[0].first, crossing[0].second);  // faces of the neighbourhood
    describe();
    __builtin_trap();
  }
  return 0;
}
