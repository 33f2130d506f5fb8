// libFuzzer harness: the mesh loader and its validation (mesh/surface_mesh.h: loadSurfaceMesh, which
// checks a closed, consistently oriented two-manifold, and summarize's checkManifold on what it accepts).
// loadSurfaceMesh picks its reader by the file's extension, so the input's first byte picks it (modulo 4:
// .obj, .off, .stl, .ply) and the rest is the file. Only the public loader is called, whatever reader sits
// behind each extension. MeshError is the documented failure; anything else escaping, a crash, a hang or a
// sanitizer report is a finding. A mesh the loader accepts must be a closed two-manifold.
#include <array>
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "incise/mesh/surface_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static constexpr std::array<const char*, 4> kNames = {"mesh.obj", "mesh.off", "mesh.stl", "mesh.ply"};
  const std::filesystem::path path = incise::fuzz::writeInput(data + 1, size - 1, kNames[data[0] % 4]);
  try {
    const incise::mesh::SurfaceMesh mesh = incise::mesh::loadSurfaceMesh(path);
    if (!incise::mesh::summarize(mesh).closed_two_manifold) __builtin_trap();
  } catch (const incise::mesh::MeshError&) {
  }
  return 0;
}
