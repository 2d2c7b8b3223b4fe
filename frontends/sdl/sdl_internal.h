/*
 * sdl_internal.h - internal interfaces of the SDL front end (not installed).
 *
 * sdl_config.c  parses and validates the scene entry (cJSON) into rbsf__config.
 * sdl_camera.c  camera state: defaults, mounted/scripted cameras, commands.
 * sdl_raster.c  draws one view of a frame into a 32-bit pixel buffer with a
 *               depth buffer (ray casting, per-sphere screen-space boxes).
 * sdl_font.c    a 5x7 bitmap font and the legend.
 * sdl_window.c  the live window on its own thread: SDL video, events, keys,
 *               mouse, redraws when the camera moves.
 * sdl_png.c     writes an SDL surface as a PNG file, every write checked.
 * sdl_renderer.c the renderer class: SDL surfaces, PNG files, contact sheet,
 *               commands.
 *
 * Only sdl_renderer.c, sdl_png.c and sdl_window.c touch SDL; the rest works
 * on plain memory so it can be reasoned about (and benchmarked) without SDL.
 */
#ifndef RBSF_SDL_INTERNAL_H
#define RBSF_SDL_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "rbsim/reel.h"

/** Most views (cameras) per renderer; tiled 2x2. */
#define RBSF__VIEWS_MAX 4
/** Longest accepted image side, pixels. */
#define RBSF__SIDE_MAX 8192
/** Side of a plane's checker cell, m. */
#define RBSF__PLANE_CELL 0.5

/* ------------------------------------------------------------------------- */
/* Configuration (sdl_config.c)                                              */
/* ------------------------------------------------------------------------- */

typedef enum rbsf__camera_mode {
    RBSF__CAMERA_FIXED = 0,   /**< stays where the scene put it (or its path) */
    RBSF__CAMERA_MOUNTED = 1, /**< target = body, position = body + offset */
    RBSF__CAMERA_FREE = 2     /**< moved by commands, keys and the mouse */
} rbsf__camera_mode;

typedef enum rbsf__window_mode {
    RBSF__WINDOW_OFF = 0,
    RBSF__WINDOW_ON = 1,  /**< required: an error if it cannot open */
    RBSF__WINDOW_AUTO = 2 /**< when a display is there */
} rbsf__window_mode;

/** One key of a scripted camera path. */
typedef struct rbsf__path_key {
    double t;           /**< simulated time, s */
    rbs_vec3 position;  /**< m */
    rbs_vec3 target;    /**< m */
} rbsf__path_key;

/** A camera as the scene gives it.  has_* flags mark keys that were given;
 * the others are filled from the first frame (see rbsf__camera_resolve). */
typedef struct rbsf__camera_def {
    rbsf__camera_mode mode;
    int has_position, has_target, has_offset, has_far;
    rbs_vec3 position, target, offset; /**< m */
    rbs_vec3 up;                       /**< unit; default 0,0,1 */
    double fov;                        /**< vertical, degrees, [1e-6, 180) */
    double znear, zfar;                /**< m, 0 < near < far */
    char mount[RBS_NAME_MAX];          /**< body name (mounted mode) */
    uint32_t path_count;
    rbsf__path_key *path;              /**< owned (malloc), t increasing */
} rbsf__camera_def;

/** The whole scene entry, validated. */
typedef struct rbsf__config {
    char *path;                /**< output folder (owned, malloc) or NULL */
    uint32_t every;            /**< as given (the projector keeps frames) */
    uint32_t width, height;    /**< of one view, pixels */
    rbsf__window_mode window;
    int tile;                  /**< views tiled into one image */
    int contact_sheet;         /**< write DIR/contact_sheet.png at finish */
    uint32_t view_count;       /**< 1..RBSF__VIEWS_MAX */
    int camera_given;          /**< 0: default camera for view 0 */
    rbsf__camera_def cameras[RBSF__VIEWS_MAX];
} rbsf__config;

/** Fill defaults: one default camera, 640x480, window auto, no tile,
 * contact sheet on, every 1, no path. */
void rbsf__config_defaults(rbsf__config *config);

/** Parse a scene entry (JSON object text; NULL keeps the defaults) into
 * config (defaults first).  On error returns RBS_E_INVALID (or RBS_E_MEMORY)
 * and writes "key: what is wrong" into err; config is left freeable. */
rbs_status rbsf__config_parse(const char *json, rbsf__config *config,
                              char *err, size_t errlen);

/** Free what the config owns.  Safe on a defaults-filled config. */
void rbsf__config_free(rbsf__config *config);

/* ------------------------------------------------------------------------- */
/* Cameras (sdl_camera.c)                                                    */
/* ------------------------------------------------------------------------- */

/** A live camera. */
typedef struct rbsf__camera {
    const rbsf__camera_def *def; /**< owned by the config */
    int resolved;                /**< defaults filled from a first frame */
    rbs_vec3 position, target;   /**< m, current (fixed/free) */
    rbs_vec3 offset;             /**< m, mounted: position - body */
    rbs_vec3 up;                 /**< unit */
    double fov, znear, zfar;     /**< degrees, m, m */
    rbs_vec3 home_position, home_target, home_offset; /**< for "reset" */
    int32_t mount_index;         /**< cached frame index of the body, -1 */
    int track;                   /**< the default camera: follows the spheres'
                                      bounding-box centre across up */
    rbs_vec3 track_origin;       /**< that centre at the first frame, m */
    int has_last_right;          /**< last_right holds a drawn frame's */
    rbs_vec3 last_right;         /**< unit right vector of the last view */
} rbsf__camera;

/** A camera's pose for one frame: an orthonormal basis and the pinhole. */
typedef struct rbsf__view {
    rbs_vec3 eye;            /**< camera position, m */
    rbs_vec3 right, up, fwd; /**< unit, right-handed: right = fwd x up */
    double focal;            /**< (height/2) / tan(fov/2), pixels */
    double znear, zfar;      /**< m, along fwd */
    uint32_t width, height;  /**< pixels */
} rbsf__view;

/** Start a camera from its definition (unresolved until the first frame).
 * track: nonzero for the default camera (no camera in the scene), which
 * moves with the centre of the spheres' bounding box, across its up vector
 * only, so the bodies stay in view and vertical motion stays visible. */
void rbsf__camera_init(rbsf__camera *camera, const rbsf__camera_def *def,
                       int track);

/** Fill what the scene left out from a frame (default oblique view of the
 * spheres' bounding box; mounted offset from the body's radius) once.
 * Returns RBS_E_INVALID with a message if the mount body is missing or the
 * camera looks along its up vector. */
rbs_status rbsf__camera_resolve(rbsf__camera *camera, const rbs_frame *frame,
                                char *err, size_t errlen);

/** Nonzero if the camera's position or target is placed from the spheres'
 * bounding box at the first frame (a fixed or free camera, no path, without
 * both "position" and "target"). */
int rbsf__camera_from_box(const rbsf__camera_def *def);

/** The view for a frame (path interpolation, mounted body); resolves first.
 * Returns RBS_E_INVALID (message in err) if the camera cannot be placed. */
rbs_status rbsf__camera_view(rbsf__camera *camera, const rbs_frame *frame,
                             uint32_t width, uint32_t height, rbsf__view *out,
                             char *err, size_t errlen);

/** Orbit about the target: yaw about up and pitch (elevation) in degrees;
 * elevation is kept within +-89 degrees.  Free and mounted cameras. */
rbs_status rbsf__camera_orbit(rbsf__camera *camera, double dyaw, double dpitch,
                              char *out, size_t outlen);
/** Move position and target along the view's right and up by dx, dy metres
 * (free cameras). */
rbs_status rbsf__camera_pan(rbsf__camera *camera, double dx, double dy,
                            char *out, size_t outlen);
/** Divide the distance to the target by factor (> 0; 2 = twice as close). */
rbs_status rbsf__camera_zoom(rbsf__camera *camera, double factor, char *out,
                             size_t outlen);
/** Back to where the camera started. */
rbs_status rbsf__camera_reset(rbsf__camera *camera, char *out, size_t outlen);
/** One line describing the camera. */
void rbsf__camera_describe(const rbsf__camera *camera, char *out,
                           size_t outlen);

/* ------------------------------------------------------------------------- */
/* Drawing (sdl_raster.c, sdl_font.c)                                        */
/* ------------------------------------------------------------------------- */

/** Where a view is drawn: a rectangle of 0xAARRGGBB pixels plus scratch. */
typedef struct rbsf__canvas {
    uint32_t *pixels;   /**< top-left pixel of the view */
    size_t pitch;       /**< pixels per row of the underlying image */
    double *depth;       /**< width*height, scratch */
    double *ray_x;      /**< width, scratch */
    double *ray_y;      /**< height, scratch */
} rbsf__canvas;

/** Draw a frame's bodies seen by view into canvas (background, planes,
 * spheres; nearest surface wins).  Allocates nothing. */
void rbsf__raster_frame(const rbsf__canvas *canvas, const rbsf__view *view,
                        const rbs_frame *frame);

/** Draw text (5x7 glyphs: A-Z, a-z shown as capitals, 0-9, space and
 * . : = - + / ( ) %) at (x, y), each glyph pixel scale x scale, clipped to
 * width x height.  Unknown characters draw as a box.  Returns the width
 * drawn, pixels. */
int rbsf__font_draw(uint32_t *pixels, size_t pitch, int width, int height,
                    int x, int y, int scale, const char *text, uint32_t argb);

/** Width of text in pixels at scale. */
int rbsf__font_width(const char *text, int scale);

/** Glyph height in pixels at scale 1. */
#define RBSF__FONT_HEIGHT 7
/** Glyph advance in pixels at scale 1. */
#define RBSF__FONT_ADVANCE 6

/** Darken a rectangle (for text backgrounds), clipped. */
void rbsf__shade_rect(uint32_t *pixels, size_t pitch, int width, int height,
                      int x, int y, int w, int h);

/** The legend: "T=<time> S", "FRAME <n>" (+ " VIEW <k>" when views > 1)
 * and "PAUSED", white on a darkened box at the view's top left. */
void rbsf__legend(uint32_t *pixels, size_t pitch, int width, int height,
                  const rbs_frame *frame, uint32_t view, uint32_t views);

/* ------------------------------------------------------------------------- */
/* Window (sdl_window.c)                                                     */
/* ------------------------------------------------------------------------- */

/** The live window: a thread of its own that owns SDL video, the windows and
 * their events, so the window stays responsive whether or not frames come
 * (e.g. while the run is paused).  Opaque. */
typedef struct rbsf__window rbsf__window;

/** What the window shows and whom it tells. */
typedef struct rbsf__window_def {
    uint32_t image_count;                   /**< windows: 1 tiled, else views */
    uint32_t image_w[RBSF__VIEWS_MAX];      /**< pixels */
    uint32_t image_h[RBSF__VIEWS_MAX];
    uint32_t views, width, height;          /**< views and the size of one */
    uint32_t view_image[RBSF__VIEWS_MAX];   /**< which image shows view v */
    uint32_t view_x[RBSF__VIEWS_MAX], view_y[RBSF__VIEWS_MAX];
    int required;                           /**< "window": true */
    /** The renderer's cameras, shared: every access from either thread is
     * made between rbsf__window_lock and rbsf__window_unlock. */
    rbsf__camera *cameras;
    void (*control)(void *context, const char *command); /**< may be NULL */
    void *control_context;
    const char *label;                      /**< output folder, for the note
                                                 on stderr; must outlive w */
} rbsf__window_def;

/** Reserve the window's memory (no thread, no SDL yet). */
rbs_status rbsf__window_create(const rbsf__window_def *def, rbsf__window **out);
/** Start the thread, which starts SDL video and opens the windows; waits
 * until they are open.  If that fails: RBS_E_RENDERER with the reason in err
 * when the window is required, else RBS_OK and a note on stderr (then
 * rbsf__window_running() is 0 and the renderer goes on without a window). */
rbs_status rbsf__window_start(rbsf__window *w, char *err, size_t errlen);
/** Nonzero while the window thread runs. */
int rbsf__window_running(const rbsf__window *w);
/** Guard the shared cameras. */
void rbsf__window_lock(rbsf__window *w);
void rbsf__window_unlock(rbsf__window *w);
/** Tell the window a camera moved (call with the lock held): it draws the
 * last frame again, e.g. after a command while the run is paused. */
void rbsf__window_moved(rbsf__window *w);
/** Show a drawn frame: copy the images (pixels[i], pitch[i] in pixels) and
 * keep the frame (to draw it again when the camera moves).  May allocate
 * only when a frame has more bodies than any before (RBS_E_MEMORY). */
rbs_status rbsf__window_publish(rbsf__window *w, const uint32_t *const *pixels,
                                const size_t *pitch, const rbs_frame *frame);
/** Stop the thread, close the windows, free everything.  NULL ok. */
void rbsf__window_destroy(rbsf__window *w);

/* ------------------------------------------------------------------------- */
/* PNG files (sdl_png.c)                                                     */
/* ------------------------------------------------------------------------- */

struct SDL_Surface;
struct rbsf_sdl_world_api;

/** A PNG writer: SDL_image encodes into a stream of ours whose every write,
 * and the file's close, is checked (IMG_SavePNG in SDL_image 2.6.3 reports
 * neither).  Opaque; one file at a time, from one thread. */
typedef struct rbsf__png rbsf__png;

/** Reserve a writer and its write buffer (about 64 KiB); NULL when out of
 * memory.  api (borrowed, may be NULL) gives the stopper its open() and
 * write() calls are made in (sdl_renderer.h, rbsf_sdl_world_api). */
rbsf__png *rbsf__png_create(const struct rbsf_sdl_world_api *api);
/** Write surface as the PNG file path (created or truncated).  RBS_OK, or
 * RBS_E_IO with `cannot write "PATH": REASON` in err (the system's reason,
 * e.g. "No space left on device", "File too large") and no file left at
 * path (a regular file), or RBS_E_CLOSED when the stopper ended an open()
 * or write() that blocked (`opening "PATH" given up: ...`, `write to "PATH"
 * given up: ...`).  Allocates nothing itself (SDL_image and libpng do
 * inside). */
rbs_status rbsf__png_save(rbsf__png *w, struct SDL_Surface *surface, const char *path,
                          char *err, size_t errlen);
/** Free a writer.  NULL ok. */
void rbsf__png_destroy(rbsf__png *w);

#endif /* RBSF_SDL_INTERNAL_H */
