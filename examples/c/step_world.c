/* An engine's update loop driving incise through its C API: a world made from a scenario, stepped frame by
 * frame with the poses that arrived since the last frame (here: the scenario's recorded trace, released at
 * their times), the haptic force read back each frame, and the tissue's mesh kept in the engine's own
 * vertex and index buffers by applying the updates each step reports, as a renderer uploads them.
 *   step_world SCENARIO.json
 * Prints the force now and then, then the mesh, the incisions and the geometry's hash (the one
 * `incise replay --fast SCENARIO.json` writes). Exit 1 on any error, with incise's message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <incise/incise.h>

/* The engine's copy of the tissue: vertex and index buffers that grow with the cut. */
typedef struct Buffers {
  double* xyz;
  uint32_t* triangles;
  uint8_t* kinds;
  uint32_t vertices, faces;
  int exact; /* the last step's updates left nothing waiting */
} Buffers;

static int failed(incise_status status, const char* what) {
  if (incise_succeeded(status)) return 0;
  fprintf(stderr, "step_world: %s: %s\n", what, incise_last_error());
  return 1;
}

static void grow(Buffers* b, uint32_t vertices, uint32_t faces) {
  if (vertices > b->vertices) b->xyz = (double*)realloc(b->xyz, sizeof(double) * 3 * vertices);
  if (faces > b->faces) {
    b->triangles = (uint32_t*)realloc(b->triangles, sizeof(uint32_t) * 3 * faces);
    b->kinds = (uint8_t*)realloc(b->kinds, faces);
  }
  if (vertices > b->vertices) b->vertices = vertices;
  if (faces > b->faces) b->faces = faces;
}

/* Applies the updates since the last read: new and moved vertices, new, changed and emptied faces. */
static int apply_updates(incise_world_id world, Buffers* b) {
  incise_mesh_update updates[512];
  uint32_t n = 0, i;
  do {
    if (failed(incise_world_read_updates(world, updates, 512, &n), "reading updates")) return 1;
    for (i = 0; i < n; ++i) {
      const incise_mesh_update* u = &updates[i];
      if (u->type == INCISE_UPDATE_STEP) {
        grow(b, u->counts[0], u->counts[1]);
        b->exact = u->kind == 1;
      }
      if (u->type == INCISE_UPDATE_VERTEX) {
        grow(b, u->index + 1, b->faces);
        memcpy(b->xyz + 3 * u->index, u->position_m, sizeof u->position_m);
      }
      if (u->type == INCISE_UPDATE_FACE) {
        grow(b, b->vertices, u->index + 1);
        memcpy(b->triangles + 3 * u->index, u->counts, sizeof u->counts);
        b->kinds[u->index] = (uint8_t)u->kind;
      }
    }
  } while (n == 512);
  return 0;
}

int main(int argc, char** argv) {
  incise_world_id world = {0, 0};
  incise_world_info info;
  incise_step_result step;
  incise_incision_figures figures[16];
  incise_pose* poses;
  Buffers buffers = {NULL, NULL, NULL, 0, 0, 1};
  uint32_t n = 0, next = 0, frame, count = 0, wall = 0, i;
  uint64_t hash = 0;
  double t0, end_s;
  if (argc != 2) {
    fprintf(stderr, "usage: step_world SCENARIO.json\n");
    return 2;
  }
  printf("incise %s (header %d)\n", incise_version_string(), INCISE_VERSION);
  if (failed(incise_world_create_from_scenario(argv[1], &world), "loading the scenario")) return 1;
  incise_world_get_info(world, &info);
  incise_world_scenario_poses(world, NULL, 0, &n);
  poses = (incise_pose*)malloc(sizeof *poses * n);
  incise_world_scenario_poses(world, poses, n, &n);

  /* The engine reads the mesh whole once, then follows the updates. */
  if (failed(incise_world_enable_updates(world, 0, 0), "enabling updates")) return 1;
  grow(&buffers, info.vertex_count, info.face_count);
  incise_world_get_vertices(world, buffers.xyz, buffers.vertices, &buffers.vertices);
  incise_world_get_faces(world, buffers.triangles, buffers.kinds, buffers.faces, &buffers.faces);

  /* The engine's loop: frame k at t0 + k period, with the poses that arrived by then. */
  t0 = poses[0].time_s;
  end_s = poses[n - 1].time_s + info.settle_s;
  for (frame = 0;; ++frame) {
    const double t = t0 + frame * info.period_s;
    const uint32_t first = next;
    while (next < n && poses[next].time_s <= t + 1e-12) ++next;
    if (failed(incise_world_step(world, poses + first, next - first, info.period_s, t, &step), "stepping")) return 1;
    if (apply_updates(world, &buffers)) return 1;
    if (frame % 250 == 0)
      printf("t = %.3f s: contact %d, force %.2f N, %u vertices\n", t, step.contact,
             sqrt(step.force_N[0] * step.force_N[0] + step.force_N[1] * step.force_N[1] +
                  step.force_N[2] * step.force_N[2]),
             buffers.vertices);
    if (next == n && !step.pending && t >= end_s) break;
  }

  for (i = 0; i < buffers.faces; ++i) wall += buffers.kinds[i] == INCISE_FACE_WALL;
  incise_world_get_incisions(world, figures, 16, &count);
  incise_world_geometry_hash(world, &hash);
  printf("%u frames, %u poses; the engine's copy: %u vertices, %u face slots (%u wall), exact: %s\n", frame + 1, n,
         buffers.vertices, buffers.faces, wall, buffers.exact ? "yes" : "no");
  for (i = 0; i < count && i < 16; ++i)
    printf("incision %u: stroke %.1f mm, groove %.1f mm (%s)\n", i + 1, 1e3 * figures[i].stroke_length_m,
           1e3 * figures[i].groove_length_m, incise_shortfall_name(figures[i].shortfall));
  printf("geometry %016llx\n", (unsigned long long)hash);
  free(poses);
  free(buffers.xyz);
  free(buffers.triangles);
  free(buffers.kinds);
  return failed(incise_world_destroy(world), "destroying the world");
}
