// Private: what the shape generators share (shapes.cpp: boxes, cylinders, spheres, the union and the robot;
// shapes_prism.cpp: prisms and the face silhouette, with CGAL): the argument checks, which throw
// std::invalid_argument naming the function and the value, and the Builder that collects a mesh.
// Threads, units and failure as in shapes.h.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "incise/core/format.h"
#include "incise/mesh/shapes.h"

namespace incise::mesh::detail {

[[noreturn]] inline void fail(const char* who, const std::string& what) {
  throw std::invalid_argument(std::string(who) + ": " + what);
}

inline void requireAtLeast(const char* who, const char* name, int value, int least) {
  if (value < least) fail(who, std::string(name) + " = " + std::to_string(value) + " is < " + std::to_string(least));
}

inline void requirePositive(const char* who, const char* name, double value) {
  if (!std::isfinite(value) || !(value > 0))
    fail(who, std::string(name) + " = " + core::formatNumber(value) + " is not finite and > 0");
}

inline void requireFinite(const char* who, const char* name, const Eigen::Vector3d& p) {
  if (!p.allFinite()) fail(who, std::string(name) + " = " + core::formatPoint(p) + " is not finite");
}

// `faces` is computed in double so that huge arguments cannot overflow before they are refused.
inline void requireFaceBudget(const char* who, double faces, const std::string& arguments) {
  if (faces > static_cast<double>(kMaxShapeFaces)) {
    fail(who, arguments + " would give " + core::formatNumber(faces) + " faces, more than " +
                  std::to_string(kMaxShapeFaces));
  }
}

// Collects vertices and triangles straight into a SurfaceMesh (every kind Original); several shapes may be
// appended to one Builder (makeRobot), each numbering its vertices from vertices() on.
class Builder {
 public:
  Builder(const char* who, long long vertices, long long faces) : who_(who) {
    mesh_.mesh().reserve(static_cast<std::size_t>(vertices), static_cast<std::size_t>(vertices + faces),
                         static_cast<std::size_t>(faces));
  }
  int vertex(const Eigen::Vector3d& p) { return mesh_.mesh().add_vertex(toOpenMesh(p)).idx(); }
  // The number of vertices added so far: the index the next vertex gets.
  int vertices() const { return static_cast<int>(mesh_.mesh().n_vertices()); }
  // Counter-clockwise seen from outside.
  void triangle(int a, int b, int c) {
    auto& m = mesh_.mesh();
    if (!m.add_face(m.vertex_handle(static_cast<unsigned>(a)), m.vertex_handle(static_cast<unsigned>(b)),
                    m.vertex_handle(static_cast<unsigned>(c)))
             .is_valid()) {
      // Construction bug, not bad input: the generators only make manifold connectivity.
      throw std::logic_error(std::string(who_) + ": OpenMesh refused face (" + std::to_string(a) + ", " +
                             std::to_string(b) + ", " + std::to_string(c) + ")");
    }
  }
  // The quad a b c d (counter-clockwise seen from outside) as triangles a b c and a c d.
  void quad(int a, int b, int c, int d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  SurfaceMesh finish() {
    mesh_.mesh().update_normals();
    return std::move(mesh_);
  }

 private:
  const char* who_;
  SurfaceMesh mesh_;
};

}  // namespace incise::mesh::detail
