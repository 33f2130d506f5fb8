// TetGen's options for tetrahedralize() (cutting/tets/include/incise/tets/tetrahedralize.h), in a header
// without OpenMesh or TetGen so that sim's public headers can hold them. Units: metres, cubic metres.
#pragma once

namespace incise::tets {

struct TetrahedralizeOptions {
  double radius_edge_ratio = 2.0;  // TetGen -q: bound on circumradius / shortest edge; 0 = no quality
                                   // refinement; otherwise finite and >= 1 (smaller may not terminate)
  double max_volume_m3 = 0;        // TetGen -a: largest tet volume; 0 = no bound; finite, >= 0
  bool keep_surface = true;        // TetGen -Y: no Steiner points on the boundary; the boundary triangles
                                   // are exactly the surface's triangles. TetGen then rejects every
                                   // refinement point that encroaches a boundary triangle, so -q and -a
                                   // hold only where that allows (a unit cube stays 6 tets whatever
                                   // max_volume_m3; the bunny at 0.01 scale goes from 6740 to 35365 tets
                                   // with max_volume_m3 = volume / 20000)
};

}  // namespace incise::tets
