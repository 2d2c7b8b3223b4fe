/*
 * scene_internal.h - the scene module's private types (never installed).
 *
 * Design: both file formats are turned into the same cJSON tree (the JSON
 * scene format, version 1) together with a position map that gives the file,
 * line and column of every value and key.  One validator walks that tree,
 * reports every error with its place, and fills the plain description below
 * (struct rbs_scene).  Worlds are built from the description only, so the
 * two formats cannot drift apart.
 */
#ifndef RBS_SCENE_INTERNAL_H
#define RBS_SCENE_INTERNAL_H

#include <cjson/cJSON.h>

#include "rbsim/reel.h"
#include "rbsim/scene.h"

#include "core/c_locale.h" /* numbers read and written in the "C" locale */
#include "core/ieee.h"

/** Deepest nesting of JSON arrays/objects accepted (cJSON allows 1000). */
#define RBS__SCENE_DEPTH_MAX 64
/** Longest number literal accepted (cJSON copies numbers into 64 bytes). */
#define RBS__SCENE_NUMBER_MAX 63
/** Largest scene file read, bytes. */
#define RBS__SCENE_FILE_MAX ((size_t)256 * 1024 * 1024)
/** Files of one scene: JSON uses one; text uses config, materials, objects. */
#define RBS__SCENE_FILES_MAX 4
/** Largest steps value: every frame time k*dt keeps an exact integer k. */
#define RBS__SCENE_STEPS_MAX 9007199254740992.0 /* 2^53 */
/* The world's ranges (rbs_world_def_validate, world.c), checked at load so
 * that the error names the key: slop in (0, RBS__SCENE_SLOP_MAX),
 * max_sweeps in 1..RBS__SCENE_SWEEPS_MAX, soft_substeps in
 * 1..RBS__SOFT_SUBSTEPS_MAX (core/world_internal.h, the world's own), and
 * soft_tolerance in [0, 1]. */
#define RBS__SCENE_SLOP_MAX 0.1
#define RBS__SCENE_SLOP_RANGE "must be in (0, 0.1) (a fraction of the smaller radius)"
#define RBS__SCENE_SWEEPS_MAX 100000
/* Keyframes of a camera's "path" (the sdl renderer's limit too). */
#define RBS__SCENE_CAMERA_KEYS_MAX 100000
/* The world's largest max_contacts (rbs_world_def_validate). */
#define RBS__SCENE_CONTACTS_MAX 67108864u /* 2^26 */
/* The largest max_substeps (the field's: the world takes any >= 1). */
#define RBS__SCENE_SUBSTEPS_MAX 4294967295.0 /* 2^32 - 1 */
/* The world's smallest tolerance (world.c: double precision). */
#define RBS__SCENE_TOLERANCE_MIN 1e-15

/** A place in a scene file. */
typedef struct rbs__loc {
    int32_t file; /* index in scene->files, -1 if none */
    int32_t line; /* 1-based, 0 if none */
    int32_t column;
} rbs__loc;

/** One source file held while parsing, with its line-start table. */
typedef struct rbs__src {
    const char *text;
    size_t len;
    size_t *lines; /* byte offset of each line start */
    size_t line_count;
} rbs__src;

/** Where an item of the tree came from: its value and, in an object, its key.
 * raw/raw_len: the value's literal text (numbers and text-format tokens). */
typedef struct rbs__pos {
    const cJSON *item;
    int32_t file;
    uint32_t value_off, key_off;
    uint32_t raw_off, raw_len;
    int32_t has_key;
} rbs__pos;

/** Map from cJSON item to rbs__pos (open addressing on the pointer). */
typedef struct rbs__posmap {
    rbs__pos *slots;
    size_t cap; /* power of two */
    size_t count;
} rbs__posmap;

typedef struct rbs__scene_err {
    char *buf; /* "text\0file\0path\0message\0" */
    int32_t file; /* index in files, -1 for the command line */
    rbs_scene_error pub;
} rbs__scene_err;

typedef struct rbs__scene_pair {
    int32_t a, b; /* material index, -1 = "*" */
    double static_friction, kinetic_friction;
    double restitution; /* < 0: the simulation's */
    double rolling, spinning;
} rbs__scene_pair;

typedef struct rbs__scene_body {
    rbs_body_type type;
    char name[RBS_NAME_MAX];
    /* spheres */
    double radius;
    double mass;    /* > 0 unless density is used */
    double density; /* > 0 when given instead of mass */
    rbs_inertia_kind inertia_kind;
    rbs_vec3 inertia;
    rbs_vec3 position;
    rbs_quat orientation;
    rbs_vec3 velocity, angular_velocity, center_of_mass, force, torque;
    int32_t fixed;
    /* planes */
    rbs_vec3 point, normal;
    /* both */
    int32_t material; /* index, -1 = none */
    uint32_t color;
    rbs_texture texture;
    int32_t ok; /* its own values were valid (cross-checks use it) */
    /* places, for cross-checks */
    rbs__loc at, at_position, at_material;
} rbs__scene_body;

typedef struct rbs__scene_renderer {
    char *type;
    char *json;
    rbs__loc at;
} rbs__scene_renderer;

struct rbs_scene {
    /* errors */
    rbs__scene_err errors[RBS_SCENE_ERRORS_MAX];
    uint32_t error_kept;
    uint32_t error_count;
    /* warnings (rbs_scene_warning_get): kept and counted as the errors */
    rbs__scene_err warnings[RBS_SCENE_ERRORS_MAX];
    uint32_t warning_kept;
    uint32_t warning_count;
    /* files, for messages */
    char *files[RBS__SCENE_FILES_MAX];
    int32_t file_count;
    /* files[k] names a file on disk the scene was read from (not a label:
     * "<json>", "(no materials file)"); see rbs_scene_source */
    uint8_t file_read[RBS__SCENE_FILES_MAX];
    /* description */
    char *description; /* NULL if none */
    uint64_t steps;
    double dt;
    rbs_vec3 gravity;
    rbs_gravity_mode gravity_mode;
    rbs_method method;
    double tolerance;
    double slop; /* allowed overlap and contact margin, of the smaller radius */
    uint32_t max_sweeps; /* impulse sweeps per contact pass (rbs_world_def.max_sweeps) */
    uint32_t max_contacts; /* contacts a step may hold; 0: 4 x max(bodies, 1) + 16
                              (rbs_world_def.max_contacts) */
    uint32_t max_substeps; /* a step's work cap (rbs_world_def.max_substeps) */
    uint32_t soft_substeps; /* sub-steps per frame of the soft method
                               (rbs_world_def.soft_substeps) */
    double soft_tolerance; /* the soft method's overlap budget, a fraction
                              of the smaller radius, in [0, 1]
                              (rbs_world_def.soft_tolerance) */
    double restitution;
    int32_t pause_on_collision;
    int32_t mutual_gravity;
    double gravity_constant, softening;
    uint32_t material_count;
    char (*materials)[RBS_NAME_MAX];
    uint32_t pair_count;
    rbs__scene_pair *pairs;
    uint32_t body_count;
    rbs__scene_body *bodies;
    uint32_t renderer_count;
    rbs__scene_renderer renderers[RBS_RENDERERS_MAX];
};

/* scene.c */
rbs_scene *rbs__scene_new(void);
int32_t rbs__scene_add_file(rbs_scene *scene, const char *name);
/** Record an error (printf-style message, numbers in the "C" locale).
 * at.line == 0: no place. */
void rbs__scene_error(rbs_scene *scene, rbs__loc at, const char *path,
                      const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/** Record a warning: what the scene allows but is likely a mistake (as
 * rbs__scene_error; it does not stop the scene building a world). */
void rbs__scene_warning(rbs_scene *scene, rbs__loc at, const char *path,
                        const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/** Order the kept errors by file, line and column (stable). */
void rbs__scene_sort_errors(rbs_scene *scene);
char *rbs__strdup(const char *s);
size_t rbs__edit_distance(const char *a, const char *b);
/** The closest of n candidates to word (stride bytes apart), or NULL if none
 * is close enough to suggest. */
const char *rbs__suggest(const char *word, const char *const *candidates,
                         size_t n);

/* scene_src.c: sources, positions */
int rbs__src_init(rbs__src *src, const char *text, size_t len);
void rbs__src_fini(rbs__src *src);
rbs__loc rbs__src_loc(const rbs__src *src, int32_t file, size_t off);
int rbs__posmap_init(rbs__posmap *map, size_t expected);
void rbs__posmap_fini(rbs__posmap *map);
int rbs__posmap_put(rbs__posmap *map, const rbs__pos *pos);
const rbs__pos *rbs__posmap_get(const rbs__posmap *map, const cJSON *item);
/* rbs__utf8_seq: core/world_internal.h (names are checked there too) */

/* scene_json.c: JSON text -> tree + positions */
/** Parse JSON text into *tree with positions for every item (file index
 * file).  On a syntax error records it and returns nonzero. */
/* "FF FE" or "FE FF" when text starts with a UTF-16 (or UTF-32 LE)
 * byte-order mark, which neither format takes (the message says to save
 * the file as UTF-8); NULL otherwise. */
static inline const char *rbs__utf16_bom(const char *text, size_t len)
{
    const unsigned char *u = (const unsigned char *)text;
    if (len >= 2 && u[0] == 0xFF && u[1] == 0xFE)
        return "FF FE";
    if (len >= 2 && u[0] == 0xFE && u[1] == 0xFF)
        return "FE FF";
    return NULL;
}

/* The message for such a file. */
#define RBS__UTF16_MESSAGE \
    "the file is UTF-16 (it starts with the byte-order mark %s): scene files are UTF-8; save it as UTF-8"

int rbs__json_parse(rbs_scene *scene, const rbs__src *src, int32_t file,
                    rbs__posmap *map, cJSON **tree);

/** Parse JSON text (strict, as above) without positions or messages; NULL
 * if invalid.  For re-reading text this module wrote. */
cJSON *rbs__json_tree(const char *text, size_t len);

/* scene_text.c: config.txt + materials.txt + objects.txt -> tree + positions */
/** Load a text scene whose config (file 0, already registered as path) was
 * read into text (len bytes, NUL-terminated; freed here).  stream: the
 * config came from a pipe, FIFO or device rather than a regular file. */
rbs_status rbs__text_load(rbs_scene *scene, const char *path, char *text, size_t len,
                          int stream);

/* scene_validate.c: tree -> description */
/** Validate a tree; fill the scene's description; record every error. */
void rbs__scene_validate(rbs_scene *scene, const cJSON *tree,
                         const rbs__posmap *map, const rbs__src *srcs,
                         int32_t src_count);

/** The method "event"'s scope as its step checks it (step_event.c), decided
 * from the scene's values.  rbs__event_rows marks in refused[k] (pair_count
 * entries) each material row with rolling or spinning resistance that the
 * materials of a moving sphere and of a body take, and returns how many
 * (-1: out of memory).  rbs__event_sphere_refused: body i is a moving sphere
 * with an off-centre mass (2) or anisotropic inertia (1), else 0. */
int rbs__event_rows(const rbs_scene *scene, unsigned char *refused);
int rbs__event_sphere_refused(const rbs_scene *scene, uint32_t i);
/* Whether the scene's mutual gravity can act: a moving sphere and another
 * sphere (the world plan's mutual_acts; switched on with one sphere, or none
 * moving, it is not in the scene, and event takes the world). */
int rbs__scene_mutual_acts(const rbs_scene *scene);

/** Whether word is a key of a sphere or a plane, or close enough to one to
 * be its misspelling (objects.txt tells a mistyped body line from a key). */
int rbs__body_key_near(const char *word);

/* scene_save.c */
/* Save as JSON or text; on failure message (if not NULL) names the file
 * that could not be written and why. */
rbs_status rbs__scene_save_json(const rbs_scene *scene, const char *path, char *message,
                                size_t message_size);
rbs_status rbs__scene_save_text(const rbs_scene *scene, const char *path, char *message,
                                size_t message_size);

/* scene.c: reading files */
/** Read a whole file into a new buffer (NUL-terminated), opening it once:
 * a pipe, FIFO or /dev/stdin works too.  A regular file over
 * RBS__SCENE_FILE_MAX is refused from its size, unread; a stream as soon as
 * it passes the limit.  Records an error naming the file on failure.
 * stream (may be NULL) is set when the file is not a regular file. */
rbs_status rbs__read_file(rbs_scene *scene, const char *path, rbs__loc at,
                          char **text, size_t *len, int *stream);

#endif /* RBS_SCENE_INTERNAL_H */
