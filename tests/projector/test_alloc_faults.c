/*
 * test_alloc_faults.c - allocation failures, SQLite style: fail the k-th
 * allocation for every k in a whole projector run (registry, projector and
 * renderers created, frames drawn by csv, json and stats, everything
 * destroyed) and check each time that the run reports an error (never a
 * silent success, never a crash) and that nothing leaks (every block
 * allocated is freed).  The allocator is wrapped at link time; the library's
 * and the dumpers' objects are linked in so that their calls are wrapped,
 * and cJSON (a shared library) is given the wrapped allocator through its
 * hooks.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#include <cmocka.h>

#include "dump.h"
#include "rbsim/reel.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

/* Shared by the run's threads: atomics. */
static long armed;      /* nonzero: count and maybe fail */
static long calls;      /* allocations seen while armed */
static long fail_at;    /* fail the call with this number (1-based), 0: none */
static long failed;     /* an allocation was failed */
static long live;       /* blocks allocated while armed minus freed */

static int should_fail(void)
{
    long n;
    if (!__atomic_load_n(&armed, __ATOMIC_SEQ_CST))
        return 0;
    n = __atomic_add_fetch(&calls, 1, __ATOMIC_SEQ_CST);
    if (n == __atomic_load_n(&fail_at, __ATOMIC_SEQ_CST)) {
        __atomic_store_n(&failed, 1, __ATOMIC_SEQ_CST);
        return 1;
    }
    return 0;
}

static void count(void *p, long d)
{
    if (p != NULL && __atomic_load_n(&armed, __ATOMIC_SEQ_CST))
        __atomic_add_fetch(&live, d, __ATOMIC_SEQ_CST);
}

void *__wrap_malloc(size_t n)
{
    void *p;
    if (should_fail())
        return NULL;
    p = __real_malloc(n);
    count(p, 1);
    return p;
}
void *__wrap_calloc(size_t n, size_t m)
{
    void *p;
    if (should_fail())
        return NULL;
    p = __real_calloc(n, m);
    count(p, 1);
    return p;
}
void *__wrap_realloc(void *p, size_t n)
{
    void *q;
    if (should_fail())
        return NULL;
    q = __real_realloc(p, n);
    if (p == NULL)
        count(q, 1);
    return q;
}
void __wrap_free(void *p)
{
    count(p, -1);
    __real_free(p);
}

/* One whole run; returns its status (the first error on the way). */
static rbs_status scenario(rbs_world *w, const char *dir)
{
    rbs_renderer_registry *reg = NULL;
    rbs_projector *p = NULL;
    rbs_renderer_config cfg[3];
    rbs_projector_def def;
    char paths[3][256];
    rbs_status st;
    int i;

    st = rbs_renderer_registry_create(&reg);
    if (st != RBS_OK)
        return st;
    if ((st = rbs_renderer_register(reg, rbsf_csv_class())) != RBS_OK ||
        (st = rbs_renderer_register(reg, rbsf_json_class())) != RBS_OK ||
        (st = rbs_renderer_register(reg, rbsf_stats_class())) != RBS_OK) {
        rbs_renderer_registry_destroy(reg);
        return st;
    }
    memset(cfg, 0, sizeof cfg);
    for (i = 0; i < 3; i++) {
        static const char *const types[] = {"csv", "json", "stats"};
        snprintf(paths[i], sizeof paths[i], "%s/out.%s", dir, types[i]);
        cfg[i].struct_size = sizeof cfg[i];
        cfg[i].type = types[i];
        cfg[i].path = paths[i];
        cfg[i].every = 1;
    }
    rbs_projector_def_init(&def);
    def.steps = 8;
    def.reel_capacity = 4;
    st = rbs_projector_create(w, reg, cfg, 3, &def, &p);
    if (st == RBS_OK)
        st = rbs_projector_run(p);
    rbs_projector_destroy(p); /* NULL ok */
    rbs_renderer_registry_destroy(reg);
    return st;
}

static rbs_world *make_world(void)
{
    rbs_world_def wd;
    rbs_world *w;
    rbs_plane_def pd;
    rbs_sphere_def sd;
    rbs_body_id id;
    rbs_world_def_init(&wd);
    wd.max_bodies = 4;
    assert_int_equal(rbs_world_create(&wd, &w), RBS_OK);
    rbs_plane_def_init(&pd);
    pd.name = "floor";
    assert_int_equal(rbs_world_add_plane(w, &pd, &id), RBS_OK);
    rbs_sphere_def_init(&sd);
    sd.name = "ball";
    sd.position.z = 0.2;
    assert_int_equal(rbs_world_add_sphere(w, &sd, &id), RBS_OK);
    return w;
}

static void every_allocation_failure_is_reported_without_leaks(void **state)
{
    char dir[64];
    long k, total;
    cJSON_Hooks hooks;
    (void)state;
    hooks.malloc_fn = __wrap_malloc;
    hooks.free_fn = __wrap_free;
    cJSON_InitHooks(&hooks);
    snprintf(dir, sizeof dir, "/tmp/rbsim-faults-%ld", (long)getpid());
    assert_int_equal(mkdir(dir, 0777) == 0 || access(dir, W_OK) == 0, 1);

    /* A clean run first: how many allocations a run makes. */
    {
        rbs_world *w = make_world();
        __atomic_store_n(&calls, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&live, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&fail_at, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&armed, 1, __ATOMIC_SEQ_CST);
        assert_int_equal(scenario(w, dir), RBS_OK);
        __atomic_store_n(&armed, 0, __ATOMIC_SEQ_CST);
        total = calls;
        assert_int_equal(live, 0);
        rbs_world_destroy(w);
    }
    print_message("a run makes %ld allocations\n", total);
    assert_true(total > 9 * 10); /* json allocates per frame: it counts */

    for (k = 1; k <= total; k++) {
        rbs_world *w = make_world();
        rbs_status st;
        __atomic_store_n(&calls, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&live, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&failed, 0, __ATOMIC_SEQ_CST);
        __atomic_store_n(&fail_at, k, __ATOMIC_SEQ_CST);
        __atomic_store_n(&armed, 1, __ATOMIC_SEQ_CST);
        st = scenario(w, dir);
        __atomic_store_n(&armed, 0, __ATOMIC_SEQ_CST);
        if (failed && st == RBS_OK)
            print_message("allocation %ld failed but the run said OK\n", k);
        if (live != 0)
            print_message("allocation %ld failed: %ld blocks leaked\n", k, live);
        assert_false(failed && st == RBS_OK);
        assert_int_equal(live, 0);
        rbs_world_destroy(w);
    }
    {
        static const char *const ext[] = {"csv", "json", "stats"};
        int i;
        for (i = 0; i < 3; i++) {
            char path[96];
            snprintf(path, sizeof path, "%s/out.%s", dir, ext[i]);
            unlink(path);
        }
    }
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_allocation_failure_is_reported_without_leaks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
