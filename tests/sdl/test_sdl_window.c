/*
 * test_sdl_window.c - the live window, without a real display: SDL's
 * "offscreen" video driver (SDL_VIDEODRIVER=offscreen) with DISPLAY set to a
 * name that is never connected to.  Events are pushed with SDL_PushEvent and
 * must come back through the control callback ("pause", "resume", "quit")
 * or move the free camera.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "sdl_test_util.h"

typedef struct cmd_log {
    char lines[16][32];
    int count;
} cmd_log;

static void control(void *context, const char *command)
{
    cmd_log *l = (cmd_log *)context;
    if (l->count < 16) snprintf(l->lines[l->count++], sizeof l->lines[0], "%s", command);
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

static void offscreen(void)
{
    setenv("DISPLAY", ":rbsim-test-no-such-display", 1);
    setenv("SDL_VIDEODRIVER", "offscreen", 1);
}

static void test_keys_and_mouse(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], before[512], after[512];
    void *inst = NULL;
    cmd_log l;
    tu_frame f;
    SDL_Event e;
    (void)state;
    memset(&l, 0, sizeof l);
    offscreen();
    assert_int_equal(tu_create_full("{\"window\":true,\"width\":160,\"height\":120}",
                                    tu_dir("keys"), NULL, 0, 0, control, &l, &inst, err,
                                    sizeof err),
                     RBS_OK);
    frame(&f, 0, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(l.count, 0);

    /* Space pauses (the frame says running). */
    key(SDLK_SPACE);
    frame(&f, 1, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(l.count, 1);
    assert_string_equal(l.lines[0], "pause");
    /* Space resumes when the frame says paused. */
    key(SDLK_SPACE);
    frame(&f, 2, 1);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_string_equal(l.lines[1], "resume");

    /* Arrows and a left-button drag orbit the free camera. */
    assert_int_equal(cls->command(inst, "camera", before, sizeof before), RBS_OK);
    key(SDLK_RIGHT);
    frame(&f, 3, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "camera", after, sizeof after), RBS_OK);
    assert_string_not_equal(before, after);
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEBUTTONDOWN;
    e.button.button = SDL_BUTTON_LEFT;
    assert_int_equal(SDL_PushEvent(&e), 1);
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEMOTION;
    e.motion.xrel = 25;
    e.motion.yrel = -5;
    assert_int_equal(SDL_PushEvent(&e), 1);
    frame(&f, 4, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "camera", before, sizeof before), RBS_OK);
    assert_string_not_equal(before, after);

    /* q, Escape, closing the window: quit. */
    key(SDLK_q);
    key(SDLK_ESCAPE);
    memset(&e, 0, sizeof e);
    e.type = SDL_QUIT;
    assert_int_equal(SDL_PushEvent(&e), 1);
    frame(&f, 5, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(l.count, 5);
    assert_string_equal(l.lines[2], "quit");
    assert_string_equal(l.lines[3], "quit");
    assert_string_equal(l.lines[4], "quit");

    /* A repeated frame (same number) is shown but not written again. */
    {
        char path[1400];
        struct stat sb;
        snprintf(path, sizeof path, "%s/frame_000005.png", tu_dir("keys"));
        assert_int_equal(stat(path, &sb), 0);
        assert_int_equal(remove(path), 0);
        f.frame.paused = 1;
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
        assert_int_not_equal(stat(path, &sb), 0);
    }
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
}

/* No usable video driver: "auto" draws PNG files without a window; true
 * fails at the first frame and says why. */
static void test_video_failure(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], path[1400];
    void *inst = NULL;
    tu_frame f;
    struct stat sb;
    (void)state;
    setenv("DISPLAY", ":rbsim-test-no-such-display", 1);
    setenv("SDL_VIDEODRIVER", "rbsim-no-such-driver", 1);
    assert_int_equal(tu_create("{\"window\":\"auto\"}", tu_dir("auto"), &inst, err,
                               sizeof err),
                     RBS_OK);
    frame(&f, 0, 0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/frame_000000.png", tu_dir("auto"));
    assert_int_equal(stat(path, &sb), 0);

    assert_int_equal(tu_create("{\"window\":true}", tu_dir("required"), &inst, err,
                               sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_E_RENDERER);
    assert_non_null(strstr(err, "window"));
    cls->destroy(inst);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keys_and_mouse),
        cmocka_unit_test(test_video_failure),
    };
    int failed;
    tu_set_base(argc > 1 ? argv[1] : ".");
    failed = cmocka_run_group_tests(tests, NULL, NULL);
    /* The process owns SDL's global state: shut it all down. */
    SDL_Quit();
    return failed;
}
