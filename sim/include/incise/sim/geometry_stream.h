// The tissue's surface (and, with a tet tissue, the tet cutter's working mesh) for readers on other threads
// (a viewer, a recorder, a test): each frame the sim thread publishes what the cut changed as fixed-size
// records in a single-producer single-consumer ring; the reader applies them in order to its own copy
// (GeometryMirror, geometry_mirror.h; TetMirror, tet_mirror.h). Snapshots (simulation.h) carry the tool; this
// stream carries the mesh. A reader never sees part of a frame, and one that falls behind loses nothing.
//
// Shapes: indices are OpenMesh handle indices of the tissue (vertices are never deleted; a deleted face
// keeps its index, kind kDeletedFace). Units: metres. Threads: attach(), publish() and flush() from the
// writer thread (the sim thread; seed() before and flush() after the loop); requestReset() and read() from one
// reader thread. Cost on the sim thread: O(journal entries + records_per_frame) a frame, whatever the mesh
// size (bench/viewer_bench.cpp, docs/benchmarks.md). Failure: the constructor throws std::invalid_argument
// for bad options; nothing else throws but attach() (std::bad_alloc).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace incise::sim {

class World;
class GeometryMirror;

enum class GeometryRecordType : std::uint8_t {
  Reset = 1,
  Vertex = 2,
  Face = 3,
  Frame = 4,
  TetReset = 5,
  TetNode = 6,
  Tet = 7,
  FaceTexCoords = 8
};
inline constexpr std::uint8_t kDeletedFace = 0xff;

// Frame record flags: every element has been sent since the last Reset; and nothing is waiting either.
// The same for the tet part since its last TetReset (never set without a tet tissue).
inline constexpr std::uint8_t kFrameComplete = 1, kFrameExact = 2, kFrameTetsComplete = 4, kFrameTetsExact = 8;

struct GeometryFrameInfo {
  std::int64_t frame;      // the sim frame (Reset: the frame the reset started in)
  std::uint32_t vertices;  // the mesh's vertex and face counts (deleted faces included)
  std::uint32_t faces;
  std::uint32_t backlog;  // Frame: elements still to send (dirty or not yet swept)
  std::uint8_t flags;     // Frame: kFrameComplete | kFrameExact | kFrameTetsComplete | kFrameTetsExact
};

// A Tet record's body: one child of base tet `index` (slot `kind` of `count`), as tets::TetChild.
struct GeometryTet {
  std::int32_t nodes[4];
  std::uint8_t count;
  std::int8_t side;
  std::uint8_t cut_faces;  // bit i: the face opposite nodes[i] lies on the cut
};

// 32 bytes. Vertex: index, kind (mesh::VertexKind), position_m. Face: index, kind (mesh::FaceKind or
// kDeletedFace), vertices (counter-clockwise from outside, in OpenMesh's order from the face's halfedge).
// TetReset: info (vertices = tet nodes, faces = base tets). TetNode: index, position_m. Tet: index (the base
// tet), kind (the slot), tet. FaceTexCoords (only for a tissue with texture coordinates, right after the
// live face's Face record): index, kind (the face's material: its index in the tissue's materials, or
// kNoMaterial for none and past 254), texcoords (u, v per corner, the Face record's order, as floats).
inline constexpr std::uint8_t kNoMaterial = 255;

struct GeometryRecord {
  GeometryRecordType type;
  std::uint8_t kind;
  std::uint16_t unused;
  std::uint32_t index;
  union {
    double position_m[3];
    std::int32_t vertices[3];
    GeometryFrameInfo info;
    GeometryTet tet;
    float texcoords[6];
  };
};
static_assert(sizeof(GeometryRecord) == 32);

struct GeometryStreamOptions {
  std::size_t ring_records = std::size_t{1} << 16;  // a power of two; 2 MiB at the default (128 full frames)
  int records_per_frame = 128;                      // the writer's budget per frame (Frame record apart)
};

// Per-publish figures (the sim thread's cost is timed by the caller) and the stream's counters.
struct GeometryPublish {
  int records = 0;  // written this frame (the Frame record included); 0 when stalled
  int marked = 0;   // journal entries taken this frame
  bool stalled = false;
};
struct GeometryCounters {
  std::int64_t frames = 0, stalled_frames = 0, records = 0, resets = 0, regrowths = 0;
};

// A reader that falls behind never sees a torn state: when the ring has no room for a frame, the writer
// writes nothing that frame (counted in stalled_frames) and keeps marking, so the reader, once it has caught
// up, gets every element changed meanwhile with its newest value. A reader's first copy is made before the
// run with seed() (no sweep), or asked for with requestReset() (a reader that starts late, or dropped its
// copy): the writer starts the next frame with a Reset record (the element counts) and then sends every
// vertex and every face within the same per-frame budget (a sweep), interleaved with the changes; once the
// sweep is over and nothing is waiting, the Frame record says `exact`: the reader's copy then equals the mesh
// bit for bit. Faces only ever name vertices the reader has, so every state a reader applies up to a Frame
// record is a valid mesh.
class GeometryStream {
 public:
  explicit GeometryStream(const GeometryStreamOptions& options = {});
  GeometryStream(const GeometryStream&) = delete;
  GeometryStream& operator=(const GeometryStream&) = delete;

  // Writer, before the loop: turns the world's change journal on and reserves the dirty sets for the mesh
  // plus the cutter's headroom. Allocates (load time). The world must outlive its use here.
  void attach(World& world);
  // Before the loop, on the thread that owns the world then (it is not running): copies the mesh into
  // `mirror` at once (sim::copyGeometry) and counts that reader as in sync, so the run starts without a
  // sweep (which, on a large mesh, would take the per-frame budget for many frames). Allocates.
  void seed(World& world, GeometryMirror& mirror);
  // Writer, once per frame after the cut (Simulation::frame, step 4). Never blocks, never throws. The cutter's
  // change journal (World::meshChanges) goes into two dirty queues (a flag per element and a FIFO of
  // indices: an element changed ten times is queued once and sent with its newest value); then at most
  // `records_per_frame` records are written with the elements' current values, oldest queued first —
  // vertices, and faces once the reader has all three of their vertices (a "sent" bit per vertex; a face
  // still waiting for a new vertex goes to the back of the queue; faces get a quarter of the budget while
  // vertices keep coming) — and a Frame record closes the frame. With more changes than budget (the wound's
  // opening moves many vertices every frame on a dense mesh) each waits its turn: a few frames later, never
  // lost. The frame's records become visible to the reader at once (one release store of the write
  // position). Cost: O(journal entries) to mark (a flag test each) plus O(records_per_frame) to write. It
  // never allocates after attach(), unless the mesh grows past the room reserved there (then the queues grow
  // once, counted in regrowths).
  //
  // With a tet tissue (World::tets()) the stream also carries the tet cutter's working mesh: TetNode records
  // (a node's deformed position) and Tet records (one per child of a base tet; all of a base tet's children
  // in the same frame, slot 0 first, once the reader has their nodes), from the tet cutter's journal
  // (tets::TetChanges) through two more dirty queues, within the same per-frame budget (a third of it while
  // the surface has work waiting, and what the surface leaves). A TetReset record (the node and base-tet
  // counts) starts a sweep of the tet part alone, after every Reset (the tet cutter never renumbers its mesh
  // after load: a new incision's rebase only appends base tets and reports what it changed). Frame flags
  // kFrameTetsComplete / kFrameTetsExact say the same of the tet part as kFrameComplete / kFrameExact of the
  // surface.
  GeometryPublish publish(World& world, std::int64_t frame) noexcept;
  // Writer, after the loop has stopped: publishes until nothing is waiting (waiting for the reader to make
  // room, up to `timeout`), so the reader ends exact. `reader`, when given, is called after each publish
  // (a reader on this same thread). False when the timeout passed first (no reader).
  bool flush(World& world, std::int64_t frame, std::chrono::milliseconds timeout,
             const std::function<void()>& reader = {});
  GeometryCounters counters() const noexcept;  // writer thread, or after it has stopped

  // Reader: asks for a full re-sync (a Reset record and a sweep of every element). Any thread.
  void requestReset() noexcept { reset_requests_.fetch_add(1, std::memory_order_acq_rel); }
  // Reader: calls apply(const GeometryRecord&) for up to `max_records` published records, oldest first, and
  // frees their room. Returns how many. O(records).
  template <typename Apply>
  std::size_t read(Apply&& apply, std::size_t max_records = SIZE_MAX) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    std::size_t n = 0;
    for (; tail != head && n < max_records; ++tail, ++n) apply(ring_[tail & mask_]);
    tail_.store(tail, std::memory_order_release);
    return n;
  }

 private:
  // Elements waiting to be sent: a flag each (so an element is queued once) and a FIFO ring of their
  // indices (oldest first: with more changes than budget, each waits at most backlog / budget frames).
  static constexpr std::uint8_t kQueued = 1, kSent = 2;  // Dirty::flag bits (kSent: vertices the reader has)
  struct Dirty {
    std::vector<std::uint8_t> flag;
    std::vector<std::uint32_t> ring;  // as large as flag: never more entries than elements
    std::size_t head = 0, count = 0;
    void reserve(std::size_t elements);
    void mark(std::size_t index, std::int64_t& regrowths);
    std::uint32_t pop() noexcept;
    bool empty() const noexcept { return count == 0; }
  };
  void take(World& world) noexcept;
  int write(World& world, std::int64_t frame, std::size_t room) noexcept;
  void startReset(std::int64_t frame, std::uint32_t n_vertices, std::uint32_t n_faces) noexcept;
  std::size_t writeVertices(const World& world, std::size_t budget) noexcept;
  std::size_t writeFaces(const World& world, std::size_t budget) noexcept;
  bool sendable(const World& world, std::uint32_t f) const noexcept;
  std::size_t backlog() const noexcept;
  void emitVertex(const World& world, std::uint32_t v) noexcept;
  std::size_t emitFace(const World& world, std::uint32_t f) noexcept;  // the records written: 1 or 2
  GeometryRecord& next() noexcept { return ring_[(head_local_++) & mask_]; }
  // The tet part (geometry_stream_tets.cpp).
  void takeTets(const World& world) noexcept;
  void startTetReset(const World& world, std::int64_t frame) noexcept;
  std::size_t writeTets(const World& world, std::size_t budget) noexcept;
  std::size_t writeTetNodes(const World& world, std::size_t budget) noexcept;
  bool sendTets(const World& world, std::uint32_t base, std::size_t& budget) noexcept;
  std::size_t tetBacklog() const noexcept;
  std::uint8_t tetFlags() const noexcept;

  std::vector<GeometryRecord> ring_;
  std::uint64_t mask_;
  int budget_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the writer (release)
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the reader (release)
  alignas(64) std::atomic<std::uint32_t> reset_requests_{0};
  // Writer-owned.
  alignas(64) std::uint64_t head_local_ = 0;
  std::uint32_t resets_done_ = 0;
  Dirty vertices_, faces_;
  bool sweeping_ = false, swept_ = false;
  std::uint32_t sweep_vertex_ = 0, sweep_face_ = 0, sweep_vertices_ = 0, sweep_faces_ = 0;
  struct TetPart {         // the tet part's queues and sweep (kSent in nodes.flag: nodes the reader has)
    bool present = false;  // the world has a tet tissue
    Dirty nodes, bases;
    bool reset_pending = false, sweeping = false, swept = false;
    std::uint32_t sweep_node = 0, sweep_base = 0, sweep_nodes = 0, sweep_bases = 0;
  } tets_;
  GeometryCounters counters_;
};

}  // namespace incise::sim
