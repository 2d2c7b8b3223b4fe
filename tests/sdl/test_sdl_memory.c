/*
 * test_sdl_memory.c - the renderer reserves its memory in create(): drawing
 * frames allocates nothing in rbsim's code.
 *
 * The test is linked with -Wl,--wrap=malloc,calloc,realloc: calls from the
 * objects linked into this program (the renderer's static library and this
 * file) go through the counters below.  Allocations inside shared libraries
 * (SDL_image's IMG_SavePNG, SDL, cJSON) are not counted: they are the
 * documented exceptions.  A window is not used here (no display).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sdl_test_util.h"

void *__real_malloc(size_t size);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t size);

static int g_counting; /* test-local: this program is one test */
static long g_count;

void *__wrap_malloc(size_t size)
{
    if (g_counting) g_count++;
    return __real_malloc(size);
}

void *__wrap_calloc(size_t n, size_t size)
{
    if (g_counting) g_count++;
    return __real_calloc(n, size);
}

void *__wrap_realloc(void *p, size_t size)
{
    if (g_counting) g_count++;
    return __real_realloc(p, size);
}

static void run(const char *json, const char *name)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512];
    void *inst = NULL;
    int k;
    /* The wrapper sees the renderer's own allocations: creation makes some. */
    g_count = 0;
    g_counting = 1;
    assert_int_equal(tu_create(json, tu_dir(name), &inst, err, sizeof err), RBS_OK);
    g_counting = 0;
    assert_true(g_count > 0);

    g_count = 0;
    for (k = 0; k < 40; k++) {
        tu_frame f;
        rbs_frame_body *b;
        tu_frame_init(&f, (uint64_t)k, 0.05 * k);
        tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
        b = tu_add_sphere(&f, "ball", 0.1 * k, 0, 0.5, 0.5, 0xd03030);
        b->texture = RBS_TEXTURE_STRIPES;
        tu_add_sphere(&f, "other", 1, 1, 0.3, 0.3, 0x3050d0)->texture = RBS_TEXTURE_CHECKER;
        g_counting = 1;
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
        assert_int_equal(cls->command(inst, "camera", err, sizeof err), RBS_OK);
        g_counting = 0;
    }
    g_counting = 1;
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    g_counting = 0;
    assert_int_equal(g_count, 0);
    cls->destroy(inst);
}

static void test_no_allocation_per_frame(void **state)
{
    (void)state;
    run("{\"window\":false,\"width\":160,\"height\":120}", "one_view");
    run("{\"window\":false,\"width\":96,\"height\":64,\"views\":[{},"
        "{\"mode\":\"mounted\",\"mount\":\"ball\"},"
        "{\"path\":[{\"t\":0,\"position\":[0,-5,2],\"target\":[0,0,0]},"
        "{\"t\":1,\"position\":[5,0,2],\"target\":[0,0,0]}]}]}",
        "views");
    run("{\"window\":false,\"width\":96,\"height\":64,\"tile\":true,\"views\":[{},{}]}",
        "tile");
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_allocation_per_frame),
    };
    tu_set_base(argc > 1 ? argv[1] : ".");
    return cmocka_run_group_tests(tests, NULL, NULL);
}
