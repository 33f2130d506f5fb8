// sim's public headers hold no OpenMesh (ARCHITECTURE.md, "Modules"): a user of incise::sim who never
// touches the tissue's mesh compiles without it. This file includes every sim header and nothing else;
// the check is at compile time.
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/latency_stats.h"
#include "incise/sim/plan.h"
#include "incise/sim/platform_noise.h"
#include "incise/sim/pose_queue.h"
#include "incise/sim/scenario.h"
#include "incise/sim/scenario_error.h"
#include "incise/sim/score.h"
#include "incise/sim/simulation.h"
#include "incise/sim/smoothness.h"
#include "incise/sim/spsc_queue.h"
#include "incise/sim/stroke_poses.h"
#include "incise/sim/tet_mirror.h"
#include "incise/sim/tissue_physics.h"
#include "incise/sim/triple_buffer.h"
#include "incise/sim/world.h"

#include <catch2/catch.hpp>

#if defined(OPENMESH_CONFIG_H) || defined(OPENMESH_TRIMESH_ARRAY_KERNEL_HH)
#error "a public sim header includes OpenMesh"
#endif

TEST_CASE("public headers: sim's headers compile without OpenMesh and hold the options by value", "[sim]") {
  incise::sim::WorldOptions options;  // the cutters' options are complete types here
  options.cutter.incision.depth_m = 0.003;
  options.tets.cutter.snap_tolerance_m = 0.0;
  options.tets.mesh.max_volume_m3 = 0.0;
  REQUIRE(options.cutter.incision.depth_m == 0.003);
  REQUIRE(options.tool.cut_button == -1);
}
