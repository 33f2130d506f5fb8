/**
 * @file incise.h
 * @brief incise's C API: a tissue cut by a scalpel in real time, for engines and other languages.
 *
 * A world holds a tissue (a closed triangle mesh, in metres) and a scalpel. The caller owns the clock: each
 * step takes the poses that arrived since the last one and the frame's time, and returns the haptic force
 * and the contact; the cut grows along the poses (the local DFFD of Schein & Elber). The tissue's vertices,
 * faces and face kinds are copied into the caller's buffers, whole or as the updates since the last read.
 * Recorded sessions are scored as `incise score` scores them.
 *
 * Conventions (the same for every function):
 *  - Every call returns an ::incise_status: ::INCISE_SUCCESS, or ::INCISE_FAILURE with detail bits
 *    (::INCISE_INVALID_PARAMETER, ::INCISE_BUFFER_TOO_SMALL, ...). On failure incise_last_error() gives the
 *    message (what, and where: file:line, element index, key path) and outputs are left unchanged unless
 *    said otherwise. No C++ exception and no signal crosses this interface.
 *  - Worlds are ids by value (index + generation): a destroyed or never-made id is refused with
 *    ::INCISE_INVALID_HANDLE, never a crash; a zero-initialised id is never valid. NULL where a pointer is
 *    needed is ::INCISE_INVALID_PARAMETER.
 *  - Buffers belong to the caller. A call that fills one takes its capacity (in elements) and writes the
 *    count: a NULL buffer asks for the count alone; a buffer smaller than the count fails with
 *    ::INCISE_BUFFER_TOO_SMALL, the count written, the buffer untouched.
 *  - Units: metres, seconds, newtons, microseconds, in the names. Integers are fixed width; enums travel as
 *    uint32_t; truth values are int32_t (0 false, anything else true).
 *  - Threads: a world is used by one thread at a time (any thread, one after another: calls on one world
 *    must not overlap); different worlds may be used from different threads at once. Functions that take no
 *    world may be called from any thread at any time. Each function says so again.
 *  - Memory: incise allocates through the C++ runtime (operator new). No allocator hook is offered:
 *    replacing operator new for one library would replace it for the whole process.
 *
 * The library is libincise_c (CMake: incise::capi); a C99 program links it with no C++ flags.
 */
#ifndef INCISE_INCISE_H
#define INCISE_INCISE_H

#include <stdint.h>

#if defined(_WIN32)
#if defined(INCISE_C_BUILDING)
#define INCISE_API __declspec(dllexport)
#else
#define INCISE_API __declspec(dllimport)
#endif
#elif defined(__GNUC__)
#define INCISE_API __attribute__((visibility("default")))
#else
#define INCISE_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** @name Version
 *  The header's version; incise_version() gives the library's, to check that they match at run time.
 *  @{ */
#define INCISE_VERSION_MAJOR 0
#define INCISE_VERSION_MINOR 1
#define INCISE_VERSION_PATCH 0
/** major * 10000 + minor * 100 + patch */
#define INCISE_VERSION (INCISE_VERSION_MAJOR * 10000 + INCISE_VERSION_MINOR * 100 + INCISE_VERSION_PATCH)
/** @} */

/** The library's version as #INCISE_VERSION computes it. Threads: any. */
INCISE_API uint32_t incise_version(void);
/** The library's version as text, "0.1.0" (static storage). Threads: any. */
INCISE_API const char* incise_version_string(void);

/** What a call returns: bit flags, tested with incise_succeeded() / incise_failed() and the detail bits. */
typedef uint32_t incise_status;

/** The bits of an ::incise_status. */
typedef enum incise_status_bits {
  INCISE_SUCCESS = 0x1, /**< the call did what it says */
  INCISE_FAILURE = 0x2, /**< it did not; a detail bit says why, incise_last_error() says more */
  INCISE_INVALID_PARAMETER =
      0x100, /**< a NULL pointer, a value out of range, a def not from incise_default_world_def() */
  INCISE_BUFFER_TOO_SMALL = 0x200, /**< a caller's buffer holds fewer elements than needed (the count was written) */
  INCISE_INVALID_HANDLE = 0x400,   /**< a world id that is not (or no longer) a world */
  INCISE_BAD_INPUT = 0x800,        /**< a file, scenario, mesh or trace refused; the message says what and where */
  INCISE_OUT_OF_MEMORY = 0x1000,   /**< an allocation failed */
  INCISE_INTERNAL_ERROR = 0x2000,  /**< an unexpected error inside incise (a bug: please report the message) */
  INCISE_STATUS_BITS_FORCE32 = 0x7fffffff
} incise_status_bits;

/** Non-zero when `status` has ::INCISE_SUCCESS. */
static inline int32_t incise_succeeded(incise_status status) { return (status & INCISE_SUCCESS) != 0; }
/** Non-zero when `status` has ::INCISE_FAILURE. */
static inline int32_t incise_failed(incise_status status) { return (status & INCISE_FAILURE) != 0; }

/** The message of the last call that failed on this thread, "function: what and where" (UTF-8); "" if
 *  none has. Valid until the next failing call on this thread. Threads: any (the message is per thread). */
INCISE_API const char* incise_last_error(void);

/** Levels of the messages the log hook receives. */
typedef enum incise_log_level {
  INCISE_LOG_ERROR = 0, /**< a call failed (the same text as incise_last_error()) */
  INCISE_LOG_WARNING =
      1, /**< a call succeeded but something was skipped (a recording's bad reports, a trace without a tissue hash) */
  INCISE_LOG_LEVEL_FORCE32 = 0x7fffffff
} incise_log_level;

/** A log hook: `level` an ::incise_log_level, `message` UTF-8 without a newline (valid during the call). */
typedef void (*incise_log_fn)(uint32_t level, const char* message, void* user);

/** Sets the log hook (NULL: no logging, the default). It is called on the thread of the call that logs,
 *  possibly from several threads at once; it must not call incise. Threads: any; calls already under way
 *  may still use the previous hook. */
INCISE_API void incise_set_log(incise_log_fn hook, void* user);

/** A world: an id by value. Zero-initialised, it names no world. */
typedef struct incise_world_id {
  uint32_t index;
  uint32_t generation;
} incise_world_id;

/** How the blade's path is refined ahead of the cut on a mesh coarser than the lattice. */
typedef enum incise_refine {
  INCISE_REFINE_OFF = 0,    /**< cut the mesh as it is */
  INCISE_REFINE_LINEAR = 1, /**< bisect long edges at their midpoints (the shape kept exactly) */
  INCISE_REFINE_PN = 2,     /**< bisect at curved PN triangles' midpoints (coarse curved models get rounder) */
  INCISE_REFINE_FORCE32 = 0x7fffffff
} incise_refine;

/** A world's parameters. Fill with incise_default_world_def(), then change what you need. */
typedef struct incise_world_def {
  uint32_t size;               /**< sizeof(incise_world_def), set by incise_default_world_def() */
  uint32_t internal_cookie;    /**< set by incise_default_world_def(); a def without it is refused */
  double scale;                /**< metres per unit of a mesh file (1) */
  int32_t subdivide;           /**< Loop subdivisions of a mesh file before use, 0..5 (0) */
  uint32_t refine;             /**< an ::incise_refine (linear) */
  double refine_edge_m;        /**< longest edge refinement keeps; 0: a quarter of the lattice's width */
  double depth_m;              /**< the cut's depth below the surface */
  double opening_m;            /**< the wound's width once retracted */
  double alpha_m;              /**< lattice spacing across the cut */
  double beta_m;               /**< lattice spacing along the normal */
  double spacing_m;            /**< the stroke's resampling step: one lattice column per spacing */
  double retraction_time_s;    /**< time for the wound to open to its full width */
  int32_t order;               /**< the B-spline order of the lattice (4) */
  int32_t wall_rows;           /**< vertices per wall column and side, the bottom included */
  double blade_length_m;       /**< from the handle end of the blade to its tip */
  int32_t cut_button;          /**< the button bit that enables cutting; -1: the blade always cuts */
  int32_t reserved;            /**< 0 */
  double stiffness_N_per_m;    /**< the penalty spring along the contact normal */
  double damping_N_s_per_m;    /**< against the normal velocity in contact */
  double cutting_resistance_N; /**< against the blade's tangential motion while it cuts */
  double max_force_N;          /**< the force is clamped to this */
  double cut_budget_us;        /**< per step, the time the cutting work may take (as inversions) */
} incise_world_def;

/** The defaults of every field (those of `incise replay`'s scenarios). Threads: any. */
INCISE_API incise_world_def incise_default_world_def(void);

/** A world over the closed triangle mesh in the file at `path` (OBJ, PLY, OFF, STL), scaled and subdivided
 *  as `def` says. Fails with ::INCISE_BAD_INPUT for a file that cannot be read or is not a closed,
 *  consistently oriented two-manifold (the message names the file and line), ::INCISE_INVALID_PARAMETER for
 *  a bad def. Cost: the load and the world's grids, milliseconds to seconds. Threads: any. */
INCISE_API incise_status incise_world_create_from_mesh_file(const char* path, const incise_world_def* def,
                                                            incise_world_id* world);

/** A world over the mesh in arrays: `xyz_m` 3 doubles per vertex (metres), `triangles` 3 vertex indices per
 *  face, counter-clockwise seen from outside. The mesh is checked as a file is (::INCISE_BAD_INPUT naming
 *  the vertex or face at fault); `def`'s scale and subdivide do not apply. Threads: any. */
INCISE_API incise_status incise_world_create_from_arrays(const double* xyz_m, uint32_t vertex_count,
                                                         const uint32_t* triangles, uint32_t face_count,
                                                         const incise_world_def* def, incise_world_id* world);

/** A world as the scenario file at `path` describes it (docs/scenarios.md): its tissue, tool, cutting and
 *  rate; its poses (a trace, a recording, generated strokes) are kept for incise_world_scenario_poses().
 *  Fails with ::INCISE_BAD_INPUT naming the file and key or line at fault. Threads: any. */
INCISE_API incise_status incise_world_create_from_scenario(const char* path, incise_world_id* world);

/** Destroys the world; its id is refused from then on. Threads: the world's (no other call on it may be under way). */
INCISE_API incise_status incise_world_destroy(incise_world_id world);

/** One reading of the scalpel: the tip, the tool's orientation (the blade along its local -z axis, the
 *  cutting edge along +x), the buttons held, the pressure when the device has a sensor. */
typedef struct incise_pose {
  double time_s;              /**< on the caller's clock; each pose after the previous one */
  double tip_m[3];            /**< the blade's tip */
  double orientation_wxyz[4]; /**< unit quaternion, tool frame to world frame */
  uint32_t buttons;           /**< bit i: button i held */
  int32_t has_pressure;       /**< non-zero: `pressure` holds a reading */
  double pressure;            /**< 0..1 */
} incise_pose;

/** What a step did: the haptic force and the contact from the newest pose, and the cut's state. */
typedef struct incise_step_result {
  double force_N[3];      /**< the force to render on the haptic device */
  double tip_m[3];        /**< the blade's tip */
  double contact_m[3];    /**< where the blade enters the surface (in contact) */
  double normal[3];       /**< the surface's outward normal there */
  double penetration_m;   /**< the tip's depth below the surface */
  int32_t contact;        /**< the tip is below the surface */
  int32_t cutting;        /**< ... and the cut button is held (or needs none) */
  int32_t poses_used;     /**< poses taken this step */
  int32_t poses_rejected; /**< non-finite, or not after the previous pose in time */
  int32_t incisions;      /**< incisions begun so far */
  int32_t pending;        /**< cutting work carried to later steps */
  int32_t cut_failed;     /**< an internal topology failure stopped the current incision (incise_world_get_incisions) */
  int32_t reserved;
} incise_step_result;

/** One frame at time `t_s` (seconds, the caller's clock) after `dt_s`: the poses that arrived since the last
 *  step (oldest first, `pose_count` may be 0), the haptic force from the newest, then the cutting work
 *  within the def's budget. The cut depends only on the poses and their order, not on how they are grouped
 *  into steps. `result` may be NULL. Bad poses are skipped and counted, never an error. Cost: a few
 *  microseconds for the force plus the cutting work (under cut_budget_us); no allocation once warmed up.
 *  Threads: the world's. */
INCISE_API incise_status incise_world_step(incise_world_id world, const incise_pose* poses, uint32_t pose_count,
                                           double dt_s, double t_s, incise_step_result* result);

/** A world's sizes and rates. */
typedef struct incise_world_info {
  uint32_t vertex_count;        /**< vertex slots (vertices are never deleted) */
  uint32_t face_count;          /**< face slots, deleted faces included: the cut deletes and adds faces */
  int32_t incisions;            /**< begun so far */
  int32_t pending;              /**< cutting work left for later steps */
  double period_s;              /**< the scenario's frame period; 0.001 for a world from a mesh */
  double settle_s;              /**< the scenario's settle time after the last pose; 0.2 for a mesh */
  uint32_t scenario_pose_count; /**< the scenario's poses (0 for a world from a mesh) */
  int32_t has_tets;             /**< the scenario's tissue has a tet volume (cut along, not read here) */
} incise_world_info;

/** The world's sizes. Cost O(1). Threads: the world's. */
INCISE_API incise_status incise_world_get_info(incise_world_id world, incise_world_info* info);

/** The poses of a world's scenario (a trace, a recording, generated strokes), in time order; count 0 for a
 *  world from a mesh. Buffer rules as above. Threads: the world's. */
INCISE_API incise_status incise_world_scenario_poses(incise_world_id world, incise_pose* poses, uint32_t capacity,
                                                     uint32_t* count);

/** The kind of a face. */
typedef enum incise_face_kind {
  INCISE_FACE_ORIGINAL = 0,  /**< skin as loaded */
  INCISE_FACE_SPLIT = 1,     /**< a piece of a skin face the cut split */
  INCISE_FACE_WALL = 2,      /**< inside the wound */
  INCISE_FACE_DELETED = 255, /**< a slot the cut emptied: its vertices are 0, 0, 0 (draws nothing) */
  INCISE_FACE_KIND_FORCE32 = 0x7fffffff
} incise_face_kind;

/** The kind of a vertex. */
typedef enum incise_vertex_kind {
  INCISE_VERTEX_ORIGINAL = 0, /**< as loaded */
  INCISE_VERTEX_SEAM = 1,     /**< on a lip of the cut */
  INCISE_VERTEX_WALL = 2,     /**< inside the wound */
  INCISE_VERTEX_KIND_FORCE32 = 0x7fffffff
} incise_vertex_kind;

/** Every vertex slot's position, 3 doubles each (metres), into `xyz_m` (`capacity` vertices). Cost O(V), a
 *  copy at memory speed. Threads: the world's. */
INCISE_API incise_status incise_world_get_vertices(incise_world_id world, double* xyz_m, uint32_t capacity,
                                                   uint32_t* count);

/** Every vertex slot's position in the tissue as simulated, 3 doubles each (metres), `capacity` vertices:
 *  the skin and the wound's walls embedded in the deformed tets, each vertex on its own side of every cut
 *  (a lip follows its own lip). A scenario whose tissue has a `material` (docs/scenarios.md) deforms: the
 *  vertices of incise_world_get_vertices() are its rest shape, where the cut is made, and these are where
 *  the tissue is now (`incise replay` writes them as cut.obj, the rest as cut_rest.obj). For a tissue that
 *  does not deform they are the same as incise_world_get_vertices(). Cost: O(V) point locations in the
 *  tets (milliseconds for thousands of vertices; it allocates): a read for output and inspection, not for
 *  every step. Threads: the world's. */
INCISE_API incise_status incise_world_get_simulated_vertices(incise_world_id world, double* xyz_m, uint32_t capacity,
                                                             uint32_t* count);

/** A world's tissue mechanics (docs/scenarios.md, `tissue.material`): all zero for a tissue that does not
 *  deform. The physics steps inline in incise_world_step(), at its own fixed rate in the step's time. */
typedef struct incise_physics_info {
  int32_t simulated;         /**< non-zero: the tissue deforms (a finite-element model on its tets) */
  int32_t pressing;          /**< the tool dented the skin at the last physics step (pressing, not cutting in) */
  double rate_hz;            /**< the physics' steps per simulated second */
  int64_t steps;             /**< physics steps taken so far */
  uint32_t node_count;       /**< the model's tet nodes (cuts add nodes) */
  uint32_t tet_count;        /**< its tets, the pieces of cut tets included */
  double press_force_N[3];   /**< the tool's force on the skin at the last step (zero when not pressing) */
  double max_displacement_m; /**< the largest distance of a node from its rest position now */
} incise_physics_info;

/** The world's tissue mechanics now (::incise_physics_info). Cost O(nodes). Threads: the world's. */
INCISE_API incise_status incise_world_get_physics(incise_world_id world, incise_physics_info* info);

/** Every face slot: 3 vertex indices each into `triangles` (counter-clockwise from outside; 0, 0, 0 for a
 *  deleted slot) and, when `kinds` is not NULL, its ::incise_face_kind into kinds[i]; `capacity` in faces
 *  (both buffers). Slots keep their index for the world's life, so the updates below can address them.
 *  Cost O(F). Threads: the world's. */
INCISE_API incise_status incise_world_get_faces(incise_world_id world, uint32_t* triangles, uint8_t* kinds,
                                                uint32_t capacity, uint32_t* count);

/** Every face slot's corners' texture coordinates, 6 doubles each (u, v per corner, the corners in
 *  incise_world_get_faces()'s order; zeros for a deleted slot), `capacity` in faces. A tissue read from a
 *  file with texture coordinates (OBJ `vt`, PLY `texcoord` or `s t`) keeps them through every cut: split
 *  faces interpolate them, the walls have their own (metres along the stroke and down the wall over a 1 cm
 *  tile). A tissue without them: `count` 0, nothing written, ::INCISE_SUCCESS. Buffer rules as above.
 *  Cost O(F). Threads: the world's. */
INCISE_API incise_status incise_world_get_texcoords(incise_world_id world, double* uv, uint32_t capacity,
                                                    uint32_t* count);

/** Every face slot's material (OBJ `usemtl`), an index for incise_world_get_material_name(); -1 for a
 *  deleted slot and for a wall (the walls' material is incise's own: `incise_wall` in the files it writes).
 *  A tissue without materials: `count` 0, nothing written, ::INCISE_SUCCESS. Buffer rules as above. Cost
 *  O(F). Threads: the world's. */
INCISE_API incise_status incise_world_get_face_materials(incise_world_id world, int32_t* materials, uint32_t capacity,
                                                         uint32_t* count);

/** Material `material`'s name, NUL-terminated into `text` (`capacity` bytes); `length` gets the bytes
 *  needed, the NUL included. ::INCISE_INVALID_PARAMETER for an index out of range. Threads: the world's. */
INCISE_API incise_status incise_world_get_material_name(incise_world_id world, uint32_t material, char* text,
                                                        uint32_t capacity, uint32_t* length);

/** The FNV-1a hash of the live mesh (mesh_hash.h; `incise replay` prints it as 16 hex digits): equal
 *  meshes, equal hashes. Cost O(V + F). Threads: the world's. */
INCISE_API incise_status incise_world_geometry_hash(incise_world_id world, uint64_t* hash);

/** Types of ::incise_mesh_update. */
typedef enum incise_update_type {
  INCISE_UPDATE_RESET = 1,  /**< start over: resize to counts[0] vertices and counts[1] faces; every element follows */
  INCISE_UPDATE_VERTEX = 2, /**< vertex slot `index` is at position_m with kind `kind` (new or moved) */
  INCISE_UPDATE_FACE = 3,   /**< face slot `index` has vertices `counts` and kind `kind` (new, changed or deleted) */
  INCISE_UPDATE_STEP = 4,   /**< the end of a step's updates: counts[0], counts[1] the world's vertex and face slots,
                                 counts[2] elements still waiting; `kind` 1 when the reader's copy is now exact */
  INCISE_UPDATE_TYPE_FORCE32 = 0x7fffffff
} incise_update_type;

/** One change to the tissue's mesh since the last read. Apply them in order: a face only ever names
 *  vertices sent before it, so the copy is a valid mesh after every ::INCISE_UPDATE_STEP. */
typedef struct incise_mesh_update {
  uint32_t type;        /**< an ::incise_update_type */
  uint32_t index;       /**< the vertex or face slot */
  uint32_t kind;        /**< ::incise_vertex_kind, ::incise_face_kind, or STEP's exact flag */
  uint32_t counts[3];   /**< a face's vertices, or RESET's and STEP's counts */
  double position_m[3]; /**< a vertex's position */
} incise_mesh_update;

/** Starts keeping the mesh's changes for incise_world_read_updates(): at most `per_step` updates are queued
 *  per step (0: 16384), the rest wait for later steps (never lost; an element changed twice is sent once
 *  with its newest value). `send_all` non-zero: the updates begin with a RESET and every element, so a
 *  reader can build its copy from them alone; zero: the reader reads the mesh whole now
 *  (incise_world_get_vertices / _faces) and the updates carry what changes after. Allocates (call before
 *  the steps that matter); again: refused. Threads: the world's. */
INCISE_API incise_status incise_world_enable_updates(incise_world_id world, uint32_t per_step, int32_t send_all);

/** The updates since the last read, oldest first, up to `capacity` into `updates` (count: how many were
 *  written); fewer than `capacity` means there are no more for now. Updates not read wait (the mesh's
 *  changes keep as flags: a reader that falls behind loses nothing). Fails without enable_updates. Cost
 *  O(count). Threads: the world's. */
INCISE_API incise_status incise_world_read_updates(incise_world_id world, incise_mesh_update* updates,
                                                   uint32_t capacity, uint32_t* count);

/** Why an incision's groove is much shorter than its stroke. */
typedef enum incise_shortfall {
  INCISE_SHORTFALL_NONE = 0,             /**< as long as the stroke (or the work is not done) */
  INCISE_SHORTFALL_FAILED = 1,           /**< an internal topology failure stopped it */
  INCISE_SHORTFALL_NO_CONTACT = 2,       /**< the first sample was not on the surface */
  INCISE_SHORTFALL_COARSE_MESH = 3,      /**< lattice columns held no vertex: the mesh is coarser than the lattice */
  INCISE_SHORTFALL_INVERSION_FAILED = 4, /**< vertices whose lattice parameters were not found */
  INCISE_SHORTFALL_NO_CROSSING = 5,      /**< no edge crossed the cut inside the blade's window */
  INCISE_SHORTFALL_SEAM_BROKEN = 6,      /**< the seam's chain did not reach most seam vertices */
  INCISE_SHORTFALL_TOO_SHORT = 7,        /**< the stroke is shorter than the lattice needs */
  INCISE_SHORTFALL_UNEXPLAINED = 8,      /**< none of the above, and still much shorter */
  INCISE_SHORTFALL_FORCE32 = 0x7fffffff
} incise_shortfall;

/** What one incision made: its stroke, its groove and where it runs, and why it fell short. */
typedef struct incise_incision_figures {
  double stroke_length_m;   /**< arc length of the stroke in contact */
  double groove_length_m;   /**< arc length at rest of the seam opened */
  double groove_start_m;    /**< where the groove starts along the stroke */
  double groove_end_m;      /**< ... and ends */
  double mean_edge_m;       /**< the surface's mean edge when the world was made */
  double lattice_width_m;   /**< the lattice's extent across the cut */
  int32_t columns;          /**< lattice columns along the stroke */
  int32_t empty_columns;    /**< of those, columns that held no vertex */
  int32_t seam_vertices;    /**< seam vertices made */
  int32_t refined_vertices; /**< vertices local refinement added */
  int32_t refined_faces;    /**< faces it added */
  int32_t done;             /**< its work is done: the last fields are final */
  uint32_t shortfall;       /**< an ::incise_shortfall */
  int32_t reserved;
} incise_incision_figures;

/** Every incision's figures, in order (the current one last). Buffer rules as above. Threads: the world's. */
INCISE_API incise_status incise_world_get_incisions(incise_world_id world, incise_incision_figures* figures,
                                                    uint32_t capacity, uint32_t* count);

/** Incision `incision`'s shortfall as a sentence for a user ("" when none), NUL-terminated into `text`
 *  (`capacity` bytes); `length` gets the bytes needed, the NUL included. Threads: the world's. */
INCISE_API incise_status incise_world_get_incision_text(incise_world_id world, uint32_t incision, char* text,
                                                        uint32_t capacity, uint32_t* length);

/** A short name of an ::incise_shortfall ("coarse_mesh"), "unknown" for other values (static storage).
 *  Threads: any. */
INCISE_API const char* incise_shortfall_name(uint32_t shortfall);

/** A session's headline figures (docs/training.md); NaN where a figure does not apply. */
typedef struct incise_score {
  int64_t frames;                      /**< simulation frames of the replay */
  int64_t poses;                       /**< poses replayed */
  int32_t strokes;                     /**< blade-in-tissue intervals */
  int32_t incisions;                   /**< incisions the replay made */
  double time_s;                       /**< first contact to last */
  double path_length_in_contact_m;     /**< the tip's path in contact */
  double economy;                      /**< plan (or straight line) / path in contact */
  double idle_time_s;                  /**< the tip (nearly) still between first and last contact */
  double peak_force_N;                 /**< the largest haptic force */
  double time_above_force_threshold_s; /**< time over the scenario's force threshold */
  double groove_length_m;              /**< the grooves cut */
  double session_path_length_m;        /**< every pose, in contact or not */
  double session_sparc;                /**< smoothness of the whole session (SPARC) */
  int32_t has_plan;                    /**< the scenario has a plan: the figures below apply */
  int32_t reserved;
  double lateral_mean_abs_m;             /**< mean |deviation| of the cut from the plan */
  double share_within_lateral_tolerance; /**< share of the plan cut within the lateral tolerance */
  double share_uncut;                    /**< share of the plan not cut */
  double depth_mean_abs_error_m;         /**< mean |depth - target| */
  double share_within_depth_tolerance;   /**< share of the plan cut within the depth tolerance */
} incise_score;

/** Scores the trace file at `trace_path` (CSV, devices/TRACE_FORMAT.md) on the scenario at
 *  `scenario_path` as `incise score` does: replayed as `incise replay --fast`, the cut measured against the
 *  plan. `score` (may be NULL) gets the headline figures; `json` (may be NULL, `json_capacity` bytes) the
 *  line `incise score` prints for it, NUL-terminated, and `json_length` (may be NULL) the bytes it needs,
 *  the NUL included: a `json` too small fails with ::INCISE_BUFFER_TOO_SMALL, `score` still filled. A trace
 *  recorded on another tissue, or empty, is refused (::INCISE_BAD_INPUT). Cost: the replay (a 60 s session
 *  about a second). Threads: any. */
INCISE_API incise_status incise_score_trace(const char* scenario_path, const char* trace_path, incise_score* score,
                                            char* json, uint32_t json_capacity, uint32_t* json_length);

/** The same for poses in memory (a session the caller recorded, `pose_count` > 0, in time order), named
 *  "poses" in the JSON line. Threads: any. */
INCISE_API incise_status incise_score_poses(const char* scenario_path, const incise_pose* poses, uint32_t pose_count,
                                            incise_score* score, char* json, uint32_t json_capacity,
                                            uint32_t* json_length);

#ifdef __cplusplus
}
#endif

#endif /* INCISE_INCISE_H */
