/*
 * test_threads.c - the soft step on threads lent by the caller
 * (rbs_world_set_workers, rbs_pool_create): the same bits for any number of
 * threads and however the pool runs them, and its settings checked.
 *
 * The scene is a busy pile: 1,100 spheres of three sizes and two materials
 * (four material-pair rows: friction, rolling off, restitution 0 to 0.9),
 * some spinning, one fixed, dropped into a box of five planes -- enough
 * spheres for four slabs, so that the groups of every level of the soft
 * step's tree (soft_detect.c) and the guards are used.  The state hash is
 * compared every 10 frames.  A pile too small for two slabs leaves the lent
 * threads idle.
 */
#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include "common.h"
#include "raw_state.h"
#include "rbsim/reel.h"

#include "busy_pile.h"

#define FRAMES 240

/* The hash every 10 frames of the busy pile stepped on `workers`. */
static void run(const rbs_workers *workers, double dt, uint64_t hashes[FRAMES / 10])
{
    rbs_world *w = busy_pile(dt);
    int k;
    CHECK_OK(rbs_world_set_workers(w, workers));
    for (k = 0; k < FRAMES; ++k) {
        step_n(w, 1);
        if (k % 10 == 9)
            hashes[k / 10] = rbs_world_hash(w);
    }
    CHECK_OK(rbs_world_set_workers(w, NULL));
    rbs_world_destroy(w);
}

static void same_hashes(const uint64_t *a, const uint64_t *b, const char *what)
{
    int k;
    for (k = 0; k < FRAMES / 10; ++k)
        if (a[k] != b[k])
            fail_msg("%s: the state differs from one thread's after frame %d", what, 10 * k + 10);
}

/* rbs_pool_create's pools of 1, 2 and 3 threads (2 to 4 threads with the
 * stepping one): the same bits as one thread, frame by frame. */
static void pools_give_the_same_bits(void **state)
{
    static uint64_t one[FRAMES / 10], many[FRAMES / 10], other[FRAMES / 10];
    uint32_t t;
    (void)state;
    run(NULL, 0.002, one);
    for (t = 1; t <= 3; ++t) {
        rbs_pool *pool = NULL;
        rbs_workers wk;
        char what[64];
        CHECK_OK(rbs_pool_create(t, &pool));
        rbs_workers_init(&wk);
        CHECK_OK(rbs_pool_workers(pool, &wk));
        assert_int_equal(wk.count, t + 1);
        run(&wk, 0.002, many);
        snprintf(what, sizeof what, "%u threads", (unsigned)(t + 1));
        same_hashes(one, many, what);
        rbs_pool_destroy(pool);
    }
    /* (the comparison can fail: a step one ulp longer is another run) */
    run(NULL, nextafter(0.002, 1.0), other);
    assert_true(other[FRAMES / 10 - 1] != one[FRAMES / 10 - 1]);
}

/* A pool of the test's own: every start makes its threads, each of which
 * waits `delay_us` before it runs its task (or runs none when `idle`). */
typedef struct test_pool {
    pthread_t thread[8];
    uint32_t n;
    long delay_us;
    int idle;
    rbs_task_fn *fn;
    void *task;
    uint32_t started, ran; /* starts, and tasks run */
    pthread_mutex_t mutex;
} test_pool;

typedef struct test_task {
    test_pool *p;
    uint32_t k;
} test_task;

static test_task tasks[8];

static void *test_thread(void *arg)
{
    test_task *t = (test_task *)arg;
    test_pool *p = t->p;
    if (p->delay_us > 0) {
        struct timespec ts;
        ts.tv_sec = 0;
        ts.tv_nsec = p->delay_us * 1000L * (long)t->k;
        nanosleep(&ts, NULL);
    }
    p->fn(p->task, t->k);
    pthread_mutex_lock(&p->mutex);
    p->ran++;
    pthread_mutex_unlock(&p->mutex);
    return NULL;
}

static void test_start(void *user, rbs_task_fn *fn, void *task, uint32_t n)
{
    test_pool *p = (test_pool *)user;
    uint32_t k;
    p->started++;
    p->fn = fn;
    p->task = task;
    p->n = p->idle ? 0 : n;
    for (k = 0; k < p->n; ++k) {
        tasks[k].p = p;
        tasks[k].k = k + 1;
        if (pthread_create(&p->thread[k], NULL, test_thread, &tasks[k]) != 0)
            fail_msg("pthread_create");
    }
}

static void test_finish(void *user)
{
    test_pool *p = (test_pool *)user;
    uint32_t k;
    for (k = 0; k < p->n; ++k)
        pthread_join(p->thread[k], NULL);
}

static void pool_run(test_pool *p, uint32_t count, uint64_t *hashes)
{
    rbs_workers wk;
    rbs_workers_init(&wk);
    wk.count = count;
    wk.start = test_start;
    wk.finish = test_finish;
    wk.user = p;
    run(&wk, 0.002, hashes);
}

/* However a pool runs the tasks -- late (each thread waits a millisecond or
 * more per frame before it starts), or never -- the same bits: the stepping
 * thread takes every share no other thread has claimed. */
static void late_or_idle_pools_give_the_same_bits(void **state)
{
    static uint64_t one[FRAMES / 10], many[FRAMES / 10];
    test_pool p;
    (void)state;
    run(NULL, 0.002, one);
    memset(&p, 0, sizeof p);
    pthread_mutex_init(&p.mutex, NULL);
    p.delay_us = 1000;
    pool_run(&p, 3, many);
    same_hashes(one, many, "3 threads starting late");
    assert_true(p.started == FRAMES && p.ran == 2 * FRAMES); /* (every task ran) */
    p.started = p.ran = 0;
    p.delay_us = 0;
    p.idle = 1;
    pool_run(&p, 4, many);
    same_hashes(one, many, "a pool that starts nothing");
    assert_true(p.started == FRAMES && p.ran == 0);
    pthread_mutex_destroy(&p.mutex);
}

/* A soft pile of n spheres (a lattice of 0.12 m over a floor) on workers
 * (NULL: none), stepped 50 frames: its hash. */
static uint64_t small_pile(uint32_t n, const rbs_workers *workers)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_plane_def pl;
    uint64_t h;
    uint32_t i;
    rbs_world_def_init(&d);
    d.max_bodies = n + 1;
    d.method = RBS_METHOD_SOFT;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_plane_def_init(&pl);
    CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
    for (i = 0; i < n; ++i) {
        rbs_sphere_def sd;
        rbs_sphere_def_init(&sd);
        sd.radius = 0.05;
        sd.position.x = 0.12 * (double)(i % 8) + 0.001 * (double)(i % 7);
        sd.position.y = 0.12 * (double)(i / 8 % 8);
        sd.position.z = 0.06 + 0.12 * (double)(i / 64);
        CHECK_OK(rbs_world_add_sphere(w, &sd, NULL));
    }
    CHECK_OK(rbs_world_set_workers(w, workers));
    step_n(w, 50);
    h = rbs_world_hash(w);
    CHECK_OK(rbs_world_set_workers(w, NULL));
    rbs_world_destroy(w);
    return h;
}

/* Fewer than 512 spheres are one slab, whose rows are one group: the step
 * leaves the lent threads idle -- no start, the same bits -- and from 512
 * spheres on starts them every frame. */
static void few_spheres_leave_the_threads_idle(void **state)
{
    test_pool p;
    rbs_workers wk;
    (void)state;
    memset(&p, 0, sizeof p);
    pthread_mutex_init(&p.mutex, NULL);
    rbs_workers_init(&wk);
    wk.count = 3;
    wk.start = test_start;
    wk.finish = test_finish;
    wk.user = &p;
    assert_true(small_pile(511, &wk) == small_pile(511, NULL));
    assert_int_equal(p.started, 0);
    assert_true(small_pile(512, &wk) == small_pile(512, NULL));
    assert_int_equal(p.started, 50);
    assert_int_equal(p.ran, 2 * 50);
    pthread_mutex_destroy(&p.mutex);
}

/* A checkpoint taken on two threads resumes on three with the same bits as
 * the run that never stopped (on one). */
static void checkpoint_resumes_on_other_threads(void **state)
{
    static unsigned char buf[4 << 20];
    rbs_world *w = busy_pile(0.002), *c = NULL;
    rbs_pool *p2 = NULL, *p3 = NULL;
    rbs_workers wk;
    size_t n = 0;
    (void)state;
    CHECK_OK(rbs_pool_create(1, &p2));
    CHECK_OK(rbs_pool_create(2, &p3));
    rbs_workers_init(&wk);
    CHECK_OK(rbs_pool_workers(p2, &wk));
    CHECK_OK(rbs_world_set_workers(w, &wk));
    step_n(w, 120);
    assert_true(rbs_world_checkpoint_size(w) <= sizeof buf);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, sizeof buf, &n));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &c));
    assert_int_equal(rbs_world_workers(c), 1); /* (a loaded world has none) */
    CHECK_OK(rbs_pool_workers(p3, &wk));
    CHECK_OK(rbs_world_set_workers(c, &wk));
    CHECK_OK(rbs_world_set_workers(w, NULL));
    step_n(w, 120);
    step_n(c, 120);
    assert_true(rbs_world_hash(w) == rbs_world_hash(c));
    CHECK_OK(rbs_world_set_workers(c, NULL));
    rbs_world_destroy(c);
    rbs_world_destroy(w);
    rbs_pool_destroy(p3);
    rbs_pool_destroy(p2);
}

/* A step that fails (a spin too fast to turn: the turn's length overflows)
 * leaves the whole world as it was -- the warm-start table too, which the
 * state hash does not see: the frame's store counts its lanes beside the
 * write-back's check but writes the table only once every body is known
 * good.  The pile that failed a step, its spin then put back, runs on with
 * the same bits as its twin that never failed, on one thread and on two.
 * (A store that wrote the table before the check fails this.) */
static void failed_step_keeps_the_warm_start(void **state)
{
    rbs_pool *pool = NULL;
    int t;
    (void)state;
    CHECK_OK(rbs_pool_create(1, &pool));
    for (t = 1; t <= 2; ++t) {
        rbs_world *a = busy_pile(0.002), *b = busy_pile(0.002);
        rbs_vec3 fast = {1e157, 1e157, 1e157};
        rbs_body_state was;
        rbs_body_id id;
        rbs_workers wk;
        uint64_t h;
        rbs_workers_init(&wk);
        if (t == 2)
            CHECK_OK(rbs_pool_workers(pool, &wk));
        CHECK_OK(rbs_world_set_workers(a, &wk));
        CHECK_OK(rbs_world_set_workers(b, &wk));
        step_n(a, 100);
        step_n(b, 100);
        /* (slot 6: a sphere of the bottom layer, in contact by now) */
        CHECK_OK(rbs_world_body_at(a, 6, &id));
        CHECK_OK(rbs_body_get_state(a, id, &was));
        h = rbs_world_hash(a);
        raw_set(a, id, RAW_ANGULAR_VELOCITY, fast); /* (beyond the setter's limit) */
        assert_int_equal(rbs_world_step(a, NULL), RBS_E_NUMERIC);
        CHECK_OK(rbs_body_set_angular_velocity(a, id, was.angular_velocity));
        assert_true(rbs_world_hash(a) == h);
        /* (the twin takes the same settings, without the failed step) */
        raw_set(b, id, RAW_ANGULAR_VELOCITY, fast);
        CHECK_OK(rbs_body_set_angular_velocity(b, id, was.angular_velocity));
        step_n(a, 20);
        step_n(b, 20);
        if (rbs_world_hash(a) != rbs_world_hash(b))
            fail_msg("%d thread(s): the run after the failed step differs from its twin's", t);
        CHECK_OK(rbs_world_set_workers(a, NULL));
        CHECK_OK(rbs_world_set_workers(b, NULL));
        rbs_world_destroy(a);
        rbs_world_destroy(b);
    }
    rbs_pool_destroy(pool);
}

/* Settings out of range are refused, naming what is wrong, and leave the
 * world's threads as they were. */
static void bad_workers_are_refused(void **state)
{
    rbs_world *w = make_world(8, 0.001, -9.81, 0.5);
    rbs_workers wk;
    rbs_pool *pool = (rbs_pool *)&wk;
    (void)state;
    rbs_workers_init(&wk);
    assert_int_equal(wk.count, 1);
    wk.count = 0;
    assert_int_equal(rbs_world_set_workers(w, &wk), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "workers.count"));
    wk.count = RBS_WORKERS_MAX + 1;
    assert_int_equal(rbs_world_set_workers(w, &wk), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "workers.count"));
    wk.count = 2;
    assert_int_equal(rbs_world_set_workers(w, &wk), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "workers.start is NULL"));
    wk.start = test_start;
    assert_int_equal(rbs_world_set_workers(w, &wk), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "workers.finish is NULL"));
    wk.struct_size = 3;
    assert_int_equal(rbs_world_set_workers(w, &wk), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "struct_size"));
    assert_int_equal(rbs_world_workers(w), 1);
    assert_int_equal(rbs_world_set_workers(NULL, &wk), RBS_E_INVALID);
    assert_int_equal(rbs_world_workers(NULL), 0);
    assert_int_equal(rbs_pool_create(0, &pool), RBS_E_INVALID);
    assert_null(pool);
    assert_int_equal(rbs_pool_create(RBS_WORKERS_MAX, &pool), RBS_E_INVALID);
    assert_int_equal(rbs_pool_create(1, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_pool_workers(NULL, &wk), RBS_E_INVALID);
    rbs_pool_destroy(NULL);
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pools_give_the_same_bits),
        cmocka_unit_test(late_or_idle_pools_give_the_same_bits),
        cmocka_unit_test(few_spheres_leave_the_threads_idle),
        cmocka_unit_test(checkpoint_resumes_on_other_threads),
        cmocka_unit_test(failed_step_keeps_the_warm_start),
        cmocka_unit_test(bad_workers_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
