// Test fixture for the tet cutter: the bunny's tissue (surface and TetGen tets), made once per size.
#pragma once

#include <map>
#include <utility>

#include "incise/tets/tet_mesh.h"
#include "incise/tets/tetrahedralize.h"
#include "stroke_fixture.h"

namespace incise::tets::testing {

struct Tissue {
  mesh::SurfaceMesh surface;
  TetMesh tets;
};

// The bunny Loop-subdivided once (the coarse bunny's faces are wider than the lattice), tetrahedralised
// with tets of at most `max_volume_m3`: 2e-8 gives about 37,000 tets, 1.2e-9 about 238,000.
inline const Tissue& bunnyTissue(double max_volume_m3 = 2e-8) {
  static std::map<double, Tissue> tissues;
  auto it = tissues.find(max_volume_m3);
  if (it == tissues.end()) {
    Tissue t{incision::testing::bunny(1), {}};
    TetrahedralizeOptions o;
    o.max_volume_m3 = max_volume_m3;
    t.tets = tetrahedralize(t.surface, o);
    it = tissues.emplace(max_volume_m3, std::move(t)).first;
  }
  return it->second;
}

}  // namespace incise::tets::testing
