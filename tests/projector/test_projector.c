/*
 * test_projector.c - the projector with test renderers: frames 0..steps in
 * order with the world's exact state, "every K", several renderers seeing the
 * same frames, commands (pause, step, resume, speed, status, quit, renderer
 * commands answered on the renderer thread), control from a renderer,
 * failures (check, create, draw, finish, a step's numerical failure) that
 * stop the run with a message, the registry, the after_step hook (and its
 * failure), quit ending the world at the last frame drawn, and a run
 * resumed from a stepped world (skip_first_frame, frame numbers kept).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "rbsim/reel.h"
#include "raw_state.h"

#define CHECK_OK(call) assert_int_equal((call), RBS_OK)

/* ---- a world: a floor and three falling spheres ------------------------- */

static rbs_world *make_world(void)
{
    rbs_world_def wd;
    rbs_world *w;
    rbs_plane_def pd;
    rbs_sphere_def sd;
    rbs_body_id id;
    int i;
    rbs_world_def_init(&wd);
    wd.max_bodies = 8;
    CHECK_OK(rbs_world_create(&wd, &w));
    rbs_plane_def_init(&pd);
    pd.name = "floor";
    CHECK_OK(rbs_world_add_plane(w, &pd, &id));
    for (i = 0; i < 3; i++) {
        char name[16];
        snprintf(name, sizeof name, "ball%d", i);
        rbs_sphere_def_init(&sd);
        sd.name = name;
        sd.radius = 0.1;
        sd.position.x = 0.5 * i;
        sd.position.z = 0.3 + 0.1 * i;
        sd.velocity.x = 0.25 * i;
        sd.angular_velocity.y = 1.0 + i;
        CHECK_OK(rbs_world_add_sphere(w, &sd, &id));
    }
    return w;
}

/* Monotonic seconds. */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- a recording renderer ----------------------------------------------- */

typedef struct rec_opts {
    int fail_check, fail_create, fail_draw_at, fail_finish;
    int draw_code; /* what draw returns at fail_draw_at (0: RBS_E_IO), and a
                      failing check, create or finish (0: their own) */
    int quit_at;          /* send "quit" through control at this frame, -1 */
    int live;
    int draw_ms;          /* each draw takes this long (a slow renderer) */
    int *created, *destroyed; /* counters shared by the test */
} rec_opts;

typedef struct rec {
    rec_opts opts;
    rbs_renderer_config config;
    uint64_t *numbers;
    double *x;           /* ball0 position x per drawn frame */
    uint64_t count, cap;
    uint64_t repeats;
    int lasts, finished, out_of_thread;
    pthread_t draw_thread;
    int have_thread;
    rbs_frame_body final[8];
    uint32_t final_count;
} rec;

/* The test reaches the instances through these (single test at a time). */
typedef struct rec_ctx {
    rec_opts opts;
    rec *made[RBS_RENDERERS_MAX];
    int n;
} rec_ctx;

static rbs_status rec_check(void *context, const rbs_renderer_config *config,
                            const rbs_world *world, char *err, size_t errlen)
{
    rec_ctx *c = context;
    (void)config;
    (void)world;
    if (c->opts.fail_check) {
        snprintf(err, errlen, "check says no");
        return c->opts.draw_code != 0 ? (rbs_status)c->opts.draw_code : RBS_E_SCENE;
    }
    return RBS_OK;
}

static rbs_status rec_create(void *context, const rbs_renderer_config *config,
                             const rbs_world *world, void **instance, char *err,
                             size_t errlen)
{
    rec_ctx *c = context;
    rec *r;
    (void)world;
    if (c->opts.fail_create) {
        snprintf(err, errlen, "cannot create");
        return c->opts.draw_code != 0 ? (rbs_status)c->opts.draw_code : RBS_E_IO;
    }
    r = calloc(1, sizeof *r);
    r->opts = c->opts;
    r->config = *config;
    r->cap = 1 << 16;
    r->numbers = calloc(r->cap, sizeof *r->numbers);
    r->x = calloc(r->cap, sizeof *r->x);
    if (c->opts.created)
        (*c->opts.created)++;
    c->made[c->n++] = r;
    *instance = r;
    return RBS_OK;
}

static rbs_status rec_draw(void *instance, const rbs_frame *f, char *err,
                           size_t errlen)
{
    rec *r = instance;
    if (!r->have_thread) {
        r->draw_thread = pthread_self();
        r->have_thread = 1;
    } else if (!pthread_equal(r->draw_thread, pthread_self())) {
        r->out_of_thread++;
    }
    if (f->paused && r->count > 0 && r->numbers[r->count - 1] == f->number) {
        r->repeats++;
        return RBS_OK;
    }
    if (r->opts.fail_draw_at >= 0 && f->number == (uint64_t)r->opts.fail_draw_at) {
        snprintf(err, errlen, "disk on fire");
        return r->opts.draw_code != 0 ? (rbs_status)r->opts.draw_code : RBS_E_IO;
    }
    if (r->count < r->cap) {
        r->numbers[r->count] = f->number;
        r->x[r->count] = f->body_count > 1 ? f->bodies[1].position[0] : 0;
        r->count++;
    }
    r->lasts += f->last != 0;
    if (r->opts.draw_ms > 0) {
        struct timespec nap = {0, (long)r->opts.draw_ms * 1000000L};
        nanosleep(&nap, NULL);
    }
    memcpy(r->final, f->bodies, f->body_count * sizeof *f->bodies);
    r->final_count = f->body_count;
    if (r->opts.quit_at >= 0 && f->number == (uint64_t)r->opts.quit_at)
        r->config.control(r->config.control_context, "quit");
    return RBS_OK;
}

static rbs_status rec_finish(void *instance, char *err, size_t errlen)
{
    rec *r = instance;
    r->finished++;
    if (r->opts.fail_finish) {
        snprintf(err, errlen, "cannot close");
        return r->opts.draw_code != 0 ? (rbs_status)r->opts.draw_code : RBS_E_IO;
    }
    return RBS_OK;
}

static void rec_destroy(void *instance)
{
    rec *r = instance;
    if (r->opts.destroyed)
        (*r->opts.destroyed)++;
    free(r->numbers);
    free(r->x);
    free(r);
}

/* Renderer commands: "ping" answers with the thread check. */
static rbs_status rec_command(void *instance, const char *line, char *out,
                              size_t outlen)
{
    rec *r = instance;
    if (strncmp(line, "ping", 4) != 0)
        return RBS_E_NOT_FOUND;
    snprintf(out, outlen, "pong%s",
             r->have_thread && !pthread_equal(r->draw_thread, pthread_self())
                 ? " from another thread"
                 : "");
    return RBS_OK;
}

static rbs_renderer_class rec_class(rec_ctx *ctx, const char *name)
{
    rbs_renderer_class c;
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.name = name;
    c.context = ctx;
    c.create = rec_create;
    c.draw = rec_draw;
    c.finish = rec_finish;
    c.destroy = rec_destroy;
    c.command = rec_command;
    c.check = rec_check;
    c.flags = ctx->opts.live ? RBS_RENDERER_LIVE : 0;
    return c;
}

static void default_opts(rec_ctx *ctx)
{
    memset(ctx, 0, sizeof *ctx);
    ctx->opts.fail_draw_at = -1;
    ctx->opts.quit_at = -1;
}

static rbs_renderer_config config_for(const char *type, uint32_t every)
{
    rbs_renderer_config c;
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.type = type;
    c.every = every;
    return c;
}

/* ---- a fixture: a world, recorder classes and a projector ---------------- */

/* The classes `name` (context ctx) and, unless NULL, `other_name` (context
 * other); cfg[0..n) holds a renderer of each, every frame.  The test adjusts
 * the options, cfg and def between fx_init and fx_create. */
typedef struct fixture {
    rbs_world *w;
    rbs_renderer_registry *reg;
    const char *name, *other_name;
    rec_ctx ctx, other;
    rbs_renderer_config cfg[RBS_RENDERERS_MAX];
    uint32_t n;
    rbs_projector_def def;
    rbs_projector *p;
} fixture;

static void fx_init(fixture *fx, const char *name, const char *other_name)
{
    memset(fx, 0, sizeof *fx);
    fx->w = make_world();
    fx->name = name;
    fx->other_name = other_name;
    default_opts(&fx->ctx);
    default_opts(&fx->other);
    fx->cfg[fx->n++] = config_for(name, 1);
    if (other_name != NULL)
        fx->cfg[fx->n++] = config_for(other_name, 1);
    rbs_projector_def_init(&fx->def);
}

/* The registry with the classes (a class takes its flags from the options:
 * set them first). */
static void fx_register(fixture *fx)
{
    rbs_renderer_class c = rec_class(&fx->ctx, fx->name);
    CHECK_OK(rbs_renderer_registry_create(&fx->reg));
    CHECK_OK(rbs_renderer_register(fx->reg, &c));
    if (fx->other_name != NULL) {
        c = rec_class(&fx->other, fx->other_name);
        CHECK_OK(rbs_renderer_register(fx->reg, &c));
    }
}

/* The projector over cfg[0..n) with def. */
static rbs_status fx_project(fixture *fx)
{
    return rbs_projector_create(fx->w, fx->reg, fx->cfg, fx->n, &fx->def,
                                &fx->p);
}

static rbs_status fx_create(fixture *fx)
{
    fx_register(fx);
    return fx_project(fx);
}

/* The projector, then the registry it uses, then the world. */
static void fx_done(fixture *fx)
{
    rbs_projector_destroy(fx->p);
    rbs_renderer_registry_destroy(fx->reg);
    rbs_world_destroy(fx->w);
}

/* ---- tests -------------------------------------------------------------- */

static void registry_finds_and_rejects(void **state)
{
    rbs_renderer_registry *reg;
    rec_ctx ctx;
    rbs_renderer_class c;
    const rbs_renderer_class *found;
    int i;
    char names[RBS_RENDERER_TYPES_MAX + 1][16];
    (void)state;
    default_opts(&ctx);
    CHECK_OK(rbs_renderer_registry_create(&reg));
    c = rec_class(&ctx, "rec");
    CHECK_OK(rbs_renderer_register(reg, &c));
    assert_int_equal(rbs_renderer_register(reg, &c), RBS_E_INVALID); /* taken */
    CHECK_OK(rbs_renderer_find(reg, "rec", &found));
    assert_ptr_equal(found->context, &ctx);
    assert_int_equal(rbs_renderer_find(reg, "nope", &found), RBS_E_NOT_FOUND);
    assert_null(found);
    c.name = NULL;
    assert_int_equal(rbs_renderer_register(reg, &c), RBS_E_INVALID);
    c.name = "x";
    c.draw = NULL;
    assert_int_equal(rbs_renderer_register(reg, &c), RBS_E_INVALID);
    c = rec_class(&ctx, "rec");
    for (i = 1; i < RBS_RENDERER_TYPES_MAX; i++) {
        snprintf(names[i], sizeof names[i], "t%d", i);
        c.name = names[i];
        CHECK_OK(rbs_renderer_register(reg, &c));
    }
    snprintf(names[0], sizeof names[0], "one-too-many");
    c.name = names[0];
    assert_int_equal(rbs_renderer_register(reg, &c), RBS_E_CAPACITY);
    rbs_renderer_registry_destroy(reg);
}

/* Run fx's projector to the end with n "rec" recorders of every frame, and
 * destroy it (the registry stays until fx_done). */
static rbs_status run_with(fixture *fx, uint32_t n, uint64_t steps)
{
    rbs_status st;
    uint32_t i;
    for (i = 0; i < n; i++)
        fx->cfg[i] = config_for("rec", 1);
    fx->n = n;
    fx->def.steps = steps;
    fx->def.reel_capacity = 4;
    st = fx_create(fx);
    if (st == RBS_OK)
        st = rbs_projector_run(fx->p);
    rbs_projector_destroy(fx->p);
    fx->p = NULL;
    return st;
}

static void every_frame_in_order_with_exact_state(void **state)
{
    fixture fx;
    rec *r;
    uint64_t k;
    rbs_state_view v;
    rbs_run_info info;
    int created = 0, destroyed = 0;
    uint32_t b;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.ctx.opts.created = &created;
    fx.ctx.opts.destroyed = &destroyed;
    fx.def.steps = 500;
    fx.def.reel_capacity = 3;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.state, RBS_RUN_READY);
    CHECK_OK(rbs_projector_run(fx.p));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_OK); /* repeatable */
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.state, RBS_RUN_DONE);
    assert_int_equal(info.result, RBS_OK);
    assert_int_equal(info.frame, 500);
    assert_int_equal(info.drawn, 501);
    assert_int_equal(info.captured, 501);
    assert_true(info.time == rbs_world_time(fx.w));
    /* The instance is read while the projector keeps it. */
    r = fx.ctx.made[0];
    assert_int_equal(r->count, 501);
    for (k = 0; k <= 500; k++)
        assert_int_equal(r->numbers[k], k);
    assert_int_equal(r->lasts, 1);
    assert_int_equal(r->finished, 1);
    assert_int_equal(r->out_of_thread, 0);
    /* The last frame holds the world's state bit for bit. */
    CHECK_OK(rbs_world_state(fx.w, &v));
    assert_int_equal(r->final_count, 4);
    for (b = 0; b < r->final_count; b++) {
        uint32_t s = r->final[b].slot;
        assert_memory_equal(r->final[b].position, v.position + 3 * s,
                            3 * sizeof(double));
        assert_memory_equal(r->final[b].velocity, v.velocity + 3 * s,
                            3 * sizeof(double));
        assert_memory_equal(r->final[b].angular_velocity,
                            v.angular_velocity + 3 * s, 3 * sizeof(double));
        assert_memory_equal(r->final[b].orientation, v.orientation + 4 * s,
                            4 * sizeof(double));
    }
    assert_string_equal(r->final[1].name, "ball0");
    assert_int_equal(r->final[0].type, RBS_BODY_PLANE);
    assert_int_equal(r->final[1].type, RBS_BODY_SPHERE);
    assert_true(r->final[1].radius == 0.1);
    rbs_projector_destroy(fx.p);
    fx.p = NULL;
    assert_int_equal(destroyed, 1);
    assert_int_equal(created, 1);
    fx_done(&fx);
}

/* Frame 0 only when steps is 0; its time is 0 and it is the last. */
static void zero_steps_gives_frame_zero(void **state)
{
    fixture fx;
    (void)state;
    fx_init(&fx, "rec", NULL);
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_run(fx.p));
    assert_int_equal(fx.ctx.made[0]->count, 1);
    assert_int_equal(fx.ctx.made[0]->numbers[0], 0);
    assert_int_equal(fx.ctx.made[0]->lasts, 1);
    assert_true(rbs_world_time(fx.w) == 0.0);
    fx_done(&fx);
}

static void every_k_keeps_multiples_and_the_last(void **state)
{
    fixture fx;
    const uint32_t every[4] = {1, 7, 100, 1000};
    uint32_t i;
    uint64_t k;
    (void)state;
    fx_init(&fx, "rec", NULL);
    for (i = 0; i < 4; i++)
        fx.cfg[i] = config_for("rec", every[i]);
    fx.n = 4;
    fx.def.steps = 250;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_run(fx.p));
    for (i = 0; i < 4; i++) {
        rec *r = fx.ctx.made[i];
        uint64_t n = 0;
        for (k = 0; k <= 250; k++)
            if (k % every[i] == 0 || k == 250) {
                assert_true(n < r->count);
                assert_int_equal(r->numbers[n], k);
                /* Every renderer sees the same frame contents. */
                assert_memory_equal(&r->x[n], &fx.ctx.made[0]->x[k],
                                    sizeof(double));
                n++;
            }
        assert_int_equal(r->count, n);
    }
    fx_done(&fx);
}

/* rbs_frame_written, the every-K rule the projector draws by and rbsim
 * run checks its png folders by, at its edges (expected values from the
 * rule as reel.h states it: a multiple of K, the starting frame unless a
 * resumed run skips it, the last unless the run is continued; nothing
 * before the start). */
static void frame_written_edges(void **state)
{
    uint64_t n;
    (void)state;
    /* K = 1 (and 0, which means 1): every frame from the start on */
    for (n = 5; n <= 9; n++) {
        assert_int_equal(rbs_frame_written(n, 1, 5, 0, 0, 0), 1);
        assert_int_equal(rbs_frame_written(n, 0, 5, 0, 0, 0), 1);
        assert_int_equal(rbs_frame_written(n, 1, 5, 0, n == 9, 1), 1);
    }
    assert_int_equal(rbs_frame_written(4, 1, 5, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(0, 1, 5, 0, 0, 0), 0);
    /* K = 7 from frame 0: the first frame, the multiples, not the others */
    assert_int_equal(rbs_frame_written(0, 7, 0, 0, 0, 0), 1);
    assert_int_equal(rbs_frame_written(1, 7, 0, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(6, 7, 0, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(7, 7, 0, 0, 0, 0), 1);
    assert_int_equal(rbs_frame_written(14, 7, 0, 0, 0, 0), 1);
    /* the last frame: kept, unless the run is continued from it (then only
     * as a multiple of K, as the whole run would keep it) */
    assert_int_equal(rbs_frame_written(13, 7, 0, 0, 1, 0), 1);
    assert_int_equal(rbs_frame_written(13, 7, 0, 0, 1, 1), 0);
    assert_int_equal(rbs_frame_written(14, 7, 0, 0, 1, 1), 1);
    /* a run from a world that has stepped (start 5, drawn): its start is
     * kept though no multiple of 7; frames before it are not the run's */
    assert_int_equal(rbs_frame_written(5, 7, 5, 0, 0, 0), 1);
    assert_int_equal(rbs_frame_written(6, 7, 5, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(0, 7, 5, 0, 0, 0), 0);
    /* resumed (skip_first): the starting frame is not drawn, not even as a
     * multiple of K or as the last of a run of no steps */
    assert_int_equal(rbs_frame_written(5, 7, 5, 1, 0, 0), 0);
    assert_int_equal(rbs_frame_written(14, 7, 14, 1, 0, 0), 0);
    assert_int_equal(rbs_frame_written(14, 1, 14, 1, 1, 0), 0);
    assert_int_equal(rbs_frame_written(15, 7, 14, 1, 0, 0), 0);
    assert_int_equal(rbs_frame_written(21, 7, 14, 1, 0, 0), 1);
    assert_int_equal(rbs_frame_written(20, 7, 14, 1, 1, 0), 1);
    assert_int_equal(rbs_frame_written(20, 7, 14, 1, 1, 1), 0);
    /* a run of no steps, not resumed: its one frame is first and last */
    assert_int_equal(rbs_frame_written(3, 7, 3, 0, 1, 1), 1);
    /* the largest K and frame numbers near 2^64 (no overflow) */
    assert_int_equal(rbs_frame_written(2ull * RBS_EVERY_MAX, RBS_EVERY_MAX, 1, 0, 0, 0), 1);
    assert_int_equal(rbs_frame_written(2ull * RBS_EVERY_MAX + 1, RBS_EVERY_MAX, 1, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(UINT64_MAX, 1, 0, 0, 0, 0), 1);
    assert_int_equal(rbs_frame_written(UINT64_MAX, 2, 0, 0, 0, 0), 0);
    assert_int_equal(rbs_frame_written(UINT64_MAX, 2, 0, 0, 1, 0), 1);
    assert_int_equal(rbs_frame_written(UINT64_MAX, 2, UINT64_MAX, 1, 1, 0), 0);
}

/* A caller compiled against an older, shorter rbs_renderer_config: the
 * array's stride is its struct_size. */
typedef struct old_config {
    uint32_t struct_size;
    const char *type, *path;
    uint32_t every;
    const char *json, *file;
    int32_t line, column;
} old_config;

static void older_config_arrays_are_read_by_their_size(void **state)
{
    fixture fx;
    old_config old[2];
    rbs_renderer_config unset;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx_register(&fx);
    memset(old, 0, sizeof old);
    old[0].struct_size = old[1].struct_size = sizeof old[0];
    old[0].type = old[1].type = "rec";
    old[0].every = 1;
    old[1].every = 10;
    fx.def.steps = 20;
    CHECK_OK(rbs_projector_create(fx.w, fx.reg,
                                  (const rbs_renderer_config *)(void *)old, 2,
                                  &fx.def, &fx.p));
    CHECK_OK(rbs_projector_run(fx.p));
    assert_int_equal(fx.ctx.made[0]->count, 21);
    assert_int_equal(fx.ctx.made[1]->count, 3); /* 0, 10, 20 */
    /* The control hook the old caller has no room for is still given. */
    assert_non_null(fx.ctx.made[1]->config.control);
    rbs_projector_destroy(fx.p);
    /* struct_size not set: refused with a message. */
    memset(&unset, 0, sizeof unset);
    unset.type = "rec";
    assert_int_equal(
        rbs_projector_create(fx.w, fx.reg, &unset, 1, &fx.def, &fx.p),
        RBS_E_INVALID);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "struct_size"));
    fx_done(&fx);
}

/* A run with four renderers ends in the same world state as with none. */
static void renderers_do_not_change_results(void **state)
{
    fixture a, b;
    (void)state;
    fx_init(&a, "rec", NULL);
    fx_init(&b, "rec", NULL);
    CHECK_OK(run_with(&a, 0, 300));
    CHECK_OK(run_with(&b, 4, 300));
    assert_int_equal(rbs_world_step_count(a.w), 300);
    assert_true(rbs_world_hash(a.w) == rbs_world_hash(b.w));
    fx_done(&a);
    fx_done(&b);
}

/* In the fixtures below ctx is the "good" class's, other the "bad" one's. */
static void failing_check_creates_nothing(void **state)
{
    fixture fx;
    int created = 0;
    (void)state;
    fx_init(&fx, "good", "bad");
    fx.ctx.opts.created = &created;
    fx.other.opts.fail_check = 1;
    fx.cfg[1].file = "scene.json";
    fx.cfg[1].line = 12;
    fx.cfg[1].column = 5;
    fx.def.steps = 10;
    assert_int_equal(fx_create(&fx), RBS_E_SCENE);
    assert_non_null(fx.p);
    assert_int_equal(created, 0); /* the good one was never created */
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "scene.json:12:5"));
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "check says no"));
    assert_int_equal(rbs_projector_start(fx.p), RBS_E_INVALID);
    rbs_projector_destroy(fx.p);

    /* Unknown type. */
    fx.cfg[1] = config_for("nonesuch", 1);
    assert_int_equal(fx_project(&fx), RBS_E_NOT_FOUND);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "nonesuch"));
    rbs_projector_destroy(fx.p);

    /* Too many renderers, bad def: plain RBS_E_INVALID, no projector. */
    fx.n = RBS_RENDERERS_MAX + 1;
    assert_int_equal(fx_project(&fx), RBS_E_INVALID);
    assert_null(fx.p);
    fx.n = 1;
    fx.def.speed = -1;
    assert_int_equal(fx_project(&fx), RBS_E_INVALID);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "speed"));
    fx_done(&fx);
}

static void failing_create_destroys_the_others(void **state)
{
    fixture fx;
    int created = 0, destroyed = 0;
    (void)state;
    fx_init(&fx, "good", "bad");
    fx.ctx.opts.created = &created;
    fx.ctx.opts.destroyed = &destroyed;
    fx.other.opts.fail_create = 1;
    fx.cfg[1].path = "out.x";
    assert_int_equal(fx_create(&fx), RBS_E_IO);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "bad renderer 'out.x'"));
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "cannot create"));
    assert_int_equal(created, 1);
    rbs_projector_destroy(fx.p);
    fx.p = NULL;
    assert_int_equal(destroyed, 1);
    fx_done(&fx);
}

/* A renderer failing mid-run stops the run with its message; the other
 * renderer is finished (complete up to the frames drawn). */
static void failing_draw_stops_the_run(void **state)
{
    fixture fx;
    rbs_run_info info;
    uint64_t k;
    (void)state;
    fx_init(&fx, "good", "bad");
    fx.other.opts.fail_draw_at = 40;
    fx.cfg[1].path = "x.out";
    fx.def.steps = 100000; /* would take long: the failure must stop it */
    fx.def.reel_capacity = 8;
    CHECK_OK(fx_create(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_IO);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "bad renderer 'x.out'"));
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "frame 40"));
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "disk on fire"));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.result, RBS_E_IO);
    assert_true(info.captured < 100); /* stopped within a reel's worth */
    /* The good renderer drew 0..40 (the frame the other failed on may be
     * drawn by it first) and was finished. */
    assert_true(fx.ctx.made[0]->count == 40 || fx.ctx.made[0]->count == 41);
    for (k = 0; k < fx.ctx.made[0]->count; k++)
        assert_int_equal(fx.ctx.made[0]->numbers[k], k);
    assert_int_equal(fx.ctx.made[0]->finished, 1);
    assert_int_equal(fx.other.made[0]->finished, 1);
    fx_done(&fx);
}

/* A draw that returns a code that is no rbs_status (a renderer's own 5)
 * ends the run with RBS_E_RENDERER naming the code, never with 5. */
static void foreign_draw_code_is_a_renderer_error(void **state)
{
    fixture fx;
    rbs_run_info info;
    (void)state;
    fx_init(&fx, "good", "bad");
    fx.other.opts.fail_draw_at = 3;
    fx.other.opts.draw_code = 5;
    fx.cfg[1].path = "x.out";
    fx.def.steps = 100;
    CHECK_OK(fx_create(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_RENDERER);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "draw returned 5, not an rbs_status"));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.result, RBS_E_RENDERER);
    fx_done(&fx);
}

/* The same for check, create and finish: a renderer's own 42 passed out
 * of rbs_projector_create and rbs_projector_wait as 42 (a probe of session
 * 40); now RBS_E_RENDERER naming the code. */
static void foreign_codes_of_every_call_are_renderer_errors(void **state)
{
    int which;
    (void)state;
    for (which = 0; which < 3; ++which) {
        fixture fx;
        fx_init(&fx, "good", "bad");
        fx.other.opts.fail_check = which == 0;
        fx.other.opts.fail_create = which == 1;
        fx.other.opts.fail_finish = which == 2;
        fx.other.opts.draw_code = 42;
        fx.def.steps = 10;
        if (which < 2) {
            assert_int_equal(fx_create(&fx), RBS_E_RENDERER);
        } else {
            CHECK_OK(fx_create(&fx));
            assert_int_equal(rbs_projector_run(fx.p), RBS_E_RENDERER);
        }
        assert_non_null(strstr(rbs_projector_last_error(fx.p),
                               which == 0   ? "check returned 42, not an rbs_status: check says no"
                               : which == 1 ? "create returned 42, not an rbs_status"
                                            : "finish returned 42, not an rbs_status"));
        fx_done(&fx);
    }
}

static void failing_finish_is_reported(void **state)
{
    fixture fx;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.ctx.opts.fail_finish = 1;
    assert_int_equal(run_with(&fx, 1, 5), RBS_E_IO);
    fx_done(&fx);
}

/* A step's failure stops the run with the world's message; frames made
 * before it are all drawn. */
static void numerical_failure_stops_the_run(void **state)
{
    fixture fx;
    rbs_body_id id;
    rbs_vec3 huge = {1e308, 0, 0};
    rbs_status st;
    (void)state;
    fx_init(&fx, "rec", NULL);
    CHECK_OK(rbs_world_find_body(fx.w, "ball0", &id));
    CHECK_OK(rbs_body_set_force(fx.w, id, huge));
    fx.def.steps = 100000;
    CHECK_OK(fx_create(&fx));
    st = rbs_projector_run(fx.p);
    print_message("%s\n", rbs_projector_last_error(fx.p));
    if (st == RBS_OK) {
        /* The core took it: then nothing to see here, but say so. */
        print_message("core accepted a 1e308 N force for 100000 steps\n");
        fail();
    }
    /* The step or the capture of its frame (the energy overflows first)
     * fails: either way a numerical failure naming the time. */
    assert_int_equal(st, RBS_E_NUMERIC);
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "t = "));
    assert_non_null(strstr(rbs_projector_last_error(fx.p), "numerical failure"));
    assert_true(fx.ctx.made[0]->count >= 1);
    assert_int_equal(fx.ctx.made[0]->numbers[fx.ctx.made[0]->count - 1],
                     fx.ctx.made[0]->count - 1);
    assert_int_equal(fx.ctx.made[0]->finished, 1);
    fx_done(&fx);
}

/* A momentum that overflows at the first frame: the message said only
 * "frame capture at t = 0 s failed: momentum: numerical failure (NaN,
 * infinity or overflow)"; it names the sphere and the term now.  (The
 * setters refuse this state since session 50, as add_sphere does, but a
 * step can reach one: it is written directly.) */
static void momentum_failure_names_the_body(void **state)
{
    fixture fx;
    rbs_body_id id;
    rbs_vec3 far = {1e300, 1e300, 1}, fast = {1e100, 0, 0};
    const char *msg;
    (void)state;
    fx_init(&fx, "rec", NULL);
    CHECK_OK(rbs_world_find_body(fx.w, "ball0", &id));
    raw_set(fx.w, id, RAW_POSITION, far);
    raw_set(fx.w, id, RAW_VELOCITY, fast);
    fx.def.steps = 10;
    CHECK_OK(fx_create(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_NUMERIC);
    msg = rbs_projector_last_error(fx.p);
    print_message("%s\n", msg);
    assert_non_null(strstr(msg, "frame capture at t = 0 s failed: momentum: "));
    assert_non_null(strstr(msg, "(\"ball0\"): its angular momentum r x m v about the "
                                "origin overflows (|r| = 1.41421e+300 m, |m v| = "));
    fx_done(&fx);
}

/* Real time, the simulation a reel ahead: pause holds the display at once
 * on the frame the reply names; step N shows N more; a step past the end
 * saturates (no wrap-around); recorders get every frame once, in order. */
static void realtime_pause_holds_the_display(void **state)
{
    fixture fx;
    rbs_run_info info;
    char reply[512], want[96];
    unsigned long long held;
    uint64_t k;
    struct timespec nap = {0, 20 * 1000 * 1000};
    int tries;
    rec *r;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 2000;
    fx.def.realtime = 1;
    fx.def.speed = 0.05; /* dt 1 ms: a frame every 20 ms */
    fx.def.reel_capacity = 64;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    for (tries = 0; tries < 500; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.drawn >= 4)
            break;
        nanosleep(&nap, NULL);
    }
    CHECK_OK(rbs_projector_command(fx.p, "pause", reply, sizeof reply));
    assert_int_equal(sscanf(reply, "paused at frame %llu", &held), 1);
    /* 0.2 s: ten frames' time; the display stays on the frame named. */
    for (tries = 0; tries < 10; tries++)
        nanosleep(&nap, NULL);
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.frame, held);
    assert_true(info.captured > held + 1); /* the simulation is ahead */

    /* step 2: two more frames on display. */
    CHECK_OK(rbs_projector_command(fx.p, "step 2", reply, sizeof reply));
    snprintf(want, sizeof want, "then paused at frame %llu", held + 2);
    assert_non_null(strstr(reply, want));
    for (tries = 0; tries < 200; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.frame == held + 2)
            break;
        nanosleep(&nap, NULL);
    }
    for (tries = 0; tries < 5; tries++)
        nanosleep(&nap, NULL);
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.frame, held + 2);

    /* The largest count, then more: saturated at the last frame. */
    CHECK_OK(rbs_projector_command(fx.p, "pause", reply, sizeof reply));
    CHECK_OK(rbs_projector_command(fx.p, "step 18446744073709551615", reply,
                                   sizeof reply));
    assert_non_null(strstr(reply, "the run ends at frame 2000"));
    CHECK_OK(rbs_projector_command(fx.p, "step 2", reply, sizeof reply));
    assert_non_null(strstr(reply, "stepping 0 frames (asked 2"));
    assert_non_null(strstr(reply, "paused at frame 2000"));
    CHECK_OK(rbs_projector_command(fx.p, "speed 1000000", reply, sizeof reply));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_OK);
    r = fx.ctx.made[0];
    assert_int_equal(r->count, 2001);
    for (k = 0; k <= 2000; k++)
        assert_int_equal(r->numbers[k], k);
    fx_done(&fx);
}

/* Commands while running: pause holds the simulation, step N advances N
 * frames, status reports, resume goes on, renderer commands are answered on
 * the renderer thread, quit stops with RBS_E_CLOSED and every frame drawn
 * up to there. */
static void commands_steer_the_run(void **state)
{
    fixture fx;
    rbs_run_info info;
    char reply[512];
    uint64_t k, before;
    struct timespec nap = {0, 30 * 1000 * 1000};
    int tries;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 1000000;
    fx.def.start_paused = 1;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));

    /* Paused after frame 0: wait for it to be drawn, then nothing moves. */
    for (tries = 0; tries < 200; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.drawn == 1)
            break;
        nanosleep(&nap, NULL);
    }
    assert_int_equal(info.drawn, 1);
    assert_true(info.paused);
    nanosleep(&nap, NULL);
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.captured, 1);

    /* step 5: exactly five more frames. */
    CHECK_OK(rbs_projector_command(fx.p, "step 5", reply, sizeof reply));
    assert_non_null(strstr(reply, "5 frames"));
    for (tries = 0; tries < 200; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.drawn == 6)
            break;
        nanosleep(&nap, NULL);
    }
    nanosleep(&nap, NULL);
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.captured, 6);
    assert_int_equal(info.frame, 5);
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    assert_non_null(strstr(reply, "frame 5 of 1000000"));
    assert_non_null(strstr(reply, "paused"));
    /* pause when paused, resume when running: the reply says nothing
     * changed (it said "paused at frame 5" again, and "resumed at frame K"
     * for a run that was never paused: a probe of session 47). */
    CHECK_OK(rbs_projector_command(fx.p, "pause", reply, sizeof reply));
    assert_string_equal(reply, "already paused at frame 5");

    /* Bad arguments are refused with a reason. */
    assert_int_equal(rbs_projector_command(fx.p, "step 0", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_non_null(strstr(reply, "step"));
    assert_int_equal(rbs_projector_command(fx.p, "step 3x", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_int_equal(rbs_projector_command(fx.p, "speed -2", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_int_equal(rbs_projector_command(fx.p, "speed nan", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_int_equal(rbs_projector_command(fx.p, "pause now", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_int_equal(rbs_projector_command(fx.p, "", reply, sizeof reply),
                     RBS_E_INVALID);
    CHECK_OK(rbs_projector_command(fx.p, "speed 2.5", reply, sizeof reply));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_true(info.speed == 2.5);

    /* Renderer commands run on the renderer thread. */
    CHECK_OK(rbs_projector_command(fx.p, "ping", reply, sizeof reply));
    assert_string_equal(reply, "pong");
    assert_int_equal(rbs_projector_command(fx.p, "warp 9", reply, sizeof reply),
                     RBS_E_NOT_FOUND);
    assert_non_null(strstr(reply, "unknown command"));

    /* Resume, let it run, quit. */
    CHECK_OK(rbs_projector_command(fx.p, "resume", reply, sizeof reply));
    for (tries = 0; tries < 500; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.captured > 6)
            break;
        nanosleep(&nap, NULL);
    }
    before = info.captured;
    assert_true(before > 6);
    CHECK_OK(rbs_projector_command(fx.p, "resume", reply, sizeof reply));
    assert_non_null(strstr(reply, "not paused: running at frame "));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_false(info.paused);
    CHECK_OK(rbs_projector_command(fx.p, "ping", reply, sizeof reply));
    assert_string_equal(reply, "pong");
    CHECK_OK(rbs_projector_command(fx.p, "quit", reply, sizeof reply));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_E_CLOSED);
    assert_true(rbs_projector_finished(fx.p, 0));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_int_equal(info.state, RBS_RUN_DONE);
    assert_int_equal(info.result, RBS_E_CLOSED);
    /* Every frame drawn, in order, none lost, up to the end. */
    for (k = 0; k < fx.ctx.made[0]->count; k++)
        assert_int_equal(fx.ctx.made[0]->numbers[k], k);
    assert_int_equal(fx.ctx.made[0]->count, info.drawn);
    assert_int_equal(fx.ctx.made[0]->finished, 1);
    assert_int_equal(fx.ctx.made[0]->lasts, 0);
    /* After the end, commands still answer. */
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    assert_non_null(strstr(reply, "done"));
    fx_done(&fx);
}

/* A renderer can send "quit" back through its control hook. */
static void renderer_control_quits(void **state)
{
    fixture fx;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.ctx.opts.quit_at = 25;
    fx.def.steps = 1000000;
    fx.def.reel_capacity = 4;
    CHECK_OK(fx_create(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_CLOSED);
    /* Frames already in the reel are still drawn: at most a reel more. */
    assert_true(fx.ctx.made[0]->count >= 26);
    assert_true(fx.ctx.made[0]->count <= 26 + 4 + 1);
    fx_done(&fx);
}

/* Destroying a running projector quits and joins. */
static void destroy_while_running(void **state)
{
    fixture fx;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.endless = 1;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    assert_int_equal(rbs_projector_start(fx.p), RBS_E_INVALID); /* once only */
    assert_false(rbs_projector_finished(fx.p, 0.05));
    fx_done(&fx);
}

/* "status" of an endless run names no last frame (it read "frame 11584 of
 * 0": the steps an endless run ignores), and "status 3" is refused (the
 * argument was ignored, where quit, pause and resume refuse theirs): a
 * probe of session 46. */
static void status_of_an_endless_run_and_its_argument(void **state)
{
    fixture fx;
    char reply[512];
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.endless = 1;
    fx.def.steps = 0;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    assert_non_null(strstr(reply, " (endless run), t = "));
    assert_null(strstr(reply, " of 0,"));
    assert_int_equal(rbs_projector_command(fx.p, "status 3", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_string_equal(reply, "status takes no argument");
    CHECK_OK(rbs_projector_command(fx.p, "quit", NULL, 0));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_E_CLOSED);
    fx_done(&fx);
}

/* One run of a world at a time: a second projector on the same world cannot
 * start while the first runs (both started, two simulation threads stepped
 * the world at once: a data race, and frames of a world stepped twice as
 * fast).  It says why, leaves its own projector unstarted, and starts once
 * the first run is over (wait returned), continuing the world where that
 * run left it, with no error of its own. */
static void one_run_of_a_world_at_a_time(void **state)
{
    fixture fx;
    rbs_projector_def def2;
    rbs_projector *p2 = NULL;
    rbs_run_info info;
    uint64_t at;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.endless = 1;
    CHECK_OK(fx_create(&fx));
    rbs_projector_def_init(&def2);
    def2.steps = 5;
    CHECK_OK(rbs_projector_create(fx.w, fx.reg, NULL, 0, &def2, &p2));
    CHECK_OK(rbs_projector_start(fx.p));
    assert_int_equal(rbs_projector_start(p2), RBS_E_INVALID);
    assert_non_null(strstr(rbs_projector_last_error(p2),
                           "the world is in use by another projector's run"));
    CHECK_OK(rbs_projector_status(p2, &info));
    assert_int_equal(info.state, RBS_RUN_READY);
    assert_int_equal(rbs_projector_wait(p2), RBS_E_INVALID); /* never started */
    CHECK_OK(rbs_projector_command(fx.p, "quit", NULL, 0));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_E_CLOSED);
    /* The world is the caller's again: the second run takes it from here. */
    at = rbs_world_step_count(fx.w);
    CHECK_OK(rbs_projector_start(p2));
    assert_string_equal(rbs_projector_last_error(p2), "");
    CHECK_OK(rbs_projector_wait(p2));
    assert_int_equal(rbs_world_step_count(fx.w), at + 5);
    /* and it is free once more after that run (the first stays once-only) */
    assert_int_equal(rbs_projector_start(fx.p), RBS_E_INVALID);
    rbs_projector_destroy(p2);
    fx_done(&fx);
}

/* Two threads start two projectors of one world at the same moment: exactly
 * one run starts (the claim is one compare-and-exchange; under the
 * ThreadSanitizer build, two runs were reported as a race on the world). */
typedef struct racer {
    rbs_projector *p;
    pthread_barrier_t *go;
    rbs_status st;
} racer;

static void *race_start(void *arg)
{
    racer *r = arg;
    pthread_barrier_wait(r->go);
    r->st = rbs_projector_start(r->p);
    return NULL;
}

static void two_starts_at_once_one_runs(void **state)
{
    int round;
    (void)state;
    for (round = 0; round < 20; round++) {
        fixture fx;
        rbs_projector_def def2;
        pthread_barrier_t go;
        pthread_t t[2];
        racer r[2];
        int i, started = 0;
        fx_init(&fx, "rec", NULL);
        fx.def.steps = 3;
        CHECK_OK(fx_create(&fx));
        rbs_projector_def_init(&def2);
        def2.steps = 3;
        r[0].p = fx.p;
        CHECK_OK(rbs_projector_create(fx.w, fx.reg, NULL, 0, &def2, &r[1].p));
        assert_int_equal(pthread_barrier_init(&go, NULL, 2), 0);
        for (i = 0; i < 2; i++) {
            r[i].go = &go;
            r[i].st = RBS_E_NOT_FOUND;
            assert_int_equal(pthread_create(&t[i], NULL, race_start, &r[i]), 0);
        }
        for (i = 0; i < 2; i++)
            assert_int_equal(pthread_join(t[i], NULL), 0);
        pthread_barrier_destroy(&go);
        for (i = 0; i < 2; i++) {
            if (r[i].st == RBS_OK) {
                started++;
                CHECK_OK(rbs_projector_wait(r[i].p));
            } else {
                assert_int_equal(r[i].st, RBS_E_INVALID);
            }
        }
        assert_int_equal(started, 1);
        assert_int_equal(rbs_world_step_count(fx.w), 3);
        rbs_projector_destroy(r[1].p);
        fx_done(&fx);
    }
}

/* Real time: 200 frames of 1 ms at speed 1 take at least 0.2 s of wall
 * time (pacing sleeps; the lower bound cannot be met by chance). */
static void realtime_paces_frames(void **state)
{
    fixture fx;
    rbs_run_info info;
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 200;
    fx.def.realtime = 1;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_run(fx.p));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    assert_true(info.wall_time >= 0.2 - 0.002); /* one frame's rounding */
    assert_int_equal(fx.ctx.made[0]->count, 201);
    fx_done(&fx);
}

/* A frame due beyond any clock (speed 1e-300: 1e297 s a frame) waits
 * answering commands: "status" replies and "quit" ends the run at once.
 * (The deadline overflowed into the past, the renderer thread spun with
 * the lock held, and nothing got through, not even quit.) */
static void realtime_wait_beyond_any_clock_still_quits(void **state)
{
    fixture fx;
    char reply[512];
    double t0;
    struct timespec nap = {0, 50000000};
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 100000; /* (more than the reel holds: quit cuts it short) */
    fx.def.realtime = 1;
    fx.def.speed = 1e-300;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    nanosleep(&nap, NULL);
    t0 = now_s();
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    assert_non_null(strstr(reply, "running"));
    CHECK_OK(rbs_projector_command(fx.p, "quit", reply, sizeof reply));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_E_CLOSED);
    assert_true(now_s() - t0 < 5.0);
    fx_done(&fx);
}

/* Live views only: the latest-only reel; frames increase strictly; while
 * paused the live view gets repeats flagged paused. */
static void live_view_gets_repeats_while_paused(void **state)
{
    fixture fx;
    struct timespec nap = {0, 200 * 1000 * 1000};
    rbs_run_info info;
    uint64_t k;
    int tries;
    (void)state;
    fx_init(&fx, "live", NULL);
    fx.ctx.opts.live = 1;
    fx.def.steps = 1000000;
    fx.def.policy = RBS_REEL_LATEST_ONLY;
    fx.def.start_paused = 1;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    nanosleep(&nap, NULL);
    nanosleep(&nap, NULL);
    CHECK_OK(rbs_projector_command(fx.p, "step 3", NULL, 0));
    for (tries = 0; tries < 250; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.drawn == 4)
            break;
        nanosleep(&nap, NULL);
    }
    CHECK_OK(rbs_projector_command(fx.p, "quit", NULL, 0));
    assert_int_equal(rbs_projector_wait(fx.p), RBS_E_CLOSED);
    /* At least 0.4 s paused at 30 Hz: about 12 repeats; 3 is a margin for a
     * loaded machine. */
    assert_true(fx.ctx.made[0]->repeats >= 3);
    for (k = 1; k < fx.ctx.made[0]->count; k++)
        assert_true(fx.ctx.made[0]->numbers[k] >
                    fx.ctx.made[0]->numbers[k - 1]);
    assert_int_equal(fx.ctx.made[0]->numbers[fx.ctx.made[0]->count - 1], 3);
    fx_done(&fx);
}

/* The reel's contract on one thread. */
static void reel_contract(void **state)
{
    rbs_reel *r;
    rbs_frame *f, *f2;
    const rbs_frame *g;
    int i;
    (void)state;
    assert_int_equal(rbs_reel_create(1, 4, RBS_REEL_LOSSLESS, &r), RBS_E_INVALID);
    assert_null(r);
    assert_int_equal(rbs_reel_create(2, 0, RBS_REEL_LOSSLESS, &r), RBS_E_INVALID);
    assert_int_equal(rbs_reel_create(2, 4, (rbs_reel_policy)7, &r), RBS_E_INVALID);
    CHECK_OK(rbs_reel_create(3, 4, RBS_REEL_LATEST_ONLY, &r));
    assert_int_equal(rbs_reel_end_write(r), RBS_E_INVALID); /* nothing begun */
    assert_int_equal(rbs_reel_end_read(r), RBS_E_INVALID);
    /* The reader holds frame 0; the writer laps the others without touching
     * it. */
    CHECK_OK(rbs_reel_begin_write(r, &f));
    assert_int_equal(rbs_reel_begin_write(r, &f2), RBS_E_INVALID); /* one at a time */
    assert_null(f2);
    f->number = 0;
    CHECK_OK(rbs_reel_end_write(r));
    CHECK_OK(rbs_reel_begin_read(r, &g));
    assert_int_equal(g->number, 0);
    for (i = 1; i <= 10; i++) {
        CHECK_OK(rbs_reel_begin_write(r, &f));
        assert_ptr_not_equal(f, g);
        f->number = (uint64_t)i;
        CHECK_OK(rbs_reel_end_write(r));
    }
    assert_int_equal(g->number, 0);
    CHECK_OK(rbs_reel_end_read(r));
    /* The two newest remain, oldest first. */
    CHECK_OK(rbs_reel_begin_read(r, &g));
    assert_int_equal(g->number, 9);
    CHECK_OK(rbs_reel_end_read(r));
    CHECK_OK(rbs_reel_begin_read(r, &g));
    assert_int_equal(g->number, 10);
    CHECK_OK(rbs_reel_end_read(r));
    assert_int_equal(rbs_reel_dropped(r), 8);
    /* Closed: published frames drain, then RBS_E_CLOSED; writes refused, a
     * frame begun before the close is discarded. */
    CHECK_OK(rbs_reel_begin_write(r, &f));
    f->number = 11;
    CHECK_OK(rbs_reel_end_write(r));
    CHECK_OK(rbs_reel_begin_write(r, &f));
    rbs_reel_close(r);
    rbs_reel_close(r); /* idempotent */
    assert_int_equal(rbs_reel_end_write(r), RBS_E_CLOSED);
    assert_int_equal(rbs_reel_begin_write(r, &f), RBS_E_CLOSED);
    CHECK_OK(rbs_reel_begin_read(r, &g));
    assert_int_equal(g->number, 11);
    CHECK_OK(rbs_reel_end_read(r));
    assert_int_equal(rbs_reel_begin_read(r, &g), RBS_E_CLOSED);
    rbs_reel_destroy(r);
    rbs_reel_destroy(NULL);
}

/* ---- after_step hook, resumed starts, quit ends at a frame -------------- */

typedef struct hook_ctx {
    uint64_t frames[256];
    uint64_t count;
    uint64_t fail_at;      /* return RBS_E_IO at this frame; 0 never */
    uint64_t quit_at;      /* send "quit" at this frame; 0 never */
    int world_mismatch;    /* frame != the world's step count */
    int on_caller_thread;  /* called on the thread that started the run */
    pthread_t caller;
    rbs_projector *projector;
} hook_ctx;

static rbs_status hook(void *context, const rbs_world *world, uint64_t frame,
                       char *err, size_t errlen)
{
    hook_ctx *h = context;
    if (h->count < 256)
        h->frames[h->count++] = frame;
    h->world_mismatch += frame != rbs_world_step_count(world);
    h->on_caller_thread += pthread_equal(pthread_self(), h->caller) != 0;
    if (h->quit_at != 0 && frame == h->quit_at)
        rbs_projector_command(h->projector, "quit", NULL, 0);
    if (h->fail_at != 0 && frame == h->fail_at) {
        snprintf(err, errlen, "no room for the checkpoint");
        return RBS_E_IO;
    }
    return RBS_OK;
}

/* A run stopped on a frame that a recorder's every K leaves out still gives
 * it that frame, as its last (the interrupted run's last frame is kept):
 * every 5, quit at frame 13 from the hook (the world ends there) -- the
 * recorder draws 0, 5, 10 and 13, once each, 13 marked last; a recorder
 * with every 1 beside it draws 0..13 as before. */
static void stopped_run_keeps_its_last_frame_under_every(void **state)
{
    fixture fx;
    static hook_ctx h;
    rec *r;
    (void)state;
    memset(&h, 0, sizeof h);
    h.caller = pthread_self();
    h.quit_at = 13;
    fx_init(&fx, "rec", NULL);
    fx.cfg[0].every = 5;
    fx.def.steps = 100000;
    fx.def.reel_capacity = 2;
    fx.def.after_step = hook;
    fx.def.after_step_context = &h;
    CHECK_OK(fx_create(&fx));
    h.projector = fx.p;
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_CLOSED);
    r = fx.ctx.made[0];
    assert_int_equal(rbs_world_step_count(fx.w), 13);
    assert_int_equal(r->count, 4);
    assert_int_equal(r->numbers[0], 0);
    assert_int_equal(r->numbers[1], 5);
    assert_int_equal(r->numbers[2], 10);
    assert_int_equal(r->numbers[3], 13);
    assert_int_equal(r->lasts, 1);
    fx_done(&fx);
}

/* The hook sees frames 1..steps in order, on the simulation thread, with
 * the world at that frame. */
static void after_step_sees_every_frame(void **state)
{
    fixture fx;
    static hook_ctx h; /* large; one test at a time */
    uint64_t i;
    (void)state;
    memset(&h, 0, sizeof h);
    h.caller = pthread_self();
    fx_init(&fx, "rec", NULL);
    assert_null(fx.def.after_step);
    assert_int_equal(fx.def.skip_first_frame, 0);
    fx.def.steps = 100;
    fx.def.reel_capacity = 3;
    fx.def.after_step = hook;
    fx.def.after_step_context = &h;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_run(fx.p));
    assert_int_equal(h.count, 100);
    for (i = 0; i < 100; i++)
        assert_int_equal(h.frames[i], i + 1);
    assert_int_equal(h.world_mismatch, 0);
    assert_int_equal(h.on_caller_thread, 0);
    assert_int_equal(fx.ctx.made[0]->count, 101);
    fx_done(&fx);
}

/* A failing hook stops the run with its status and message; the outputs
 * hold every frame up to the failing one, and are finished. */
static void after_step_failure_stops_the_run(void **state)
{
    fixture fx;
    static hook_ctx h;
    uint64_t i;
    (void)state;
    memset(&h, 0, sizeof h);
    h.caller = pthread_self();
    h.fail_at = 7;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 1000;
    fx.def.after_step = hook;
    fx.def.after_step_context = &h;
    CHECK_OK(fx_create(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_IO);
    assert_non_null(strstr(rbs_projector_last_error(fx.p),
                           "after frame 7: no room for the checkpoint"));
    assert_int_equal(h.count, 7);
    assert_int_equal(fx.ctx.made[0]->count, 8);
    for (i = 0; i < 8; i++)
        assert_int_equal(fx.ctx.made[0]->numbers[i], i);
    assert_int_equal(fx.ctx.made[0]->finished, 1);
    assert_int_equal(rbs_world_step_count(fx.w), 7);
    fx_done(&fx);
}

/* "quit" stops after the frame being made: the world ends at the last
 * frame drawn, never a step beyond it (what a final checkpoint needs). */
static void quit_ends_at_the_last_frame(void **state)
{
    fixture fx;
    static hook_ctx h;
    rec *r;
    (void)state;
    memset(&h, 0, sizeof h);
    h.caller = pthread_self();
    h.quit_at = 30;
    fx_init(&fx, "rec", NULL);
    fx.def.steps = 100000;
    fx.def.reel_capacity = 2;
    fx.def.after_step = hook;
    fx.def.after_step_context = &h;
    CHECK_OK(fx_create(&fx));
    h.projector = fx.p;
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_CLOSED);
    r = fx.ctx.made[0];
    assert_int_equal(rbs_world_step_count(fx.w), 30);
    assert_int_equal(r->count, 31);
    assert_int_equal(r->numbers[r->count - 1], 30);
    rbs_projector_destroy(fx.p);

    /* Quit from the renderer side too: the world is at the last frame
     * drawn, whichever frame the simulation was making. */
    rbs_world_destroy(fx.w);
    fx.w = make_world();
    default_opts(&fx.ctx);
    fx.ctx.opts.quit_at = 25;
    rbs_projector_def_init(&fx.def);
    fx.def.steps = 100000;
    fx.def.reel_capacity = 4;
    CHECK_OK(fx_project(&fx));
    assert_int_equal(rbs_projector_run(fx.p), RBS_E_CLOSED);
    r = fx.ctx.made[0];
    assert_int_equal(rbs_world_step_count(fx.w), r->numbers[r->count - 1]);
    fx_done(&fx);
}

/* "status" names the frame shown, and the frame the counters run to when
 * the simulation is ahead of it (a slow renderer, a reel of 8). */
static void status_says_how_far_the_simulation_is(void **state)
{
    fixture fx;
    rbs_run_info info;
    char reply[512];
    int tries;
    struct timespec nap = {0, 5000000};
    (void)state;
    fx_init(&fx, "rec", NULL);
    fx.ctx.opts.draw_ms = 50;
    fx.def.steps = 40;
    fx.def.reel_capacity = 8;
    CHECK_OK(fx_create(&fx));
    CHECK_OK(rbs_projector_start(fx.p));
    for (tries = 0; tries < 400; tries++) {
        CHECK_OK(rbs_projector_status(fx.p, &info));
        if (info.captured >= 8)
            break;
        nanosleep(&nap, NULL);
    }
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    CHECK_OK(rbs_projector_status(fx.p, &info));
    /* (the status taken after the reply: the simulation may have gone on) */
    assert_non_null(strstr(reply, "made ahead of the frame shown"));
    {
        unsigned long long shown = 0, made = 0;
        const char *at = strstr(reply, "counts to frame ");
        assert_int_equal(sscanf(reply, "frame %llu of 40", &shown), 1);
        assert_non_null(at);
        assert_int_equal(sscanf(at, "counts to frame %llu", &made), 1);
        assert_true(made > shown);
        assert_true(made <= info.captured - 1);
        assert_true(shown <= info.frame);
    }
    CHECK_OK(rbs_projector_wait(fx.p));
    CHECK_OK(rbs_projector_command(fx.p, "status", reply, sizeof reply));
    assert_non_null(strstr(reply, "frame 40 of 40"));
    assert_null(strstr(reply, "ahead"));
    fx_done(&fx);
}

/* A world that has stepped k times (as a checkpoint restores it) projects
 * frames numbered from k; with skip_first_frame frame k is not drawn.  The
 * frames are bit for bit those of a run from frame 0, and "every K" keeps
 * the same frame numbers (multiples of K) in both. */
static void resumed_world_keeps_frame_numbers(void **state)
{
    fixture fx; /* fx.w: the uninterrupted run; ctx "full", other "rec" */
    rbs_world *w;
    rbs_renderer_config cfg[2];
    rbs_projector *p;
    rec *all, *every, *r;
    uint64_t i;
    (void)state;
    fx_init(&fx, "full", "rec");
    w = make_world();
    fx_register(&fx);

    /* The uninterrupted run: frames 0..100. */
    fx.n = 1;
    fx.def.steps = 100;
    /* (the recorders live until their projector is destroyed) */
    CHECK_OK(fx_project(&fx));
    CHECK_OK(rbs_projector_run(fx.p));
    all = fx.ctx.made[0];
    assert_int_equal(all->count, 101);

    /* 40 steps by hand, then 60 more through the projector. */
    for (i = 0; i < 40; i++)
        CHECK_OK(rbs_world_step(w, NULL));
    cfg[0] = config_for("rec", 1);
    cfg[1] = config_for("rec", 25);
    rbs_projector_def_init(&fx.def);
    fx.def.steps = 60;
    fx.def.skip_first_frame = 1;
    CHECK_OK(rbs_projector_create(w, fx.reg, cfg, 2, &fx.def, &p));
    CHECK_OK(rbs_projector_run(p));
    r = fx.other.made[0];
    every = fx.other.made[1];
    assert_int_equal(r->count, 60);
    for (i = 0; i < 60; i++) {
        assert_int_equal(r->numbers[i], 41 + i);
        /* exact: the same steps on the same state */
        assert_memory_equal(&r->x[i], &all->x[41 + i], sizeof(double));
    }
    assert_int_equal(r->lasts, 1);
    assert_int_equal(every->count, 3);
    assert_int_equal(every->numbers[0], 50);
    assert_int_equal(every->numbers[1], 75);
    assert_int_equal(every->numbers[2], 100);
    rbs_projector_destroy(p);
    rbs_projector_destroy(fx.p);
    fx.p = NULL;

    /* Without skip_first_frame the starting frame is drawn (and kept). */
    rbs_world_destroy(w);
    w = make_world();
    for (i = 0; i < 40; i++)
        CHECK_OK(rbs_world_step(w, NULL));
    default_opts(&fx.other);
    rbs_projector_def_init(&fx.def);
    fx.def.steps = 10;
    CHECK_OK(rbs_projector_create(w, fx.reg, &cfg[1], 1, &fx.def, &p));
    CHECK_OK(rbs_projector_run(p));
    every = fx.other.made[0];
    assert_int_equal(every->count, 2);
    assert_int_equal(every->numbers[0], 40);
    assert_int_equal(every->numbers[1], 50);
    rbs_projector_destroy(p);

    rbs_world_destroy(w);
    fx_done(&fx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reel_contract),
        cmocka_unit_test(registry_finds_and_rejects),
        cmocka_unit_test(every_frame_in_order_with_exact_state),
        cmocka_unit_test(zero_steps_gives_frame_zero),
        cmocka_unit_test(every_k_keeps_multiples_and_the_last),
        cmocka_unit_test(frame_written_edges),
        cmocka_unit_test(renderers_do_not_change_results),
        cmocka_unit_test(older_config_arrays_are_read_by_their_size),
        cmocka_unit_test(failing_check_creates_nothing),
        cmocka_unit_test(failing_create_destroys_the_others),
        cmocka_unit_test(failing_draw_stops_the_run),
        cmocka_unit_test(foreign_draw_code_is_a_renderer_error),
        cmocka_unit_test(foreign_codes_of_every_call_are_renderer_errors),
        cmocka_unit_test(failing_finish_is_reported),
        cmocka_unit_test(numerical_failure_stops_the_run),
        cmocka_unit_test(momentum_failure_names_the_body),
        cmocka_unit_test(commands_steer_the_run),
        cmocka_unit_test(renderer_control_quits),
        cmocka_unit_test(after_step_sees_every_frame),
        cmocka_unit_test(after_step_failure_stops_the_run),
        cmocka_unit_test(quit_ends_at_the_last_frame),
        cmocka_unit_test(status_says_how_far_the_simulation_is),
        cmocka_unit_test(stopped_run_keeps_its_last_frame_under_every),
        cmocka_unit_test(resumed_world_keeps_frame_numbers),
        cmocka_unit_test(destroy_while_running),
        cmocka_unit_test(status_of_an_endless_run_and_its_argument),
        cmocka_unit_test(one_run_of_a_world_at_a_time),
        cmocka_unit_test(two_starts_at_once_one_runs),
        cmocka_unit_test(realtime_paces_frames),
        cmocka_unit_test(realtime_wait_beyond_any_clock_still_quits),
        cmocka_unit_test(live_view_gets_repeats_while_paused),
        cmocka_unit_test(realtime_pause_holds_the_display),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
