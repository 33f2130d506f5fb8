#include "incise/viewer/skin_embedding.h"

#include <algorithm>
#include <bit>

namespace incise::viewer {

namespace {

Eigen::Vector3d asVector(const std::array<double, 3>& p) { return {p[0], p[1], p[2]}; }

bool liveFace(std::uint8_t kind) noexcept { return kind != sim::kDeletedFace; }

// FNV-1a over 64-bit words (indices, and doubles by their bits): a change detector, not a stored hash.
struct WordHash {
  std::uint64_t h = 14695981039346656037ull;
  void add(std::uint64_t x) noexcept { h = (h ^ x) * 1099511628211ull; }
  void add(const std::array<double, 3>& p) noexcept {
    for (const double c : p) add(std::bit_cast<std::uint64_t>(c));
  }
};

}  // namespace

bool SkinEmbedding::update(const sim::GeometryMirror& mirror) {
  const sim::TetMirror& tets = mirror.tets();
  if (!mirror.complete() || !tets.complete()) return false;
  const std::size_t n = mirror.positions_m().size();
  const bool tets_changed = tets.version() != tets_version_ || tets.resets() != tets_resets_;
  if (tets_changed) rebuildLocator(tets);
  vertices_.resize(n);
  embedded_at_m_.resize(n);
  tried_.resize(n, 0);
  embedded_faces_.resize(n, 0);
  bases_.resize(n, physics::EmbedBases{-1, -1, -1});
  adjacency(mirror);
  bool changed = false;
  for (std::size_t v = 0; v < n; ++v) {
    physics::Embedded& e = vertices_[v];
    if (face_offsets_[v] == face_offsets_[v + 1]) {  // used by no face: not drawn
      changed = changed || e.nodes[0] >= 0;
      e = {}, tried_[v] = 0;
      continue;
    }
    const bool moved = !tried_[v] || embedded_at_m_[v] != mirror.positions_m()[v] ||
                       embedded_faces_[v] != faces_now_[v];  // new, moved, or its faces changed (its probe)
    const bool gone = tets_changed && std::any_of(bases_[v].begin(), bases_[v].end(), [&](int b) {
                        return b < 0 || base_changed_[static_cast<std::size_t>(b)] != 0;
                      });
    if (moved || gone) embed(mirror, v), changed = true;
  }
  embedded_ = static_cast<std::size_t>(
      std::count_if(vertices_.begin(), vertices_.end(), [](const physics::Embedded& e) { return e.nodes[0] >= 0; }));
  version_ += changed ? 1 : 0;
  return changed;
}

void SkinEmbedding::positions(const sim::GeometryMirror& mirror, const sim::PhysicsState& state,
                              std::vector<std::array<double, 3>>& out_m) const {
  const std::vector<std::array<double, 3>>& rest_m = mirror.positions_m();
  const std::vector<std::array<double, 3>>& node_rest_m = mirror.tets().positions_m();
  out_m.assign(rest_m.begin(), rest_m.end());
  const std::size_t nodes = std::min({state.nodes, state.x_m.size(), node_rest_m.size()});
  for (std::size_t v = 0; v < out_m.size() && v < vertices_.size(); ++v) {
    const physics::Embedded& e = vertices_[v];
    if (e.nodes[0] < 0) continue;
    // Nodes the state holds move the vertex by their weights; a node the physics has not taken yet (a cut
    // ahead of the physics thread) is not there: the vertex then moves by the mean displacement of the
    // others (weighted by |w|), so that it stays with the tissue around it.
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), displacement_m = Eigen::Vector3d::Zero();
    double held_weight = 0.0;
    bool all = true;
    for (std::size_t k = 0; k < 4; ++k) {
      const auto n = static_cast<std::size_t>(e.nodes[k]);
      if (n >= nodes) {
        all = false;
        continue;
      }
      p += e.weights[k] * state.x_m[n];
      displacement_m += std::abs(e.weights[k]) * (state.x_m[n] - asVector(node_rest_m[n]));
      held_weight += std::abs(e.weights[k]);
    }
    if (!all)
      p = asVector(rest_m[v]) +
          (held_weight > 0.0 ? Eigen::Vector3d(displacement_m / held_weight) : Eigen::Vector3d::Zero());
    out_m[v] = {p.x(), p.y(), p.z()};
  }
}

void SkinEmbedding::rebuildLocator(const sim::TetMirror& tets) {
  const bool reset = tets.resets() != tets_resets_;
  tets_version_ = tets.version();
  tets_resets_ = tets.resets();
  // Which base tets' pieces (their nodes, rest positions, sides) changed since the last build (all of them
  // after a reset).
  const std::size_t bases = tets.baseTetCount();
  base_changed_.resize(bases);
  base_hash_.resize(bases, 0);
  for (std::size_t b = 0; b < bases; ++b) {
    WordHash h;
    for (const sim::TetMirror::Child& c : tets.children(b)) {
      for (const std::int32_t n : c.nodes) {
        h.add(static_cast<std::uint32_t>(n));
        h.add(tets.positions_m()[static_cast<std::size_t>(n)]);
      }
      h.add(static_cast<std::uint8_t>(c.side));
    }
    base_changed_[b] = reset || h.h != base_hash_[b];
    base_hash_[b] = h.h;
  }
  scratch_m_.clear();
  for (const auto& p : tets.positions_m()) scratch_m_.push_back(asVector(p));
  // Each piece's key orders it as a whole build lists it (base, then child): ties break alike either way.
  const auto piecesOf = [&](std::size_t b, std::vector<physics::LocatorTet>& out) {
    const auto children = tets.children(b);
    for (std::size_t c = 0; c < children.size(); ++c)
      out.push_back({{children[c].nodes[0], children[c].nodes[1], children[c].nodes[2], children[c].nodes[3]},
                     {static_cast<int>(b), children[c].side},
                     static_cast<std::int64_t>(b) << 32 | static_cast<std::int64_t>(c)});
  };
  std::vector<physics::LocatorTet> list;
  std::vector<int> slots;
  if (reset || rebuilds_ == 0) {  // every base tet's pieces, entered at once
    list.reserve(tets.tetCount());
    for (std::size_t b = 0; b < bases; ++b) piecesOf(b, list);
    locator_.build(scratch_m_, list, &slots);
    base_slots_.assign(bases, {});
    for (std::size_t b = 0, i = 0; b < bases; ++b)
      for (std::size_t c = 0; c < tets.children(b).size(); ++c) base_slots_[b].push_back(slots[i++]);
  } else {  // only the changed base tets' pieces: out with the old, in with the new
    base_slots_.resize(bases);
    std::vector<int> removed;
    for (std::size_t b = 0; b < bases; ++b) {
      if (!base_changed_[b]) continue;
      removed.insert(removed.end(), base_slots_[b].begin(), base_slots_[b].end());
      piecesOf(b, list);
    }
    locator_.update(scratch_m_, removed, list, slots);
    for (std::size_t b = 0, i = 0; b < bases; ++b) {
      if (!base_changed_[b]) continue;
      base_slots_[b].assign(slots.begin() + static_cast<std::ptrdiff_t>(i),
                            slots.begin() + static_cast<std::ptrdiff_t>(i + tets.children(b).size()));
      i += tets.children(b).size();
    }
  }
  ++rebuilds_;
}

// Each vertex's live faces, as offsets into one list (the mirror's faces are few enough to redo this at
// every update).
void SkinEmbedding::adjacency(const sim::GeometryMirror& mirror) {
  const std::size_t n = mirror.positions_m().size();
  const auto& faces = mirror.faces();
  const auto& kinds = mirror.faceKind();
  face_offsets_.assign(n + 1, 0);
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (liveFace(kinds[f]))
      for (const std::int32_t v : faces[f]) ++face_offsets_[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < n; ++v) face_offsets_[v + 1] += face_offsets_[v];
  face_list_.resize(face_offsets_[n]);
  std::vector<std::uint32_t>& next = face_fill_;
  next.assign(face_offsets_.begin(), face_offsets_.end() - 1);
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (liveFace(kinds[f]))
      for (const std::int32_t v : faces[f])
        face_list_[next[static_cast<std::size_t>(v)]++] = static_cast<std::uint32_t>(f);
  // Each live face's hash (FNV-1a over its index, its corners and their positions), then each vertex's over
  // its faces' (in face order): a vertex whose faces changed or whose neighbours moved is embedded again (its
  // probe depends on them). Faces are hashed once each, not once per corner.
  const auto& p = mirror.positions_m();
  face_hash_.resize(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!liveFace(kinds[f])) continue;
    WordHash h;
    h.add(f);
    for (const std::int32_t u : faces[f]) {
      h.add(static_cast<std::uint32_t>(u));
      h.add(p[static_cast<std::size_t>(u)]);
    }
    face_hash_[f] = h.h;
  }
  faces_now_.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    WordHash h;
    for (std::uint32_t i = face_offsets_[v]; i < face_offsets_[v + 1]; ++i) h.add(face_hash_[face_list_[i]]);
    faces_now_[v] = h.h;
  }
}

// Vertex v embedded by physics::embedSurfaceVertex, its probe from its neighbours and faces.
void SkinEmbedding::embed(const sim::GeometryMirror& mirror, std::size_t v) {
  const auto& p = mirror.positions_m();
  const auto& faces = mirror.faces();
  const Eigen::Vector3d x = asVector(p[v]);
  std::vector<std::int32_t>& neighbours = neighbour_scratch_;
  neighbours.clear();
  Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();
  double area_sum = 0.0;
  for (std::uint32_t i = face_offsets_[v]; i < face_offsets_[v + 1]; ++i) {
    const auto& t = faces[face_list_[i]];
    const Eigen::Vector3d a = asVector(p[static_cast<std::size_t>(t[0])]);
    const Eigen::Vector3d cross =
        (asVector(p[static_cast<std::size_t>(t[1])]) - a).cross(asVector(p[static_cast<std::size_t>(t[2])]) - a);
    area_normal += cross, area_sum += cross.norm();
    for (const std::int32_t u : t)
      if (static_cast<std::size_t>(u) != v && std::find(neighbours.begin(), neighbours.end(), u) == neighbours.end())
        neighbours.push_back(u);
  }
  scratch_m_.clear();
  for (const std::int32_t u : neighbours) scratch_m_.push_back(asVector(p[static_cast<std::size_t>(u)]));
  const Eigen::Vector3d beside_m = physics::probeBeside(x, scratch_m_, area_normal, area_sum);
  const std::optional<physics::Embedded> e = physics::embedSurfaceVertex(locator_, x, beside_m, &bases_[v]);
  vertices_[v] = e ? *e : physics::Embedded{};
  embedded_at_m_[v] = p[v];
  embedded_faces_[v] = faces_now_[v];
  tried_[v] = 1;
}

}  // namespace incise::viewer
