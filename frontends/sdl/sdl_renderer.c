/*
 * sdl_renderer.c - the "sdl" renderer class: frames to PNG files (and a
 * window when a display is there), one folder per view or the views tiled.
 *
 * Design notes.
 *  - Headless first.  Drawing is ray casting into SDL surfaces in memory
 *    (sdl_raster.c); surfaces need no SDL_Init, and PNG files are written
 *    by sdl_png.c, which checks every write (a failed one removes the file
 *    and fails the draw or finish with RBS_E_IO).  SDL video is initialised only for a window, only when
 *    DISPLAY or WAYLAND_DISPLAY is set, and only on the window's own thread
 *    (sdl_window.c), started at the first frame; that thread polls the
 *    window's events, so the window answers even while no frame comes.
 *    The cameras are shared with it under its lock.
 *  - Memory.  create() reserves every buffer: the view images, a depth
 *    buffer, ray tables, the contact sheet's thumbnails and the sheet itself,
 *    the file-name buffer and the PNG writer's buffer.  draw() allocates
 *    nothing itself; SDL_image allocates inside IMG_SavePNG_RW (its
 *    libpng/zlib state and a converted copy of the surface).  With a window, the frame is also copied to the
 *    window thread (its buffers are reserved at create too; the copy of the
 *    bodies grows only when a frame has more bodies than any before).
 *    finish() makes one small SDL_Surface header for the contact sheet.
 *  - Contact sheet.  The frame count is unknown in advance, so the sheet
 *    keeps RBSF_SHEET_SLOTS (16) thumbnails of frames 0, s, 2s, ... of the
 *    frames drawn (s = 1 at first).  When all slots are full and frame 16s
 *    comes, every other thumbnail is dropped (decimation by 2) and s doubles;
 *    so the kept frames stay evenly spaced, between 8 and 16 of them.  The
 *    newest frame is kept in one extra slot and shown last if it is not on
 *    the grid already, so the sheet always ends with the final frame.
 *  - A repeated frame (same number as the previous one, as a live view
 *    would get while paused) is neither drawn nor written again.
 */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <SDL.h>

#include "c_locale.h"
#include "sdl_internal.h"
#include "sdl_renderer.h"

/* Contact-sheet grid slots (plus one for the newest frame) and columns. */
#define RBSF_SHEET_SLOTS 16
#define RBSF_SHEET_COLUMNS 4
/* Largest thumbnail width, pixels, and the gap between thumbnails. */
#define RBSF_THUMB_WIDTH 240
#define RBSF_SHEET_GAP 4
/* Height of the caption strip under each thumbnail, pixels. */
#define RBSF_SHEET_CAPTION (RBSF__FONT_HEIGHT + 4)

typedef struct sdl_instance {
    rbsf__config cfg;
    char *dir;     /* output folder (owned) */
    char *made;    /* made[i]: create made the folder dir[0..i) (owned) */
    int view_made[RBSF__VIEWS_MAX]; /* create made DIR/viewK */
    int draw_called; /* draw was called: the folders stay */
    char *file;    /* file-name buffer (owned), file_cap bytes */
    size_t file_cap;
    rbsf__png *png; /* writes every PNG file (owned) */
    void (*control)(void *context, const char *command);
    void *control_context;

    /* Views: images and where each view sits in its image. */
    uint32_t views;
    rbsf__camera cameras[RBSF__VIEWS_MAX];
    SDL_Surface *images[RBSF__VIEWS_MAX]; /* tiled: images[0] only */
    uint32_t image_count;
    uint32_t layout_cols, layout_rows; /* views arranged cols x rows */
    uint32_t view_image[RBSF__VIEWS_MAX];
    uint32_t view_x[RBSF__VIEWS_MAX], view_y[RBSF__VIEWS_MAX];
    double *depth;
    double *ray_x, *ray_y;

    /* Contact sheet. */
    uint32_t thumb_w, thumb_h;
    uint32_t *thumbs; /* (RBSF_SHEET_SLOTS + 1) * thumb_w * thumb_h */
    uint64_t thumb_number[RBSF_SHEET_SLOTS + 1];
    double thumb_time[RBSF_SHEET_SLOTS + 1];
    uint32_t thumb_count;
    uint64_t stride, seen;
    uint32_t *sheet; /* sheet_w * sheet_h pixels */
    uint32_t sheet_w, sheet_h;

    /* Frames. */
    int drawn_any;
    uint64_t last_number;

    /* Window (its own thread, see sdl_window.c); NULL when there is none. */
    int want_window; /* decided by prepare() */
    rbsf__window *window;
    int window_started;
    uint32_t selected; /* view for commands */
} sdl_instance;

/* ------------------------------------------------------------------------- */
/* Helpers                                                                   */
/* ------------------------------------------------------------------------- */

/* Write a message (the key and what is wrong; the projector or the command
 * line puts the scene's place and the renderer's name in front). */
static rbs_status say(char *err, size_t errlen, rbs_status st, const char *what)
{
    if (err != NULL && errlen > 0) snprintf(err, errlen, "%s", what);
    return st;
}

/* strerror_r into why (n bytes), "errno N" if it has no text. */
static void reason(int e, char *why, size_t n)
{
    if (strerror_r(e, why, n) != 0) snprintf(why, n, "errno %d", e);
}

/* The longest name the renderer puts after its folder's path: "/viewK"
 * (several views, not tiled), then "/frame_" with a frame number of up to
 * 20 digits and ".png" ("/contact_sheet.png" is shorter). */
static size_t longest_file(const rbsf__config *cfg)
{
    size_t n = strlen("/frame_") + 20 + strlen(".png");
    if (cfg->view_count > 1 && !cfg->tile) n += strlen("/view0");
    return n;
}

/* Whether mkdir -p of path, and the files the renderer writes in it (names
 * up to tail bytes after path), can work, found before anything is kept:
 *  - the path with the files' names fits the system's limit (PATH_MAX), and
 *    each of its names the file system's (NAME_MAX of the folder it is in);
 *  - each folder on the way that exists is a folder;
 *  - the first that does not is made and removed again: that proves its
 *    parent takes a new folder where access() alone would not (root may
 *    "write" in /proc and /sys, which take no folder), and the folders below
 *    it are made in it;
 *  - a folder that exists takes a file: a ".rbsim-XXXXXX" made and removed.
 * path is restored.  0, or -1 with the reason in err. */
static int folder_can_be(char *path, size_t tail, char *err, size_t errlen);

/* path[up..end) is a ".." after a folder that is still to be made (mkdir -p
 * makes it a real folder, so "new/.." is the folder new is made in): check
 * the path with that name, the "." names after it and the ".." taken out. */
static int folder_can_be_up(const char *path, size_t up, size_t end, size_t tail,
                            char *err, size_t errlen)
{
    size_t n = strlen(path), ps = up, pe;
    char *reduced;
    int rc;
    for (;;) { /* the name before: skip slashes, then "." names */
        while (ps > 0 && path[ps - 1] == '/') ps--;
        pe = ps;
        while (ps > 0 && path[ps - 1] != '/') ps--;
        if (!(pe - ps == 1 && path[ps] == '.')) break;
    }
    reduced = (char *)malloc(n + 2);
    if (reduced == NULL) {
        say(err, errlen, RBS_E_MEMORY, "out of memory");
        return -1;
    }
    memcpy(reduced, path, ps);
    if (ps == 0 && path[end] == '/') end++; /* stay relative */
    strcpy(reduced + ps, path + end);
    if (reduced[0] == '\0') strcpy(reduced, ".");
    rc = folder_can_be(reduced, tail, err, errlen);
    free(reduced);
    return rc;
}

static int folder_can_be(char *path, size_t tail, char *err, size_t errlen)
{
    size_t i, start = 0, n = strlen(path);
    long name_max = pathconf(path[0] == '/' ? "/" : ".", _PC_NAME_MAX);
    int missing = 0; /* a folder is missing: the rest are only measured */
    char msg[600], why[128];
#ifdef PATH_MAX
    if (n + tail >= (size_t)PATH_MAX) {
        snprintf(msg, sizeof msg,
                 "path: too long: %lu bytes, and the files' names in it add up to "
                 "%lu more, past the system's limit of %d bytes for a path",
                 (unsigned long)n, (unsigned long)tail, PATH_MAX - 1);
        say(err, errlen, RBS_E_IO, msg);
        return -1;
    }
#endif
    for (i = 0; i <= n; i++) {
        size_t len;
        char c;
        struct stat sb;
        if (path[i] != '/' && path[i] != '\0') continue;
        len = i - start;
        if (len == 0) { /* the root, or a doubled or trailing slash */
            start = i + 1;
            continue;
        }
        if (name_max > 0 && len > (size_t)name_max) {
            snprintf(msg, sizeof msg,
                     "path: the name \"%.40s%s\" is %lu bytes long, longer than the "
                     "file system takes (%ld bytes)",
                     path + start, len > 40 ? "..." : "", (unsigned long)len, name_max);
            say(err, errlen, RBS_E_IO, msg);
            return -1;
        }
        if (missing && len == 2 && path[start] == '.' && path[start + 1] == '.')
            return folder_can_be_up(path, start, i, tail, err, errlen);
        start = i + 1;
        if (missing) continue;
        c = path[i];
        path[i] = '\0';
        if (stat(path, &sb) == 0) {
            long m;
            if (!S_ISDIR(sb.st_mode)) {
                snprintf(msg, sizeof msg, "path: \"%s\" exists and is not a folder", path);
                path[i] = c;
                say(err, errlen, RBS_E_IO, msg);
                return -1;
            }
            m = pathconf(path, _PC_NAME_MAX);
            if (m > 0) name_max = m;
            path[i] = c;
            continue;
        }
        if (errno == ENOENT && mkdir(path, 0700) == 0) {
            /* the first missing folder: it can be made (and is not kept) */
            if (rmdir(path) != 0) {
                reason(errno, why, sizeof why);
                snprintf(msg, sizeof msg,
                         "path: cannot remove \"%s\" again (made to test the path): %s",
                         path, why);
                path[i] = c;
                say(err, errlen, RBS_E_IO, msg);
                return -1;
            }
            path[i] = c;
            missing = 1;
            continue;
        }
        reason(errno, why, sizeof why);
        snprintf(msg, sizeof msg, "path: cannot create folder \"%s\": %s", path, why);
        path[i] = c;
        say(err, errlen, RBS_E_IO, msg);
        return -1;
    }
    if (!missing) {
        /* The folder exists: does it take a file? */
        char *probe = (char *)malloc(n + 16);
        int fd;
        if (probe == NULL) {
            say(err, errlen, RBS_E_MEMORY, "out of memory");
            return -1;
        }
        snprintf(probe, n + 16, "%s/.rbsim-XXXXXX", path);
        fd = mkstemp(probe);
        if (fd < 0) {
            reason(errno, why, sizeof why);
            snprintf(msg, sizeof msg, "path: cannot write in folder \"%s\": %s", path, why);
            free(probe);
            say(err, errlen, RBS_E_IO, msg);
            return -1;
        }
        close(fd);
        unlink(probe);
        free(probe);
    }
    return 0;
}

/* mkdir -p.  made (strlen(path) + 1 flags, all 0 on entry) marks each
 * folder this call made: made[i] for the folder path[0..i); unmake_dirs
 * removes them again. */
static int make_dirs(char *path, char *made, char *err, size_t errlen)
{
    size_t i, n = strlen(path);
    for (i = 1; i <= n; i++) {
        if (path[i] == '/' || path[i] == '\0') {
            char c = path[i];
            struct stat sb;
            if (path[i - 1] == '/') continue; /* a doubled or trailing slash */
            path[i] = '\0';
            if (mkdir(path, 0777) == 0) {
                made[i] = 1;
            } else if (errno != EEXIST) {
                char why[128];
                char msg[600];
                reason(errno, why, sizeof why);
                snprintf(msg, sizeof msg, "path: cannot create folder \"%s\": %s", path, why);
                path[i] = c;
                say(err, errlen, RBS_E_IO, msg);
                return -1;
            }
            if (stat(path, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
                char msg[600];
                snprintf(msg, sizeof msg, "path: \"%s\" exists and is not a folder", path);
                path[i] = c;
                say(err, errlen, RBS_E_IO, msg);
                return -1;
            }
            path[i] = c;
        }
    }
    return 0;
}

/* Remove the folders make_dirs marked in made, deepest first.  Only empty
 * ones go (rmdir): a file put there since stays, with its folders. */
static void unmake_dirs(char *path, char *made)
{
    size_t i = strlen(path) + 1;
    while (i-- > 0) {
        if (made[i]) {
            char c = path[i];
            path[i] = '\0';
            rmdir(path);
            path[i] = c;
            made[i] = 0;
        }
    }
}

static uint32_t *image_pixels(SDL_Surface *s) { return (uint32_t *)s->pixels; }
static size_t image_pitch(SDL_Surface *s) { return (size_t)s->pitch / 4; }

/* Top-left pixel of view v and its row pitch in pixels. */
static uint32_t *view_pixels(const sdl_instance *r, uint32_t v, size_t *pitch)
{
    SDL_Surface *s = r->images[r->view_image[v]];
    *pitch = image_pitch(s);
    return image_pixels(s) + (size_t)r->view_y[v] * *pitch + r->view_x[v];
}

static void destroy(void *instance);

/* ------------------------------------------------------------------------- */
/* create                                                                    */
/* ------------------------------------------------------------------------- */

static int has_display(void)
{
    const char *x = getenv("DISPLAY"), *w = getenv("WAYLAND_DISPLAY");
    return (x != NULL && x[0] != '\0') || (w != NULL && w[0] != '\0');
}

/* Parse and validate a configuration into r (no files, no SDL): the part
 * of create() that check() shares. */
static rbs_status prepare(sdl_instance *r, const rbs_renderer_config *config,
                          char *err, size_t errlen)
{
    char msg[512];
    rbs_status st;
    const char *path;
    /* The callback fields exist only in configs that are large enough. */
    if (config->struct_size >= offsetof(rbs_renderer_config, control_context) +
                                   sizeof(void *)) {
        r->control = config->control;
        r->control_context = config->control_context;
    }

    /* Parse and validate the scene entry. */
    st = rbsf__config_parse(config->json, &r->cfg, msg, sizeof msg);
    if (st != RBS_OK) return say(err, errlen, st, msg);
    path = config->path != NULL && config->path[0] != '\0' ? config->path : r->cfg.path;
    if (path == NULL)
        return say(err, errlen, RBS_E_INVALID,
                   "path: missing (the folder the PNG files go to)");
    if (strcmp(path, "-") == 0)
        return say(err, errlen, RBS_E_INVALID,
                   "path: \"-\" would be standard output, and PNG files go to a "
                   "folder; for a folder named \"-\" write \"./-\"");
    r->dir = (char *)malloc(strlen(path) + 1);
    r->file_cap = strlen(path) + 64;
    r->file = (char *)malloc(r->file_cap);
    if (r->dir == NULL || r->file == NULL)
        return say(err, errlen, RBS_E_MEMORY, "out of memory");
    strcpy(r->dir, path);
    if (folder_can_be(r->dir, longest_file(&r->cfg), err, errlen) != 0)
        return RBS_E_IO;
    if (!r->cfg.tile && r->cfg.view_count > 1) {
        /* DIR/viewK: each is a folder if it is there */
        uint32_t v;
        for (v = 0; v < r->cfg.view_count; v++) {
            struct stat sb;
            snprintf(r->file, r->file_cap, "%s/view%u", r->dir, v);
            if (stat(r->file, &sb) == 0 && !S_ISDIR(sb.st_mode)) {
                snprintf(msg, sizeof msg, "path: \"%s\" exists and is not a folder",
                         r->file);
                return say(err, errlen, RBS_E_IO, msg);
            }
        }
    }

    /* Window: decided here, opened at the first draw (on its own thread). */
    if (r->cfg.window == RBSF__WINDOW_ON && !has_display())
        return say(err, errlen, RBS_E_RENDERER,
                   "window: true, but there is no display (DISPLAY and "
                   "WAYLAND_DISPLAY are unset); use \"auto\" or false");
    r->want_window = r->cfg.window != RBSF__WINDOW_OFF && has_display();
    return RBS_OK;
}

/* Place each camera that is placed from the spheres' bounding box as the
 * first frame, the world's start, will place it, and refuse one with no
 * usable view (spheres near +-1e100 m put it beyond 1e100 m) before the run,
 * naming the key.  (The run started and stopped at frame 0 with exit 4, and
 * "rbsim check" passed the scene: a probe of session 46.) */
static rbs_status cameras_fit(const sdl_instance *r, const rbsf_sdl_world_api *api,
                              const rbs_world *world, char *err, size_t errlen)
{
    rbs_state_view sv;
    rbs_frame frame;
    rbsf__camera cam;
    rbsf__view view;
    char why[400], msg[440];
    uint32_t v, cap;
    rbs_status st = RBS_OK;
    /* (without the library's functions, or a world, the first frame checks) */
    if (api == NULL || api->state == NULL || api->capture == NULL || world == NULL)
        return RBS_OK;
    if ((st = api->state(world, &sv)) != RBS_OK)
        return say(err, errlen, st, "cannot read the world's start");
    cap = sv.slots > 0 ? sv.slots : 1;
    memset(&frame, 0, sizeof frame);
    frame.bodies = (rbs_frame_body *)calloc(cap, sizeof *frame.bodies);
    if (frame.bodies == NULL) return say(err, errlen, RBS_E_MEMORY, "out of memory");
    if ((st = api->capture(world, &frame, cap)) != RBS_OK) {
        free(frame.bodies);
        return say(err, errlen, st, "cannot read the world's start");
    }
    for (v = 0; v < r->cfg.view_count && st == RBS_OK; v++) {
        const rbsf__camera_def *def = &r->cfg.cameras[v];
        if (!rbsf__camera_from_box(def)) continue;
        rbsf__camera_init(&cam, def, !r->cfg.camera_given);
        if (rbsf__camera_view(&cam, &frame, r->cfg.width, r->cfg.height, &view, why,
                              sizeof why) != RBS_OK) {
            snprintf(msg, sizeof msg, "view %u: %s", v, why);
            st = say(err, errlen, RBS_E_INVALID, msg);
        }
    }
    free(frame.bodies);
    return st;
}

static rbs_status check(void *context, const rbs_renderer_config *config,
                        const rbs_world *world, char *err, size_t errlen)
{
    sdl_instance *r;
    rbs_status st;
    if (config == NULL)
        return say(err, errlen, RBS_E_INVALID, "config: NULL");
    r = (sdl_instance *)calloc(1, sizeof *r);
    if (r == NULL) return say(err, errlen, RBS_E_MEMORY, "out of memory");
    st = prepare(r, config, err, errlen);
    if (st == RBS_OK)
        st = cameras_fit(r, (const rbsf_sdl_world_api *)context, world, err, errlen);
    destroy(r);
    return st;
}

static rbs_status create(void *context, const rbs_renderer_config *config,
                         const rbs_world *world, void **out, char *err,
                         size_t errlen)
{
    sdl_instance *r;
    char msg[512];
    rbs_status st;
    uint32_t v, W = 0, H = 0;
    (void)world;
    if (out == NULL) return RBS_E_INVALID;
    *out = NULL;
    if (config == NULL)
        return say(err, errlen, RBS_E_INVALID, "config: NULL");
    r = (sdl_instance *)calloc(1, sizeof *r);
    if (r == NULL) return say(err, errlen, RBS_E_MEMORY, "out of memory");
    if ((st = prepare(r, config, err, errlen)) != RBS_OK) {
        destroy(r);
        return st;
    }

    /* Views and their images. */
    W = r->cfg.width;
    H = r->cfg.height;
    r->views = r->cfg.view_count;
    r->layout_cols = r->views >= 2 ? 2 : 1;
    r->layout_rows = r->views >= 3 ? 2 : 1;
    for (v = 0; v < r->views; v++)
        rbsf__camera_init(&r->cameras[v], &r->cfg.cameras[v], !r->cfg.camera_given);
    if (r->cfg.tile) {
        r->image_count = 1;
        r->images[0] = SDL_CreateRGBSurfaceWithFormat(
            0, (int)(W * r->layout_cols), (int)(H * r->layout_rows), 32,
            SDL_PIXELFORMAT_ARGB8888);
        if (r->images[0] == NULL) goto nomem;
        SDL_FillRect(r->images[0], NULL, 0xff000000u);
        for (v = 0; v < r->views; v++) {
            r->view_image[v] = 0;
            r->view_x[v] = (v % 2) * W;
            r->view_y[v] = (v / 2) * H;
        }
    } else {
        r->image_count = r->views;
        for (v = 0; v < r->views; v++) {
            r->images[v] = SDL_CreateRGBSurfaceWithFormat(
                0, (int)W, (int)H, 32, SDL_PIXELFORMAT_ARGB8888);
            if (r->images[v] == NULL) goto nomem;
            r->view_image[v] = v;
        }
    }
    r->depth = (double *)malloc((size_t)W * H * sizeof *r->depth);
    r->ray_x = (double *)malloc((size_t)W * sizeof *r->ray_x);
    r->ray_y = (double *)malloc((size_t)H * sizeof *r->ray_y);
    r->png = rbsf__png_create((const rbsf_sdl_world_api *)context);
    if (r->depth == NULL || r->ray_x == NULL || r->ray_y == NULL || r->png == NULL)
        goto nomem;

    /* Contact sheet: thumbnails of the views laid out cols x rows. */
    if (r->cfg.contact_sheet) {
        uint64_t cw = (uint64_t)W * r->layout_cols, ch = (uint64_t)H * r->layout_rows;
        uint32_t rows = (RBSF_SHEET_SLOTS + 1 + RBSF_SHEET_COLUMNS - 1) / RBSF_SHEET_COLUMNS;
        r->thumb_w = (uint32_t)(cw < RBSF_THUMB_WIDTH ? cw : RBSF_THUMB_WIDTH);
        r->thumb_h = (uint32_t)((ch * r->thumb_w + cw / 2) / cw);
        if (r->thumb_h < 1) r->thumb_h = 1;
        r->thumbs = (uint32_t *)malloc((size_t)(RBSF_SHEET_SLOTS + 1) * r->thumb_w *
                                       r->thumb_h * sizeof *r->thumbs);
        r->sheet_w = RBSF_SHEET_COLUMNS * (r->thumb_w + RBSF_SHEET_GAP) + RBSF_SHEET_GAP;
        r->sheet_h = rows * (r->thumb_h + RBSF_SHEET_CAPTION + RBSF_SHEET_GAP) + RBSF_SHEET_GAP;
        r->sheet = (uint32_t *)malloc((size_t)r->sheet_w * r->sheet_h * sizeof *r->sheet);
        if (r->thumbs == NULL || r->sheet == NULL) goto nomem;
        r->stride = 1;
    }

    /* The window's memory (its thread starts at the first frame). */
    if (r->want_window) {
        rbsf__window_def wd;
        memset(&wd, 0, sizeof wd);
        wd.image_count = r->image_count;
        for (v = 0; v < r->image_count; v++) {
            wd.image_w[v] = (uint32_t)r->images[v]->w;
            wd.image_h[v] = (uint32_t)r->images[v]->h;
        }
        wd.views = r->views;
        wd.width = W;
        wd.height = H;
        for (v = 0; v < r->views; v++) {
            wd.view_image[v] = r->view_image[v];
            wd.view_x[v] = r->view_x[v];
            wd.view_y[v] = r->view_y[v];
        }
        wd.required = r->cfg.window == RBSF__WINDOW_ON;
        wd.cameras = r->cameras;
        wd.control = r->control;
        wd.control_context = r->control_context;
        wd.label = r->dir;
        if (rbsf__window_create(&wd, &r->window) != RBS_OK) goto nomem;
    }

    /* Output folders (a failure removes those made: destroy). */
    r->made = (char *)calloc(strlen(r->dir) + 1, 1);
    if (r->made == NULL) goto nomem;
    if (make_dirs(r->dir, r->made, err, errlen) != 0) {
        destroy(r);
        return RBS_E_IO;
    }
    if (!r->cfg.tile && r->views > 1) {
        for (v = 0; v < r->views; v++) {
            struct stat sb;
            snprintf(r->file, r->file_cap, "%s/view%u", r->dir, v);
            int e = mkdir(r->file, 0777) == 0 ? 0 : errno;
            if (e == 0) {
                r->view_made[v] = 1;
            } else if (e != EEXIST || stat(r->file, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
                char why[128];
                if (e == EEXIST)
                    snprintf(msg, sizeof msg, "path: \"%s\" exists and is not a folder",
                             r->file);
                else {
                    reason(e, why, sizeof why);
                    snprintf(msg, sizeof msg, "path: cannot create folder \"%s\": %s",
                             r->file, why);
                }
                say(err, errlen, RBS_E_IO, msg);
                destroy(r);
                return RBS_E_IO;
            }
        }
    }
    *out = r;
    return RBS_OK;

nomem:
    snprintf(msg, sizeof msg, "out of memory for %u view%s of %ux%u pixels",
             r->views, r->views > 1 ? "s" : "", W, H);
    say(err, errlen, RBS_E_MEMORY, msg);
    destroy(r);
    return RBS_E_MEMORY;
}

/* ------------------------------------------------------------------------- */
/* Cameras are shared with the window thread                                 */
/* ------------------------------------------------------------------------- */

static void cameras_lock(sdl_instance *r)
{
    if (r->window != NULL) rbsf__window_lock(r->window);
}

static void cameras_unlock(sdl_instance *r)
{
    if (r->window != NULL) rbsf__window_unlock(r->window);
}

/* ------------------------------------------------------------------------- */
/* Contact sheet                                                             */
/* ------------------------------------------------------------------------- */

/* Box-filter the views into thumbnail slot k. */
static void make_thumb(sdl_instance *r, uint32_t k)
{
    uint32_t tw = r->thumb_w, th = r->thumb_h, v, W = r->cfg.width, H = r->cfg.height;
    uint32_t *dst = r->thumbs + (size_t)k * tw * th;
    uint64_t cw = (uint64_t)W * r->layout_cols, ch = (uint64_t)H * r->layout_rows;
    uint32_t tx, ty;
    for (ty = 0; ty < th; ty++)
        for (tx = 0; tx < tw; tx++) dst[(size_t)ty * tw + tx] = 0xff000000u;
    for (v = 0; v < r->views; v++) {
        size_t pitch;
        const uint32_t *src = view_pixels(r, v, &pitch);
        uint64_t ox = (uint64_t)(v % 2) * W, oy = (uint64_t)(v / 2) * H;
        if (r->layout_cols == 1) ox = 0;
        for (ty = 0; ty < th; ty++) {
            /* Composite rows [y0, y1) map to thumbnail row ty. */
            uint64_t y0 = (uint64_t)ty * ch / th, y1 = ((uint64_t)ty + 1) * ch / th;
            if (y1 <= y0) y1 = y0 + 1;
            if (y1 <= oy || y0 >= oy + H) continue;
            for (tx = 0; tx < tw; tx++) {
                uint64_t x0 = (uint64_t)tx * cw / tw, x1 = ((uint64_t)tx + 1) * cw / tw;
                uint64_t sr = 0, sg = 0, sb = 0, n = 0, x, y;
                if (x1 <= x0) x1 = x0 + 1;
                if (x1 <= ox || x0 >= ox + W) continue;
                for (y = y0 > oy ? y0 : oy; y < y1 && y < oy + H; y++) {
                    const uint32_t *row = src + (size_t)(y - oy) * pitch;
                    for (x = x0 > ox ? x0 : ox; x < x1 && x < ox + W; x++) {
                        uint32_t p = row[x - ox];
                        sr += (p >> 16) & 0xff;
                        sg += (p >> 8) & 0xff;
                        sb += p & 0xff;
                        n++;
                    }
                }
                if (n > 0)
                    dst[(size_t)ty * tw + tx] =
                        0xff000000u | (uint32_t)((sr + n / 2) / n) << 16 |
                        (uint32_t)((sg + n / 2) / n) << 8 | (uint32_t)((sb + n / 2) / n);
            }
        }
    }
}

/* Keep frames 0, s, 2s, ... of those drawn; decimate by 2 when full. */
static void sheet_add(sdl_instance *r, uint64_t number, double time)
{
    uint64_t k = r->seen++;
    size_t size = (size_t)r->thumb_w * r->thumb_h;
    if (k % r->stride == 0 && r->thumb_count == RBSF_SHEET_SLOTS) {
        uint32_t i;
        for (i = 0; i < RBSF_SHEET_SLOTS / 2; i++) {
            memmove(r->thumbs + i * size, r->thumbs + 2 * i * size, size * sizeof *r->thumbs);
            r->thumb_number[i] = r->thumb_number[2 * i];
            r->thumb_time[i] = r->thumb_time[2 * i];
        }
        r->thumb_count = RBSF_SHEET_SLOTS / 2;
        r->stride *= 2;
    }
    if (k % r->stride == 0) {
        make_thumb(r, r->thumb_count);
        r->thumb_time[r->thumb_count] = time;
        r->thumb_number[r->thumb_count++] = number;
    } else {
        make_thumb(r, RBSF_SHEET_SLOTS); /* the newest, shown last */
        r->thumb_time[RBSF_SHEET_SLOTS] = time;
        r->thumb_number[RBSF_SHEET_SLOTS] = number;
    }
}

static rbs_status sheet_write(sdl_instance *r, char *err, size_t errlen)
{
    uint32_t n = r->thumb_count, i, x, y, rows, h;
    size_t size = (size_t)r->thumb_w * r->thumb_h;
    int newest = r->seen > 0 && (r->seen - 1) % r->stride != 0;
    SDL_Surface *s;
    rbs_status st;
    if (newest) n++;
    rows = (n + RBSF_SHEET_COLUMNS - 1) / RBSF_SHEET_COLUMNS;
    h = rows * (r->thumb_h + RBSF_SHEET_CAPTION + RBSF_SHEET_GAP) + RBSF_SHEET_GAP;
    for (i = 0; i < r->sheet_w * h; i++) r->sheet[i] = 0xff202020u;
    for (i = 0; i < n; i++) {
        uint32_t slot = newest && i == n - 1 ? RBSF_SHEET_SLOTS : i;
        uint32_t x0 = RBSF_SHEET_GAP + (i % RBSF_SHEET_COLUMNS) * (r->thumb_w + RBSF_SHEET_GAP);
        uint32_t y0 = RBSF_SHEET_GAP + (i / RBSF_SHEET_COLUMNS) *
                                           (r->thumb_h + RBSF_SHEET_CAPTION + RBSF_SHEET_GAP);
        const uint32_t *t = r->thumbs + slot * size;
        char label[64];
        uint32_t *corner = r->sheet + (size_t)y0 * r->sheet_w + x0;
        for (y = 0; y < r->thumb_h; y++)
            for (x = 0; x < r->thumb_w; x++)
                corner[(size_t)y * r->sheet_w + x] = t[(size_t)y * r->thumb_w + x];
        /* Caption under the thumbnail: frame number and time. */
        snprintf(label, sizeof label, "%llu T=%.3f",
                 (unsigned long long)r->thumb_number[slot], r->thumb_time[slot]);
        rbsf__font_draw(corner + (size_t)(r->thumb_h + 2) * r->sheet_w, r->sheet_w,
                        (int)r->thumb_w, RBSF__FONT_HEIGHT, 0, 0, 1, label, 0xffe0e0e0u);
    }
    s = SDL_CreateRGBSurfaceWithFormatFrom(r->sheet, (int)r->sheet_w, (int)h, 32,
                                           (int)(r->sheet_w * 4), SDL_PIXELFORMAT_ARGB8888);
    snprintf(r->file, r->file_cap, "%s/contact_sheet.png", r->dir);
    if (s == NULL) {
        char msg[600];
        snprintf(msg, sizeof msg, "cannot write \"%s\": %s", r->file, SDL_GetError());
        return say(err, errlen, RBS_E_IO, msg);
    }
    st = rbsf__png_save(r->png, s, r->file, err, errlen);
    SDL_FreeSurface(s);
    return st;
}

/* ------------------------------------------------------------------------- */
/* draw / finish / destroy                                                   */
/* ------------------------------------------------------------------------- */

static rbs_status draw(void *instance, const rbs_frame *frame, char *err, size_t errlen)
{
    sdl_instance *r = (sdl_instance *)instance;
    uint32_t v;
    int repeat;
    rbs_status st;
    if (r == NULL || frame == NULL)
        return say(err, errlen, RBS_E_INVALID, "draw: NULL instance or frame");
    if (frame->body_count > 0 && frame->bodies == NULL)
        return say(err, errlen, RBS_E_INVALID, "frame: bodies is NULL");
    repeat = r->drawn_any && frame->number == r->last_number;
    r->draw_called = 1;

    /* The window opens at the first frame, on its own thread. */
    if (r->window != NULL && !r->window_started) {
        r->window_started = 1;
        if ((st = rbsf__window_start(r->window, err, errlen)) != RBS_OK) return st;
        if (!rbsf__window_running(r->window)) {
            rbsf__window_destroy(r->window); /* "auto" and no display after all */
            r->window = NULL;
        }
    }
    /* A frame seen before (a live view's repeat) is neither drawn nor
     * written again; the window thread redraws on its own. */
    if (repeat) return RBS_OK;

    /* Place the cameras (shared with the window thread), then draw. */
    for (v = 0; v < r->views; v++) {
        rbsf__view view;
        rbsf__canvas cv;
        char msg[400];
        cameras_lock(r);
        st = rbsf__camera_view(&r->cameras[v], frame, r->cfg.width, r->cfg.height, &view,
                               msg, sizeof msg);
        cameras_unlock(r);
        if (st != RBS_OK) {
            char full[480];
            if (r->views > 1)
                snprintf(full, sizeof full, "views[%u].%s", v, msg);
            else
                snprintf(full, sizeof full, "%s%s", r->cfg.camera_given ? "camera." : "", msg);
            return say(err, errlen, RBS_E_INVALID, full);
        }
        cv.pixels = view_pixels(r, v, &cv.pitch);
        cv.depth = r->depth;
        cv.ray_x = r->ray_x;
        cv.ray_y = r->ray_y;
        rbsf__raster_frame(&cv, &view, frame);
        rbsf__legend(cv.pixels, cv.pitch, (int)r->cfg.width, (int)r->cfg.height, frame, v,
                     r->views);
    }
    if (r->window != NULL) {
        const uint32_t *px[RBSF__VIEWS_MAX];
        size_t pitch[RBSF__VIEWS_MAX];
        for (v = 0; v < r->image_count; v++) {
            px[v] = image_pixels(r->images[v]);
            pitch[v] = image_pitch(r->images[v]);
        }
        if (rbsf__window_publish(r->window, px, pitch, frame) != RBS_OK)
            return say(err, errlen, RBS_E_MEMORY,
                       "window: out of memory for the shown frame's bodies");
    }
    r->drawn_any = 1;
    r->last_number = frame->number;

    /* Write the PNG files. */
    for (v = 0; v < r->image_count; v++) {
        if (r->image_count > 1)
            snprintf(r->file, r->file_cap, "%s/view%u/frame_%06llu.png", r->dir, v,
                     (unsigned long long)frame->number);
        else
            snprintf(r->file, r->file_cap, "%s/frame_%06llu.png", r->dir,
                     (unsigned long long)frame->number);
        if ((st = rbsf__png_save(r->png, r->images[v], r->file, err, errlen)) != RBS_OK)
            return st;
    }
    if (r->cfg.contact_sheet) sheet_add(r, frame->number, frame->time);
    return RBS_OK;
}

static rbs_status finish(void *instance, char *err, size_t errlen)
{
    sdl_instance *r = (sdl_instance *)instance;
    if (r == NULL) return RBS_E_INVALID;
    /* The sheet shows the frames whose files were written (seen counts
     * them): none, as when the first file could not be written, no sheet. */
    if (r->cfg.contact_sheet && r->seen > 0) return sheet_write(r, err, errlen);
    return RBS_OK;
}

static void destroy(void *instance)
{
    sdl_instance *r = (sdl_instance *)instance;
    uint32_t i;
    if (r == NULL) return;
    rbsf__window_destroy(r->window); /* first: its thread uses the cameras */
    /* Never drawn (create failed, or the run was rejected after it): the
     * folders create made go again, empty, so a rejected run leaves none. */
    if (!r->draw_called && r->made != NULL) {
        for (i = 0; i < RBSF__VIEWS_MAX; i++) {
            if (!r->view_made[i]) continue;
            snprintf(r->file, r->file_cap, "%s/view%u", r->dir, i);
            rmdir(r->file);
        }
        unmake_dirs(r->dir, r->made);
    }
    for (i = 0; i < RBSF__VIEWS_MAX; i++)
        if (r->images[i] != NULL) SDL_FreeSurface(r->images[i]);
    free(r->depth);
    free(r->ray_x);
    free(r->ray_y);
    free(r->thumbs);
    free(r->sheet);
    free(r->dir);
    free(r->made);
    free(r->file);
    rbsf__png_destroy(r->png);
    rbsf__config_free(&r->cfg);
    free(r);
}

/* ------------------------------------------------------------------------- */
/* command                                                                   */
/* ------------------------------------------------------------------------- */

/* Parse exactly n numbers after the command word by the rule the
 * projector's "speed" uses: each a whole word strtod reads in the "C" locale,
 * decimal only (not "0x2", "inf", "nan", "1,5"), finite and in range.
 * Returns 0 on success, -1 when the count of words is not n, and 1 when a
 * word is not such a number: *bad and *bad_len then name it.  (strtod took
 * "zoom 0x2" as 2 and "orbit inf 0" as infinity: a probe of session 46.) */
static int numbers(const char *s, double *out, int n, const char **bad, int *bad_len)
{
    int i;
    for (i = 0;; i++) {
        const char *w;
        char word[64], *end;
        size_t len;
        double x;
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
        if (*s == '\0') return i == n ? 0 : -1;
        w = s;
        while (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\r' && *s != '\n') s++;
        len = (size_t)(s - w);
        if (i >= n) return -1;
        *bad = w;
        *bad_len = len > 200 ? 200 : (int)len;
        if (len >= sizeof word) return 1;
        memcpy(word, w, len);
        word[len] = '\0';
        errno = 0;
        x = strtod(word, &end);
        if (end == word || *end != '\0' || errno != 0 || !isfinite(x) ||
            strpbrk(word, "xXpP") != NULL)
            return 1;
        out[i] = x;
    }
}

/* Parse exactly one view index after "view": a word of digits only (not
 * "1.0", "-0", "+1", "1e0": a probe took "view 1.0" and "view -0" as whole
 * numbers), its value saturated at UINT32_MAX (out of any range).  Returns
 * 0, -1 or 1 with *bad as numbers() does. */
static int view_index(const char *s, uint32_t *out, const char **bad, int *bad_len)
{
    const char *w;
    size_t len, k;
    uint64_t v = 0;
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
    if (*s == '\0') return -1;
    w = s;
    while (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\r' && *s != '\n') s++;
    len = (size_t)(s - w);
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
    if (*s != '\0') return -1;
    *bad = w;
    *bad_len = len > 200 ? 200 : (int)len;
    for (k = 0; k < len; k++) {
        if (w[k] < '0' || w[k] > '9') return 1;
        if (v <= UINT32_MAX) v = v * 10 + (uint64_t)(w[k] - '0');
    }
    *out = v > UINT32_MAX ? UINT32_MAX : (uint32_t)v;
    return 0;
}

static rbs_status command(void *instance, const char *line, char *out, size_t outlen)
{
    static const char *const usage[] = {
        "orbit DYAW DPITCH (degrees)", "pan DX DY (metres)",
        "zoom FACTOR (> 0, 2 = twice as close)"};
    sdl_instance *r = (sdl_instance *)instance;
    char word[16], reply[400];
    size_t n = 0;
    double a[2] = {0.0, 0.0};
    const char *bad = "";
    int bad_len = 0, got = 0;
    uint32_t index = 0;
    rbs_status st;
    rbsf__camera *cam;
    if (r == NULL || line == NULL) return RBS_E_INVALID;
    while (*line == ' ' || *line == '\t') line++;
    while (line[n] != '\0' && line[n] != ' ' && line[n] != '\t' && line[n] != '\r' &&
           line[n] != '\n' && n < sizeof word - 1) {
        word[n] = line[n];
        n++;
    }
    word[n] = '\0';
    line += n;
    cam = &r->cameras[r->selected];
    /* Check the arguments first, then act on the camera under the lock it
     * shares with the window thread. */
    if (strcmp(word, "orbit") == 0 || strcmp(word, "pan") == 0) {
        if ((got = numbers(line, a, 2, &bad, &bad_len)) != 0) goto bad_usage;
    } else if (strcmp(word, "zoom") == 0) {
        if ((got = numbers(line, a, 1, &bad, &bad_len)) != 0) goto bad_usage;
    } else if (strcmp(word, "view") == 0) {
        if ((got = view_index(line, &index, &bad, &bad_len)) != 0) goto bad_usage;
    } else if (strcmp(word, "reset") == 0 || strcmp(word, "camera") == 0) {
        if ((got = numbers(line, a, 0, &bad, &bad_len)) != 0) goto bad_usage;
    } else {
        return RBS_E_NOT_FOUND;
    }
    if (strcmp(word, "view") == 0) {
        if (index >= r->views) goto bad_usage;
        r->selected = index;
        cam = &r->cameras[r->selected];
    }
    st = RBS_OK;
    cameras_lock(r);
    if (strcmp(word, "orbit") == 0)
        st = rbsf__camera_orbit(cam, a[0], a[1], reply, sizeof reply);
    else if (strcmp(word, "pan") == 0)
        st = rbsf__camera_pan(cam, a[0], a[1], reply, sizeof reply);
    else if (strcmp(word, "zoom") == 0)
        st = rbsf__camera_zoom(cam, a[0], reply, sizeof reply);
    else if (strcmp(word, "reset") == 0)
        st = rbsf__camera_reset(cam, reply, sizeof reply);
    else
        rbsf__camera_describe(cam, reply, sizeof reply);
    if (st == RBS_OK && r->window != NULL) rbsf__window_moved(r->window);
    cameras_unlock(r);
    if (out != NULL && outlen > 0) snprintf(out, outlen, "view %u: %s", r->selected, reply);
    return st;

bad_usage:
    if (out != NULL && outlen > 0) {
        if (got == 1 && strcmp(word, "view") == 0)
            snprintf(out, outlen, "view: expected a view index, a non-negative "
                     "whole number written with digits only, got '%.*s'; ",
                     bad_len, bad);
        else if (got == 1)
            snprintf(out, outlen, "%s: expected a decimal number, got '%.*s'; ",
                     word, bad_len, bad);
        else
            out[0] = '\0';
        n = strlen(out);
        out += n;
        outlen -= n;
        if (strcmp(word, "view") == 0)
            snprintf(out, outlen, "usage: view N (0..%u)", r->views - 1);
        else if (strcmp(word, "orbit") == 0)
            snprintf(out, outlen, "usage: %s", usage[0]);
        else if (strcmp(word, "pan") == 0)
            snprintf(out, outlen, "usage: %s", usage[1]);
        else if (strcmp(word, "zoom") == 0)
            snprintf(out, outlen, "usage: %s", usage[2]);
        else
            snprintf(out, outlen, "usage: %s (no arguments)", word);
    }
    return RBS_E_INVALID;
}

/* ------------------------------------------------------------------------- */
/* The class                                                                 */
/* ------------------------------------------------------------------------- */

/* Every entry point runs in the "C" locale on its thread (c_locale.h): the
 * entry's numbers and messages, the legend and captions drawn into the
 * pictures, the camera commands' numbers and replies.  destroy formats
 * nothing. */
static rbs_status c_check(void *context, const rbs_renderer_config *config,
                          const rbs_world *world, char *err, size_t errlen)
{
    rbsf__locale l;
    rbs_status st;
    rbsf__c_locale_push(&l);
    st = check(context, config, world, err, errlen);
    rbsf__c_locale_pop(&l);
    return st;
}

static rbs_status c_create(void *context, const rbs_renderer_config *config,
                           const rbs_world *world, void **out, char *err, size_t errlen)
{
    rbsf__locale l;
    rbs_status st;
    rbsf__c_locale_push(&l);
    st = create(context, config, world, out, err, errlen);
    rbsf__c_locale_pop(&l);
    return st;
}

static rbs_status c_draw(void *instance, const rbs_frame *frame, char *err, size_t errlen)
{
    rbsf__locale l;
    rbs_status st;
    rbsf__c_locale_push(&l);
    st = draw(instance, frame, err, errlen);
    rbsf__c_locale_pop(&l);
    return st;
}

static rbs_status c_finish(void *instance, char *err, size_t errlen)
{
    rbsf__locale l;
    rbs_status st;
    rbsf__c_locale_push(&l);
    st = finish(instance, err, errlen);
    rbsf__c_locale_pop(&l);
    return st;
}

static rbs_status c_command(void *instance, const char *line, char *out, size_t outlen)
{
    rbsf__locale l;
    rbs_status st;
    rbsf__c_locale_push(&l);
    st = command(instance, line, out, outlen);
    rbsf__c_locale_pop(&l);
    return st;
}

/* A recorder (flags 0): it must see every kept frame to write it, so it is
 * not RBS_RENDERER_LIVE (that would allow a latest-only reel to drop frames).
 * While the run is paused no frame comes; the window thread keeps the window
 * alive and redraws the last frame when the camera moves. */
static const rbs_renderer_class kSdlClass = {
    .struct_size = sizeof(rbs_renderer_class),
    .name = "sdl",
    .context = NULL,
    .create = c_create,
    .draw = c_draw,
    .finish = c_finish,
    .destroy = destroy,
    .command = c_command,
    .flags = 0,
    .check = c_check,
};

const rbs_renderer_class *rbsf_sdl_class(void) { return &kSdlClass; }

rbs_renderer_class rbsf_sdl_class_with(rbsf_sdl_world_api *api)
{
    rbs_renderer_class c = kSdlClass;
    c.context = api;
    return c;
}
