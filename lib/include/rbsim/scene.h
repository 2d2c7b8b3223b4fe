/*
 * rbsim/scene.h - scene files: the JSON scene (format version 1) and the
 * seed's config.txt / materials.txt / objects.txt.  See scenes/FORMAT.md.
 *
 * A scene is parsed and validated before any world exists; parsing may
 * allocate and frees everything in rbs_scene_free().  A scene object is not
 * thread-safe; distinct scenes may be used from distinct threads.
 */
#ifndef RBSIM_SCENE_H
#define RBSIM_SCENE_H

#include "rbsim/rbsim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A parsed scene (or the errors that rejected it).  Opaque. */
typedef struct rbs_scene rbs_scene;

/** Most errors kept per scene; further ones are counted, not kept. */
#define RBS_SCENE_ERRORS_MAX 50

/** One error in a scene, e.g. "bad.json:12:17: bodies[3].radius: must be > 0,
 * got -0.1".  Strings are owned by the scene.  path, message and text are
 * safe to print: input text they repeat has each control character, C1
 * control, invisible formatting character (e.g. U+202E) and byte of invalid
 * UTF-8 replaced by one '?'. */
typedef struct rbs_scene_error {
    const char *file;    /**< path as given */
    int32_t line;        /**< 1-based; 0 if not tied to a place */
    int32_t column;      /**< 1-based, in bytes */
    const char *path;    /**< key path, e.g. "bodies[3].radius"; may be "" */
    const char *message; /**< what was wrong and what was expected */
    const char *text;    /**< the whole line "file:line:col: path: message" */
} rbs_scene_error;

/** Scene file formats. */
typedef enum rbs_scene_format {
    RBS_SCENE_AUTO = 0, /**< by name and content: ".json", or a file that starts
                             with '{', is JSON; a folder or anything else is
                             text */
    RBS_SCENE_JSON = 1,
    RBS_SCENE_TEXT = 2, /**< config.txt with materials.txt and objects.txt */
    RBS_SCENE_FORMAT_FORCE32 = 0x7fffffff
} rbs_scene_format;

/** Load and validate a scene file.  format RBS_SCENE_AUTO: a path ending in
 * ".json" or a file whose first non-blank byte is '{' is JSON, anything else
 * text; a folder stands for its config.txt.  The file is opened and read
 * once, so a pipe, FIFO or /dev/stdin works: its bytes decide the format.  A
 * config.txt's files are looked for beside its path (for a pipe such as
 * /dev/stdin: give them as absolute paths).  A file over 256 MiB is refused
 * (RBS_E_IO), a regular file from its size, a stream just past the limit.
 * Returns RBS_OK, RBS_E_SCENE (rejected: every error is recorded, see
 * rbs_scene_error_get) or RBS_E_IO (a file could not be read; recorded the
 * same way): in these three cases *out is set and must be freed with
 * rbs_scene_free.  On other errors (RBS_E_INVALID arguments, RBS_E_MEMORY)
 * *out is NULL.  Numbers are read in the "C" locale whatever the process's
 * LC_NUMERIC.  Thread-safe for distinct scenes (no global state). */
RBS_API rbs_status rbs_scene_load(const char *path, rbs_scene_format format,
                                  rbs_scene **out);

/** Parse a JSON scene held in memory: len bytes, NUL not required, never
 * read past; any bytes are safe.  name labels errors (NULL: "<json>").
 * Same results and ownership as rbs_scene_load. */
RBS_API rbs_status rbs_scene_parse_json(const char *text, size_t len,
                                        const char *name, rbs_scene **out);

/** Free a scene.  NULL ok. */
RBS_API void rbs_scene_free(rbs_scene *scene);

/** Number of errors found (kept ones are at most RBS_SCENE_ERRORS_MAX); 0
 * for NULL.  A scene with errors builds no world. */
RBS_API uint32_t rbs_scene_error_count(const rbs_scene *scene);
/** The i-th kept error, sorted by file, line and column (errors of a later
 * rbs_scene_override follow); RBS_E_NOT_FOUND past the kept ones.  The
 * strings live as long as the scene. */
RBS_API rbs_status rbs_scene_error_get(const rbs_scene *scene, uint32_t i,
                                       rbs_scene_error *out);

/** Number of warnings found: what a scene may say but is likely a mistake,
 * each kept as an rbs_scene_error is (place, key path, message; at most
 * RBS_SCENE_ERRORS_MAX kept, all counted).  Warnings do not stop a scene
 * building its world.  Today one kind: a material named in a "materials"
 * row that no body has ("materials[1].pair[0]: material \"stel\" is on no
 * body, so this row applies to no contact (did you mean \"steel\"?)"), the
 * typo that would leave the bodies' contacts to a "*" row unnoticed; once
 * a material, at its first row.  0 for NULL. */
RBS_API uint32_t rbs_scene_warning_count(const rbs_scene *scene);
/** The i-th kept warning, in file order, as rbs_scene_error_get gives
 * errors (the strings live as long as the scene, safe to print);
 * RBS_E_NOT_FOUND past the kept ones. */
RBS_API rbs_status rbs_scene_warning_get(const rbs_scene *scene, uint32_t i,
                                         rbs_scene_error *out);

/** The candidate nearest to word, by the rule of the scene's own "did you
 * mean" suggestions: within max(2, strlen(word) / 3) edits (Levenshtein,
 * over the first 64 bytes of each), else one that word begins when word
 * has 3 bytes or more (an abbreviation); of equally near ones the first
 * in the array.  Returns one of candidates (not a copy), or NULL for none
 * or when word or candidates is NULL.  Pure and thread-safe: front ends
 * use it so that their messages suggest as the library's do. */
RBS_API const char *rbs_scene_suggest(const char *word, const char *const *candidates, size_t n);

/** The world definition the scene asks for: settings from "simulation",
 * capacities that fit the scene exactly (max_bodies, max_materials and
 * max_pairs its counts, each at least 1; max_contacts the scene's or
 * 4*max_bodies+16, so 20 with no bodies), the
 * rest rbs_world_def_init defaults.  RBS_E_SCENE if the scene has errors. */
RBS_API rbs_status rbs_scene_world_def(const rbs_scene *scene, rbs_world_def *out);
/** Add the scene's materials, pairs and bodies, in file order, to an empty
 * world made from rbs_scene_world_def (or larger).  Returns the core's status
 * (e.g. RBS_E_CAPACITY) if the world refuses one; RBS_E_SCENE if the scene
 * has errors. */
RBS_API rbs_status rbs_scene_populate(const rbs_scene *scene, rbs_world *world);
/** rbs_world_create with rbs_scene_world_def, then rbs_scene_populate; on
 * any error no world is left (*out NULL).  Free with rbs_world_destroy. */
RBS_API rbs_status rbs_scene_build(const rbs_scene *scene, rbs_world **out);

/** simulation.steps (after any override); 0 for NULL. */
RBS_API uint64_t rbs_scene_steps(const rbs_scene *scene);
/** simulation.dt, s (after any override); 0 for NULL. */
RBS_API double rbs_scene_dt(const rbs_scene *scene);
/** The scene's "description" ("" if none); owned by the scene. */
RBS_API const char *rbs_scene_description(const rbs_scene *scene);
/** simulation.pause_on_collision (nonzero: pause at impacts); 0 for NULL. */
RBS_API int32_t rbs_scene_pause_on_collision(const rbs_scene *scene);
/** Command-line overrides: steps (0 keeps), dt in s (<= 0 keeps; NaN and
 * infinities are errors), method name (NULL keeps).  Validated like the
 * file's values: on RBS_E_SCENE nothing is changed, the errors are recorded
 * ("command line: --dt: ...") and the scene then builds no world. */
RBS_API rbs_status rbs_scene_override(rbs_scene *scene, uint64_t steps, double dt,
                                      const char *method);

/** Command-line override of simulation.slop (a fraction of the smaller
 * radius of a pair, in (0, 0.1); see rbs_world_def.slop).  Out of range,
 * NaN or infinite is RBS_E_SCENE with the error recorded ("command line:
 * --slop: ..."), the scene unchanged and then building no world.  Start
 * positions were checked against the file's slop when it was loaded. */
RBS_API rbs_status rbs_scene_override_slop(rbs_scene *scene, double slop);

/** A renderer entry of the scene ("renderers": [...]). */
typedef struct rbs_scene_renderer {
    const char *type;  /**< "csv", "json", "sdl", or a registered name */
    const char *json;  /**< the entry as a JSON object text (owned by scene) */
    const char *file;  /**< where it was written, for error messages */
    int32_t line, column;
} rbs_scene_renderer;

/** Number of renderer entries (at most RBS_RENDERERS_MAX); 0 for NULL. */
RBS_API uint32_t rbs_scene_renderer_count(const rbs_scene *scene);
/** The i-th renderer entry, in file order (RBS_E_NOT_FOUND past the end).
 * Strings live as long as the scene.  "type", "path" and "every" are checked
 * for every entry, all keys of "csv", "json" and "sdl" (see
 * scenes/FORMAT.md); other types get their entry unchecked otherwise. */
RBS_API rbs_status rbs_scene_renderer_get(const rbs_scene *scene, uint32_t i,
                                          rbs_scene_renderer *out);

/** The i-th file the scene was read from: the path rbs_scene_load opened
 * (a folder's config.txt), then a text scene's materials and objects files
 * as opened (beside the config); NULL past the last, and for i = 0 of a
 * scene from rbs_scene_parse_json, which read no file.  Lets a caller keep
 * its outputs off the scene's own files.  The string lives as long as the
 * scene. */
RBS_API const char *rbs_scene_source(const rbs_scene *scene, uint32_t i);

/** Write the scene in a format (RBS_SCENE_AUTO: by path, as for loading).
 * JSON: one file.  TEXT: path names the config file; materials.txt and
 * objects.txt are written beside it ("X.materials.txt", "X.objects.txt" if
 * the name is not config.txt).  A missing parent folder (one level) is made
 * (and removed again if the save fails).
 * Every value is written (defaults included) with the fewest digits that
 * read back exactly, so loading the result gives an equal scene and a
 * bit-identical world.  Every file is written to a temporary beside it and
 * renamed into place only when all are complete, so a failed save leaves
 * what was there; a path that names a folder, device or FIFO is refused,
 * and so is a file with no write permission; one that names a symbolic
 * link writes the link's target.  A target that is a file the scene was
 * read from (its own file, a text scene's materials.txt and objects.txt,
 * by any path or link) is refused with RBS_E_OWN_INPUT before anything is
 * written.  RBS_E_SCENE for
 * a scene with errors, RBS_E_IO if a file cannot be written,
 * RBS_E_UNSUPPORTED if a renderer entry has a key the text format cannot
 * spell (empty, 63 bytes or more, containing '.', '[', '=', blanks ..., or
 * a nested key path of 512 bytes or more).  Reads the scene only: safe
 * to call from several threads on one scene. */
RBS_API rbs_status rbs_scene_save(const rbs_scene *scene, const char *path,
                                  rbs_scene_format format);

/** rbs_scene_save, and on RBS_E_IO a message ("cannot write 'PATH':
 * REASON", naming the file that failed: each file is flushed before the next
 * is written, so a full disk is named at the file that filled it), on
 * RBS_E_OWN_INPUT one naming the target and the scene's file it is
 * ("cannot write 'b.json': it is 'a.json', a file this scene was read
 * from; write elsewhere"), on RBS_E_UNSUPPORTED one naming
 * the renderer entry, its key and why the text format cannot write it, in
 * message (message_size bytes,
 * NUL-terminated; "" on success).  message may be NULL. */
RBS_API rbs_status rbs_scene_save_v2(const rbs_scene *scene, const char *path,
                                     rbs_scene_format format, char *message,
                                     size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* RBSIM_SCENE_H */
