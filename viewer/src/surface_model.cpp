#include "incise/viewer/surface_model.h"

#include <algorithm>
#include <array>
#include <limits>

#include <Eigen/Geometry>

namespace incise::viewer {

namespace {

constexpr std::uint8_t kWallKind = 2;  // mesh::FaceKind::Wall

bool live(std::uint8_t kind) { return kind != sim::kDeletedFace; }

void addUnique(std::vector<std::uint8_t>& flags, std::vector<std::uint32_t>& list, std::uint32_t i) {
  if (i >= flags.size()) flags.resize(std::max<std::size_t>(i + 1, 2 * flags.size()), 0);
  if (flags[i]) return;
  flags[i] = 1;
  list.push_back(i);
}

}  // namespace

bool SurfaceModel::update(const sim::GeometryMirror& mirror) {
  if (!mirror.complete()) return false;
  if (mirror.rebuilt() || !ready_) {
    rebuild(mirror.positions_m(), mirror.faces(), mirror.faceKind());
    copyTexCoords(mirror);
    return true;
  }
  const auto& p = mirror.positions_m();
  if (p.size() > vertexCount()) {
    positions_m_.resize(3 * p.size(), 0.0);
    positions_.resize(3 * p.size(), 0.0f);
    normals_.resize(3 * p.size(), 0.0f);
    vertex_faces_.resize(p.size());
  }
  if (mirror.faces().size() > faceCount()) {
    indices_.resize(3 * mirror.faces().size(), 0);
    kinds_.resize(mirror.faces().size(), sim::kDeletedFace);
  }
  if (!mirror.faceTexCoords().empty()) {
    texcoords_.resize(6 * faceCount(), 0.0f);
    materials_.resize(faceCount(), sim::kNoMaterial);
  }
  for (const std::uint32_t f : mirror.changedFaces()) {
    setFace(f, mirror.faces()[f], mirror.faceKind()[f]);
    copyTexCoords(mirror, f);
  }
  for (const std::uint32_t v : mirror.changedVertices()) {
    for (int a = 0; a < 3; ++a) {
      positions_m_[3 * v + a] = p[v][static_cast<std::size_t>(a)];
      positions_[3 * v + a] = static_cast<float>(p[v][static_cast<std::size_t>(a)]);
    }
    addUnique(vertex_dirty_, dirty_.vertices, v);
    markNormal(v);
    for (const std::uint32_t f : vertex_faces_[v])
      for (int c = 0; c < 3; ++c) markNormal(indices_[3 * f + c]);
  }
  for (const std::uint32_t v : normal_list_) recomputeNormal(v);
  for (const std::uint32_t v : normal_list_) normal_dirty_[v] = 0, addUnique(vertex_dirty_, dirty_.vertices, v);
  normal_list_.clear();
  std::sort(dirty_.vertices.begin(), dirty_.vertices.end());
  std::sort(dirty_.faces.begin(), dirty_.faces.end());
  return true;
}

bool SurfaceModel::update(const sim::TetMirror& tets) { return updateTets(tets, nullptr); }

bool SurfaceModel::update(const sim::TetMirror& tets, const sim::PhysicsState& state) {
  return updateTets(tets, &state);
}

bool SurfaceModel::updateTets(const sim::TetMirror& tets, const sim::PhysicsState* state) {
  const std::int64_t step = state ? state->step : -1;
  if (!tets.complete() || (ready_ && tets.version() == tets_version_ && step == state_step_)) return false;
  tets_version_ = tets.version();
  state_step_ = step;
  skin_drawn_ = false;
  std::vector<std::uint8_t> kinds;
  const std::vector<std::array<std::int32_t, 3>> faces = tets.boundary(&kinds);
  for (std::uint8_t& k : kinds) k = k ? kWallKind : 0;  // mesh::FaceKind::Wall / Original
  if (state == nullptr) {
    rebuild(tets.positions_m(), faces, kinds);
    return true;
  }
  std::vector<std::array<double, 3>> positions_m = tets.positions_m();
  const std::size_t simulated = std::min({positions_m.size(), state->nodes, state->x_m.size()});
  for (std::size_t n = 0; n < simulated; ++n)
    positions_m[n] = {state->x_m[n].x(), state->x_m[n].y(), state->x_m[n].z()};
  rebuild(positions_m, faces, kinds);
  return true;
}

bool SurfaceModel::update(const sim::GeometryMirror& mirror, const SkinEmbedding& skin,
                          const sim::PhysicsState& state) {
  if (!mirror.complete()) return false;
  if (ready_ && skin_drawn_ && state.step == state_step_ && skin.version() == skin_version_ &&
      mirror.resets() == skin_resets_)
    return false;
  state_step_ = state.step, skin_version_ = skin.version(), skin_resets_ = mirror.resets();
  skin_drawn_ = true, tets_version_ = 0;  // what update(tets, ...) drew is gone
  skin.positions(mirror, state, skin_m_);
  rebuild(skin_m_, mirror.faces(), mirror.faceKind());
  copyTexCoords(mirror);
  return true;
}

void SurfaceModel::copyTexCoords(const sim::GeometryMirror& mirror, std::uint32_t f) {
  if (texcoords_.empty()) return;
  const auto& uv = mirror.faceTexCoords();
  float* to = &texcoords_[6 * static_cast<std::size_t>(f)];
  if (f < uv.size() && live(kinds_[f])) {  // a deleted face's are what it had: not drawn, kept as zeros
    std::copy(uv[f].begin(), uv[f].end(), to);
    materials_[f] = mirror.faceMaterial()[f];
  } else {
    std::fill(to, to + 6, 0.0f);
    materials_[f] = sim::kNoMaterial;
  }
}

void SurfaceModel::copyTexCoords(const sim::GeometryMirror& mirror) {
  texcoords_.clear();
  materials_.clear();
  if (mirror.faceTexCoords().empty()) return;
  texcoords_.resize(6 * faceCount(), 0.0f);
  materials_.resize(faceCount(), sim::kNoMaterial);
  for (std::uint32_t f = 0; f < faceCount(); ++f) copyTexCoords(mirror, f);
}

void SurfaceModel::rebuild(const std::vector<std::array<double, 3>>& p,
                           const std::vector<std::array<std::int32_t, 3>>& faces,
                           const std::vector<std::uint8_t>& kind) {
  const std::size_t n = p.size(), m = faces.size();
  ready_ = false;
  positions_m_.assign(3 * n, 0.0);
  positions_.assign(3 * n, 0.0f);
  normals_.assign(3 * n, 0.0f);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t a = 0; a < 3; ++a) positions_m_[3 * v + a] = p[v][a], positions_[3 * v + a] = float(p[v][a]);
  indices_.assign(3 * m, 0);
  kinds_.assign(m, sim::kDeletedFace);
  texcoords_.clear();  // a mirror's rebuild copies them again
  materials_.clear();
  vertex_faces_.assign(n, {});
  live_faces_ = wall_faces_ = 0;
  for (std::size_t f = 0; f < m; ++f) setFace(static_cast<std::uint32_t>(f), faces[f], kind[f]);
  for (std::uint32_t v = 0; v < n; ++v) recomputeNormal(v);
  normal_dirty_.assign(n, 0);
  normal_list_.clear();
  clearDirty();
  dirty_.all = true;
  ready_ = true;
}

void SurfaceModel::setFace(std::uint32_t f, const std::array<std::int32_t, 3>& t, std::uint8_t kind) {
  if (live(kinds_[f])) {  // off its old vertices
    --live_faces_;
    wall_faces_ -= kinds_[f] == kWallKind;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = indices_[3 * f + c];
      auto& list = vertex_faces_[v];
      list.erase(std::remove(list.begin(), list.end(), f), list.end());
      if (ready_) markNormal(v);
    }
  }
  kinds_[f] = kind;
  if (!live(kind)) {
    indices_[3 * f] = indices_[3 * f + 1] = indices_[3 * f + 2] = 0;
  } else {
    ++live_faces_;
    wall_faces_ += kind == kWallKind;
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<std::uint32_t>(t[static_cast<std::size_t>(c)]);
      indices_[3 * f + c] = v;
      vertex_faces_[v].push_back(f);
      if (ready_) markNormal(v);
    }
  }
  if (ready_) addUnique(face_dirty_, dirty_.faces, f);
}

void SurfaceModel::markNormal(std::uint32_t v) {
  if (v >= normal_dirty_.size()) normal_dirty_.resize(std::max<std::size_t>(v + 1, 2 * normal_dirty_.size()), 0);
  if (normal_dirty_[v]) return;
  normal_dirty_[v] = 1;
  normal_list_.push_back(v);
}

void SurfaceModel::recomputeNormal(std::uint32_t v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const auto at = [&](std::uint32_t i) { return Eigen::Vector3d(&positions_m_[3 * i]); };
  for (const std::uint32_t f : vertex_faces_[v]) {
    if (kinds_[f] == kWallKind) continue;
    const Eigen::Vector3d a = at(indices_[3 * f]), b = at(indices_[3 * f + 1]), c = at(indices_[3 * f + 2]);
    sum += (b - a).cross(c - a);  // twice the area, along the face's normal
  }
  const double length = sum.norm();
  const Eigen::Vector3d n = length > 0.0 ? Eigen::Vector3d(sum / length) : Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) normals_[3 * v + a] = static_cast<float>(n[a]);
}

void SurfaceModel::clearDirty() {
  for (const std::uint32_t v : dirty_.vertices) vertex_dirty_[v] = 0;
  for (const std::uint32_t f : dirty_.faces) face_dirty_[f] = 0;
  dirty_.vertices.clear();
  dirty_.faces.clear();
  dirty_.all = false;
}

Eigen::Vector3d SurfaceModel::normalNear(const Eigen::Vector3d& p_m) const {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t v = 0; v < vertexCount(); ++v) {
    const Eigen::Vector3d n(normals_[3 * v], normals_[3 * v + 1], normals_[3 * v + 2]);
    const double d = (Eigen::Vector3d(&positions_m_[3 * v]) - p_m).squaredNorm();
    if (n.squaredNorm() > 0.5 && d < best) best = d, normal = n;
  }
  return normal;
}

Eigen::AlignedBox3d SurfaceModel::bounds() const {
  Eigen::AlignedBox3d box;
  for (std::size_t v = 0; v < vertexCount(); ++v) box.extend(Eigen::Vector3d(&positions_m_[3 * v]));
  return box;
}

}  // namespace incise::viewer
