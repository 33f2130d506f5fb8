// A fingerprint of a surface mesh's geometry and topology: FNV-1a (64 bit) over the non-deleted vertices'
// positions (their IEEE-754 bytes, in handle order) and the non-deleted faces' vertex indices (re-indexed
// past deleted vertices) and kinds. Equal meshes give equal hashes; a one-bit change of any coordinate
// changes it. Used to check determinism (the same scenario and trace give the same bytes).
// Cost O(V + F). Threads: any, on a mesh nobody is changing. Never throws.
#pragma once

#include <cstdint>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

std::uint64_t geometryHash(const SurfaceMesh& mesh) noexcept;

}  // namespace incise::mesh
