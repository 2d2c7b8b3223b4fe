/*
 * test_sdl_output.c - the files the "sdl" renderer writes: names and sizes
 * of the PNG frames, one folder per view or the views tiled, the contact
 * sheet and its decimation, the legend, the camera commands, and what is
 * left when a write fails.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "sdl_test_util.h"

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static SDL_Surface *load_fmt(const char *fmt, const char *dir, unsigned long long k)
{
    char path[1400];
    snprintf(path, sizeof path, fmt, dir, k);
    return tu_load(path);
}

static int is_red(uint32_t c)
{
    int r = (c >> 16) & 0xff, g = (c >> 8) & 0xff, b = c & 0xff;
    return r > 40 && g * 2 < r && b * 2 < r;
}

/* Frame numbers name the files; every file decodes to width x height. */
static void test_png_names_and_sizes(void **state)
{
    static const uint64_t numbers[3] = {0, 3, 17};
    const char *json = "{\"type\":\"sdl\",\"width\":200,\"height\":150,"
                       "\"window\":false,\"contact_sheet\":false}";
    const rbs_renderer_class *cls = rbsf_sdl_class();
    void *inst = NULL;
    char err[512], path[1400];
    int k;
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("names"), &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 3; k++) {
        tu_frame f;
        tu_frame_init(&f, numbers[k], 0.01 * (double)numbers[k]);
        tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
        tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    for (k = 0; k < 3; k++) {
        SDL_Surface *s = load_fmt("%s/frame_%06llu.png", tu_dir("names"), numbers[k]);
        assert_non_null(s);
        assert_int_equal(s->w, 200);
        assert_int_equal(s->h, 150);
        /* The default camera sees the ball. */
        assert_true(is_red(tu_pixel(s, 100, 75)));
        SDL_FreeSurface(s);
    }
    snprintf(path, sizeof path, "%s/frame_000001.png", tu_dir("names"));
    assert_false(exists(path));
    snprintf(path, sizeof path, "%s/contact_sheet.png", tu_dir("names"));
    assert_false(exists(path));
}

/* Four spheres of four colours far apart, one view aimed at each. */
static const uint32_t kColors[4] = {0xd03030, 0x30c030, 0x3050d0, 0xd0c020};
static const char *kViews =
    "\"views\":["
    "{\"position\":[0,-5,0],\"target\":[0,0,0]},"
    "{\"position\":[20,-5,0],\"target\":[20,0,0]},"
    "{\"position\":[40,-5,0],\"target\":[40,0,0]},"
    "{\"position\":[60,-5,0],\"target\":[60,0,0]}]";

static void four_balls(tu_frame *f, uint64_t number)
{
    int i;
    tu_frame_init(f, number, 0.0);
    for (i = 0; i < 4; i++) tu_add_sphere(f, "ball", 20.0 * i, 0, 0, 1.0, kColors[i]);
}

static double hue_gap(uint32_t a, uint32_t b)
{
    double d = fabs(tu_hue(a) - tu_hue(b));
    return d > 180 ? 360 - d : d;
}

static void test_views_folders(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char json[1024], err[512], fmt[64];
    void *inst = NULL;
    tu_frame f;
    int v;
    (void)state;
    snprintf(json, sizeof json, "{\"width\":160,\"height\":120,\"window\":false,%s}", kViews);
    assert_int_equal(tu_create(json, tu_dir("views"), &inst, err, sizeof err), RBS_OK);
    four_balls(&f, 5);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    for (v = 0; v < 4; v++) {
        SDL_Surface *s;
        snprintf(fmt, sizeof fmt, "%%s/view%d/frame_%%06llu.png", v);
        s = load_fmt(fmt, tu_dir("views"), 5);
        assert_non_null(s);
        assert_int_equal(s->w, 160);
        assert_int_equal(s->h, 120);
        assert_true(hue_gap(tu_pixel(s, 80, 60), kColors[v]) < 2.0);
        SDL_FreeSurface(s);
    }
}

/* Tiled: one 2W x 2H image per frame, view k in quadrant k (left to right,
 * top to bottom). */
static void test_tile(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char json[1024], err[512];
    void *inst = NULL;
    tu_frame f;
    SDL_Surface *s;
    int v;
    (void)state;
    snprintf(json, sizeof json,
             "{\"width\":160,\"height\":120,\"window\":false,\"tile\":true,%s}", kViews);
    assert_int_equal(tu_create(json, tu_dir("tile"), &inst, err, sizeof err), RBS_OK);
    four_balls(&f, 2);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    s = load_fmt("%s/frame_%06llu.png", tu_dir("tile"), 2);
    assert_non_null(s);
    assert_int_equal(s->w, 320);
    assert_int_equal(s->h, 240);
    for (v = 0; v < 4; v++) {
        int cx = 80 + 160 * (v % 2), cy = 60 + 120 * (v / 2);
        assert_true(hue_gap(tu_pixel(s, cx, cy), kColors[v]) < 2.0);
    }
    SDL_FreeSurface(s);
}

/* The legend (top left) shows time and frame: it differs between frames
 * that differ only in those, and is white text on a dark box. */
static void test_legend(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    const char *json = "{\"width\":320,\"height\":240,\"window\":false,"
                       "\"contact_sheet\":false}";
    char err[512];
    void *inst = NULL;
    SDL_Surface *a, *b;
    int x, y, diff = 0, white = 0, rest_diff = 0;
    tu_frame f;
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("legend"), &inst, err, sizeof err), RBS_OK);
    tu_frame_init(&f, 1, 0.25);
    tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    f.frame.number = 2;
    f.frame.time = 0.5;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    a = load_fmt("%s/frame_%06llu.png", tu_dir("legend"), 1);
    b = load_fmt("%s/frame_%06llu.png", tu_dir("legend"), 2);
    assert_non_null(a);
    assert_non_null(b);
    for (y = 0; y < 240; y++)
        for (x = 0; x < 320; x++) {
            int in = x < 80 && y < 24;
            if (tu_pixel(a, x, y) != tu_pixel(b, x, y)) {
                if (in) diff++;
                else rest_diff++;
            }
            if (in && tu_pixel(a, x, y) == 0xffffff) white++;
        }
    assert_true(diff > 0);
    assert_int_equal(rest_diff, 0);
    assert_true(white > 20);
    SDL_FreeSurface(a);
    SDL_FreeSurface(b);
}

/* The contact sheet after 40 frames: 16 slots, decimated by 2 at frames 16
 * and 32, keeps frames 0, 4, ..., 36 (10) plus the newest, 39: 11
 * thumbnails in 4 columns, 3 rows.  Thumbnails are 240 px wide for a 320 px
 * view (180 px high) with an 11 px caption under each, 4 px apart.  A ball moving right with the frame number
 * is further right in each thumbnail, in order. */
static void test_contact_sheet(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    const char *json = "{\"width\":320,\"height\":240,\"window\":false,"
                       "\"camera\":{\"position\":[0,-12,0],\"target\":[0,0,0]}}";
    char err[512], path[1400];
    void *inst = NULL;
    SDL_Surface *s;
    int k, last = -1;
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("sheet"), &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 40; k++) {
        tu_frame f;
        tu_frame_init(&f, (uint64_t)k, 0.1 * k);
        tu_add_sphere(&f, "ball", -4.0 + 0.2 * k, 0, 0, 0.5, 0xd03030);
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/contact_sheet.png", tu_dir("sheet"));
    s = tu_load(path);
    assert_non_null(s);
    assert_int_equal(s->w, 4 * (240 + 4) + 4);
    assert_int_equal(s->h, 3 * (180 + 11 + 4) + 4);
    for (k = 0; k < 11; k++) {
        int x0 = 4 + (k % 4) * 244, y0 = 4 + (k / 4) * 195, bx0, by0, bx1, by1;
        assert_true(tu_bbox(s, x0, y0, 240, 180, is_red, &bx0, &by0, &bx1, &by1) > 0);
        /* Frames 0, 4, ..., 36, 39: the ball moves 0.8 m (or 0.6 m) to the
         * right between thumbnails, several pixels at this scale. */
        assert_true(bx0 - x0 > last);
        last = bx0 - x0;
        (void)by0;
        (void)by1;
        (void)bx1;
    }
    SDL_FreeSurface(s);
}

static void test_io_error(void **state)
{
    char err[512], path[1400];
    void *inst = NULL;
    FILE *fp;
    (void)state;
    /* The output folder's name is taken by a regular file. */
    assert_true(mkdir(tu_dir(""), 0777) == 0 || errno == EEXIST);
    assert_true(mkdir(tu_dir("a_file_dir"), 0777) == 0 || errno == EEXIST);
    snprintf(path, sizeof path, "%s/blocker", tu_dir("a_file_dir"));
    fp = fopen(path, "w");
    assert_non_null(fp);
    fclose(fp);
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_E_IO);
    assert_null(inst);
    assert_non_null(strstr(err, "path:"));
    /* check() finds it too, before anything is made. */
    {
        rbs_renderer_config c;
        memset(&c, 0, sizeof c);
        c.struct_size = sizeof c;
        c.type = "sdl";
        c.path = path;
        c.json = "{\"window\":false}";
        err[0] = '\0';
        assert_int_equal(rbsf_sdl_class()->check(NULL, &c, NULL, err, sizeof err), RBS_E_IO);
    }
    /* And a file in the way deeper down. */
    snprintf(path, sizeof path, "%s/blocker/sub", tu_dir("a_file_dir"));
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_E_IO);
    assert_null(inst);
    assert_non_null(strstr(err, "path:"));
    assert_non_null(strstr(err, "blocker"));
}

/* check() of path alone: RBS_OK, or the status with the message in err. */
static rbs_status check_path(const char *json, const char *path, char *err, size_t errlen)
{
    rbs_renderer_config c;
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.type = "sdl";
    c.path = path;
    c.json = json;
    err[0] = '\0';
    return rbsf_sdl_class()->check(NULL, &c, NULL, err, errlen);
}

/* Paths that cannot work are refused by check() (and create()) before any
 * folder is made: a name longer than the file system takes, at any depth
 * (only the first missing folder's parent was checked, so "x/y/<300 z>"
 * passed and create() left x and x/y behind); a path that with the files'
 * names passes PATH_MAX; a folder in a file system that takes none; "-". */
static void test_path_refused(void **state)
{
    char err[512], path[6000], base[1200];
    size_t i;
    void *inst = NULL;
    (void)state;
    assert_true(mkdir(tu_dir(""), 0777) == 0 || errno == EEXIST);
    snprintf(base, sizeof base, "%s", tu_dir("path_refused"));
    assert_true(mkdir(base, 0777) == 0 || errno == EEXIST);

    /* A 300-byte name two levels below the first missing folder. */
    i = (size_t)snprintf(path, sizeof path, "%s/x/y/", base);
    memset(path + i, 'z', 300);
    path[i + 300] = '\0';
    assert_int_equal(check_path("{\"window\":false}", path, err, sizeof err), RBS_E_IO);
    assert_non_null(strstr(err, "300 bytes long, longer than the file system takes"));
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_E_IO);
    assert_null(inst);
    snprintf(path, sizeof path, "%s/x", base);
    assert_false(exists(path));

    /* 4200 bytes of d/d/d/...: past PATH_MAX (it left ~2050 folders). */
    i = (size_t)snprintf(path, sizeof path, "%s/", base);
    while (i < 4200) {
        path[i++] = 'd';
        path[i++] = '/';
    }
    path[i - 1] = '\0';
    assert_int_equal(check_path("{\"window\":false}", path, err, sizeof err), RBS_E_IO);
    assert_non_null(strstr(err, "path: too long"));
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_E_IO);
    snprintf(path, sizeof path, "%s/d", base);
    assert_false(exists(path));

    /* /proc takes no folder, though root's access(W_OK) says it may. */
    if (exists("/proc/self")) {
        assert_int_equal(check_path("{\"window\":false}", "/proc/rbsim-nope/png", err,
                                    sizeof err),
                         RBS_E_IO);
        assert_non_null(strstr(err, "cannot create folder \"/proc/rbsim-nope\""));
        /* and, existing, no file */
        assert_int_equal(check_path("{\"window\":false}", "/proc", err, sizeof err),
                         RBS_E_IO);
        assert_non_null(strstr(err, "cannot write in folder \"/proc\""));
    }

    /* "-" is not standard output for PNG files. */
    assert_int_equal(check_path("{\"window\":false}", "-", err, sizeof err), RBS_E_INVALID);
    assert_non_null(strstr(err, "standard output"));
    assert_false(exists("-"));

    /* A views folder taken by a file: found by check(), before view0 is
     * made. */
    snprintf(path, sizeof path, "%s/views", base);
    assert_true(mkdir(path, 0777) == 0 || errno == EEXIST);
    snprintf(path, sizeof path, "%s/views/view1", base);
    {
        FILE *fp = fopen(path, "w");
        char json[1024];
        assert_non_null(fp);
        fclose(fp);
        snprintf(json, sizeof json, "{\"window\":false,%s}", kViews);
        snprintf(path, sizeof path, "%s/views", base);
        assert_int_equal(check_path(json, path, err, sizeof err), RBS_E_IO);
        assert_non_null(strstr(err, "view1\" exists and is not a folder"));
        snprintf(path, sizeof path, "%s/views/view0", base);
        assert_false(exists(path));
    }
}

/* The folders create() made go again (empty) when it fails at a later
 * level, or when the renderer is destroyed without a draw (a run rejected
 * after create, as when another output fails); folders that were there
 * stay, and so do those of a renderer that drew. */
static void test_folders_undone(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], path[1600], base[1400], json[1024];
    void *inst = NULL;
    tu_frame f;
    FILE *fp;
    (void)state;
    assert_true(mkdir(tu_dir(""), 0777) == 0 || errno == EEXIST);
    snprintf(base, sizeof base, "%s", tu_dir("undone"));
    assert_true(mkdir(base, 0777) == 0 || errno == EEXIST);
    {
        /* what a failed earlier run of this test may have left */
        static const char *const old[] = {"new", "a/b", "a", "v/view0", "v/view1",
                                          "v/view2", "v/view3"};
        size_t k;
        for (k = 0; k < sizeof old / sizeof old[0]; k++) {
            snprintf(path, sizeof path, "%s/%s", base, old[k]);
            rmdir(path);
        }
    }

    /* A later level fails: "new/../blocker/png", blocker a file. */
    snprintf(path, sizeof path, "%s/blocker", base);
    fp = fopen(path, "w");
    assert_non_null(fp);
    fclose(fp);
    snprintf(path, sizeof path, "%s/new/../blocker/png", base);
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_E_IO);
    assert_null(inst);
    assert_non_null(strstr(err, "blocker\" exists and is not a folder"));
    snprintf(path, sizeof path, "%s/new", base);
    assert_false(exists(path));

    /* Made, never drawn, destroyed: gone; the folder that was there stays. */
    snprintf(path, sizeof path, "%s/a/b", base);
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_OK);
    assert_true(exists(path));
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/a", base);
    assert_false(exists(path));
    assert_true(exists(base));

    /* Views into an existing folder: only the viewK folders go. */
    snprintf(json, sizeof json, "{\"window\":false,%s}", kViews);
    snprintf(path, sizeof path, "%s/v", base);
    assert_true(mkdir(path, 0777) == 0 || errno == EEXIST);
    assert_int_equal(tu_create(json, path, &inst, err, sizeof err), RBS_OK);
    snprintf(path, sizeof path, "%s/v/view3", base);
    assert_true(exists(path));
    cls->destroy(inst);
    assert_false(exists(path));
    snprintf(path, sizeof path, "%s/v/view0", base);
    assert_false(exists(path));
    snprintf(path, sizeof path, "%s/v", base);
    assert_true(exists(path));

    /* A file put in a made folder keeps it (and its parents). */
    snprintf(path, sizeof path, "%s/c/d", base);
    assert_int_equal(tu_create("{\"window\":false}", path, &inst, err, sizeof err), RBS_OK);
    snprintf(path, sizeof path, "%s/c/d/mine.txt", base);
    fp = fopen(path, "w");
    assert_non_null(fp);
    fclose(fp);
    cls->destroy(inst);
    assert_true(exists(path));

    /* Drawn: the folder and its frame stay. */
    snprintf(path, sizeof path, "%s/e/f", base);
    assert_int_equal(tu_create("{\"window\":false,\"width\":64,\"height\":48}", path, &inst,
                               err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/e/f/frame_000000.png", base);
    assert_true(exists(path));
}

/* Size of a file in bytes, -1 if it is missing. */
static long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

/* Whether a file ends with a PNG's IEND chunk (length 0, "IEND", its CRC):
 * the last bytes a whole PNG has. */
static int ends_with_iend(const char *path)
{
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D',
                                           0xae, 0x42, 0x60, 0x82};
    unsigned char tail[12];
    FILE *fp = fopen(path, "rb");
    int ok;
    if (fp == NULL) return 0;
    ok = fseek(fp, -12, SEEK_END) == 0 && fread(tail, 1, 12, fp) == 12 &&
         memcmp(tail, iend, 12) == 0;
    fclose(fp);
    return ok;
}

static void set_file_limit(rlim_t bytes)
{
    struct rlimit rl;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &rl), 0);
    rl.rlim_cur = bytes;
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &rl), 0);
}

/* Teardown of test_write_error, also when an assertion left it early: the
 * soft file size limit back to the hard one (which the test never lowers),
 * SIGXFSZ back to its default. */
static int lift_file_limit(void **state)
{
    struct rlimit rl;
    (void)state;
    signal(SIGXFSZ, SIG_DFL);
    if (getrlimit(RLIMIT_FSIZE, &rl) != 0) return -1;
    rl.rlim_cur = rl.rlim_max;
    return setrlimit(RLIMIT_FSIZE, &rl);
}

/* A write that fails (here: a file size limit, EFBIG, as `ulimit -f` sets)
 * fails draw() and finish() with RBS_E_IO and `cannot write "FILE": REASON`,
 * and the file is removed, so the PNG files left are whole.  SDL_image
 * 2.6.3's IMG_SavePNG reported success with the file cut at the limit.  The
 * limit is half of frame 0's file (frame 1 differs only in its legend, so
 * it does not fit); only the soft limit is lowered, and it is put back. */
static void test_write_error(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    const char *json = "{\"width\":200,\"height\":150,\"window\":false}";
    const char *dir = tu_dir("write_error");
    char err[512], path[1400], want[1600];
    void *inst = NULL;
    struct rlimit saved;
    long size0;
    SDL_Surface *s;
    int k;
    (void)state;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &saved), 0);
    signal(SIGXFSZ, SIG_IGN); /* a failed write, not the default's death */
    assert_int_equal(tu_create(json, dir, &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 3; k++) {
        tu_frame f;
        rbs_status st;
        tu_frame_init(&f, (uint64_t)k, 0.01 * k);
        tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
        tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030)->texture = RBS_TEXTURE_STRIPES;
        if (k == 1) {
            snprintf(path, sizeof path, "%s/frame_000000.png", dir);
            size0 = file_size(path);
            assert_true(size0 > 1000);
            set_file_limit((rlim_t)size0 / 2);
        }
        err[0] = '\0';
        st = cls->draw(inst, &f.frame, err, sizeof err);
        if (k == 1) {
            /* Frame 1 fails and leaves nothing; the limit goes again. */
            assert_int_equal(st, RBS_E_IO);
            snprintf(path, sizeof path, "%s/frame_000001.png", dir);
            snprintf(want, sizeof want, "cannot write \"%s\": %s", path, strerror(EFBIG));
            assert_string_equal(err, want);
            assert_int_equal(file_size(path), -1);
            assert_int_equal(setrlimit(RLIMIT_FSIZE, &saved), 0);
        } else {
            /* The writer is whole again after a failure. */
            assert_int_equal(st, RBS_OK);
        }
    }
    /* The contact sheet (frames 0 and 2) fails the same way in finish(). */
    set_file_limit(100);
    err[0] = '\0';
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_E_IO);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &saved), 0);
    snprintf(path, sizeof path, "%s/contact_sheet.png", dir);
    snprintf(want, sizeof want, "cannot write \"%s\": %s", path, strerror(EFBIG));
    assert_string_equal(err, want);
    assert_int_equal(file_size(path), -1);
    cls->destroy(inst);
    /* Frames 0 and 2 are whole pictures. */
    for (k = 0; k < 3; k += 2) {
        snprintf(path, sizeof path, "%s/frame_%06d.png", dir, k);
        assert_true(ends_with_iend(path));
        s = tu_load(path);
        assert_non_null(s);
        assert_int_equal(s->w, 200);
        assert_int_equal(s->h, 150);
        SDL_FreeSurface(s);
    }
}

/* Camera commands through the class's command hook. */
static void test_commands(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], out[512];
    void *inst = NULL, *fixed = NULL;
    tu_frame f;
    SDL_Surface *a, *b, *c;
    (void)state;
    /* The default camera is free. */
    assert_int_equal(tu_create("{\"width\":160,\"height\":120,\"window\":false,"
                               "\"contact_sheet\":false}",
                               tu_dir("commands"), &inst, err, sizeof err),
                     RBS_OK);
    /* Before the first frame the camera has no place yet. */
    assert_int_equal(cls->command(inst, "orbit 10 0", out, sizeof out), RBS_E_INVALID);
    tu_frame_init(&f, 0, 0.0);
    tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
    tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "orbit 30 10", out, sizeof out), RBS_OK);
    assert_non_null(strstr(out, "view 0"));
    /* Any finite yaw is a yaw modulo a turn, any pitch stops at 89 degrees:
     * "orbit 1e308 1e308" was refused as "no usable view" (the azimuth's
     * radians overflowed).  1e308 is 296 degrees modulo 360 (exact: 1e308
     * = 2^1023 * 1.112..., and 2^k mod 360 follows from 2^k mod 45 and 8),
     * so the azimuth moves by 296 - 360 = -64 degrees, and back with
     * -1e308; to the reply's 0.1 degree. */
    {
        double az0, az1, az2, want;
        assert_non_null(strstr(out, "azimuth "));
        az0 = strtod(strstr(out, "azimuth ") + 8, NULL);
        assert_int_equal(cls->command(inst, "orbit 1e308 1e308", out, sizeof out), RBS_OK);
        assert_non_null(strstr(out, "elevation 89.0 deg"));
        az1 = strtod(strstr(out, "azimuth ") + 8, NULL);
        want = az0 - 64.0 < -180.0 ? az0 - 64.0 + 360.0 : az0 - 64.0;
        assert_true(fabs(az1 - want) <= 0.11);
        assert_int_equal(cls->command(inst, "orbit -1e308 -1e308", out, sizeof out), RBS_OK);
        assert_non_null(strstr(out, "elevation -89.0 deg"));
        az2 = strtod(strstr(out, "azimuth ") + 8, NULL);
        assert_true(fabs(az2 - az0) <= 0.11 || fabs(fabs(az2 - az0) - 360.0) <= 0.11);
    }
    assert_int_equal(cls->command(inst, "orbit 0 99", out, sizeof out), RBS_OK);
    f.frame.number = 1;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "zoom 2", out, sizeof out), RBS_OK);
    assert_int_equal(cls->command(inst, "pan 0.1 -0.2", out, sizeof out), RBS_OK);
    assert_int_equal(cls->command(inst, "reset", out, sizeof out), RBS_OK);
    f.frame.number = 2;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    /* Bad arguments, other renderers' commands. */
    assert_int_equal(cls->command(inst, "orbit 10", out, sizeof out), RBS_E_INVALID);
    assert_non_null(strstr(out, "usage: orbit"));
    assert_int_equal(cls->command(inst, "zoom 0", out, sizeof out), RBS_E_INVALID);
    assert_int_equal(cls->command(inst, "zoom x", out, sizeof out), RBS_E_INVALID);
    /* Numbers by speed's rule: decimal, finite; the reply names the command
     * and the word (strtod took "zoom 0x2" as 2: a probe of session 46). */
    {
        static const char *const words[][2] = {
            {"zoom 0x2", "zoom: expected a decimal number, got '0x2'; usage: zoom"},
            {"orbit inf 0", "orbit: expected a decimal number, got 'inf'; usage: orbit"},
            {"orbit 0 nan", "orbit: expected a decimal number, got 'nan'; usage: orbit"},
            {"pan 1 infinity", "pan: expected a decimal number, got 'infinity'; usage: pan"},
            {"pan 0x1p3 0", "pan: expected a decimal number, got '0x1p3'; usage: pan"},
            {"zoom 1e999", "zoom: expected a decimal number, got '1e999'; usage: zoom"},
            {"view 0x0", "view: expected a view index, a non-negative whole number "
                         "written with digits only, got '0x0'; usage: view N (0..0)"},
            /* A view index is digits only: "view 0.0" and "view -0" were
             * taken as view 0 (a probe of session 47). */
            {"view 0.0", "view: expected a view index, a non-negative whole number "
                         "written with digits only, got '0.0'; usage: view N (0..0)"},
            {"view -0", "view: expected a view index, a non-negative whole number "
                        "written with digits only, got '-0'; usage: view N (0..0)"},
            {"view +0", "view: expected a view index, a non-negative whole number "
                        "written with digits only, got '+0'; usage: view N (0..0)"},
            {"view 0e0", "view: expected a view index, a non-negative whole number "
                         "written with digits only, got '0e0'; usage: view N (0..0)"},
            {"view 99999999999999999999", "usage: view N (0..0)"},
            {"view 0 0", "usage: view N (0..0)"},
            {"zoom 2x", "zoom: expected a decimal number, got '2x'; usage: zoom"}};
        size_t k;
        for (k = 0; k < sizeof words / sizeof words[0]; k++) {
            assert_int_equal(cls->command(inst, words[k][0], out, sizeof out),
                             RBS_E_INVALID);
            if (strncmp(out, words[k][1], strlen(words[k][1])) != 0)
                fail_msg("'%s' replied '%s'", words[k][0], out);
        }
        assert_int_equal(cls->command(inst, "zoom 1e0", out, sizeof out), RBS_OK);
        assert_int_equal(cls->command(inst, "view 00", out, sizeof out), RBS_OK);
        assert_int_equal(cls->command(inst, " view 0 ", out, sizeof out), RBS_OK);
    }
    assert_int_equal(cls->command(inst, "pan 1 2 3", out, sizeof out), RBS_E_INVALID);
    assert_int_equal(cls->command(inst, "view 1", out, sizeof out), RBS_E_INVALID);
    assert_int_equal(cls->command(inst, "status", out, sizeof out), RBS_E_NOT_FOUND);
    assert_int_equal(cls->command(inst, "camera", out, sizeof out), RBS_OK);
    assert_non_null(strstr(out, "free"));
    cls->destroy(inst);
    a = tu_load(tu_dir("commands/frame_000000.png"));
    b = tu_load(tu_dir("commands/frame_000001.png"));
    c = tu_load(tu_dir("commands/frame_000002.png"));
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(c);
    {
        /* Orbit moved the picture; reset brought it back (outside the
         * legend, which shows the frame number). */
        int x, y, ab = 0, ac = 0;
        for (y = 30; y < 120; y++)
            for (x = 0; x < 160; x++) {
                ab += tu_pixel(a, x, y) != tu_pixel(b, x, y);
                ac += tu_pixel(a, x, y) != tu_pixel(c, x, y);
            }
        assert_true(ab > 500);
        assert_int_equal(ac, 0);
    }
    SDL_FreeSurface(a);
    SDL_FreeSurface(b);
    SDL_FreeSurface(c);

    /* A fixed camera refuses to move and says why. */
    assert_int_equal(tu_create("{\"window\":false,\"camera\":{\"position\":[0,-5,1],"
                               "\"target\":[0,0,0]}}",
                               tu_dir("commands_fixed"), &fixed, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(fixed, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(fixed, "orbit 10 0", out, sizeof out), RBS_E_INVALID);
    assert_non_null(strstr(out, "fixed"));
    cls->destroy(fixed);
}

/* Where the commands put a free camera, checked through the picture: a
 * small ball must appear where the pinhole formula puts it for the camera
 * the commands should have made (computed here by hand).  Start: eye
 * (5, 0, 1) looking at (0, 0, 1), up z.  "orbit 90 0": yaw +90 degrees about
 * z (counter-clockwise seen from above): eye (0, 5, 1).  "orbit 0 30":
 * elevation 30 degrees: eye (0, 5 cos 30, 1 + 5 sin 30).  "zoom 2": half the
 * distance.  "pan 0.5 0.2": eye and target move by 0.5 right + 0.2 up of the
 * picture. */
static void test_camera_commands_exact(void **state)
{
    static const double ball[3] = {0.4, -0.3, 1.2}, zup[3] = {0, 0, 1};
    const char *cmds[4] = {"orbit 90 0", "orbit 0 30", "zoom 2", "pan 0.5 0.2"};
    const rbs_renderer_class *cls = rbsf_sdl_class();
    const double c30 = sqrt(3.0) / 2.0, s30 = 0.5;
    double eye[4][3] = {{0, 5, 1}, {0, 5 * c30, 1 + 5 * s30}, {0, 2.5 * c30, 1 + 2.5 * s30}};
    double target[4][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    char err[512], out[512];
    void *inst = NULL;
    tu_frame f;
    int k, i;
    (void)state;
    /* Pan: right = fwd x up, picture up = right x fwd, from eye[2]. */
    {
        double fwd[3], right[3], up[3], l;
        for (i = 0; i < 3; i++) fwd[i] = target[2][i] - eye[2][i];
        l = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
        for (i = 0; i < 3; i++) fwd[i] /= l;
        right[0] = fwd[1] * zup[2] - fwd[2] * zup[1];
        right[1] = fwd[2] * zup[0] - fwd[0] * zup[2];
        right[2] = fwd[0] * zup[1] - fwd[1] * zup[0];
        l = sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
        for (i = 0; i < 3; i++) right[i] /= l;
        up[0] = right[1] * fwd[2] - right[2] * fwd[1];
        up[1] = right[2] * fwd[0] - right[0] * fwd[2];
        up[2] = right[0] * fwd[1] - right[1] * fwd[0];
        for (i = 0; i < 3; i++) {
            eye[3][i] = eye[2][i] + 0.5 * right[i] + 0.2 * up[i];
            target[3][i] = target[2][i] + 0.5 * right[i] + 0.2 * up[i];
        }
    }
    assert_int_equal(tu_create("{\"width\":320,\"height\":240,\"window\":false,"
                               "\"contact_sheet\":false,\"camera\":{\"mode\":\"free\","
                               "\"position\":[5,0,1],\"target\":[0,0,1]}}",
                               tu_dir("exact"), &inst, err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", ball[0], ball[1], ball[2], 0.08, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    for (k = 0; k < 4; k++) {
        assert_int_equal(cls->command(inst, cmds[k], out, sizeof out), RBS_OK);
        f.frame.number = (uint64_t)k + 1;
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    cls->destroy(inst);
    for (k = 0; k < 4; k++) {
        SDL_Surface *s = load_fmt("%s/frame_%06llu.png", tu_dir("exact"),
                                  (unsigned long long)k + 1);
        double u, v, z;
        int x0, y0, x1, y1;
        assert_non_null(s);
        assert_true(tu_project(eye[k], target[k], zup, 50.0, 320, 240, ball, &u, &v, &z));
        assert_true(tu_bbox(s, 0, 30, 320, 210, is_red, &x0, &y0, &x1, &y1) > 0);
        /* A small ball: the ellipse's offset from the projected centre is
         * under 0.1 px; one pixel for sampling. */
        assert_true(fabs((x0 + x1 + 1) / 2.0 - u) <= 1.0);
        assert_true(fabs((y0 + y1 + 1) / 2.0 - v) <= 1.0);
        SDL_FreeSurface(s);
    }
}

/* Commands whose camera would have no usable view (not finite, beyond
 * 1e100 m, or the eye on the target) are refused with the reason; the camera
 * keeps its place and the next frame is drawn. */
static void test_commands_refused(void **state)
{
    static const char *const bad[] = {"zoom 1e300", "zoom 1e-300", "pan 1e308 0",
                                      "pan 1e308 0", "pan 0 1e200"};
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], out[512], before[512];
    void *inst = NULL;
    tu_frame f;
    size_t i;
    (void)state;
    assert_int_equal(tu_create("{\"width\":64,\"height\":48,\"window\":false,"
                               "\"contact_sheet\":false}",
                               tu_dir("refused"), &inst, err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "camera", before, sizeof before), RBS_OK);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(cls->command(inst, bad[i], out, sizeof out), RBS_E_INVALID);
        assert_non_null(strstr(out, "refused"));
        assert_null(strstr(out, "nan"));
        assert_int_equal(cls->command(inst, "camera", out, sizeof out), RBS_OK);
        assert_string_equal(out, before);
    }
    f.frame.number = 1;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    /* A large but usable zoom still works. */
    assert_int_equal(cls->command(inst, "zoom 1e-50", out, sizeof out), RBS_OK);
    f.frame.number = 2;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png_names_and_sizes),
        cmocka_unit_test(test_views_folders),
        cmocka_unit_test(test_tile),
        cmocka_unit_test(test_legend),
        cmocka_unit_test(test_contact_sheet),
        cmocka_unit_test(test_io_error),
        cmocka_unit_test(test_path_refused),
        cmocka_unit_test(test_folders_undone),
        cmocka_unit_test_teardown(test_write_error, lift_file_limit),
        cmocka_unit_test(test_commands),
        cmocka_unit_test(test_commands_refused),
        cmocka_unit_test(test_camera_commands_exact),
    };
    tu_set_base(argc > 1 ? argv[1] : ".");
    return cmocka_run_group_tests(tests, NULL, NULL);
}
