// The C API's reads of a world's tissue: whole (vertices at rest and as simulated, faces, hash), as updates
// since the last read (sim::GeometryStream), its mechanics, and the incisions' figures (incise.h).
#include <algorithm>
#include <cstring>

#include "capi_convert.h"
#include "capi_status.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/physics/tissue_model.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/tissue_physics.h"
#include "world_registry.h"

using incise::capi::fail;
using incise::capi::guarded;
using incise::capi::InvalidArgument;

namespace incise::capi {

namespace {

constexpr std::uint32_t kDefaultUpdatesPerStep = 16384;
constexpr std::uint32_t kMostUpdatesPerStep = 1u << 22;

// A stream record as the C API's update; false for the tet part's records (not offered here).
bool toUpdate(const sim::GeometryRecord& r, incise_mesh_update& u) noexcept {
  u = incise_mesh_update{};
  u.index = r.index;
  u.kind = r.kind;
  switch (r.type) {
    case sim::GeometryRecordType::Reset:
    case sim::GeometryRecordType::Frame:
      u.type = r.type == sim::GeometryRecordType::Reset ? INCISE_UPDATE_RESET : INCISE_UPDATE_STEP;
      u.kind = r.type == sim::GeometryRecordType::Frame && (r.info.flags & sim::kFrameExact) ? 1 : 0;
      u.counts[0] = r.info.vertices, u.counts[1] = r.info.faces, u.counts[2] = r.info.backlog;
      return true;
    case sim::GeometryRecordType::Vertex:
      u.type = INCISE_UPDATE_VERTEX;
      for (int a = 0; a < 3; ++a) u.position_m[a] = r.position_m[a];
      return true;
    case sim::GeometryRecordType::Face:
      u.type = INCISE_UPDATE_FACE;
      if (r.kind != sim::kDeletedFace)
        for (int a = 0; a < 3; ++a) u.counts[a] = static_cast<std::uint32_t>(r.vertices[a]);
      return true;
    default:
      return false;
  }
}

std::size_t pow2AtLeast(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}

incise_incision_figures figuresOf(const incision::IncisionFigures& f) noexcept {
  incise_incision_figures out{};
  out.stroke_length_m = f.stroke_length_m;
  out.groove_length_m = f.groove_length_m;
  out.groove_start_m = f.groove_start_m;
  out.groove_end_m = f.groove_end_m;
  out.mean_edge_m = f.mean_edge_m;
  out.lattice_width_m = f.lattice_width_m;
  out.columns = f.columns;
  out.empty_columns = f.empty_columns;
  out.seam_vertices = f.seam_vertices;
  out.refined_vertices = f.refined_vertices;
  out.refined_faces = f.refined_faces;
  out.done = f.done ? 1 : 0;
  out.shortfall = static_cast<std::uint32_t>(f.shortfall);
  return out;
}

}  // namespace

// A per-face-slot array (`width` values a slot) that only some tissues have (`present`; else the count is
// 0): the buffer rule, then fill(face, its values) for every slot.
template <class T, class Fill>
incise_status perFaceSlot(const char* function, const mesh::TriMesh& m, bool present, T* out, std::size_t width,
                          std::uint32_t capacity, std::uint32_t* count, Fill fill) {
  incise_status status;
  const std::size_t needed = present ? m.n_faces() : 0;
  if (!bufferFits(function, out, capacity, needed, count, &status)) return status;
  for (std::size_t f = 0; f < needed; ++f) fill(mesh::TriMesh::FaceHandle(static_cast<int>(f)), out + width * f);
  return INCISE_SUCCESS;
}

}  // namespace incise::capi

extern "C" {

INCISE_API incise_status incise_world_get_vertices(incise_world_id world, double* xyz_m, uint32_t capacity,
                                                   uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const mesh::TriMesh& m = w.world->tissue().mesh();
    incise_status status;
    if (!capi::bufferFits(__func__, xyz_m, capacity, m.n_vertices(), count, &status)) return status;
    static_assert(sizeof(mesh::TriMesh::Point) == 3 * sizeof(double));
    if (m.n_vertices() > 0) std::memcpy(xyz_m, m.points(), m.n_vertices() * sizeof(mesh::TriMesh::Point));
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_simulated_vertices(incise_world_id world, double* xyz_m, uint32_t capacity,
                                                             uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const mesh::SurfaceMesh& rest = w.world->tissue();
    incise_status status;
    if (!capi::bufferFits(__func__, xyz_m, capacity, rest.mesh().n_vertices(), count, &status)) return status;
    const sim::TissuePhysics* physics = w.world->physics();
    const mesh::SurfaceMesh now = physics ? physics->deformedSurface(rest) : rest;
    const mesh::TriMesh& m = now.mesh();
    if (m.n_vertices() > 0) std::memcpy(xyz_m, m.points(), m.n_vertices() * sizeof(mesh::TriMesh::Point));
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_physics(incise_world_id world, incise_physics_info* info) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    if (!info) return capi::nullArgument(__func__, "info");
    *info = incise_physics_info{};
    const sim::TissuePhysics* physics = w.world->physics();
    if (!physics) return INCISE_SUCCESS;
    const physics::TissueModel& model = physics->model();
    info->simulated = 1;
    info->rate_hz = physics->rateHz();
    info->steps = physics->stepsDone();
    info->node_count = static_cast<uint32_t>(model.nodeCount());
    info->tet_count = static_cast<uint32_t>(model.elementCount());
    const Eigen::Vector3d press_N = model.toolPressForce_N();
    info->pressing = press_N.squaredNorm() > 0.0 ? 1 : 0;
    for (int a = 0; a < 3; ++a) info->press_force_N[a] = press_N[a];
    info->max_displacement_m = model.maxDisplacement_m();
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_faces(incise_world_id world, uint32_t* triangles, uint8_t* kinds,
                                                uint32_t capacity, uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const mesh::SurfaceMesh& tissue = w.world->tissue();
    const mesh::TriMesh& m = tissue.mesh();
    incise_status status;
    if (!capi::bufferFits(__func__, triangles, capacity, m.n_faces(), count, &status)) return status;
    for (std::size_t f = 0; f < m.n_faces(); ++f) {
      const mesh::TriMesh::FaceHandle h(static_cast<int>(f));
      uint32_t* t = triangles + 3 * f;
      const bool deleted = m.status(h).deleted();
      t[0] = t[1] = t[2] = 0;
      if (!deleted) {
        int i = 0;
        for (auto v = m.cfv_iter(h); v.is_valid() && i < 3; ++v) t[i++] = static_cast<uint32_t>(v->idx());
      }
      if (kinds)
        kinds[f] =
            static_cast<uint8_t>(deleted ? static_cast<int>(INCISE_FACE_DELETED) : static_cast<int>(tissue.kind(h)));
    }
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_texcoords(incise_world_id world, double* uv, uint32_t capacity,
                                                    uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const mesh::SurfaceMesh& tissue = w.world->tissue();
    const mesh::TriMesh& m = tissue.mesh();
    return capi::perFaceSlot(__func__, m, tissue.hasTexCoords(), uv, 6, capacity, count,
                             [&](mesh::TriMesh::FaceHandle face, double* corners) {
                               std::fill(corners, corners + 6, 0.0);
                               if (m.status(face).deleted()) return;
                               auto h = m.halfedge_handle(face);  // as cfv_iter gives the vertices: get_faces'
                               for (int i = 0; i < 3; ++i, h = m.next_halfedge_handle(h)) {
                                 const Eigen::Vector2d c = tissue.texCoord(h);
                                 corners[2 * i] = c.x();
                                 corners[2 * i + 1] = c.y();
                               }
                             });
  });
}

INCISE_API incise_status incise_world_get_face_materials(incise_world_id world, int32_t* materials, uint32_t capacity,
                                                         uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const mesh::SurfaceMesh& tissue = w.world->tissue();
    const mesh::TriMesh& m = tissue.mesh();
    return capi::perFaceSlot(__func__, m, tissue.hasMaterials(), materials, 1, capacity, count,
                             [&](mesh::TriMesh::FaceHandle face, int32_t* material) {
                               const bool own = m.status(face).deleted() || tissue.kind(face) == mesh::FaceKind::Wall;
                               *material = own ? -1 : tissue.material(face);
                             });
  });
}

INCISE_API incise_status incise_world_get_material_name(incise_world_id world, uint32_t material, char* text,
                                                        uint32_t capacity, uint32_t* length) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    const std::vector<incise::mesh::Material>& all = w.world->tissue().materials();
    if (material >= all.size())
      return fail(__func__, INCISE_INVALID_PARAMETER,
                  "material " + std::to_string(material) + " of " + std::to_string(all.size()));
    return incise::capi::copyText(__func__, all[material].name, text, capacity, length);
  });
}

INCISE_API incise_status incise_world_geometry_hash(incise_world_id world, uint64_t* hash) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    if (!hash) return incise::capi::nullArgument(__func__, "hash");
    *hash = incise::mesh::geometryHash(w.world->tissue());
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_enable_updates(incise_world_id world, uint32_t per_step, int32_t send_all) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    if (w.stream) return fail(__func__, INCISE_INVALID_PARAMETER, "the world's updates are on already");
    if (per_step == 0) per_step = capi::kDefaultUpdatesPerStep;
    if (per_step > capi::kMostUpdatesPerStep)
      return fail(__func__, INCISE_INVALID_PARAMETER,
                  "per_step = " + std::to_string(per_step) + " is over " + std::to_string(capi::kMostUpdatesPerStep));
    sim::GeometryStreamOptions options;
    options.records_per_frame = static_cast<int>(per_step);
    options.ring_records = std::max<std::size_t>(std::size_t{1} << 16, capi::pow2AtLeast(4 * std::size_t{per_step}));
    auto stream = std::make_unique<sim::GeometryStream>(options);
    stream->attach(*w.world);
    if (send_all) {
      stream->requestReset();
    } else {
      sim::GeometryMirror scratch;  // the reader reads the mesh whole now: the stream starts in sync
      stream->seed(*w.world, scratch);
    }
    w.stream = std::move(stream);
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_read_updates(incise_world_id world, incise_mesh_update* updates,
                                                   uint32_t capacity, uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    if (!updates) return capi::nullArgument(__func__, "updates");
    if (!count) return capi::nullArgument(__func__, "count");
    if (!w.stream)
      return fail(__func__, INCISE_INVALID_PARAMETER, "the world's updates are off (incise_world_enable_updates)");
    uint32_t written = 0;
    while (written < capacity) {
      const std::size_t read = w.stream->read(
          [&](const sim::GeometryRecord& r) {
            if (capi::toUpdate(r, updates[written])) ++written;
          },
          capacity - written);
      if (read == 0) break;
    }
    *count = written;
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_incisions(incise_world_id world, incise_incision_figures* figures,
                                                    uint32_t capacity, uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const std::vector<incision::IncisionFigures>& all = w.world->cutter().stats().figures;
    incise_status status;
    if (!capi::bufferFits(__func__, figures, capacity, all.size(), count, &status)) return status;
    for (std::size_t i = 0; i < all.size(); ++i) figures[i] = capi::figuresOf(all[i]);
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_incision_text(incise_world_id world, uint32_t incision, char* text,
                                                        uint32_t capacity, uint32_t* length) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    const std::vector<incision::IncisionFigures>& all = w.world->cutter().stats().figures;
    if (incision >= all.size())
      return fail(__func__, INCISE_INVALID_PARAMETER,
                  "incision " + std::to_string(incision) + " of " + std::to_string(all.size()));
    return capi::copyText(__func__, incision::describeShortfall(all[incision]), text, capacity, length);
  });
}

}  // extern "C"
