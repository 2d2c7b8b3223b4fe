/*
 * test_alloc.c - the methods allocate nothing per step.  malloc, calloc,
 * realloc and free are wrapped (-Wl,--wrap) and counted.  Verlet and RK4
 * worlds take exactly one allocation (their block); an adaptive world also
 * takes GSL's workspaces, once, at creation or when switched to adaptive,
 * and gives every one of them back in rbs_world_destroy.  Stepping 10,000
 * frames of a scene with impacts, resting contact, friction and mutual
 * gravity allocates nothing with any method.
 */
#include <stdlib.h>

#include "common.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

static int counting;
static long allocations, frees;

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
    if (counting && p) frees++;
    __real_free(p);
}

static rbs_world *scene(rbs_method m)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_material_id mat;
    int i;
    rbs_world_def_init(&d);
    d.max_bodies = 16;
    d.method = m;
    d.mutual_gravity = 1;
    d.gravity_constant = 1e-3;
    d.restitution = 0.8;
    CHECK_OK(rbs_world_create(&d, &w));
    mat = material(w, "felt", 0.4, 0.2, -1.0);
    floor_plane(w, mat);
    ball(w, 0.1, 1.0, -2, 0, 1.0, 0, 0, 0, mat);
    ball(w, 0.05, 0.2, 0, 0, 0.05, 3.0, 0, 0, mat);
    for (i = 0; i < 5; ++i)
        ball(w, 0.05, 0.2, 1.0 + 0.1 * i, 0, 0.05, 0, 0, 0, mat);
    return w;
}

static void no_allocation_while_stepping(void **state)
{
    const rbs_method ms[4] = {RBS_METHOD_VERLET, RBS_METHOD_RK4, RBS_METHOD_ADAPTIVE, RBS_METHOD_SOFT};
    int k, i;
    (void)state;
    for (k = 0; k < 4; ++k) {
        rbs_world *w;
        rbs_step_info info;
        long contacts = 0;
        allocations = frees = 0;
        counting = 1;
        w = scene(ms[k]);
        counting = 0;
        if (ms[k] == RBS_METHOD_ADAPTIVE)
            assert_true(allocations > 1); /* the block and GSL's workspaces */
        else
            assert_int_equal(allocations, 1);
        allocations = 0;
        counting = 1;
        for (i = 0; i < 10000; ++i) {
            CHECK_OK(rbs_world_step(w, &info));
            contacts += info.contacts;
        }
        counting = 0;
        assert_true(contacts > 1000); /* the scene really had contacts */
        assert_int_equal(allocations, 0);
        assert_int_equal(frees, 0);
        rbs_world_destroy(w);
    }
}

/* Switching to adaptive reserves once; switching back and forth again takes
 * nothing more; destroy frees all of it. */
static void adaptive_workspaces_once_and_freed(void **state)
{
    rbs_world *w;
    long after_switch;
    (void)state;
    allocations = frees = 0;
    counting = 1;
    w = scene(RBS_METHOD_EULER);
    assert_int_equal(allocations, 1);
    CHECK_OK(rbs_world_set_method(w, RBS_METHOD_ADAPTIVE, 1e-8));
    after_switch = allocations;
    assert_true(after_switch > 1);
    CHECK_OK(rbs_world_set_method(w, RBS_METHOD_RK4, 0.0));
    CHECK_OK(rbs_world_set_method(w, RBS_METHOD_ADAPTIVE, 1e-9));
    assert_int_equal(allocations, after_switch);
    CHECK_OK(rbs_world_step(w, NULL));
    rbs_world_destroy(w);
    counting = 0;
    assert_int_equal(frees, allocations);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(no_allocation_while_stepping),
        cmocka_unit_test(adaptive_workspaces_once_and_freed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
