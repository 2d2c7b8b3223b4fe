/*
 * test_warm.c - the warm-start table: one entry per contact that held,
 * sorted by pair key, found by a search that gallops from where the last
 * one ended.  Contacts are stored in the order rbs__detect makes them and in
 * shuffled orders (the order of the grid's own walk, when the candidate list
 * cannot hold the pairs): every stored pair must be found with its impulse
 * rates, bit for bit, whatever order the pass asks in; pairs not stored must
 * not be found.  Internal: linked against the library's objects.
 */
#include <stdlib.h>
#include <string.h>

#include "common.h"
#include "core/world_internal.h"

#define SPHERES 120

static uint64_t next(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 2685821657736338717ull;
}

/* A floor and a wall, and a crowd of spheres: detection gives plane contacts
 * and sphere pairs. */
static rbs_world *crowd(void)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_plane_def p;
    int i;
    rbs_world_def_init(&d);
    d.max_bodies = SPHERES + 2;
    d.gravity.z = -9.81;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_plane_def_init(&p);
    CHECK_OK(rbs_world_add_plane(w, &p, NULL));
    p.point.x = -0.05;
    p.normal.x = 1.0;
    p.normal.z = 0.0;
    CHECK_OK(rbs_world_add_plane(w, &p, NULL));
    for (i = 0; i < SPHERES; ++i) {
        rbs_sphere_def s;
        rbs_sphere_def_init(&s);
        s.radius = 0.05;
        s.position.x = 0.1 * (i % 10);
        s.position.y = 0.1 * ((i / 10) % 4);
        s.position.z = 0.05 + 0.1 * (i / 40);
        CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    }
    return w;
}

static void stored_pairs_are_found_in_any_order(void **state)
{
    rbs_world *w = crowd();
    rbs__contact saved[4 * SPHERES + 16];
    uint32_t order[4 * SPHERES + 16];
    uint64_t seed = 99;
    uint32_t n, i, k, held;
    int trial;
    const double h = 1e-3;
    (void)state;
    rbs__world_plan(w); /* (rbs_world_step plans before detecting) */
    CHECK_OK(rbs__detect(w, 1e-3, 1));
    n = w->contact_count;
    assert_true(n > 2 * SPHERES); /* planes and pairs */
    memcpy(saved, w->contact, n * sizeof *saved);
    for (trial = 0; trial < 40; ++trial) {
        uint32_t at = 0;
        /* trial 0: detection's order; then shuffled (Fisher-Yates) */
        for (i = 0; i < n; ++i)
            order[i] = i;
        for (i = n; trial > 0 && i > 1; --i) {
            uint32_t j = (uint32_t)(next(&seed) % i), t = order[i - 1];
            order[i - 1] = order[j];
            order[j] = t;
        }
        /* about a third hold nothing (jn = 0: not stored) */
        held = 0;
        for (i = 0; i < n; ++i) {
            rbs__contact *c = &w->contact[i];
            *c = saved[order[i]];
            c->jn = next(&seed) % 3 == 0 ? 0.0 : 1e-3 * (double)(1 + order[i]);
            c->jt = v3_make(1e-6 * order[i], -2e-6 * order[i], 3e-6);
            held += c->jn != 0.0;
        }
        rbs__warm_store(w, h);
        assert_int_equal(w->warm_used, held);
        for (k = 1; k < w->warm_used; ++k)
            assert_true(w->warm[k - 1].key < w->warm[k].key);
        /* asked in detection's order, then in another shuffled order */
        for (k = 0; k < 2; ++k) {
            at = 0;
            for (i = 0; i < n; ++i) {
                uint32_t q = k == 0 ? i : (uint32_t)(next(&seed) % n);
                const rbs__contact *c = &w->contact[q];
                const rbs__warm *e = rbs__warm_find(w, rbs__warm_key(w, c), &at);
                if (c->jn == 0.0) {
                    if (e != NULL)
                        fail_msg("trial %d: contact %u (held nothing) was found", trial, (unsigned)q);
                    continue;
                }
                if (e == NULL)
                    fail_msg("trial %d: contact %u (%u, %u) not found", trial, (unsigned)q,
                             (unsigned)c->a, (unsigned)c->b);
                assert_true(e->n == c->jn / h);
                assert_true(e->t.x == c->jt.x * (1.0 / h) && e->t.y == c->jt.y * (1.0 / h) &&
                            e->t.z == c->jt.z * (1.0 / h));
            }
        }
    }
    /* detection's own order is key order: stored without sorting */
    memcpy(w->contact, saved, n * sizeof *saved);
    for (i = 0; i + 1 < n; ++i)
        assert_true(rbs__warm_key(w, &w->contact[i]) < rbs__warm_key(w, &w->contact[i + 1]));
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stored_pairs_are_found_in_any_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
