#include "incise/sim/geometry_stream.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>

#include "incise/cutting/surface_mesh.h"
#include "incise/sim/world.h"

namespace incise::sim {

namespace {

// Room beyond the mesh for the elements a few incisions add (the surface cutter reserves 200,000 new
// vertices per incision, topped up between incisions).
constexpr std::size_t kHeadroomVertices = 400000, kHeadroomFaces = 800000;

}  // namespace

GeometryStream::GeometryStream(const GeometryStreamOptions& options)
    : mask_(options.ring_records - 1), budget_(options.records_per_frame) {
  const std::size_t n = options.ring_records;
  if (n < 64 || (n & (n - 1)) != 0)
    throw std::invalid_argument("GeometryStream: ring_records = " + std::to_string(n) +
                                " must be a power of two >= 64");
  if (options.records_per_frame < 1 || static_cast<std::size_t>(options.records_per_frame) + 2 > n)
    throw std::invalid_argument("GeometryStream: records_per_frame = " + std::to_string(options.records_per_frame) +
                                " must be in [1, ring_records - 2]");
  ring_.resize(n);
}

void GeometryStream::Dirty::mark(std::size_t index, std::int64_t& regrowths) {
  if (index >= flag.size()) {  // past the room reserved at attach(): grow once, amortised
    flag.resize(std::max(index + 1, 2 * flag.size()), 0);
    list.reserve(flag.size());
    ++regrowths;
  }
  if (flag[index]) return;
  flag[index] = 1;
  list.push_back(static_cast<std::uint32_t>(index));  // within the reserve: never reallocates
}

void GeometryStream::attach(World& world) {
  const cutting::TriMesh& m = world.tissue().mesh();
  vertices_.flag.assign(m.n_vertices() + m.n_vertices() / 2 + kHeadroomVertices, 0);
  vertices_.list.clear();
  vertices_.list.reserve(vertices_.flag.size());
  faces_.flag.assign(m.n_faces() + m.n_faces() / 2 + kHeadroomFaces, 0);
  faces_.list.clear();
  faces_.list.reserve(faces_.flag.size());
  world.recordMeshChanges(true);
}

void GeometryStream::take(World& world) noexcept {
  const cutting::MeshChanges& changes = world.meshChanges();
  try {
    for (const int v : changes.vertices) vertices_.mark(static_cast<std::size_t>(v), counters_.regrowths);
    for (const int f : changes.faces) faces_.mark(static_cast<std::size_t>(f), counters_.regrowths);
  } catch (...) {  // out of memory growing the flags: a reader re-syncs everything
    requestReset();
  }
  world.clearMeshChanges();
}

void GeometryStream::emitVertex(const World& world, std::uint32_t v) noexcept {
  const cutting::SurfaceMesh& tissue = world.tissue();
  const cutting::TriMesh::VertexHandle h(static_cast<int>(v));
  const auto& p = tissue.mesh().point(h);
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Vertex;
  r.kind = static_cast<std::uint8_t>(tissue.kind(h));
  r.index = v;
  r.position_m[0] = p[0], r.position_m[1] = p[1], r.position_m[2] = p[2];
}

void GeometryStream::emitFace(const World& world, std::uint32_t f) noexcept {
  const cutting::SurfaceMesh& tissue = world.tissue();
  const cutting::TriMesh& m = tissue.mesh();
  const cutting::TriMesh::FaceHandle h(static_cast<int>(f));
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Face;
  r.index = f;
  if (m.status(h).deleted()) {
    r.kind = kDeletedFace;
    r.vertices[0] = r.vertices[1] = r.vertices[2] = -1;
    return;
  }
  r.kind = static_cast<std::uint8_t>(tissue.kind(h));
  int i = 0;
  for (auto v = m.cfv_iter(h); v.is_valid() && i < 3; ++v) r.vertices[i++] = v->idx();
}

int GeometryStream::write(World& world, std::int64_t frame, std::size_t room) noexcept {
  const cutting::TriMesh& m = world.tissue().mesh();
  const auto n_vertices = static_cast<std::uint32_t>(m.n_vertices());
  const auto n_faces = static_cast<std::uint32_t>(m.n_faces());
  const std::uint64_t first = head_local_;
  const std::uint32_t requests = reset_requests_.load(std::memory_order_acquire);
  if (requests != resets_done_) {  // a full re-sync: the counts, then every element within the budget
    resets_done_ = requests;
    GeometryRecord& r = next();
    r.type = GeometryRecordType::Reset;
    r.index = 0;
    r.info = {frame, n_vertices, n_faces, 0, 0};
    sweeping_ = true;
    swept_ = false;
    sweep_vertex_ = sweep_face_ = 0;
    sweep_vertices_ = n_vertices, sweep_faces_ = n_faces;
    ++counters_.resets;
    --room;
  }
  std::size_t left = std::min(room - 1, static_cast<std::size_t>(budget_));  // one for the Frame record
  for (; left > 0 && !vertices_.list.empty(); --left) {
    const std::uint32_t v = vertices_.list.back();
    vertices_.list.pop_back();
    vertices_.flag[v] = 0;
    emitVertex(world, v);
  }
  for (; left > 0 && sweeping_ && sweep_vertex_ < sweep_vertices_; --left) emitVertex(world, sweep_vertex_++);
  // Faces only once the reader has every vertex (a face never names a vertex the reader lacks).
  if (vertices_.list.empty() && !(sweeping_ && sweep_vertex_ < sweep_vertices_)) {
    for (; left > 0 && !faces_.list.empty(); --left) {
      const std::uint32_t f = faces_.list.back();
      faces_.list.pop_back();
      faces_.flag[f] = 0;
      emitFace(world, f);
    }
    for (; left > 0 && sweeping_ && sweep_face_ < sweep_faces_; --left) emitFace(world, sweep_face_++);
  }
  if (sweeping_ && sweep_vertex_ == sweep_vertices_ && sweep_face_ == sweep_faces_) sweeping_ = false, swept_ = true;
  const std::size_t backlog = vertices_.list.size() + faces_.list.size() +
                              (sweeping_ ? (sweep_vertices_ - sweep_vertex_) + (sweep_faces_ - sweep_face_) : 0);
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Frame;
  r.index = 0;
  const std::uint8_t flags =
      static_cast<std::uint8_t>((swept_ ? kFrameComplete : 0) | (swept_ && backlog == 0 ? kFrameExact : 0));
  r.info = {frame, n_vertices, n_faces, static_cast<std::uint32_t>(backlog), flags};
  head_.store(head_local_, std::memory_order_release);  // the whole frame at once
  return static_cast<int>(head_local_ - first);
}

GeometryPublish GeometryStream::publish(World& world, std::int64_t frame) noexcept {
  GeometryPublish out;
  out.marked = static_cast<int>(world.meshChanges().vertices.size() + world.meshChanges().faces.size());
  take(world);
  ++counters_.frames;
  const std::uint32_t requests = reset_requests_.load(std::memory_order_acquire);
  if (requests == 0) return out;  // no reader yet: keep marking, send nothing
  const std::size_t used = static_cast<std::size_t>(head_local_ - tail_.load(std::memory_order_acquire));
  const std::size_t room = ring_.size() - used;
  const std::size_t sweep_left = sweeping_ ? (sweep_vertices_ - sweep_vertex_) + (sweep_faces_ - sweep_face_) : 0;
  const std::size_t waiting = vertices_.list.size() + faces_.list.size() + sweep_left +
                              (requests != resets_done_ ? static_cast<std::size_t>(budget_) : 0);
  if (room < std::min(waiting, static_cast<std::size_t>(budget_)) + 2) {  // the reader is behind: wait for it
    out.stalled = true;
    ++counters_.stalled_frames;
    return out;
  }
  out.records = write(world, frame, room);
  counters_.records += out.records;
  return out;
}

bool GeometryStream::flush(World& world, std::int64_t frame, std::chrono::milliseconds timeout,
                           const std::function<void()>& reader) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const GeometryPublish p = publish(world, frame);
    if (reader) reader();
    if (!p.stalled && reset_requests_.load(std::memory_order_acquire) != 0 && !sweeping_ && swept_ &&
        vertices_.list.empty() && faces_.list.empty())
      return true;
    if (!reader && (p.stalled || reset_requests_.load(std::memory_order_acquire) == 0))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

GeometryCounters GeometryStream::counters() const noexcept { return counters_; }

}  // namespace incise::sim
