/*
 * test_threads.c - two worlds stepped in two threads give bit-identical
 * results to the same two stepped one after the other (no shared state).
 */
#include <pthread.h>

#include "common.h"

typedef struct job {
    int variant;
    uint64_t hash;
} job;

static rbs_world *build(int variant)
{
    rbs_world *w = make_world(32, 1e-3, -9.81, 0.6);
    rbs_material_id m = material(w, "m", 0.5, 0.3, -1.0);
    int i;
    floor_plane(w, m);
    for (i = 0; i < 10; ++i)
        ball(w, 0.05, 0.1, 0.11 * i, 0.01 * variant, 0.3 + 0.05 * i, 0.3 * variant, 0, 0, m);
    return w;
}

static void *run(void *arg)
{
    job *j = (job *)arg;
    rbs_world *w = build(j->variant);
    int k;
    for (k = 0; k < 3000; ++k)
        if (rbs_world_step(w, NULL) != RBS_OK)
            break;
    j->hash = rbs_world_hash(w);
    rbs_world_destroy(w);
    return NULL;
}

static void threads_match_sequential(void **state)
{
    job seq[2] = {{1, 0}, {2, 0}}, par[2] = {{1, 0}, {2, 0}};
    pthread_t t[2];
    (void)state;
    run(&seq[0]);
    run(&seq[1]);
    assert_int_equal(pthread_create(&t[0], NULL, run, &par[0]), 0);
    assert_int_equal(pthread_create(&t[1], NULL, run, &par[1]), 0);
    pthread_join(t[0], NULL);
    pthread_join(t[1], NULL);
    assert_true(seq[0].hash == par[0].hash);
    assert_true(seq[1].hash == par[1].hash);
    assert_true(seq[0].hash != seq[1].hash); /* the variants really differ */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(threads_match_sequential),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
