// sim::World embedded in the caller's own loop: the caller owns the clock (a fixed 1 kHz tick, paced
// against the steady clock with --realtime, else as fast as possible), reads its device each tick (here a
// stroke generated across the tissue, standing in for a stylus), runs the haptic part, hands the force to
// its device through a callback, then lets the world cut within its budget.
//   haptic_loop MESH.obj SCALE [--realtime]      e.g. <prefix>/share/incise/scenarios/meshes/bunny.obj 0.01
// Prints the peak force, the frames in contact, the incision's figures and the geometry's hash.
#include <incise/incision/surface_cutter.h>
#include <incise/mesh/mesh_hash.h>
#include <incise/mesh/surface_mesh.h>
#include <incise/sim/stroke_poses.h>
#include <incise/sim/world.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

namespace {

using ForceCallback = std::function<void(const Eigen::Vector3d& force_N, double t_s)>;

// The caller's loop: tick k at k x period; the device's poses that are due go to the world, the force out.
void runLoop(incise::sim::World& world, const std::vector<incise::devices::PoseSample>& device, double period_s,
             bool realtime, const ForceCallback& force) {
  const auto start = std::chrono::steady_clock::now();
  std::size_t next = 0;
  const double end_s = device.back().time_s + 0.2;  // the wound settles after the last pose
  for (long k = 0;; ++k) {
    const double t_s = device.front().time_s + static_cast<double>(k) * period_s;
    const std::size_t first = next;
    while (next < device.size() && device[next].time_s <= t_s) ++next;
    const std::span<const incise::devices::PoseSample> due(device.data() + first, next - first);
    const incise::sim::HapticState haptic = world.updateTool(due, period_s);  // microseconds
    force(haptic.force_N, t_s);
    world.cut(t_s);  // the cutting work, within the world's per-frame budget
    if (next == device.size() && !world.pending() && t_s >= end_s) return;
    if (realtime) std::this_thread::sleep_until(start + std::chrono::duration<double>((k + 1) * period_s));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: haptic_loop MESH SCALE [--realtime]\n");
    return 2;
  }
  const bool realtime = argc > 3 && std::strcmp(argv[3], "--realtime") == 0;
  try {
    incise::mesh::SurfaceMesh tissue =
        incise::mesh::subdivided(incise::mesh::loadSurfaceMesh(argv[1], std::stod(argv[2])), 2);
    incise::sim::WorldOptions options;
    options.tissue.stiffness_N_per_m = 500.0;
    // The device: a 4 cm stroke along +x at 5 cm/s over the bunny's back (rays go down -y onto the tissue).
    incise::sim::StrokeSpec stroke;
    stroke.start_m = Eigen::Vector3d(-0.012, 0.0, 0.015);
    stroke.length_m = 0.04;
    const std::vector<incise::devices::PoseSample> device =
        incise::sim::posesForStrokes(tissue, {stroke}, options, 1000.0);
    incise::sim::World world(std::move(tissue), options);

    double peak_N = 0.0;
    long in_contact = 0;
    runLoop(world, device, 0.001, realtime, [&](const Eigen::Vector3d& force_N, double) {
      peak_N = std::max(peak_N, force_N.norm());  // a haptic device would render it here
      in_contact += force_N.squaredNorm() > 0.0;
    });

    const auto& figures = world.cutter().stats().figures;
    std::printf("%zu poses, %ld frames with a force, peak %.2f N\n", device.size(), in_contact, peak_N);
    for (std::size_t i = 0; i < figures.size(); ++i)
      std::printf("incision %zu: stroke %.1f mm, groove %.1f mm\n", i + 1, 1e3 * figures[i].stroke_length_m,
                  1e3 * figures[i].groove_length_m);
    std::printf("geometry %016llx\n", static_cast<unsigned long long>(incise::mesh::geometryHash(world.tissue())));
    return figures.size() == 1 && figures[0].groove_length_m > 0.03 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "haptic_loop: %s\n", e.what());
    return 1;
  }
}
