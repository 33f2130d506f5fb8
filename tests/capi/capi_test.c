/* The C API (incise.h) from a C99 program, as an engine would use it. Each check prints "ok - what" or
 * "FAIL - what (file:line)"; the exit status is the number of failures (0: all passed).
 *   capi_test SCENARIOS_DIR OUT_DIR
 * It steps pad-straight.json's poses frame by frame as `incise replay --fast` feeds them and writes the
 * world's geometry hash to OUT_DIR/step_hash.txt, and scores the shipped pad-straight trace into
 * OUT_DIR/score_line.json; capi_test.sh compares both with the CLI's. It runs under AddressSanitizer in
 * scripts/test.sh's sanitizer pass. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "incise/incise.h"

static int failures = 0;

#define CHECK(cond, what)                                                 \
  do {                                                                    \
    if (cond) {                                                           \
      printf("ok - %s\n", what);                                          \
    } else {                                                              \
      printf("FAIL - %s (%s:%d): %s\n", what, __FILE__, __LINE__, #cond); \
      printf("       last error: %s\n", incise_last_error());             \
      ++failures;                                                         \
    }                                                                     \
  } while (0)

static char scenarios[1024];
static char out_dir[1024];

static const char* path_in(const char* folder, const char* name) {
  static char buffer[4][2048];
  static int next = 0;
  char* p = buffer[next++ % 4];
  snprintf(p, sizeof buffer[0], "%s/%s", folder, name);
  return p;
}

static int logged_errors = 0;
static void count_errors(uint32_t level, const char* message, void* user) {
  (void)message;
  if (level == INCISE_LOG_ERROR) ++*(int*)user;
}

static void check_version(void) {
  char expected[32];
  CHECK(incise_version() == INCISE_VERSION, "the library's version is the header's");
  snprintf(expected, sizeof expected, "%d.%d.%d", INCISE_VERSION_MAJOR, INCISE_VERSION_MINOR, INCISE_VERSION_PATCH);
  CHECK(strcmp(incise_version_string(), expected) == 0, "the version string is major.minor.patch");
}

static void check_defs(void) {
  incise_world_def def;
  incise_world_id world = {0, 0};
  incise_status s;
  memset(&def, 0xab, sizeof def);
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), &def, &world);
  CHECK(incise_failed(s) && (s & INCISE_INVALID_PARAMETER), "a def not from incise_default_world_def is refused");
  CHECK(strstr(incise_last_error(), "incise_default_world_def") != NULL, "... and the message says how to make one");
  CHECK(world.generation == 0, "... and no world is made");
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), NULL, &world);
  CHECK(s == (INCISE_FAILURE | INCISE_INVALID_PARAMETER), "a NULL def is an invalid parameter");
  def = incise_default_world_def();
  CHECK(def.size == sizeof def && def.depth_m > 0.0 && def.max_force_N > 0.0, "the default def is filled");
  def.subdivide = 9;
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), &def, &world);
  CHECK((s & INCISE_INVALID_PARAMETER) && strstr(incise_last_error(), "subdivide") != NULL,
        "a subdivide out of range is refused, named");
  def = incise_default_world_def();
  def.order = 1;
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), &def, &world);
  CHECK(incise_failed(s) && (s & INCISE_INVALID_PARAMETER),
        "a lattice order the cutter refuses is an invalid parameter");
}

static void check_handles(void) {
  incise_world_id none = {0, 0}, world = {0, 0}, stale;
  incise_world_info info;
  incise_world_def def = incise_default_world_def();
  incise_status s;
  CHECK(incise_world_get_info(none, &info) == (INCISE_FAILURE | INCISE_INVALID_HANDLE), "a zero id names no world");
  none.index = 12345;
  none.generation = 7;
  CHECK(incise_world_step(none, NULL, 0, 0.001, 0.0, NULL) == (INCISE_FAILURE | INCISE_INVALID_HANDLE),
        "an id never made is refused by step");
  def.scale = 0.01;
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), &def, &world);
  CHECK(incise_succeeded(s) && world.generation != 0, "a world from the bunny's file");
  CHECK(incise_succeeded(incise_world_get_info(world, &info)) && info.vertex_count > 1000 && info.face_count > 2000,
        "... whose info gives its sizes");
  stale = world;
  CHECK(incise_succeeded(incise_world_destroy(world)), "destroyed");
  CHECK(incise_world_destroy(stale) == (INCISE_FAILURE | INCISE_INVALID_HANDLE), "destroyed twice: refused");
  CHECK(incise_world_get_vertices(stale, NULL, 0, &info.vertex_count) == (INCISE_FAILURE | INCISE_INVALID_HANDLE),
        "a destroyed id is refused by every call");
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/bunny.obj"), &def, &world);
  CHECK(incise_succeeded(s) && world.index == stale.index && world.generation != stale.generation,
        "a new world in the same slot has another generation");
  CHECK(incise_world_get_info(stale, &info) == (INCISE_FAILURE | INCISE_INVALID_HANDLE),
        "... and the old id still names nothing");
  CHECK(incise_succeeded(incise_world_destroy(world)), "destroyed again");
}

/* A unit cube: 8 vertices, 12 triangles counter-clockwise from outside. */
static const double cube_xyz[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_faces[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                        1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};

static void check_inputs(void) {
  incise_world_def def = incise_default_world_def();
  incise_world_id world = {0, 0};
  incise_mesh_update update;
  uint32_t faces[36];
  incise_status s;
  int before = logged_errors;
  s = incise_world_create_from_mesh_file(path_in(scenarios, "meshes/no-such-mesh.obj"), &def, &world);
  CHECK((s & INCISE_BAD_INPUT) && strstr(incise_last_error(), "no-such-mesh.obj") != NULL,
        "a missing mesh file is bad input, named");
  CHECK(logged_errors == before + 1, "... and the log hook heard of it");
  s = incise_world_create_from_arrays(cube_xyz, 8, cube_faces, 11, &def, &world);
  CHECK((s & INCISE_BAD_INPUT) && strstr(incise_last_error(), "closed two-manifold") != NULL,
        "an open mesh (a face missing) is refused");
  memcpy(faces, cube_faces, sizeof faces);
  faces[7] = 8;
  s = incise_world_create_from_arrays(cube_xyz, 8, faces, 12, &def, &world);
  CHECK((s & INCISE_BAD_INPUT) && strstr(incise_last_error(), "face 2: vertex index 8 is out of range") != NULL,
        "an index out of range is refused, naming the face");
  s = incise_world_create_from_arrays(cube_xyz, 8, cube_faces, 12, &def, &world);
  CHECK(incise_succeeded(s), "a closed cube from arrays makes a world");
  CHECK(incise_world_step(world, NULL, 0, NAN, 0.0, NULL) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "a NaN dt_s is refused, not thrown");
  CHECK(incise_world_step(world, NULL, 3, 0.001, 0.0, NULL) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "NULL poses with a count are refused");
  CHECK(incise_world_read_updates(world, &update, 1, &faces[0]) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "updates read without enabling them: refused");
  CHECK(incise_succeeded(incise_world_destroy(world)), "the cube's world destroyed");
  s = incise_world_create_from_scenario(path_in(scenarios, "no-such-scenario.json"), &world);
  CHECK(s & INCISE_BAD_INPUT, "a missing scenario is bad input");
}

/* The planar map the textured cube's file gives its corners: linear in the position. */
static void cube_map(const double* x, double* uv) {
  uv[0] = x[0] + 0.5 * x[2] + 0.125;
  uv[1] = x[1] - 0.25 * x[2] + 0.5;
}

/* The unit cube as an OBJ with a `vt` per vertex (the map) and two materials (6 faces each) in OUT_DIR. */
static const char* write_textured_cube(void) {
  const char* obj = path_in(out_dir, "textured_cube.obj");
  FILE* f = fopen(path_in(out_dir, "textured_cube.mtl"), "w");
  int i;
  if (f == NULL) return obj;
  fprintf(f, "newmtl skin_a\nKd 0.9 0.7 0.6\n\nnewmtl skin_b\nKd 0.7 0.5 0.4\n");
  fclose(f);
  f = fopen(obj, "w");
  if (f == NULL) return obj;
  fprintf(f, "mtllib textured_cube.mtl\n");
  for (i = 0; i < 8; ++i)
    fprintf(f, "v %.17g %.17g %.17g\n", cube_xyz[3 * i], cube_xyz[3 * i + 1], cube_xyz[3 * i + 2]);
  for (i = 0; i < 8; ++i) {
    double uv[2];
    cube_map(cube_xyz + 3 * i, uv);
    fprintf(f, "vt %.17g %.17g\n", uv[0], uv[1]);
  }
  for (i = 0; i < 12; ++i) {
    const uint32_t* t = cube_faces + 3 * i;
    if (i % 6 == 0) fprintf(f, "usemtl %s\n", i == 0 ? "skin_a" : "skin_b");
    fprintf(f, "f %u/%u %u/%u %u/%u\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1);
  }
  fclose(f);
  return obj;
}

/* Texture coordinates and materials as the file gave them, corner by corner in get_faces' order; a world
 * without them answers with a count of 0. */
static void check_textures(void) {
  incise_world_def def = incise_default_world_def();
  incise_world_id world = {0, 0};
  double xyz[24], uv[72], expected[2];
  uint32_t tri[36], count = 99, i, worst_corner = 0, bad = 0;
  int32_t material[12];
  char name[16];
  uint32_t length = 0;
  CHECK(incise_succeeded(incise_world_create_from_arrays(cube_xyz, 8, cube_faces, 12, &def, &world)),
        "a cube from arrays");
  CHECK(incise_succeeded(incise_world_get_texcoords(world, uv, 12, &count)) && count == 0,
        "a mesh without texture coordinates has none (count 0)");
  CHECK(incise_succeeded(incise_world_get_face_materials(world, material, 12, &count)) && count == 0,
        "... nor materials");
  incise_world_destroy(world);
  CHECK(incise_succeeded(incise_world_create_from_mesh_file(write_textured_cube(), &def, &world)),
        "a textured cube from an OBJ with vt and usemtl");
  CHECK(incise_world_get_texcoords(world, uv, 11, &count) == (INCISE_FAILURE | INCISE_BUFFER_TOO_SMALL) && count == 12,
        "texture coordinates: a buffer too small fails with the count");
  CHECK(incise_succeeded(incise_world_get_texcoords(world, uv, 12, &count)) && count == 12,
        "texture coordinates: 6 per face slot");
  incise_world_get_vertices(world, xyz, 8, &count);
  incise_world_get_faces(world, tri, NULL, 12, &count);
  for (i = 0; i < 36; ++i) {
    cube_map(xyz + 3 * tri[i], expected);
    if (fabs(uv[2 * i] - expected[0]) > 1e-12 || fabs(uv[2 * i + 1] - expected[1]) > 1e-12) ++bad, worst_corner = i;
  }
  CHECK(bad == 0, "... each corner's is the file's for that corner's vertex");
  if (bad) printf("       %u corners differ, e.g. corner %u\n", bad, worst_corner);
  CHECK(incise_succeeded(incise_world_get_face_materials(world, material, 12, &count)) && count == 12,
        "materials: one per face slot");
  CHECK(material[0] == 0 && material[5] == 0 && material[6] == 1 && material[11] == 1, "... as the file's usemtl");
  CHECK(incise_succeeded(incise_world_get_material_name(world, 1, name, sizeof name, &length)) &&
            strcmp(name, "skin_b") == 0 && length == 7,
        "material 1 is named skin_b");
  CHECK(incise_world_get_material_name(world, 2, name, sizeof name, &length) ==
            (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "material 2 of 2: refused");
  incise_world_destroy(world);
}

static void check_buffers(incise_world_id world) {
  uint32_t count = 0, small = 0;
  double sentinel[6] = {-1, -1, -1, -1, -1, -1};
  CHECK(incise_succeeded(incise_world_get_vertices(world, NULL, 0, &count)) && count > 0,
        "a NULL buffer asks for the vertex count");
  CHECK(incise_world_get_vertices(world, sentinel, 2, &small) == (INCISE_FAILURE | INCISE_BUFFER_TOO_SMALL),
        "a buffer too small fails");
  CHECK(small == count && sentinel[0] == -1 && sentinel[5] == -1, "... with the count written, the buffer untouched");
  CHECK(incise_world_get_vertices(world, sentinel, 2, NULL) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "a NULL count is refused");
}

/* The reader's copy of the mesh, kept by updates. */
typedef struct Copy {
  double* xyz;
  uint32_t* tri;
  uint8_t* kind;
  uint32_t vertices, faces, capacity_v, capacity_f;
  int exact;
} Copy;

static void copy_resize(Copy* c, uint32_t vertices, uint32_t faces) {
  if (vertices > c->capacity_v) {
    c->xyz = (double*)realloc(c->xyz, 3 * sizeof(double) * vertices);
    c->capacity_v = vertices;
  }
  if (faces > c->capacity_f) {
    c->tri = (uint32_t*)realloc(c->tri, 3 * sizeof(uint32_t) * faces);
    c->kind = (uint8_t*)realloc(c->kind, faces);
    c->capacity_f = faces;
  }
  c->vertices = vertices;
  c->faces = faces;
}

static void copy_apply(Copy* c, const incise_mesh_update* u) {
  uint32_t i = u->index;
  switch (u->type) {
    case INCISE_UPDATE_RESET:
      copy_resize(c, u->counts[0], u->counts[1]);
      break;
    case INCISE_UPDATE_VERTEX:
      if (i >= c->vertices) copy_resize(c, i + 1, c->faces);
      memcpy(c->xyz + 3 * i, u->position_m, sizeof u->position_m);
      break;
    case INCISE_UPDATE_FACE:
      if (i >= c->faces) copy_resize(c, c->vertices, i + 1);
      memcpy(c->tri + 3 * i, u->counts, sizeof u->counts);
      c->kind[i] = (uint8_t)u->kind;
      break;
    case INCISE_UPDATE_STEP:
      copy_resize(c, u->counts[0], u->counts[1]);
      c->exact = u->kind == 1;
      break;
  }
}

static void copy_read(Copy* c, incise_world_id world) {
  incise_mesh_update updates[256];
  uint32_t n = 0, k;
  do {
    if (!incise_succeeded(incise_world_read_updates(world, updates, 256, &n))) return;
    for (k = 0; k < n; ++k) copy_apply(c, &updates[k]);
  } while (n == 256);
}

/* Whole reads of the world equal the copy. */
static int copy_equals(const Copy* c, incise_world_id world) {
  uint32_t nv = 0, nf = 0;
  int same;
  double* xyz;
  uint32_t* tri;
  uint8_t* kind;
  incise_world_get_vertices(world, NULL, 0, &nv);
  incise_world_get_faces(world, NULL, NULL, 0, &nf);
  if (nv != c->vertices || nf != c->faces) return 0;
  xyz = (double*)malloc(3 * sizeof(double) * nv);
  tri = (uint32_t*)malloc(3 * sizeof(uint32_t) * nf);
  kind = (uint8_t*)malloc(nf);
  incise_world_get_vertices(world, xyz, nv, &nv);
  incise_world_get_faces(world, tri, kind, nf, &nf);
  same = memcmp(xyz, c->xyz, 3 * sizeof(double) * nv) == 0 && memcmp(tri, c->tri, 3 * sizeof(uint32_t) * nf) == 0 &&
         memcmp(kind, c->kind, nf) == 0;
  free(xyz);
  free(tri);
  free(kind);
  return same;
}

/* Steps both worlds (made from the same scenario) over the scenario's poses as `incise replay --fast`
 * feeds them (frame k at t0 + k period takes the poses due by then) until every pose is in, no work is
 * pending and the settle time is over; each world's reader follows its updates after every step. */
static uint64_t step_scenario(const incise_world_id world[2], Copy copy[2]) {
  incise_world_info info;
  incise_pose* poses;
  incise_step_result r;
  uint32_t n = 0, fed = 0, taken = 0, frame = 0, contact_frames = 0, max_force_ok = 1, w;
  uint64_t hash = 0;
  double t0, t, end_s;
  incise_world_get_info(world[0], &info);
  incise_world_scenario_poses(world[0], NULL, 0, &n);
  poses = (incise_pose*)malloc(sizeof *poses * n);
  CHECK(
      incise_succeeded(incise_world_scenario_poses(world[0], poses, n, &n)) && n == info.scenario_pose_count && n > 100,
      "the scenario's poses are read");
  t0 = poses[0].time_s;
  end_s = poses[n - 1].time_s + info.settle_s;
  for (;; ++frame) {
    t = t0 + (double)frame * info.period_s;
    while (fed < n && poses[fed].time_s <= t + 1e-12) ++fed;
    for (w = 0; w < 2; ++w) {
      if (!incise_succeeded(incise_world_step(world[w], poses + taken, fed - taken, info.period_s, t, &r))) break;
      copy_read(&copy[w], world[w]);
    }
    taken = fed;
    if (r.contact) ++contact_frames;
    if (sqrt(r.force_N[0] * r.force_N[0] + r.force_N[1] * r.force_N[1] + r.force_N[2] * r.force_N[2]) > 8.0 + 1e-9)
      max_force_ok = 0;
    if (taken == n && !r.pending && t >= end_s) break;
  }
  CHECK(taken == n && r.incisions >= 1, "every pose stepped, an incision made");
  CHECK(contact_frames > 100 && max_force_ok, "the blade was in contact, the force within max_force_N");
  incise_world_geometry_hash(world[0], &hash);
  /* Steps without poses until the copies are exact (the updates' per-step budget spreads the last ones). */
  for (frame = 0; frame < 100 && !(copy[0].exact && copy[1].exact); ++frame)
    for (w = 0; w < 2; ++w) {
      incise_world_step(world[w], NULL, 0, info.period_s, end_s + 1.0 + info.period_s * frame, NULL);
      copy_read(&copy[w], world[w]);
    }
  free(poses);
  return hash;
}

static void write_text(const char* name, const char* text) {
  FILE* f = fopen(path_in(out_dir, name), "w");
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

static void check_scenario_world(void) {
  incise_world_id world[2] = {{0, 0}, {0, 0}};
  incise_incision_figures figures[4];
  Copy copy[2];
  uint32_t count = 0, length = 0, nv = 0, nf = 0;
  uint64_t hash[2] = {0, 0};
  char text[64];
  memset(copy, 0, sizeof copy);
  CHECK(incise_succeeded(incise_world_create_from_scenario(path_in(scenarios, "pad-straight.json"), &world[0])) &&
            incise_succeeded(incise_world_create_from_scenario(path_in(scenarios, "pad-straight.json"), &world[1])),
        "two worlds from pad-straight.json");
  check_buffers(world[0]);
  /* World 0's reader builds its copy from the updates alone; world 1's reads the mesh whole first. */
  CHECK(incise_succeeded(incise_world_enable_updates(world[0], 4096, 1)), "updates on, everything sent first");
  CHECK(incise_world_enable_updates(world[0], 0, 1) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER), "... not twice");
  CHECK(incise_succeeded(incise_world_enable_updates(world[1], 4096, 0)), "updates on, after a whole read");
  incise_world_get_vertices(world[1], NULL, 0, &nv);
  incise_world_get_faces(world[1], NULL, NULL, 0, &nf);
  copy_resize(&copy[1], nv, nf);
  incise_world_get_vertices(world[1], copy[1].xyz, nv, &nv);
  incise_world_get_faces(world[1], copy[1].tri, copy[1].kind, nf, &nf);
  const uint64_t stepped = step_scenario(world, copy);
  CHECK(copy[0].exact && copy_equals(&copy[0], world[0]), "the copy built from updates alone equals the mesh");
  CHECK(copy[1].exact && copy_equals(&copy[1], world[1]), "the copy read whole, then updated, equals the mesh");
  CHECK(incise_succeeded(incise_world_get_incisions(world[0], figures, 4, &count)) && count == 1,
        "one incision's figures");
  CHECK(figures[0].done && figures[0].groove_length_m > 0.04 && figures[0].shortfall == INCISE_SHORTFALL_NONE,
        "... a groove about as long as the 5 cm stroke, no shortfall");
  CHECK(strcmp(incise_shortfall_name(INCISE_SHORTFALL_COARSE_MESH), "coarse_mesh") == 0 &&
            strcmp(incise_shortfall_name(99), "unknown") == 0,
        "shortfalls have names");
  CHECK(incise_world_get_incision_text(world[0], 0, text, sizeof text, &length) == INCISE_SUCCESS && length == 1 &&
            text[0] == '\0',
        "no shortfall: an empty sentence");
  CHECK(incise_world_get_incision_text(world[0], 5, text, sizeof text, &length) ==
            (INCISE_FAILURE | INCISE_INVALID_PARAMETER),
        "an incision that does not exist is refused");
  CHECK(incise_succeeded(incise_world_geometry_hash(world[0], &hash[0])) &&
            incise_succeeded(incise_world_geometry_hash(world[1], &hash[1])) && hash[0] == hash[1] && hash[0] != 0,
        "both worlds have the same geometry hash");
  snprintf(text, sizeof text, "%016llx\n", (unsigned long long)stepped);
  write_text("step_hash.txt", text);
  for (count = 0; count < 2; ++count) {
    free(copy[count].xyz), free(copy[count].tri), free(copy[count].kind);
    CHECK(incise_succeeded(incise_world_destroy(world[count])), "a scenario's world destroyed");
  }
}

static void check_score(void) {
  incise_score score;
  uint32_t length = 0;
  char small[8];
  char* json;
  incise_status s = incise_score_trace(path_in(scenarios, "pad-straight.json"),
                                       path_in(scenarios, "traces/pad-straight.csv"), NULL, NULL, 0, &length);
  CHECK(incise_succeeded(s) && length > 100, "scoring asks for the JSON line's length");
  s = incise_score_trace(path_in(scenarios, "pad-straight.json"), path_in(scenarios, "traces/pad-straight.csv"), &score,
                         small, sizeof small, &length);
  CHECK(s == (INCISE_FAILURE | INCISE_BUFFER_TOO_SMALL) && length > 100, "a JSON buffer too small fails");
  CHECK(score.has_plan && score.share_within_lateral_tolerance > 0.9 && score.strokes == 1 && score.frames > 1000,
        "... with the score still filled: one stroke, cut along the plan");
  json = (char*)malloc(length);
  s = incise_score_trace(path_in(scenarios, "pad-straight.json"), path_in(scenarios, "traces/pad-straight.csv"), NULL,
                         json, length, &length);
  CHECK(incise_succeeded(s) && strncmp(json, "{\"trace\":", 9) == 0 && strlen(json) + 1 == length,
        "the line `incise score` prints");
  write_text("score_line.json", json);
  free(json);
  s = incise_score_trace(path_in(scenarios, "pad-straight.json"), path_in(scenarios, "traces/bunny-straight.csv"),
                         &score, NULL, 0, NULL);
  CHECK((s & INCISE_BAD_INPUT) && strstr(incise_last_error(), "recorded on another tissue") != NULL,
        "a trace recorded on another tissue is refused");
  s = incise_score_poses(path_in(scenarios, "pad-straight.json"), NULL, 0, &score, NULL, 0, NULL);
  CHECK(s & INCISE_INVALID_PARAMETER, "scoring NULL poses is refused");
}

/* A tissue with a material (the shipped tensioned pad) deforms as it is stepped: its mechanics are read,
 * and its vertices as simulated, written to OUT_DIR/simulated_xyz.txt (capi_test.sh compares them with
 * `incise replay --fast`'s cut.obj). A tissue without one reads the same at rest and as simulated. */
static void check_simulated_world(void) {
  incise_world_id world = {0, 0};
  incise_world_info info;
  incise_physics_info physics;
  incise_pose* poses;
  incise_step_result r;
  double *rest, *now, moved_m = 0.0, d;
  uint32_t n = 0, fed = 0, taken = 0, frame = 0, count = 0, i, a, first_nodes, finite = 1;
  double t0, t, end_s;
  FILE* out;
  CHECK(incise_succeeded(incise_world_create_from_scenario(path_in(scenarios, "pad-tension.json"), &world)),
        "a world from the tensioned pad (a tissue with a material)");
  CHECK(incise_world_get_physics(world, NULL) == (INCISE_FAILURE | INCISE_INVALID_PARAMETER), "a NULL info is refused");
  CHECK(incise_succeeded(incise_world_get_physics(world, &physics)) && physics.simulated && physics.steps == 0 &&
            physics.rate_hz >= 100.0 && physics.node_count > 100 && physics.tet_count > 100,
        "it is simulated: its rate, nodes and tets before the first step");
  first_nodes = physics.node_count;
  incise_world_get_info(world, &info);
  incise_world_scenario_poses(world, NULL, 0, &n);
  poses = (incise_pose*)malloc(sizeof *poses * n);
  incise_world_scenario_poses(world, poses, n, &n);
  t0 = poses[0].time_s;
  end_s = poses[n - 1].time_s + info.settle_s;
  for (;; ++frame) { /* as `incise replay --fast` feeds them */
    t = t0 + (double)frame * info.period_s;
    while (fed < n && poses[fed].time_s <= t + 1e-12) ++fed;
    if (!incise_succeeded(incise_world_step(world, poses + taken, fed - taken, info.period_s, t, &r))) break;
    taken = fed;
    if (taken == n && !r.pending && t >= end_s) break;
  }
  free(poses);
  CHECK(taken == n && r.incisions >= 1, "the pad's stroke stepped, an incision made");
  CHECK(incise_succeeded(incise_world_get_physics(world, &physics)) &&
            physics.steps >= (int64_t)(0.9 * physics.rate_hz * (t - t0)) && physics.node_count > first_nodes &&
            physics.max_displacement_m > 1e-4,
        "the physics stepped at its rate, the cut added nodes, the tissue moved");
  incise_world_get_info(world, &info);
  CHECK(incise_succeeded(incise_world_get_simulated_vertices(world, NULL, 0, &count)) && count == info.vertex_count,
        "the simulated vertices: one per vertex slot");
  CHECK(
      incise_world_get_simulated_vertices(world, (double*)&d, 0, &count) == (INCISE_FAILURE | INCISE_BUFFER_TOO_SMALL),
      "... into a buffer too small: refused");
  rest = (double*)malloc(sizeof *rest * 3 * count);
  now = (double*)malloc(sizeof *now * 3 * count);
  incise_world_get_vertices(world, rest, count, &count);
  CHECK(incise_succeeded(incise_world_get_simulated_vertices(world, now, count, &count)), "read as simulated");
  for (i = 0; i < count; ++i) {
    d = 0.0;
    for (a = 0; a < 3; ++a) {
      finite = finite && isfinite(now[3 * i + a]);
      d += (now[3 * i + a] - rest[3 * i + a]) * (now[3 * i + a] - rest[3 * i + a]);
    }
    if (sqrt(d) > moved_m) moved_m = sqrt(d);
  }
  CHECK(finite && moved_m > 5e-4, "the skin as simulated is away from its rest (the wound gapes: over 0.5 mm)");
  out = fopen(path_in(out_dir, "simulated_xyz.txt"), "w");
  for (i = 0; out && i < count; ++i) fprintf(out, "%.17g %.17g %.17g\n", now[3 * i], now[3 * i + 1], now[3 * i + 2]);
  if (out) fclose(out);
  free(rest);
  free(now);
  CHECK(incise_succeeded(incise_world_destroy(world)), "the pad's world destroyed");

  CHECK(incise_succeeded(incise_world_create_from_scenario(path_in(scenarios, "pad-straight.json"), &world)),
        "a world from the pad without a material");
  CHECK(incise_succeeded(incise_world_get_physics(world, &physics)) && !physics.simulated && physics.steps == 0 &&
            physics.node_count == 0,
        "... is not simulated");
  incise_world_get_info(world, &info);
  rest = (double*)malloc(sizeof *rest * 3 * info.vertex_count);
  now = (double*)malloc(sizeof *now * 3 * info.vertex_count);
  incise_world_get_vertices(world, rest, info.vertex_count, &count);
  CHECK(incise_succeeded(incise_world_get_simulated_vertices(world, now, info.vertex_count, &count)) &&
            memcmp(rest, now, sizeof *rest * 3 * count) == 0,
        "... its vertices as simulated are its vertices");
  free(rest);
  free(now);
  CHECK(incise_succeeded(incise_world_destroy(world)), "destroyed");
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: capi_test SCENARIOS_DIR OUT_DIR\n");
    return 2;
  }
  snprintf(scenarios, sizeof scenarios, "%s", argv[1]);
  snprintf(out_dir, sizeof out_dir, "%s", argv[2]);
  incise_set_log(count_errors, &logged_errors);
  check_version();
  check_defs();
  check_handles();
  check_inputs();
  check_textures();
  check_scenario_world();
  check_simulated_world();
  check_score();
  incise_set_log(NULL, NULL);
  printf("%d failure(s)\n", failures);
  return failures;
}
