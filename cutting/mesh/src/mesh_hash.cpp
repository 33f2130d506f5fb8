#include "incise/mesh/mesh_hash.h"

#include <cstring>
#include <vector>

namespace incise::mesh {

namespace {

struct Fnv1a {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t size) noexcept {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      h ^= bytes[i];
      h *= 1099511628211ull;
    }
  }
};

}  // namespace

std::uint64_t geometryHash(const SurfaceMesh& surface) noexcept {
  const TriMesh& mesh = surface.mesh();
  Fnv1a fnv;
  std::vector<int> compact(mesh.n_vertices(), -1);
  int next = 0;
  for (const auto v : mesh.vertices()) {  // skips deleted vertices
    compact[static_cast<std::size_t>(v.idx())] = next++;
    const auto& p = mesh.point(v);
    fnv.add(p.data(), 3 * sizeof(double));
  }
  for (const auto f : mesh.faces()) {
    for (auto v = mesh.cfv_iter(f); v.is_valid(); ++v) {
      const int index = compact[static_cast<std::size_t>(v->idx())];
      fnv.add(&index, sizeof index);
    }
    const auto kind = static_cast<std::uint8_t>(surface.kind(f));
    fnv.add(&kind, 1);
  }
  return fnv.h;
}

}  // namespace incise::mesh
