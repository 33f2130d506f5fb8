#include "incise/sim/geometry_stream.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>

#include "incise/mesh/surface_mesh.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/world.h"
#include "incise/tets/tet_cutter.h"

namespace incise::sim {

namespace {

// Room beyond the mesh for the elements a few incisions add (the surface cutter reserves 200,000 new
// vertices per incision, topped up between incisions).
constexpr std::size_t kHeadroomVertices = 400000, kHeadroomFaces = 800000;
// The tet cutter's: nodes and base tets a few incisions add (it reserves 20,000 new nodes for its life, and
// a new incision appends the previous one's extra pieces as base tets).
constexpr std::size_t kHeadroomTetNodes = 100000;

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

void GeometryStream::Dirty::reserve(std::size_t elements) {
  std::vector<std::uint32_t> order;  // the queue's entries, oldest first, into the larger ring
  order.reserve(count);
  for (std::size_t i = 0; i < count; ++i) order.push_back(ring[(head + i) % ring.size()]);
  flag.resize(elements, 0);
  ring.assign(elements, 0);
  std::copy(order.begin(), order.end(), ring.begin());
  head = 0;
}

void GeometryStream::Dirty::mark(std::size_t index, std::int64_t& regrowths) {
  if (index >= flag.size()) {  // past the room reserved at attach(): grow once, amortised
    reserve(std::max(index + 1, 2 * flag.size()));
    ++regrowths;
  }
  if (flag[index] & kQueued) return;
  flag[index] |= kQueued;
  ring[(head + count++) % ring.size()] = static_cast<std::uint32_t>(index);
}

std::uint32_t GeometryStream::Dirty::pop() noexcept {
  const std::uint32_t index = ring[head];
  head = (head + 1) % ring.size();
  --count;
  flag[index] &= static_cast<std::uint8_t>(~kQueued);
  return index;
}

void GeometryStream::attach(World& world) {
  const mesh::TriMesh& m = world.tissue().mesh();
  vertices_.reserve(m.n_vertices() + m.n_vertices() / 2 + kHeadroomVertices);
  faces_.reserve(m.n_faces() + m.n_faces() / 2 + kHeadroomFaces);
  if (const tets::TetCutter* tets = world.tets()) {
    tets_.present = true;
    tets_.nodes.reserve(static_cast<std::size_t>(tets->nodeCount()) * 3 / 2 + kHeadroomTetNodes);
    tets_.bases.reserve(static_cast<std::size_t>(tets->tetCount()) * 3 / 2 + kHeadroomTetNodes);
  }
  world.recordMeshChanges(true);
}

void GeometryStream::seed(World& world, GeometryMirror& mirror) {
  copyGeometry(world, -1, mirror);  // the mirror now counts its reset as answered
  const std::size_t n = world.tissue().mesh().n_vertices();
  if (vertices_.flag.size() < n) vertices_.reserve(n);
  for (std::size_t v = 0; v < n; ++v) vertices_.flag[v] |= kSent;
  if (const tets::TetCutter* tets = world.tets()) {
    const auto nodes = static_cast<std::size_t>(tets->nodeCount());
    if (tets_.nodes.flag.size() < nodes) tets_.nodes.reserve(nodes);
    for (std::size_t i = 0; i < nodes; ++i) tets_.nodes.flag[i] |= kSent;
    tets_.reset_pending = tets_.sweeping = false;
    tets_.swept = true;
  }
  reset_requests_.store(1, std::memory_order_release);
  resets_done_ = 1;
  sweeping_ = false;
  swept_ = true;
  world.recordMeshChanges(true);  // from now on every change is this stream's
}

void GeometryStream::take(World& world) noexcept {
  const incision::MeshChanges& changes = world.meshChanges();
  try {
    for (const int v : changes.vertices) vertices_.mark(static_cast<std::size_t>(v), counters_.regrowths);
    for (const int f : changes.faces) faces_.mark(static_cast<std::size_t>(f), counters_.regrowths);
  } catch (...) {  // out of memory growing the flags: a reader re-syncs everything
    requestReset();
  }
  takeTets(world);
  world.clearMeshChanges();
}

void GeometryStream::emitVertex(const World& world, std::uint32_t v) noexcept {
  const mesh::SurfaceMesh& tissue = world.tissue();
  const mesh::TriMesh::VertexHandle h(static_cast<int>(v));
  const auto& p = tissue.mesh().point(h);
  vertices_.flag[v] |= kSent;  // a vertex sent was marked or swept: within the flags
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Vertex;
  r.kind = static_cast<std::uint8_t>(tissue.kind(h));
  r.index = v;
  r.position_m[0] = p[0], r.position_m[1] = p[1], r.position_m[2] = p[2];
}

std::size_t GeometryStream::emitFace(const World& world, std::uint32_t f) noexcept {
  const mesh::SurfaceMesh& tissue = world.tissue();
  const mesh::TriMesh& m = tissue.mesh();
  const mesh::TriMesh::FaceHandle h(static_cast<int>(f));
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Face;
  r.index = f;
  if (m.status(h).deleted()) {
    r.kind = kDeletedFace;
    r.vertices[0] = r.vertices[1] = r.vertices[2] = -1;
    return 1;
  }
  r.kind = static_cast<std::uint8_t>(tissue.kind(h));
  int i = 0;
  for (auto v = m.cfv_iter(h); v.is_valid() && i < 3; ++v) r.vertices[i++] = v->idx();
  if (!tissue.hasTexCoords()) return 1;
  GeometryRecord& t = next();
  t.type = GeometryRecordType::FaceTexCoords;
  const int material = tissue.material(h);
  t.kind = material >= 0 && material < kNoMaterial ? static_cast<std::uint8_t>(material) : kNoMaterial;
  t.index = f;
  auto corner = m.halfedge_handle(h);  // the corners as cfv_iter gave the vertices
  for (int k = 0; k < 3; ++k, corner = m.next_halfedge_handle(corner)) {
    const OpenMesh::Vec2d& uv = m.property(tissue.texCoordProperty(), corner);
    t.texcoords[2 * k] = static_cast<float>(uv[0]);
    t.texcoords[2 * k + 1] = static_cast<float>(uv[1]);
  }
  return 2;
}

void GeometryStream::startReset(std::int64_t frame, std::uint32_t n_vertices, std::uint32_t n_faces) noexcept {
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Reset;
  r.index = 0;
  r.info = {frame, n_vertices, n_faces, 0, 0};
  sweeping_ = true;
  swept_ = false;
  sweep_vertex_ = sweep_face_ = 0;
  sweep_vertices_ = n_vertices, sweep_faces_ = n_faces;
  for (std::uint8_t& f : vertices_.flag) f &= static_cast<std::uint8_t>(~kSent);  // the reader starts over
  tets_.reset_pending = tets_.present;  // the tet part starts over too, right after
  ++counters_.resets;
}

bool GeometryStream::sendable(const World& world, std::uint32_t f) const noexcept {
  const mesh::TriMesh& m = world.tissue().mesh();
  const mesh::TriMesh::FaceHandle h(static_cast<int>(f));
  if (m.status(h).deleted()) return true;
  for (auto v = m.cfv_iter(h); v.is_valid(); ++v)
    if (static_cast<std::size_t>(v->idx()) >= vertices_.flag.size() ||
        !(vertices_.flag[static_cast<std::size_t>(v->idx())] & kSent))
      return false;
  return true;
}

std::size_t GeometryStream::writeVertices(const World& world, std::size_t budget) noexcept {
  std::size_t n = 0;
  for (; n < budget && !vertices_.empty(); ++n) emitVertex(world, vertices_.pop());
  for (; n < budget && sweeping_ && sweep_vertex_ < sweep_vertices_; ++n) emitVertex(world, sweep_vertex_++);
  return n;
}

// A face whose vertices the reader does not all have yet (a new vertex still queued) goes to the back of
// the queue: the reader never gets a face naming a vertex it lacks. Every face looked at counts against
// the budget, sent or not. The sweep's faces come once its vertices have all gone.
std::size_t GeometryStream::writeFaces(const World& world, std::size_t budget) noexcept {
  // A face of a textured tissue takes two records (Face, FaceTexCoords): each face looked at counts as many.
  const std::size_t per_face = world.tissue().hasTexCoords() ? 2 : 1;
  std::size_t work = 0;
  for (std::size_t tries = std::min(faces_.count, budget / per_face); tries > 0; --tries, work += per_face) {
    const std::uint32_t f = faces_.pop();
    if (sendable(world, f))
      emitFace(world, f);
    else
      faces_.mark(f, counters_.regrowths);  // room for it: it was just popped
  }
  if (!sweeping_ || sweep_vertex_ < sweep_vertices_) return work;
  for (; work + per_face <= budget && sweep_face_ < sweep_faces_; ++sweep_face_, work += per_face) {
    if (sendable(world, sweep_face_))
      emitFace(world, sweep_face_);
    else
      faces_.mark(sweep_face_, counters_.regrowths);
  }
  return work;
}

std::size_t GeometryStream::backlog() const noexcept {
  return vertices_.count + faces_.count +
         (sweeping_ ? (sweep_vertices_ - sweep_vertex_) + (sweep_faces_ - sweep_face_) : 0);
}

int GeometryStream::write(World& world, std::int64_t frame, std::size_t room) noexcept {
  const mesh::TriMesh& m = world.tissue().mesh();
  const auto n_vertices = static_cast<std::uint32_t>(m.n_vertices());
  const auto n_faces = static_cast<std::uint32_t>(m.n_faces());
  const std::uint64_t first = head_local_;
  const std::uint32_t requests = reset_requests_.load(std::memory_order_acquire);
  if (requests != resets_done_) {  // a full re-sync: the counts, then every element within the budget
    resets_done_ = requests;
    startReset(frame, n_vertices, n_faces);
    --room;
  }
  if (tets_.reset_pending) {
    startTetReset(world, frame);
    --room;
  }
  const std::size_t budget = std::min(room - 1, static_cast<std::size_t>(budget_));  // one for the Frame record
  // Faces get a quarter of the budget while vertices keep coming (the wound's opening moves many every
  // frame): neither starves.
  const bool faces_waiting =
      !faces_.empty() || (sweeping_ && sweep_vertex_ == sweep_vertices_ && sweep_face_ < sweep_faces_);
  // The tet part gets a third while the surface has work waiting, and whatever the surface leaves.
  const std::size_t surface_budget = tetBacklog() > 0 ? budget - budget / 3 : budget;
  const std::size_t vertex_budget = faces_waiting ? surface_budget - surface_budget / 4 : surface_budget;
  const std::size_t vertices = writeVertices(world, vertex_budget);
  const std::size_t faces = writeFaces(world, surface_budget - vertices);
  writeTets(world, budget - vertices - faces);
  if (sweeping_ && sweep_vertex_ == sweep_vertices_ && sweep_face_ == sweep_faces_) sweeping_ = false, swept_ = true;
  const std::size_t waiting = backlog();
  GeometryRecord& r = next();
  r.type = GeometryRecordType::Frame;
  r.index = 0;
  const std::uint8_t flags = static_cast<std::uint8_t>((swept_ ? kFrameComplete : 0) |
                                                       (swept_ && waiting == 0 ? kFrameExact : 0) | tetFlags());
  r.info = {frame, n_vertices, n_faces, static_cast<std::uint32_t>(waiting), flags};
  head_.store(head_local_, std::memory_order_release);  // the whole frame at once
  return static_cast<int>(head_local_ - first);
}

GeometryPublish GeometryStream::publish(World& world, std::int64_t frame) noexcept {
  GeometryPublish out;
  out.marked = static_cast<int>(world.meshChanges().vertices.size() + world.meshChanges().faces.size());
  if (const tets::TetCutter* tets = world.tets())
    out.marked += static_cast<int>(tets->changes().nodes.size() + tets->changes().base_tets.size());
  take(world);
  ++counters_.frames;
  const std::uint32_t requests = reset_requests_.load(std::memory_order_acquire);
  if (requests == 0) return out;  // no reader yet: keep marking, send nothing
  const std::size_t used = static_cast<std::size_t>(head_local_ - tail_.load(std::memory_order_acquire));
  const std::size_t room = ring_.size() - used;
  const std::size_t waiting =
      backlog() + tetBacklog() + (requests != resets_done_ ? static_cast<std::size_t>(budget_) : 0);
  if (room < std::min(waiting, static_cast<std::size_t>(budget_)) + 3) {  // the reader is behind: wait for it
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
    const bool tets_done = !tets_.present || (tets_.swept && tetBacklog() == 0);
    if (!p.stalled && reset_requests_.load(std::memory_order_acquire) != 0 && swept_ && backlog() == 0 && tets_done)
      return true;
    if (!reader && (p.stalled || reset_requests_.load(std::memory_order_acquire) == 0))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

GeometryCounters GeometryStream::counters() const noexcept { return counters_; }

}  // namespace incise::sim
