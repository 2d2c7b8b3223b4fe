/*
 * rbsim.h - the public C API of rbsim, a fixed-memory rigid-body simulator of
 * spheres and planes.
 *
 * Conventions (see docs/design.md):
 *  - SI units and double precision throughout.
 *  - Every fallible call returns an rbs_status: RBS_OK (0) or a negative error.
 *    rbs_status_string() explains a code; rbs_world_last_error() gives detail.
 *  - The world is an opaque pointer.  Bodies and materials are small ids passed
 *    by value (index + generation); the all-zero id is null, a stale id is an
 *    error code, never a crash.
 *  - Definition structs (*_def) are filled with defaults by their init macro,
 *    which records the caller's sizeof so that newer libraries can grow them.
 *    Structs the library fills (rbs_step_info, rbs_body_state) carry reserved
 *    room instead; all public structs only ever grow at the end.
 *  - Thread safety: a world is not thread-safe; distinct worlds may be used from
 *    distinct threads at once.  The library has no global mutable state.
 *  - Numbers in text (messages, rbs_world_explain, scene files, commands) are
 *    written and read in the "C" locale ('.' as the decimal point) whatever
 *    the process's locale: the library switches its own thread with
 *    uselocale for each such call and back, never with setlocale.
 *  - Quaternions are [w, x, y, z] and rotate body-frame vectors to world frame.
 */
#ifndef RBSIM_RBSIM_H
#define RBSIM_RBSIM_H

#include <stddef.h>
#include <stdint.h>

#include "rbsim/version.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(RBS_BUILDING_LIBRARY) && defined(__GNUC__)
#define RBS_API __attribute__((visibility("default")))
#else
#define RBS_API
#endif

/* ------------------------------------------------------------------------- */
/* Status codes                                                              */
/* ------------------------------------------------------------------------- */

/* One list generates the enum, rbs_status_name() and rbs_status_string()
 * (and the Python exception mapping).  Values are pinned. */
#define RBS_STATUS_LIST(X)                                                     \
    X(OK, 0, "success")                                                        \
    X(E_INVALID, -1, "invalid argument")                                       \
    X(E_CAPACITY, -2, "capacity exceeded")                                     \
    X(E_STALE_ID, -3, "null, stale or foreign id")                             \
    X(E_NUMERIC, -4, "numerical failure (NaN, infinity or overflow)")          \
    X(E_OVERLAP, -5, "bodies overlap and could not be separated")              \
    X(E_MEMORY, -6, "out of memory or buffer too small")                       \
    X(E_IO, -7, "input/output error")                                          \
    X(E_SCENE, -8, "scene error")                                              \
    X(E_UNSUPPORTED, -9, "not supported")                                      \
    X(E_NOT_FOUND, -10, "not found")                                           \
    X(E_RENDERER, -11, "renderer failure")                                     \
    X(E_CLOSED, -12, "closed or interrupted")                                  \
    X(E_VERSION, -13, "version mismatch")                                      \
    X(E_CORRUPT, -14, "corrupt or foreign data")                               \
    X(E_OWN_INPUT, -15, "the output is a file the input was read from")

#define RBS_STATUS_ENUM_ITEM(name, value, text) RBS_##name = value,
/** Status of a call: RBS_OK (0) or a negative error code. */
typedef enum rbs_status {
    RBS_STATUS_LIST(RBS_STATUS_ENUM_ITEM)
    RBS_STATUS_FORCE32 = 0x7fffffff
} rbs_status;
#undef RBS_STATUS_ENUM_ITEM

/** Short English text for a status code; never NULL, static storage. */
RBS_API const char *rbs_status_string(rbs_status status);

/** How much of text[0 .. len) a front end may write to a terminal as it is:
 * the length in bytes (1 to 4) of the character at text[0] if it is
 * well-formed UTF-8 (RFC 3629) that shows as itself, else 0 -- an ASCII
 * control or DEL, a C1 control, a Unicode space other than ' ', a line or
 * paragraph separator, an invisible formatting character (zero-width ones,
 * the bidirectional marks, overrides and isolates, the byte order mark), or
 * a byte that starts no well-formed sequence within len.  *skip (if not
 * NULL) gets the bytes that character or byte takes (1 to 4; 0 when len is
 * 0), for the caller to show as one '?'.  The library's scene errors show
 * the text they quote by this rule, and names (RBS_NAME_MAX) may hold only
 * characters it shows.  Pure; thread-safe. */
RBS_API size_t rbs_text_shown_len(const char *text, size_t len, size_t *skip);
/** The code's name without prefix ("E_CAPACITY"); never NULL, static storage. */
RBS_API const char *rbs_status_name(rbs_status status);

/* ------------------------------------------------------------------------- */
/* Version                                                                   */
/* ------------------------------------------------------------------------- */

/** Run-time library version as "MAJOR.MINOR.PATCH"; static storage. */
RBS_API const char *rbs_version(void);
/** Run-time version as MAJOR*10000 + MINOR*100 + PATCH, to compare with
 * RBS_VERSION_NUMBER from the header a caller was compiled against. */
RBS_API uint32_t rbs_version_number(void);

/* ------------------------------------------------------------------------- */
/* Basic types                                                               */
/* ------------------------------------------------------------------------- */

/** A vector in metres, metres per second, newtons, ... (see each use). */
typedef struct rbs_vec3 {
    double x, y, z;
} rbs_vec3;

/** A unit quaternion [w, x, y, z]: rotates body-frame vectors to world frame. */
typedef struct rbs_quat {
    double w, x, y, z;
} rbs_quat;

/** Body handle: slot index + generation; {0, 0} is null. Pass by value. */
typedef struct rbs_body_id {
    uint32_t index;      /**< slot index */
    uint32_t generation; /**< 0 means null; starts at 1 */
} rbs_body_id;

/** Material handle; {0, 0} is null and stands for "any material" ("*") in a
 * material pair. */
typedef struct rbs_material_id {
    uint32_t index;
    uint32_t generation;
} rbs_material_id;

/** Opaque world: bodies, materials, contacts and state in one memory block. */
typedef struct rbs_world rbs_world;

/** How gravity acts. */
typedef enum rbs_gravity_mode {
    RBS_GRAVITY_ACCELERATION = 0, /**< every body falls alike: a = g */
    RBS_GRAVITY_FORCE = 1,        /**< the same force g (N) on every body */
    RBS_GRAVITY_MODE_FORCE32 = 0x7fffffff
} rbs_gravity_mode;

/** Stepping method (see docs/methods.md). */
typedef enum rbs_method {
    RBS_METHOD_EULER = 0,     /**< semi-implicit Euler, global rollback */
    RBS_METHOD_SELECTIVE = 1, /**< Euler, only overlapping groups roll back */
    RBS_METHOD_EVENT = 2,     /**< exact event-driven stepping */
    RBS_METHOD_VERLET = 3,    /**< velocity Verlet between contacts */
    RBS_METHOD_RK4 = 4,       /**< classical Runge-Kutta between contacts */
    RBS_METHOD_ADAPTIVE = 5,  /**< GSL odeiv2 with error control */
    RBS_METHOD_SOFT = 6,      /**< fixed sub-steps with soft contacts and a
                                   restitution pass (piles; docs/methods.md) */
    RBS_METHOD_AUTO = 7,      /**< (default) chosen at each step from the world:
                                   RBS_METHOD_SOFT when at least
                                   RBS_METHOD_AUTO_SOFT_BODIES spheres move,
                                   their masses within a ratio of
                                   RBS_METHOD_AUTO_SOFT_MASS_RATIO, its
                                   sink within RBS_METHOD_AUTO_SOFT_SINK
                                   of their smallest radius (on up to
                                   RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS
                                   times soft_substeps),
                                   and there is no mutual gravity, else
                                   RBS_METHOD_EULER -- bit for bit the method
                                   chosen (rbs_world_method_in_use) */
    RBS_METHOD_COUNT = 8,
    RBS_METHOD_FORCE32 = 0x7fffffff
} rbs_method;

/** RBS_METHOD_AUTO takes RBS_METHOD_SOFT from this many moving spheres on:
 * below it a scene keeps Euler's exact impacts (cradles, billiards, stacks),
 * from it on Euler's global rollback costs 4x to 50x the soft step on a pile
 * (docs/methods.md, "auto"). */
#define RBS_METHOD_AUTO_SOFT_BODIES 64
/** ... and only while the moving spheres' largest mass is at most this many
 * times their smallest: soft sinks a contact by its load over
 * m_eff omega^2, so a heavy ball crushes a light one (1e9 kg on 1 kg) and a
 * heavy-on-light pair settles only to about this ratio at the default
 * sub-steps; beyond it RBS_METHOD_AUTO keeps RBS_METHOD_EULER, which holds
 * such stacks (docs/methods.md, "auto"). */
#define RBS_METHOD_AUTO_SOFT_MASS_RATIO 10000
/** ... and only while the deepest soft could sink a contact -- the
 * moving spheres' largest load |m a| (gravity and applied force) on the
 * lightest of them, max |m a| / (m_min omega^2), with the contact
 * frequency omega = 2 pi soft_substeps / (3 dt) -- is at most this
 * fraction of their smallest radius.  The sink is a length whatever the
 * radius (a sphere's own weight: 0.25 um at dt = 1 ms and 3 sub-steps, so
 * equal spheres from 0.25 mm up): small grains would sink into the floor
 * and each other (1 um ones by a quarter of their radius, 1 nm ones
 * through the floor) and a heavy ball into a light one (1000 kg on 0.1 kg
 * of 0.05 m: 4.6 % of its radius).  Beyond it RBS_METHOD_AUTO takes soft
 * on the fewest sub-steps that bring the sink within (it falls with h^2),
 * if at most RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS times soft_substeps, and
 * RBS_METHOD_EULER otherwise (docs/methods.md, "auto"). */
#define RBS_METHOD_AUTO_SOFT_SINK 1e-3
/** ... the most sub-steps RBS_METHOD_AUTO gives the soft step, as a
 * multiple of soft_substeps, to keep its sink within RBS_METHOD_AUTO_SOFT_SINK
 * (4: at most 4x the soft step's work, where Euler's global rollback costs
 * 4x to 140x it on heaps of 64 to 1,000); the results are those of
 * RBS_METHOD_SOFT with that many soft_substeps, bit for bit. */
#define RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS 4

/** Name of a method ("euler", ...), or NULL when out of range. */
RBS_API const char *rbs_method_name(rbs_method method);
/** Look a method up by name; RBS_E_NOT_FOUND if unknown. */
RBS_API rbs_status rbs_method_from_name(const char *name, rbs_method *out);

/** Body kind. */
typedef enum rbs_body_type {
    RBS_BODY_NONE = 0, /**< free slot */
    RBS_BODY_SPHERE = 1,
    RBS_BODY_PLANE = 2,
    RBS_BODY_TYPE_FORCE32 = 0x7fffffff
} rbs_body_type;

/** How a sphere's moment of inertia is given. */
typedef enum rbs_inertia_kind {
    RBS_INERTIA_SOLID = 0,     /**< 2/5 m r^2 */
    RBS_INERTIA_HOLLOW = 1,    /**< 2/3 m r^2 (thin shell) */
    RBS_INERTIA_PRINCIPAL = 2, /**< rbs_sphere_def.inertia: principal moments
                                    about the geometric centre, body axes */
    RBS_INERTIA_KIND_FORCE32 = 0x7fffffff
} rbs_inertia_kind;

/** Texture drawn on a body by renderers (no effect on physics). */
typedef enum rbs_texture {
    RBS_TEXTURE_NONE = 0,
    RBS_TEXTURE_STRIPES = 1,
    RBS_TEXTURE_CHECKER = 2,
    RBS_TEXTURE_FORCE32 = 0x7fffffff
} rbs_texture;

/* ------------------------------------------------------------------------- */
/* Definitions                                                               */
/* ------------------------------------------------------------------------- */

/** Longest body or material name, including the terminating NUL.  Names
 * follow the scene files' rule (scenes/FORMAT.md, "Names"), so that every
 * name a world holds could be written in a scene file (no function writes
 * a world as a scene: rbs_scene_save writes a scene read from files, whose
 * bodies all have names; a body added unnamed through this API is kept, as
 * "", by checkpoints, rbs_world_save): 1 to RBS_NAME_MAX - 1 bytes of
 * well-formed UTF-8 without blanks or control characters, '#', '"', '=',
 * ',', Unicode's spaces, C1 controls, line and paragraph separators or
 * invisible formatting characters (zero-width ones, bidirectional marks,
 * the byte order mark, ...).  Any other name is RBS_E_INVALID, the
 * message (rbs_world_last_error) naming the character and its byte. */
#define RBS_NAME_MAX 64

/** World definition: capacities (fixed for the world's life) and settings.
 * Initialise with rbs_world_def_init(&def). */
typedef struct rbs_world_def {
    uint32_t struct_size;     /**< set by rbs_world_def_init; do not touch */
    uint32_t max_bodies;      /**< spheres + planes; default 64, >= 1 */
    uint32_t max_materials;   /**< named materials; default 16 */
    uint32_t max_pairs;       /**< material-pair rows; default 64 */
    uint32_t max_contacts;    /**< contacts per step; default 4*max_bodies+16.
                                   euler and selective also keep pairs a
                                   resting approach closes within the step
                                   (speculative contacts) while room is
                                   left, in the order found; a touching
                                   pair with no room left is
                                   RBS_E_CAPACITY.  soft's reach is each
                                   body's |v| dt + |a| dt^2 (its own speed,
                                   not the pair's approach), so a fast
                                   cloud -- even one moving as a whole --
                                   fills the room with pairs that are apart
                                   and stops at a touching one (30 balls at
                                   300 m/s, dt = 1 ms, 2 touching: over
                                   140); give it room for every pair within
                                   that reach */
    double dt;                /**< step, s; default 0.001, > 0 */
    rbs_vec3 gravity;         /**< m/s^2 (or N in force mode); default 0,0,-9.81 */
    rbs_gravity_mode gravity_mode; /**< default acceleration */
    double restitution;       /**< fallback coefficient of restitution, [0,1];
                                   default 0.5 */
    rbs_method method;        /**< default RBS_METHOD_AUTO */
    double tolerance;         /**< adaptive method's error tolerance; default 1e-9,
                                   >= 1e-15 */
    double slop;              /**< allowed overlap and contact margin, relative to
                                   the smaller radius of a pair; default 1e-6 */
    uint32_t max_halvings;    /**< rollback floor: dt / 2^max_halvings; default 30 */
    uint32_t max_sweeps;      /**< impulse sweeps per resting-contact pass
                                   (100 times as many for the collision pass,
                                   which an elastic impact through a chain
                                   of touching bodies needs, and for the
                                   impacts a body takes in a selective
                                   step; the warm resting passes of euler,
                                   verlet, rk4 and adaptive take it times
                                   the moving spheres' mass ratio, its
                                   whole part, 1 to 100 times) and
                                   separation iterations; default 20 */
    int32_t mutual_gravity;   /**< nonzero: Newtonian attraction between bodies */
    double gravity_constant;  /**< G, m^3 kg^-1 s^-2; default 6.674e-11;
                                   finite, > 0 with mutual_gravity on */
    double softening;         /**< Plummer softening length, m; default 0 */
    int32_t prune;            /**< nonzero (default): leave out stages that cannot
                                   change the result; 0 runs every stage */
    uint32_t max_substeps;    /**< work cap per step: sub-steps + rollbacks of the
                                   rollback methods (euler, verlet, rk4),
                                   never exceeded: a rollback is taken only
                                   while the retry and the rest of the frame
                                   fit, and the last try takes the rest of
                                   the frame as one sub-step with its
                                   overlap pushed apart instead of rolled
                                   back (the potential energy the pushes
                                   give is taken back from the speeds of
                                   the bodies they lift, along their
                                   pushes, as far as those speeds allow)
                                   -- impacts in it may be
                                   missed or wrong, a ball may pass through
                                   another (reported in work_limit); also
                                   this many contact events of adaptive in
                                   one frame (then the same, its rest one
                                   RK4 sub-step), 256x this many rotation
                                   sub-steps (verlet, rk4; then the rest of
                                   the turn by euler's stable update, |L|
                                   kept, and work_limit) and events (event;
                                   then RBS_E_UNSUPPORTED), 25x this many
                                   adaptive steps (then RBS_E_NUMERIC);
                                   default 4096, >= 1 (a scene's
                                   simulation.max_substeps) */
    uint32_t soft_substeps;   /**< sub-steps per frame of RBS_METHOD_SOFT, each
                                   one solve and one relax pass over the
                                   contacts; default 3, 1 to 1000.  More
                                   make piles stiffer (less overlap) at a
                                   cost in proportion (docs/methods.md) */
    double soft_tolerance;    /**< RBS_METHOD_SOFT: 0 (default) takes
                                   soft_substeps every frame; > 0 lets a frame
                                   take the fewest n of soft_substeps halved
                                   (down to 1) for which every contact's
                                   reachable overlap -- its overlap at the
                                   frame's start plus its approach over the
                                   frame -- is under soft_tolerance x n /
                                   soft_substeps of its pair's smaller radius.
                                   Bodies no contact touches always take
                                   soft_substeps, and so does every world the
                                   soft step takes in its general layout
                                   (mutual gravity that can act: a moving
                                   sphere and another sphere; rolling or
                                   spinning resistance; an anisotropic or
                                   off-centre sphere).  A fraction of the radius,
                                   [0, 1] (docs/methods.md, "soft") */
} rbs_world_def;

/** Fill a world definition with defaults.  Prefer the rbs_world_def_init macro. */
RBS_API void rbs_world_def_init_sized(rbs_world_def *def, size_t def_size);
#define rbs_world_def_init(def) rbs_world_def_init_sized((def), sizeof *(def))

/** Sphere definition.  Initialise with rbs_sphere_def_init(&def). */
typedef struct rbs_sphere_def {
    uint32_t struct_size;       /**< set by the init macro */
    const char *name;           /**< optional (NULL or "": unnamed), copied,
                                     unique; the rule of RBS_NAME_MAX */
    double radius;              /**< m, > 0; default 0.1 */
    double mass;                /**< kg, > 0; default 1; ignored if density > 0 */
    double density;             /**< kg/m^3; 0 (default) means use mass */
    rbs_inertia_kind inertia_kind; /**< default solid */
    rbs_vec3 inertia;           /**< principal moments about the centre, kg m^2,
                                     used with RBS_INERTIA_PRINCIPAL */
    rbs_vec3 position;          /**< geometric centre, m */
    rbs_quat orientation;       /**< normalised on add; default identity */
    rbs_vec3 velocity;          /**< velocity of the centre of mass, m/s */
    rbs_vec3 angular_velocity;  /**< rad/s, world frame */
    rbs_vec3 center_of_mass;    /**< offset from the centre, body frame, m;
                                     |c| < radius, and the inertia about
                                     the COM must stay positive definite
                                     (solid: |c| < sqrt(2/5) r = 0.632 r,
                                     hollow: sqrt(2/3) r = 0.816 r) */
    rbs_vec3 force;             /**< constant applied force at the COM, N, world */
    rbs_vec3 torque;            /**< constant applied torque, N m, world */
    rbs_material_id material;   /**< null: no material (matches only "*") */
    uint32_t color;             /**< 0xRRGGBB; default 0xd03030 */
    rbs_texture texture;        /**< default stripes */
    int32_t fixed;              /**< nonzero: never moves (infinite mass);
                                     velocity, angular_velocity, force and
                                     torque must then be zero (else
                                     RBS_E_INVALID) */
} rbs_sphere_def;

RBS_API void rbs_sphere_def_init_sized(rbs_sphere_def *def, size_t def_size);
#define rbs_sphere_def_init(def) rbs_sphere_def_init_sized((def), sizeof *(def))

/** Plane definition: a half-space whose solid side lies behind the normal. */
typedef struct rbs_plane_def {
    uint32_t struct_size;
    const char *name;          /**< optional (NULL or "": unnamed), copied,
                                    unique; the rule of RBS_NAME_MAX */
    rbs_vec3 point;            /**< a point on the plane, m */
    rbs_vec3 normal;           /**< outward normal, normalised on add; nonzero;
                                    default 0,0,1 */
    rbs_material_id material;
    uint32_t color;            /**< default 0x808080 */
    rbs_texture texture;       /**< default checker */
} rbs_plane_def;

RBS_API void rbs_plane_def_init_sized(rbs_plane_def *def, size_t def_size);
#define rbs_plane_def_init(def) rbs_plane_def_init_sized((def), sizeof *(def))

/** Contact properties of an unordered pair of materials.  A null material id
 * stands for "*" (any).  The most specific row wins: exact pair, then one
 * wildcard, then "*"/"*" (any pair no other row covers); of two one-wildcard
 * rows that both match, the one set first. */
typedef struct rbs_pair_def {
    uint32_t struct_size;
    rbs_material_id a, b;
    double static_friction;   /**< mu_s >= kinetic; default 0.5 */
    double kinetic_friction;  /**< mu_k >= 0; default 0.3 */
    double restitution;       /**< [0,1], or negative (default) for the world's */
    double rolling;           /**< rolling resistance, dimensionless
                                   (torque <= rolling * radius * normal force) */
    double spinning;          /**< spinning resistance, m
                                   (torque <= spinning * normal force) */
} rbs_pair_def;

RBS_API void rbs_pair_def_init_sized(rbs_pair_def *def, size_t def_size);
#define rbs_pair_def_init(def) rbs_pair_def_init_sized((def), sizeof *(def))

/* ------------------------------------------------------------------------- */
/* World life cycle                                                          */
/* ------------------------------------------------------------------------- */

/** Check a world definition without creating anything.  On error writes
 * the reason into message (message_size bytes; may be NULL/0). */
RBS_API rbs_status rbs_world_def_validate(const rbs_world_def *def, char *message,
                                          size_t message_size);

/** Bytes a world of these capacities needs (pure; 0 if def is invalid). */
RBS_API size_t rbs_world_memory_size(const rbs_world_def *def);

/** Build a world inside caller memory of at least rbs_world_memory_size()
 * bytes, aligned to 16.  The caller owns the buffer and frees it after
 * rbs_world_destroy().  No other memory is taken, now or later -- except by
 * the adaptive method, whose GSL workspaces GSL allocates (malloc) when a
 * world is created with or switched to it.  The first
 * rbs_world_memory_size() bytes of the buffer are written (zeroed) here
 * (bytes past them are not touched), so every page the world uses is
 * resident from the start: the choice for a program that must not take a
 * page fault while stepping. */
RBS_API rbs_status rbs_world_create_in(void *buffer, size_t bytes,
                                       const rbs_world_def *def,
                                       rbs_world **out);
/** rbs_world_create_in for a buffer whose first rbs_world_memory_size()
 * bytes are all zero already (calloc, a fresh anonymous mapping, numpy's
 * zeros): they are not written over, so, as with rbs_world_create, the
 * operating system backs the pages as the world first writes them and
 * capacity a run never reaches costs address space, not memory.  A buffer
 * that is not all zero gives a world of garbage: the caller's promise. */
RBS_API rbs_status rbs_world_create_in_zeroed(void *buffer, size_t bytes,
                                              const rbs_world_def *def,
                                              rbs_world **out);

/** Allocate exactly once (calloc of rbs_world_memory_size() bytes; the
 * adaptive method's GSL workspaces besides, as for rbs_world_create_in) and
 * build a world there.  Free with rbs_world_destroy().  GSL's default error
 * handler aborts when its allocator fails; a program that must survive that
 * turns it off once at start (gsl_set_error_handler_off(), process-wide: its
 * decision, not the library's), and the failure is then RBS_E_MEMORY.
 * Stepping allocates nothing;
 * the operating system backs the block's pages as they are first written, so
 * resident memory is what the run uses (capacity never reached costs
 * address space only). */
RBS_API rbs_status rbs_world_create(const rbs_world_def *def, rbs_world **out);

/** Destroy a world; frees its memory if rbs_world_create made it.  NULL ok. */
RBS_API void rbs_world_destroy(rbs_world *world);

/** Detail of the world's last error ("" if none); owned by the world, valid
 * until the next call on it.  Calls that change the world and step set it;
 * read-only queries (find, get_state) return a status only. */
RBS_API const char *rbs_world_last_error(const rbs_world *world);

/** The definition the world was created with (capacities and settings as
 * they are now).  Initialise *out with rbs_world_def_init() first: its
 * struct_size says how much the caller can take. */
RBS_API rbs_status rbs_world_get_def(const rbs_world *world, rbs_world_def *out);

/* ------------------------------------------------------------------------- */
/* Materials and bodies                                                      */
/* ------------------------------------------------------------------------- */

/** Add a named material (name copied; the rule of RBS_NAME_MAX, and not
 * "*", which means any material in a pair; else RBS_E_INVALID).
 * RBS_E_CAPACITY leaves the world unchanged. */
RBS_API rbs_status rbs_world_add_material(rbs_world *world, const char *name,
                                          rbs_material_id *out);
/** Find a material by name: RBS_E_NOT_FOUND if no material has it ("" and
 * any other string no material could be named included), RBS_E_INVALID for
 * NULL -- the rule of rbs_world_find_body.  *out is written only when
 * found.  Read-only. */
RBS_API rbs_status rbs_world_find_material(const rbs_world *world,
                                           const char *name,
                                           rbs_material_id *out);
/** Set (add or replace) the row of a material pair. */
RBS_API rbs_status rbs_world_set_pair(rbs_world *world, const rbs_pair_def *def);
/** The index-th material (0 <= index < the number added): its id into *out
 * and its name into *name (owned by the world, valid while it lives); either
 * may be NULL.  RBS_E_NOT_FOUND past the last.  Read-only; thread-safe with
 * other readers. */
RBS_API rbs_status rbs_world_material_at(const rbs_world *world, uint32_t index,
                                         rbs_material_id *out, const char **name);
/** The index-th material-pair row, in the order rows were first set, into
 * *out (initialise it with rbs_pair_def_init() first: its struct_size says
 * how much the caller can take).  Restitution is as set (negative: the
 * world's).  RBS_E_NOT_FOUND past the last.  Read-only. */
RBS_API rbs_status rbs_world_pair_at(const rbs_world *world, uint32_t index,
                                     rbs_pair_def *out);

/** Add a sphere.  Invalid values give RBS_E_INVALID with the reason in
 * rbs_world_last_error(), among them the limits a scene's sphere has
 * (scenes/FORMAT.md, "Limits of a sphere"): moments of inertia and their
 * inverses finite and nonzero, and for a movable sphere 1 / mass finite and
 * each energy at the start (kinetic, rotational, potential in gravity and
 * of its force) at most 1e300 J, and its momentum m v, angular momentum
 * about the origin r x m v and spin (at most trace(I) |w|) at most 1e300 in
 * SI units, so that rbs_world_energy() and rbs_world_momentum() sums stay
 * finite (the setters apply the same limits to their argument, with
 * mutual gravity's pair potential).  RBS_E_CAPACITY leaves the
 * world unchanged. */
RBS_API rbs_status rbs_world_add_sphere(rbs_world *world,
                                        const rbs_sphere_def *def,
                                        rbs_body_id *out);
/** Add a plane (see rbs_world_add_sphere). */
RBS_API rbs_status rbs_world_add_plane(rbs_world *world,
                                       const rbs_plane_def *def,
                                       rbs_body_id *out);
/** Remove a body; its id and slot's old ids become stale. */
RBS_API rbs_status rbs_world_remove_body(rbs_world *world, rbs_body_id id);
/** Find a body by name: RBS_E_NOT_FOUND if no body has it -- "" included
 * (no body is found by it: an unnamed body is found by its slot,
 * rbs_world_body_at), as any other string no body could be named --
 * RBS_E_INVALID for NULL only; the rule of rbs_world_find_material (a
 * lookup of a string is answered, found or not; only a missing argument is
 * a fault).  *out is written only when found.  Read-only. */
RBS_API rbs_status rbs_world_find_body(const rbs_world *world, const char *name,
                                       rbs_body_id *out);
/** Id of the body in a slot, or RBS_E_NOT_FOUND if the slot is free. */
RBS_API rbs_status rbs_world_body_at(const rbs_world *world, uint32_t slot,
                                     rbs_body_id *out);

/** A body's full state, copied out. */
typedef struct rbs_body_state {
    rbs_body_type type;
    uint32_t slot;
    const char *name;          /**< owned by the world; "" if unnamed */
    rbs_vec3 position;         /**< sphere centre or plane point, m */
    rbs_quat orientation;
    rbs_vec3 velocity;         /**< COM velocity, m/s */
    rbs_vec3 angular_velocity; /**< rad/s */
    rbs_vec3 normal;           /**< planes only */
    double radius;             /**< spheres only, m */
    double mass;               /**< kg as given (fixed spheres too); 0 for planes */
    rbs_vec3 force, torque;
    rbs_material_id material;
    uint32_t color;
    rbs_texture texture;
    int32_t fixed;
    double reserved[8];        /**< zero; room to grow without an ABI break */
} rbs_body_state;

RBS_API rbs_status rbs_body_get_state(const rbs_world *world, rbs_body_id id,
                                      rbs_body_state *out);
/** A body's mass distribution as the world keeps it: *center_of_mass the
 * offset of its centre of mass from its centre (body frame, m) and
 * inertia[9] the inertia tensor about the centre of mass (body frame,
 * row-major, kg m^2; a fixed sphere keeps the inertia it was given).
 * Planes: zeros.  Either pointer may be NULL.  Read-only: safe while no
 * thread changes the world. */
RBS_API rbs_status rbs_body_get_inertia(const rbs_world *world, rbs_body_id id,
                                        rbs_vec3 *center_of_mass, double inertia[9]);
/** Setters: finite values only (RBS_E_NUMERIC otherwise, world unchanged);
 * RBS_E_STALE_ID for a stale id; the velocity, force and torque setters
 * refuse a nonzero value for a body that does not move (a plane or fixed
 * sphere: RBS_E_INVALID).  A sphere's value is held to the limits
 * rbs_world_add_sphere applies to the same argument (scenes/FORMAT.md,
 * "Limits of a sphere"; one check in the library), the sphere's other
 * values as they are now: for a movable sphere, velocity its kinetic
 * energy, momentum m v and angular momentum r x m v; angular velocity its
 * rotational energy and spin; position (and orientation, which moves an
 * off-centre sphere's centre of mass) its potential energies in gravity
 * and of its force and r x m v; force its potential f.x -- each at most
 * 1e300 in SI units; and with mutual gravity, position and orientation the
 * potential with each other sphere (a pair of fixed ones excepted).
 * Torque has no limit but finite.  Beyond a limit: RBS_E_INVALID, the
 * message (rbs_world_last_error) naming the setter, the argument, its
 * value and the limit ("set_velocity: velocity (1e+308, 0, 0) m/s: the
 * sphere's kinetic energy ... would be inf J, beyond 1e300 J ..."), and
 * the world unchanged.  Moving a body into overlap is allowed; the next
 * step separates it.  Not thread-safe against other calls on the world. */
RBS_API rbs_status rbs_body_set_position(rbs_world *world, rbs_body_id id, rbs_vec3 p);
RBS_API rbs_status rbs_body_set_orientation(rbs_world *world, rbs_body_id id, rbs_quat q);
RBS_API rbs_status rbs_body_set_velocity(rbs_world *world, rbs_body_id id, rbs_vec3 v);
RBS_API rbs_status rbs_body_set_angular_velocity(rbs_world *world, rbs_body_id id, rbs_vec3 w);
RBS_API rbs_status rbs_body_set_force(rbs_world *world, rbs_body_id id, rbs_vec3 f);
RBS_API rbs_status rbs_body_set_torque(rbs_world *world, rbs_body_id id, rbs_vec3 t);

/* ------------------------------------------------------------------------- */
/* Stepping                                                                  */
/* ------------------------------------------------------------------------- */

/** What one call of rbs_world_step did. */
typedef struct rbs_step_info {
    uint32_t contacts;    /**< contacts touching at the end of the step */
    uint32_t colliding;   /**< impacts resolved with restitution (in the
                               sub-steps kept: a sub-step rolled back takes
                               its impacts and resting impulses back) */
    uint32_t resting;     /**< resting-contact impulses */
    uint32_t substeps;    /**< accepted sub-steps (1 if no rollback) */
    uint32_t rollbacks;   /**< sub-steps undone because of overlap */
    uint32_t floor_hits;  /**< sub-steps accepted with overlap left (then
                               pushed apart): at the rollback floor
                               (dt / 2^max_halvings), a rollback the work
                               cap refused, or a body jammed in a
                               selective step */
    uint32_t sweep_limit; /**< contact passes that hit max_sweeps */
    uint32_t events;      /**< events processed (event method) */
    double max_overlap;   /**< deepest overlap at the end of the step, m */
    uint32_t work_limit;  /**< 1 if the work cap (rbs_world_def.max_substeps)
                               changed the step: some of the frame was
                               taken at reduced accuracy -- a rollback
                               refused or a sub-step lengthened (overlap
                               there was pushed apart, not resolved in time
                               order, so its impacts may be missed or
                               wrong), adaptive's rest of a frame taken
                               without events, or a turn past the rotation
                               budget.  0 for a frame that only ends at the
                               cap in the sub-steps it would take anyway */
    uint32_t reserved[7]; /**< zero; room for new counters without an ABI break */
} rbs_step_info;

/** Advance the world by dt (one frame).  Sub-steps are internal: afterwards
 * the world is at time (step_count) * dt.  On error the world stays at its
 * last good state -- the bodies and what the next step reads of the last
 * (warm-start impulses, adaptive's step size; the candidate pairs are found
 * again) -- so stepping on after an error takes the bits of a world
 * restored from a checkpoint written before the failed step.  info may be NULL.  Allocates nothing. */
RBS_API rbs_status rbs_world_step(rbs_world *world, rbs_step_info *info);

/** Simulated time, s: step count * dt, each step counted with the dt it
 * was taken with (rbs_world_set_dt changes the steps after it only). */
RBS_API double rbs_world_time(const rbs_world *world);
/** Steps taken since creation (or the checkpoint's count). */
RBS_API uint64_t rbs_world_step_count(const rbs_world *world);
/** Steps, since creation or loading (not kept in checkpoints), in which the
 * rounding of a sphere's coordinates changed its move by more than 1 % (and
 * by more than 1e-9 of its radius) where the move was under a thousandth
 * of its radius: far from the origin or at a tiny dt, that slow motion is
 * partly lost (0.05 m/s at 1e12 m froze).  Faster moves rounded so are
 * refused (RBS_E_NUMERIC).  0 for a NULL world.  Not thread-safe against
 * rbs_world_step. */
RBS_API uint64_t rbs_world_rounded_steps(const rbs_world *world);
/** Change the step size, s (finite, > 0) for the steps from now on; the
 * time elapsed so far is kept. */
RBS_API rbs_status rbs_world_set_dt(rbs_world *world, double dt);
/** The method the next step takes: def.method, or for RBS_METHOD_AUTO the
 * one it resolves to for the world as it is now (RBS_METHOD_EULER or
 * RBS_METHOD_SOFT).  RBS_METHOD_COUNT for a NULL or destroyed world.  Not
 * thread-safe against calls that change the world. */
RBS_API rbs_method rbs_world_method_in_use(const rbs_world *world);

/** Change the method and its tolerance (tolerance <= 0 keeps the current). */
RBS_API rbs_status rbs_world_set_method(rbs_world *world, rbs_method method,
                                        double tolerance);

/** Zero-copy view of the state, structure of arrays over body slots
 * 0 .. slots-1 (free slots hold zeros).  Pointers stay valid for the world's
 * life; the arrays change when the world steps.  Write only through setters. */
typedef struct rbs_state_view {
    uint32_t slots;                 /**< slots in use (high-water mark) */
    uint32_t capacity;              /**< max_bodies */
    const double *position;         /**< slots x 3, m */
    const double *velocity;         /**< slots x 3, m/s */
    const double *angular_velocity; /**< slots x 3, rad/s */
    const double *orientation;      /**< slots x 4, [w x y z] */
    const int32_t *type;            /**< slots, rbs_body_type */
} rbs_state_view;

RBS_API rbs_status rbs_world_state(const rbs_world *world, rbs_state_view *out);

/* ------------------------------------------------------------------------- */
/* Worker threads                                                            */
/* ------------------------------------------------------------------------- */

/** The most threads a world steps on (rbs_workers.count). */
#define RBS_WORKERS_MAX 16

/** A task a step gives to the caller's threads: fn(task, k), k = 1 .. n. */
typedef void rbs_task_fn(void *task, uint32_t k);

/** Threads the caller lends a world's steps.  The library never starts a
 * thread of its own: a step calls start once, to run the step's task on up
 * to count - 1 other threads while its own thread runs it too, and finish
 * before it returns.  The soft step's gathered layout (every pile) then
 * splits its stages among them; every other step runs on the caller's
 * thread alone.  Results are the same bits whatever count is, and whether
 * the pool runs the tasks at once, late or never (the step's thread takes
 * every share no other thread has claimed; it never waits for a task to
 * begin).  rbs_pool_create (reel.h) makes such a pool.  Initialise with
 * rbs_workers_init(&w): count 1, no callbacks. */
typedef struct rbs_workers {
    uint32_t struct_size; /**< set by the init macro */
    uint32_t count;       /**< threads, the step's own included: 1 (default,
                               the caller's thread only) to RBS_WORKERS_MAX */
    /** Start fn(task, k) for k = 1 .. n, each on a thread of its own, and
     * return without waiting for them.  Called from the stepping thread. */
    void (*start)(void *user, rbs_task_fn *fn, void *task, uint32_t n);
    /** Return when every fn the last start started has returned. */
    void (*finish)(void *user);
    void *user;           /**< passed to start and finish */
} rbs_workers;

RBS_API void rbs_workers_init_sized(rbs_workers *workers, size_t size);
#define rbs_workers_init(w) rbs_workers_init_sized((w), sizeof *(w))

/** Lend the world threads for its steps (copied; workers NULL or count 1:
 * the caller's thread only, the default).  RBS_E_INVALID for a count
 * outside 1 .. RBS_WORKERS_MAX or, with count > 1, a NULL start or finish;
 * RBS_E_UNSUPPORTED when the library was built without atomics (a compiler
 * other than GCC or Clang).  The pool must outlive its use: set NULL before
 * destroying it.  Not a checkpoint's (a loaded world has none).  Not
 * thread-safe: call it between steps. */
RBS_API rbs_status rbs_world_set_workers(rbs_world *world, const rbs_workers *workers);
/** The threads the world's steps may use (1 without a pool). */
RBS_API uint32_t rbs_world_workers(const rbs_world *world);

/* ------------------------------------------------------------------------- */
/* Diagnostics                                                               */
/* ------------------------------------------------------------------------- */

/** Energies, J.  Potential counts uniform gravity (relative to the origin)
 * and mutual gravity when on. */
typedef struct rbs_energy {
    double kinetic;
    double potential;
    double total;
} rbs_energy;

/** Kinetic (translation and rotation) and potential energy (uniform
 * gravity, constant forces, and with mutual_gravity -G ma mb / sqrt(d^2 +
 * softening^2) for every pair of spheres of which at least one moves; the
 * constant of a pair of fixed spheres is left out).  RBS_E_NUMERIC if a
 * sum overflows (huge but finite states) or is infinite (two spheres at one
 * point under unsoftened mutual gravity): the values written are then not
 * to be trusted. */
RBS_API rbs_status rbs_world_energy(const rbs_world *world, rbs_energy *out);
/** Total linear momentum (kg m/s) and angular momentum about the origin
 * (kg m^2/s). Either pointer may be NULL.  RBS_E_NUMERIC if a sum
 * overflows. */
RBS_API rbs_status rbs_world_momentum(const rbs_world *world, rbs_vec3 *linear,
                                      rbs_vec3 *angular);

/** Memory use, for sizing worlds: run, read the high-water marks, shrink. */
typedef struct rbs_usage {
    size_t bytes;                /**< size of the world's block */
    uint32_t bodies, bodies_high;
    uint32_t materials, pairs;
    uint32_t contacts_high;      /**< most contacts seen in a pass */
} rbs_usage;

RBS_API rbs_status rbs_world_usage(const rbs_world *world, rbs_usage *out);

/** Deterministic 64-bit hash (FNV-1a) of the full state bits (the step
 * count and every slot's position, velocity, angular velocity and
 * orientation, up to the last body); for determinism tests and golden
 * files. */
RBS_API uint64_t rbs_world_hash(const rbs_world *world);

/* ------------------------------------------------------------------------- */
/* Checkpoints                                                               */
/* ------------------------------------------------------------------------- */

/** Bytes a checkpoint of this world takes (0 if world is invalid). */
RBS_API size_t rbs_world_checkpoint_size(const rbs_world *world);

/** Write the exact state (every double bit for bit, the step count, bodies,
 * materials and settings) with a format version and a 64-bit checksum into
 * buf.  RBS_E_MEMORY if size is too small.  written may be NULL. */
RBS_API rbs_status rbs_world_checkpoint_write(const rbs_world *world, void *buf, size_t size,
                                              size_t *written);

/** Create a world (one allocation) from a checkpoint.  A corrupt, truncated
 * or foreign buffer is RBS_E_CORRUPT; another format version RBS_E_VERSION. */
RBS_API rbs_status rbs_world_create_from_checkpoint(const void *buf, size_t size,
                                                    rbs_world **out);
/** rbs_world_create_from_checkpoint, and on failure the reason (truncated
 * to how many bytes, which version, a checksum mismatch, ...) in message
 * (message_size bytes, NUL-terminated; "" on success).  message may be
 * NULL. */
RBS_API rbs_status rbs_world_create_from_checkpoint_v2(const void *buf, size_t size,
                                                       rbs_world **out, char *message,
                                                       size_t message_size);

/** Save a checkpoint to a file atomically: a temporary file beside it,
 * fsync, rename.  A crash mid-write leaves any previous file intact.  A
 * path that exists and is not a regular file (a device, FIFO or folder) is
 * refused with RBS_E_IO, never replaced; through a symbolic link the file
 * it points to is written (created if missing) and the link kept.
 * Reads the world only: safe while no thread steps it. */
RBS_API rbs_status rbs_world_save(const rbs_world *world, const char *path);
/** rbs_world_save, and on failure "PATH: REASON" (the file that could not
 * be written -- a link's target -- and why) in message (message_size
 * bytes, NUL-terminated; "" on success).  message may be NULL. */
RBS_API rbs_status rbs_world_save_v2(const rbs_world *world, const char *path, char *message,
                                     size_t message_size);

/** Load a world saved by rbs_world_save().  path may be a pipe or FIFO
 * (/dev/stdin): the file is read to its end without seeking.  On error *out
 * is NULL and, when message is not NULL, the reason ("PATH: truncated: ...",
 * a read error with the system's reason) is written there. */
RBS_API rbs_status rbs_world_load(const char *path, rbs_world **out, char *message,
                                  size_t message_size);

/* ------------------------------------------------------------------------- */
/* Methods and pipeline                                                      */
/* ------------------------------------------------------------------------- */

/** Describe as text the pipeline rbs_world_step() runs for this world as it
 * is now: bodies, the method and its sub-steps, and each stage in or out
 * with the reason (the body or material pair that needs it; with
 * def.prune = 0 every stage runs).  Lines end in '\n'.  Writes at most size
 * bytes, NUL-terminated when size > 0; buf may be NULL when size is 0.
 * *needed (may be NULL) receives the full length including the NUL.
 * Returns RBS_E_MEMORY when the text did not fit (always when size is 0),
 * RBS_E_INVALID for a NULL or destroyed world.  Does not change the world;
 * as thread-safe as other read-only calls on it. */
RBS_API rbs_status rbs_world_explain(const rbs_world *world, char *buf, size_t size,
                                     size_t *needed);

#ifdef __cplusplus
}
#endif

#endif /* RBSIM_RBSIM_H */
