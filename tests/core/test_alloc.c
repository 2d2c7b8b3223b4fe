/*
 * test_alloc.c - nothing that runs per step allocates.  malloc, calloc,
 * realloc and free are wrapped (-Wl,--wrap) and counted across 10,000 steps
 * of a scene with contacts (a ball bouncing then resting, a billiards-like
 * row of spheres, friction): the count must be zero.
 */
#include <stdlib.h>

#include "common.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

static int counting;
static long allocations;

void *__wrap_malloc(size_t n)
{
    if (counting) allocations++;
    return __real_malloc(n);
}
void *__wrap_calloc(size_t n, size_t m)
{
    if (counting) allocations++;
    return __real_calloc(n, m);
}
void *__wrap_realloc(void *p, size_t n)
{
    if (counting) allocations++;
    return __real_realloc(p, n);
}
void __wrap_free(void *p)
{
    if (counting && p) allocations++;
    __real_free(p);
}

static void no_allocation_while_stepping(void **state)
{
    rbs_world *w;
    /* the wrap sees the library's calls: creation allocates exactly once */
    counting = 1;
    w = make_world(16, 1e-3, -9.81, 0.8);
    counting = 0;
    assert_int_equal(allocations, 1);
    allocations = 0;
    {
    rbs_material_id m = material(w, "felt", 0.4, 0.2, -1.0);
    rbs_step_info info;
    long contacts = 0;
    int i, k;
    (void)state;
    floor_plane(w, m);
    ball(w, 0.1, 1.0, -2, 0, 1.0, 0, 0, 0, m);
    ball(w, 0.05, 0.2, 0, 0, 0.05, 3.0, 0, 0, m);
    for (i = 0; i < 5; ++i)
        ball(w, 0.05, 0.2, 1.0 + 0.1 * i, 0, 0.05, 0, 0, 0, m);
    counting = 1;
    for (k = 0; k < 10000; ++k) {
        CHECK_OK(rbs_world_step(w, &info));
        contacts += info.contacts;
    }
    counting = 0;
    assert_true(contacts > 10000); /* the scene really had contacts */
    assert_int_equal(allocations, 0);
    rbs_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(no_allocation_while_stepping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
