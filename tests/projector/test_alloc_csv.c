/*
 * test_alloc_csv.c - no allocation per step with the CSV renderer attached.
 *
 * malloc, calloc, realloc and free are wrapped at link time (-Wl,--wrap) and
 * the library's and the dumpers' objects are linked into this program, so
 * every call they make is counted.  The projector runs 1200 steps with a CSV
 * renderer (wrapped by a counting renderer that forwards to it); the count
 * is read when frame 200 is drawn (after warm-up: files open, stdio and the
 * threads set up) and again at frame 1100.  In between the simulation thread
 * steps and captures ~900 frames and the renderer thread formats and writes
 * them: the difference must be exactly zero.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "dump.h"
#include "rbsim/reel.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

static unsigned long allocations; /* atomic: both threads count */

void *__wrap_malloc(size_t n)
{
    __atomic_fetch_add(&allocations, 1, __ATOMIC_RELAXED);
    return __real_malloc(n);
}
void *__wrap_calloc(size_t n, size_t m)
{
    __atomic_fetch_add(&allocations, 1, __ATOMIC_RELAXED);
    return __real_calloc(n, m);
}
void *__wrap_realloc(void *p, size_t n)
{
    __atomic_fetch_add(&allocations, 1, __ATOMIC_RELAXED);
    return __real_realloc(p, n);
}
void __wrap_free(void *p)
{
    if (p != NULL)
        __atomic_fetch_add(&allocations, 1, __ATOMIC_RELAXED);
    __real_free(p);
}

#define WARM 200u
#define END 1100u

typedef struct counting {
    void *csv;
    unsigned long at_warm, at_end;
    int have_warm, have_end;
} counting;

typedef struct counting_ctx {
    counting *made;
} counting_ctx;

static rbs_status c_create(void *context, const rbs_renderer_config *config,
                           const rbs_world *world, void **instance, char *err,
                           size_t errlen)
{
    counting_ctx *ctx = context;
    counting *c = calloc(1, sizeof *c);
    rbs_status st = rbsf_csv_class()->create(rbsf_csv_class()->context, config,
                                             world, &c->csv, err, errlen);
    if (st != RBS_OK) {
        free(c);
        return st;
    }
    ctx->made = c;
    *instance = c;
    return RBS_OK;
}

static rbs_status c_draw(void *instance, const rbs_frame *f, char *err,
                         size_t errlen)
{
    counting *c = instance;
    rbs_status st;
    if (f->number == WARM) {
        c->at_warm = __atomic_load_n(&allocations, __ATOMIC_RELAXED);
        c->have_warm = 1;
    }
    st = rbsf_csv_class()->draw(c->csv, f, err, errlen);
    if (f->number == END) {
        c->at_end = __atomic_load_n(&allocations, __ATOMIC_RELAXED);
        c->have_end = 1;
    }
    return st;
}

static rbs_status c_finish(void *instance, char *err, size_t errlen)
{
    counting *c = instance;
    return rbsf_csv_class()->finish(c->csv, err, errlen);
}

static void c_destroy(void *instance)
{
    counting *c = instance;
    rbsf_csv_class()->destroy(c->csv);
    free(c);
}

static void no_allocation_per_step_with_csv(void **state)
{
    rbs_world_def wd;
    rbs_world *w;
    rbs_plane_def pd;
    rbs_sphere_def sd;
    rbs_body_id id;
    rbs_renderer_registry *reg;
    rbs_renderer_class cls;
    rbs_renderer_config cfg;
    rbs_projector_def def;
    rbs_projector *p;
    counting_ctx ctx;
    char path[64];
    int i;
    unsigned long got;
    (void)state;

    /* Spheres bouncing on a floor and on each other: contacts every step. */
    rbs_world_def_init(&wd);
    wd.max_bodies = 16;
    assert_int_equal(rbs_world_create(&wd, &w), RBS_OK);
    rbs_plane_def_init(&pd);
    pd.name = "floor";
    assert_int_equal(rbs_world_add_plane(w, &pd, &id), RBS_OK);
    for (i = 0; i < 8; i++) {
        char name[16];
        snprintf(name, sizeof name, "b%d", i);
        rbs_sphere_def_init(&sd);
        sd.name = name;
        sd.radius = 0.1;
        sd.position.x = 0.15 * i;
        sd.position.z = 0.1 + 0.05 * i;
        sd.velocity.x = i % 2 ? -1.0 : 1.0;
        assert_int_equal(rbs_world_add_sphere(w, &sd, &id), RBS_OK);
    }

    memset(&cls, 0, sizeof cls);
    cls.struct_size = sizeof cls;
    cls.name = "counting-csv";
    cls.context = &ctx;
    cls.create = c_create;
    cls.draw = c_draw;
    cls.finish = c_finish;
    cls.destroy = c_destroy;
    memset(&ctx, 0, sizeof ctx);
    assert_int_equal(rbs_renderer_registry_create(&reg), RBS_OK);
    assert_int_equal(rbs_renderer_register(reg, &cls), RBS_OK);
    snprintf(path, sizeof path, "/tmp/rbsim-alloc-%ld.csv", (long)getpid());
    memset(&cfg, 0, sizeof cfg);
    cfg.struct_size = sizeof cfg;
    cfg.type = "counting-csv";
    cfg.path = path;
    cfg.every = 1;
    rbs_projector_def_init(&def);
    def.steps = 1200;
    def.reel_capacity = 8;
    assert_int_equal(rbs_projector_create(w, reg, &cfg, 1, &def, &p), RBS_OK);
    assert_int_equal(rbs_projector_run(p), RBS_OK);
    assert_true(ctx.made->have_warm && ctx.made->have_end);
    got = ctx.made->at_end - ctx.made->at_warm;
    if (got != 0)
        print_message("%lu allocations during %u frames\n", got, END - WARM);
    assert_int_equal(got, 0);
    /* The count really counts: creating a reel allocates. */
    {
        rbs_reel *r;
        unsigned long before = __atomic_load_n(&allocations, __ATOMIC_RELAXED);
        assert_int_equal(rbs_reel_create(2, 1, RBS_REEL_LOSSLESS, &r), RBS_OK);
        assert_true(__atomic_load_n(&allocations, __ATOMIC_RELAXED) > before);
        rbs_reel_destroy(r);
    }
    rbs_projector_destroy(p);
    rbs_renderer_registry_destroy(reg);
    rbs_world_destroy(w);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(no_allocation_per_step_with_csv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
