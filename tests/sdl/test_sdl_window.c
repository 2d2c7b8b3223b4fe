/*
 * test_sdl_window.c - the live window, without a real display: SDL's
 * "offscreen" video driver (SDL_VIDEODRIVER=offscreen) with DISPLAY set to a
 * name that is never connected to.  Events are pushed with SDL_PushEvent;
 * the window's own thread must turn them into control commands ("pause",
 * "resume", "quit") or camera moves, also while no frame comes (a paused
 * run).  The thread answers asynchronously, so the test waits for each
 * effect, at most 5 s (a bound, not a timing: a working window answers in
 * about 30 ms).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <pthread.h>

#include "sdl_test_util.h"

typedef struct cmd_log {
    pthread_mutex_t mu; /* the window thread writes, the test reads */
    char lines[16][32];
    int count;
} cmd_log;

static void control(void *context, const char *command)
{
    cmd_log *l = (cmd_log *)context;
    pthread_mutex_lock(&l->mu);
    if (l->count < 16) snprintf(l->lines[l->count++], sizeof l->lines[0], "%s", command);
    pthread_mutex_unlock(&l->mu);
}

/* Wait until the log holds n commands (or 5 s pass); returns the count. */
static int wait_count(cmd_log *l, int n)
{
    int k, count = 0;
    for (k = 0; k < 1000; k++) {
        pthread_mutex_lock(&l->mu);
        count = l->count;
        pthread_mutex_unlock(&l->mu);
        if (count >= n) break;
        SDL_Delay(5);
    }
    return count;
}

/* Wait until the "camera" command's reply differs from before. */
static int wait_camera_change(void *inst, const char *before)
{
    char now[512];
    int k;
    for (k = 0; k < 1000; k++) {
        assert_int_equal(rbsf_sdl_class()->command(inst, "camera", now, sizeof now), RBS_OK);
        if (strcmp(now, before) != 0) return 1;
        SDL_Delay(5);
    }
    return 0;
}

static void key(SDL_Keycode sym)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = SDL_KEYDOWN;
    e.key.keysym.sym = sym;
    assert_int_equal(SDL_PushEvent(&e), 1);
}

static void frame(tu_frame *f, uint64_t number, int paused)
{
    tu_frame_init(f, number, 0.01 * (double)number);
    f->frame.paused = paused;
    tu_add_plane(f, 0, 0, 0, 0, 0, 1, 0x808080);
    tu_add_sphere(f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
}

/* Use SDL's offscreen driver; skip the test if this SDL was built without
 * it (then there is no way to open a window without a display). */
static void offscreen(void)
{
    static int calls;
    int i, n = SDL_GetNumVideoDrivers(), found = 0;
    for (i = 0; i < n; i++)
        if (strcmp(SDL_GetVideoDriver(i), "offscreen") == 0) found = 1;
    if (!found) {
        fprintf(stderr, "SDL has no offscreen video driver: skipped\n");
        skip();
    }
    setenv("DISPLAY", ":rbsim-test-no-such-display", 1);
    /* named as SDL reads the variable: any case, in a list (the window
     * takes a driver that shows nothing only when it is named) */
    setenv("SDL_VIDEODRIVER", (calls++ % 2) ? "rbsim-no-such-driver,OffScreen" : "offscreen", 1);
}

static void test_keys_and_mouse(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], before[512];
    void *inst = NULL;
    cmd_log l;
    tu_frame f;
    SDL_Event e;
    (void)state;
    memset(&l, 0, sizeof l);
    pthread_mutex_init(&l.mu, NULL);
    offscreen();
    assert_int_equal(tu_create_full("{\"window\":true,\"width\":160,\"height\":120}",
                                    tu_dir("keys"), NULL, 0, 0, control, &l, &inst, err,
                                    sizeof err),
                     RBS_OK);
    frame(&f, 0, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(wait_count(&l, 0), 0);

    /* Space pauses; with no frame drawn since, space again resumes: the
     * window answers while the run is paused. */
    key(SDLK_SPACE);
    assert_int_equal(wait_count(&l, 1), 1);
    assert_string_equal(l.lines[0], "pause");
    key(SDLK_SPACE);
    assert_int_equal(wait_count(&l, 2), 2);
    assert_string_equal(l.lines[1], "resume");
    /* A frame that says "paused" makes the next space a "resume". */
    frame(&f, 1, 1);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    key(SDLK_SPACE);
    assert_int_equal(wait_count(&l, 3), 3);
    assert_string_equal(l.lines[2], "resume");

    /* Arrows and a left-button drag orbit the free camera, no frame needed. */
    assert_int_equal(cls->command(inst, "camera", before, sizeof before), RBS_OK);
    key(SDLK_RIGHT);
    assert_true(wait_camera_change(inst, before));
    assert_int_equal(cls->command(inst, "camera", before, sizeof before), RBS_OK);
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEBUTTONDOWN;
    e.button.button = SDL_BUTTON_LEFT;
    assert_int_equal(SDL_PushEvent(&e), 1);
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEMOTION;
    e.motion.xrel = 25;
    e.motion.yrel = -5;
    assert_int_equal(SDL_PushEvent(&e), 1);
    assert_true(wait_camera_change(inst, before));
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEBUTTONUP;
    assert_int_equal(SDL_PushEvent(&e), 1);
    /* The moved camera draws the next frame. */
    frame(&f, 2, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);

    /* q, Escape, closing the window: quit. */
    key(SDLK_q);
    key(SDLK_ESCAPE);
    memset(&e, 0, sizeof e);
    e.type = SDL_QUIT;
    assert_int_equal(SDL_PushEvent(&e), 1);
    assert_int_equal(wait_count(&l, 6), 6);
    assert_string_equal(l.lines[3], "quit");
    assert_string_equal(l.lines[4], "quit");
    assert_string_equal(l.lines[5], "quit");

    /* A repeated frame (same number) is not written again. */
    {
        char path[1400];
        struct stat sb;
        snprintf(path, sizeof path, "%s/frame_000002.png", tu_dir("keys"));
        assert_int_equal(stat(path, &sb), 0);
        assert_int_equal(remove(path), 0);
        f.frame.paused = 1;
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
        assert_int_not_equal(stat(path, &sb), 0);
    }
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    pthread_mutex_destroy(&l.mu);
}

/* With DISPLAY naming a display that does not answer and SDL_VIDEODRIVER
 * set to driver (NULL: unset): "auto" draws the PNG files without a window
 * (in folder tag_auto) and true fails at the first frame, saying why. */
static void no_window_to_be_had(const char *driver, const char *tag)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], path[1400], dir[64];
    void *inst = NULL;
    tu_frame f;
    struct stat sb;
    setenv("DISPLAY", ":rbsim-test-no-such-display", 1);
    if (driver != NULL)
        setenv("SDL_VIDEODRIVER", driver, 1);
    else
        unsetenv("SDL_VIDEODRIVER");
    snprintf(dir, sizeof dir, "%s_auto", tag);
    assert_int_equal(tu_create("{\"window\":\"auto\"}", tu_dir(dir), &inst, err, sizeof err),
                     RBS_OK);
    frame(&f, 0, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/frame_000000.png", tu_dir(dir));
    assert_int_equal(stat(path, &sb), 0);

    snprintf(dir, sizeof dir, "%s_required", tag);
    assert_int_equal(tu_create("{\"window\":true}", tu_dir(dir), &inst, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_E_RENDERER);
    assert_non_null(strstr(err, "window"));
    cls->destroy(inst);
}

/* No usable video driver. */
static void test_video_failure(void **state)
{
    (void)state;
    no_window_to_be_had("rbsim-no-such-driver", "nodriver");
}

/* A display that does not answer, and no driver asked for: SDL falls back
 * to "offscreen" (or fails to start), which shows nothing: an invisible
 * window was opened and true ran as if shown. */
static void test_display_that_does_not_answer(void **state)
{
    (void)state;
    no_window_to_be_had(NULL, "silent");
}

/* Newest "SDL_window<id>-<n>.bmp" the offscreen driver saved in the
 * current folder (SDL_VIDEO_OFFSCREEN_SAVE_FRAMES), by number; 0 if none. */
static int newest_bmp(char *name, size_t n)
{
    int k, found = 0, id;
    for (id = 1; id < 16; id++)
        for (k = 1; k < 100000; k++) {
            char try_name[64];
            struct stat sb;
            snprintf(try_name, sizeof try_name, "SDL_window%d-%08d.bmp", id, k);
            if (stat(try_name, &sb) != 0) break;
            if (k > found) {
                found = k;
                snprintf(name, n, "%s", try_name);
            }
        }
    return found;
}

/* Remove saved pictures of an earlier run of this test. */
static void remove_bmps(void)
{
    int k, id;
    for (id = 1; id < 16; id++)
        for (k = 1; k < 100000; k++) {
            char name[64];
            snprintf(name, sizeof name, "SDL_window%d-%08d.bmp", id, k);
            if (remove(name) != 0) break;
        }
}

static long rgb_differences(SDL_Surface *a, SDL_Surface *b)
{
    long d = 0;
    int x, y;
    if (a->w != b->w || a->h != b->h) return -1;
    for (y = 0; y < a->h; y++)
        for (x = 0; x < a->w; x++)
            d += tu_pixel(a, x, y) != tu_pixel(b, x, y);
    return d;
}

/* The newest saved window picture, as ARGB8888 (NULL if none yet). */
static SDL_Surface *newest_shown(void)
{
    char name[64];
    SDL_Surface *raw, *s;
    if (newest_bmp(name, sizeof name) == 0) return NULL;
    raw = SDL_LoadBMP(name);
    if (raw == NULL) return NULL; /* being written: try again */
    s = SDL_ConvertSurfaceFormat(raw, SDL_PIXELFORMAT_ARGB8888, 0);
    SDL_FreeSurface(raw);
    return s;
}

/* Wait (at most 5 s) until the window shows a picture that differs from
 * ref in at least min pixels (min > 0) or equals it (min == 0). */
static int wait_shown(SDL_Surface *ref, long min)
{
    int k;
    for (k = 0; k < 500; k++) {
        SDL_Surface *s = newest_shown();
        if (s != NULL) {
            long d = rgb_differences(s, ref);
            SDL_FreeSurface(s);
            if (min == 0 ? d == 0 : d >= min) return 1;
        }
        SDL_Delay(10);
    }
    return 0;
}

/* What the window shows, read back from the offscreen driver's saved
 * frames: the frame drawn (equal to its PNG file), and, with no frame
 * coming (a paused run), the same frame from the new place after an arrow
 * key or a camera command. */
static void test_window_shows_and_redraws(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], cwd[1400], reply[512];
    void *inst = NULL;
    tu_frame f;
    SDL_Surface *file0;
    (void)state;
    assert_non_null(getcwd(cwd, sizeof cwd));
    offscreen();
    assert_int_equal(tu_create("{\"window\":true,\"width\":160,\"height\":120}",
                               tu_dir("shown"), &inst, err, sizeof err),
                     RBS_OK);
    assert_int_equal(chdir(tu_dir("shown")), 0);
    remove_bmps();
    setenv("SDL_VIDEO_OFFSCREEN_SAVE_FRAMES", "1", 1);
    frame(&f, 0, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    file0 = tu_load("frame_000000.png");
    assert_non_null(file0);
    /* The window shows the frame written. */
    assert_true(wait_shown(file0, 0));
    /* No frame comes; an arrow key moves the free camera: a new picture. */
    key(SDLK_LEFT);
    assert_true(wait_shown(file0, 500));
    /* A typed camera command redraws too: back to the start. */
    assert_int_equal(cls->command(inst, "reset", reply, sizeof reply), RBS_OK);
    assert_true(wait_shown(file0, 0));

    cls->destroy(inst);
    unsetenv("SDL_VIDEO_OFFSCREEN_SAVE_FRAMES");
    assert_int_equal(chdir(cwd), 0);
    SDL_FreeSurface(file0);
}

/* Two windowed renderers in one process: SDL has one event queue, so the
 * second is refused ("window": true) or goes without a window ("auto"). */
static void test_one_window_per_process(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512];
    void *a = NULL, *b = NULL, *c = NULL;
    tu_frame f;
    (void)state;
    offscreen();
    frame(&f, 0, 0);
    assert_int_equal(tu_create("{\"window\":true,\"width\":64,\"height\":48}",
                               tu_dir("first"), &a, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(a, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(tu_create("{\"window\":true,\"width\":64,\"height\":48}",
                               tu_dir("second"), &b, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(b, &f.frame, err, sizeof err), RBS_E_RENDERER);
    assert_non_null(strstr(err, "already in use"));
    assert_int_equal(tu_create("{\"window\":\"auto\",\"width\":64,\"height\":48}",
                               tu_dir("third"), &c, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(c, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(c);
    cls->destroy(b);
    cls->destroy(a);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keys_and_mouse),
        cmocka_unit_test(test_video_failure),
        cmocka_unit_test(test_display_that_does_not_answer),
        cmocka_unit_test(test_one_window_per_process),
        cmocka_unit_test(test_window_shows_and_redraws),
    };
    int failed;
    tu_set_base(argc > 1 ? argv[1] : ".");
    failed = cmocka_run_group_tests(tests, NULL, NULL);
    /* The process owns SDL's global state: shut it all down. */
    SDL_Quit();
    return failed;
}
