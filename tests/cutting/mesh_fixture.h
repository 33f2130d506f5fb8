// Shared by the surface mesh tests (surface_mesh_test.cpp, surface_mesh_formats_test.cpp): the MeshError
// message of loading a file. Threads: any. Failure: fails the test when loading succeeds.
#pragma once

#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh::test {

// The MeshError message of loading `path`; fails the test if loading succeeds.
inline std::string loadError(const std::filesystem::path& path) {
  try {
    loadSurfaceMesh(path);
  } catch (const MeshError& e) {
    return e.what();
  }
  FAIL("loading " << path << " did not throw MeshError");
  return {};
}

}  // namespace incise::mesh::test
