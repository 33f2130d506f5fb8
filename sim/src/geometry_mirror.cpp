#include "incise/sim/geometry_mirror.h"

#include <algorithm>
#include <chrono>
#include <span>

#include <Eigen/Core>

#include "incise/mesh/surface_mesh.h"
#include "incise/physics/tissue_model.h"
#include "incise/sim/tissue_physics.h"
#include "incise/sim/world.h"

namespace incise::sim {

std::size_t GeometryMirror::pull(GeometryStream& stream, std::size_t max_records) {
  if (!requested_) {
    requested_ = true;
    stream.requestReset();
  }
  return stream.read([this](const GeometryRecord& r) { apply(r); }, max_records);
}

void GeometryMirror::touch(std::vector<std::uint8_t>& flags, std::vector<std::uint32_t>& list, std::uint32_t index) {
  if (rebuilt_) return;  // everything is new anyway
  if (index >= flags.size()) flags.resize(std::max<std::size_t>(index + 1, 2 * flags.size()), 0);
  if (flags[index]) return;
  flags[index] = 1;
  list.push_back(index);
}

void GeometryMirror::apply(const GeometryRecord& r) {
  if (r.type == GeometryRecordType::Reset) {
    if (!requested_) return;
    started_ = true;
    ++resets_;
    positions_m_.assign(r.info.vertices, {0.0, 0.0, 0.0});
    vertex_kind_.assign(r.info.vertices, 0);
    faces_.assign(r.info.faces, {-1, -1, -1});
    face_kind_.assign(r.info.faces, kDeletedFace);
    face_texcoords_.clear();
    face_material_.clear();
    flags_ = 0;
    frame_ = r.info.frame;
    clearChanges();
    rebuilt_ = true;
    return;
  }
  if (!started_) return;
  switch (r.type) {
    case GeometryRecordType::Vertex:
      if (r.index >= positions_m_.size()) {
        positions_m_.resize(r.index + 1, {0.0, 0.0, 0.0});
        vertex_kind_.resize(r.index + 1, 0);
      }
      positions_m_[r.index] = {r.position_m[0], r.position_m[1], r.position_m[2]};
      vertex_kind_[r.index] = r.kind;
      touch(vertex_changed_, changed_vertices_, r.index);
      break;
    case GeometryRecordType::Face:
      if (r.index >= faces_.size()) {
        faces_.resize(r.index + 1, {-1, -1, -1});
        face_kind_.resize(r.index + 1, kDeletedFace);
      }
      faces_[r.index] = {r.vertices[0], r.vertices[1], r.vertices[2]};
      face_kind_[r.index] = r.kind;
      touch(face_changed_, changed_faces_, r.index);
      break;
    case GeometryRecordType::FaceTexCoords:  // right after its Face record: the face is in faces_
      if (face_texcoords_.size() < faces_.size()) {
        face_texcoords_.resize(faces_.size(), std::array<float, 6>{});
        face_material_.resize(faces_.size(), kNoMaterial);
      }
      if (r.index < face_texcoords_.size()) {
        std::copy(r.texcoords, r.texcoords + 6, face_texcoords_[r.index].begin());
        face_material_[r.index] = r.kind;
      }
      break;
    case GeometryRecordType::Frame:
      frame_ = r.info.frame;
      flags_ = r.info.flags;
      backlog_ = r.info.backlog;
      tets_.frame(r.info.flags);
      break;
    default:
      tets_.apply(r);
      break;
  }
}

void GeometryMirror::clearChanges() noexcept {
  for (const std::uint32_t v : changed_vertices_) vertex_changed_[v] = 0;
  for (const std::uint32_t f : changed_faces_) face_changed_[f] = 0;
  changed_vertices_.clear();
  changed_faces_.clear();
  rebuilt_ = false;
}

std::size_t GeometryMirror::liveFaces() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(face_kind_.begin(), face_kind_.end(), [](std::uint8_t k) { return k != kDeletedFace; }));
}

void copyGeometry(World& world, std::int64_t frame, GeometryMirror& mirror) {
  GeometryStreamOptions options;
  options.records_per_frame = static_cast<int>(options.ring_records / 2);
  GeometryStream stream(options);
  stream.attach(world);
  mirror.restart();
  mirror.pull(stream);  // asks for the full copy
  stream.flush(world, frame, std::chrono::hours(1), [&] { mirror.pull(stream); });
  world.recordMeshChanges(false);
}

void copySimulatedGeometry(World& world, std::int64_t frame, GeometryMirror& mirror) {
  copyGeometry(world, frame, mirror);
  const TissuePhysics* physics = world.physics();
  if (physics == nullptr || physics->threaded()) return;
  const mesh::SurfaceMesh deformed = physics->deformedSurface(world.tissue());
  for (const auto v : deformed.mesh().vertices()) {
    const auto index = static_cast<std::uint32_t>(v.idx());
    if (index >= mirror.positions_m().size()) continue;
    GeometryRecord r{};
    r.type = GeometryRecordType::Vertex;
    r.kind = mirror.vertexKind()[index];
    r.index = index;
    const auto& p = deformed.mesh().point(v);
    r.position_m[0] = p[0], r.position_m[1] = p[1], r.position_m[2] = p[2];
    mirror.apply(r);
  }
  // The tets' nodes where the model has them (the cutter's node n is the model's node n).
  if (!mirror.tets().present()) return;
  const std::span<const Eigen::Vector3d> x = physics->model().positions_m();
  const std::size_t nodes = std::min(x.size(), mirror.tets().positions_m().size());
  for (std::size_t n = 0; n < nodes; ++n) {
    GeometryRecord r{};
    r.type = GeometryRecordType::TetNode;
    r.index = static_cast<std::uint32_t>(n);
    r.position_m[0] = x[n].x(), r.position_m[1] = x[n].y(), r.position_m[2] = x[n].z();
    mirror.apply(r);
  }
}

}  // namespace incise::sim
