/*
 * test_pairs.c - the broad phase's candidate-pair list against brute force.
 *
 * rbs__broadphase_pairs must visit exactly the pairs of items whose centres
 * are closer than the sum of their reaches (and, with a query mask, of which
 * one item is queried), each once, in order of (i, j) -- whether its list is
 * built for the call or kept from an earlier one.  Every check below compares
 * the visits, in order, with an O(n^2) loop over all pairs using the same
 * floating-point test, over rounds of moves: small ones (the list is kept),
 * large ones and teleports (it must be rebuilt), growing reaches, query
 * masks, radii a thousand times apart, positions 1e6 m from the origin, and
 * a list too small for the pairs (the grid's own walk: the same set, in any
 * order).  One case follows a single fast sphere: its own skin (grown with
 * the motion in its reach) keeps the list over several frames of its
 * travel, and the list is rebuilt once the sphere leaves it.  Internal:
 * linked against the library's objects.
 */
#include <stdlib.h>
#include <string.h>

#include "common.h"
#include "core/world_internal.h"

#define N_MAX 300
#define PAIRS_MAX (N_MAX * N_MAX / 2)

typedef struct visits {
    uint32_t count;
    uint32_t pair[2 * PAIRS_MAX];
} visits;

static void record(void *ctx, uint32_t i, uint32_t j)
{
    visits *v = (visits *)ctx;
    if (v->count < PAIRS_MAX) {
        v->pair[2 * v->count] = i;
        v->pair[2 * v->count + 1] = j;
    }
    v->count++;
}

/* xorshift64*: a fixed sequence, so every run checks the same rounds */
static double uniform(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static void brute(const rbs_world *w, uint32_t n, const uint8_t *query, visits *out)
{
    const double *C = w->bp_center, *R = w->bp_reach;
    uint32_t a, b;
    out->count = 0;
    for (a = 0; a < n; ++a)
        for (b = a + 1; b < n; ++b) {
            double ex = C[3 * a] - C[3 * b], ey = C[3 * a + 1] - C[3 * b + 1], ez = C[3 * a + 2] - C[3 * b + 2];
            double sr = R[a] + R[b];
            if (query && !query[a] && !query[b])
                continue;
            if (ex * ex + ey * ey + ez * ez <= sr * sr)
                record(out, a, b);
        }
}

static int cmp_pair(const void *x, const void *y)
{
    const uint32_t *p = (const uint32_t *)x, *q = (const uint32_t *)y;
    if (p[0] != q[0])
        return p[0] < q[0] ? -1 : 1;
    return p[1] < q[1] ? -1 : p[1] > q[1];
}

/* got must equal want pair for pair; sorted: in the same order too */
static void same(visits *got, const visits *want, int sorted, const char *what, int round)
{
    uint32_t k;
    if (got->count != want->count)
        fail_msg("%s, round %d: %u pairs visited, %u expected", what, round, (unsigned)got->count,
                 (unsigned)want->count);
    if (!sorted)
        qsort(got->pair, got->count, 2 * sizeof(uint32_t), cmp_pair);
    for (k = 0; k < got->count; ++k)
        if (got->pair[2 * k] != want->pair[2 * k] || got->pair[2 * k + 1] != want->pair[2 * k + 1])
            fail_msg("%s, round %d: visit %u is (%u, %u), expected (%u, %u)", what, round, (unsigned)k,
                     (unsigned)got->pair[2 * k], (unsigned)got->pair[2 * k + 1], (unsigned)want->pair[2 * k],
                     (unsigned)want->pair[2 * k + 1]);
}

/* A world of n spheres (radii r, or 1000 r for every 37th when mixed) in a
 * box of side L at offset; max_contacts sets the list's capacity. */
static rbs_world *crowd(uint32_t n, uint32_t max_contacts, double r, double L, double offset, int mixed,
                        uint64_t *seed)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    uint32_t i;
    rbs_world_def_init(&d);
    d.max_bodies = n;
    d.max_contacts = max_contacts;
    d.gravity.z = 0.0;
    CHECK_OK(rbs_world_create(&d, &w));
    for (i = 0; i < n; ++i) {
        rbs_sphere_def s;
        rbs_sphere_def_init(&s);
        s.radius = mixed && i % 37 == 5 ? 1000.0 * r : r;
        s.position.x = offset + L * uniform(seed);
        s.position.y = offset + L * uniform(seed);
        s.position.z = offset + L * uniform(seed);
        CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    }
    return w;
}

static visits got, want;
static int list_passes, grid_passes, kept_passes;

/* A pass that kept or built a list (vl_valid) visits in order; one whose
 * pairs did not fit the list took the grid's walk, the same set.  sorted: the
 * list must have held them (more pairs than it holds would fail). */
static void check(const rbs_world *w, visits *g, const visits *want, int sorted, const char *what,
                  int round)
{
    if (w->vl_valid) {
        list_passes++;
        /* a list built for this pass holds this pass's centres */
        if (memcmp(w->vl_pos, w->bp_center, 3 * (size_t)w->sphere_count * sizeof(double)) != 0)
            kept_passes++;
        same(g, want, 1, what, round);
        return;
    }
    grid_passes++;
    if (sorted) {
        /* the list holds every pair (a query only filters its visits) */
        static visits all;
        brute(w, w->sphere_count, NULL, &all);
        if (all.count <= w->vl_cap)
            fail_msg("%s, round %d: %u pairs fit the list of %u, but it was not used", what, round,
                     (unsigned)all.count, (unsigned)w->vl_cap);
    }
    same(g, want, 0, what, round);
}

/* Rounds of moves and reach changes; each round checks a pass without and
 * with a query mask.  sorted: the list holds every pair (else the grid's
 * walk is taken and only the set is compared). */
static void rounds(rbs_world *w, double r, double L, int sorted, const char *what, uint64_t *seed)
{
    uint32_t n = w->sphere_count, i, k;
    uint8_t query[N_MAX];
    int round;
    assert_true(n <= N_MAX);
    for (i = 0; i < n; ++i) {
        memcpy(&w->bp_center[3 * i], &w->pos[3 * w->spheres[i]], 3 * sizeof(double));
        w->bp_reach[i] = w->radius[w->spheres[i]] * 1.01;
    }
    for (round = 0; round < 200; ++round) {
        double u = uniform(seed), fixed;
        if (u < 0.6) {
            /* small moves: within the list's margin, mostly */
            for (i = 0; i < 3 * n; ++i)
                w->bp_center[i] += 0.004 * r * (2.0 * uniform(seed) - 1.0);
        } else if (u < 0.7) {
            /* a teleport across the box */
            i = (uint32_t)(uniform(seed) * n) % n;
            for (k = 0; k < 3; ++k)
                w->bp_center[3 * i + k] = w->bp_center[3 * ((i + 1) % n) + k] + 0.5 * r * uniform(seed);
        } else if (u < 0.8) {
            /* one item's reach grows (a fast sphere's swept path) */
            i = (uint32_t)(uniform(seed) * n) % n;
            w->bp_reach[i] = w->radius[w->spheres[i]] * (1.0 + 3.0 * uniform(seed));
        } else if (u < 0.9) {
            /* every reach back to its radius plus a little */
            for (i = 0; i < n; ++i)
                w->bp_reach[i] = w->radius[w->spheres[i]] * (1.0 + 0.02 * uniform(seed));
        } else {
            /* large moves of everything */
            for (i = 0; i < 3 * n; ++i)
                w->bp_center[i] += 0.1 * L * (2.0 * uniform(seed) - 1.0);
        }
        /* the callers' fixed part of the reach (it only sizes the skins):
         * none, some, and more than any reach (no motion at all) */
        fixed = round % 3 == 0 ? 0.0 : round % 3 == 1 ? 0.1 : 10.0;
        got.count = 0;
        rbs__broadphase_pairs(w, NULL, n, NULL, fixed, record, &got);
        brute(w, n, NULL, &want);
        check(w, &got, &want, sorted, what, round);
        for (i = 0; i < n; ++i)
            query[i] = uniform(seed) < 0.2;
        got.count = 0;
        rbs__broadphase_pairs(w, NULL, n, query, fixed, record, &got);
        brute(w, n, query, &want);
        check(w, &got, &want, sorted, what, round);
    }
}

static void list_matches_brute_force(void **state)
{
    uint64_t seed = 0x9E3779B97F4A7C15ull;
    rbs_world *w;
    (void)state;
    /* a dense crowd: about 10 candidates a sphere */
    w = crowd(N_MAX, 0, 0.05, 0.9, 0.0, 0, &seed);
    rounds(w, 0.05, 0.9, 1, "dense crowd", &seed);
    rbs_world_destroy(w);
    /* radii a thousand times apart (big items, tested against all) */
    w = crowd(N_MAX, 0, 0.01, 2.0, 0.0, 1, &seed);
    rounds(w, 0.01, 2.0, 1, "mixed radii", &seed);
    rbs_world_destroy(w);
    /* 1e6 m from the origin: rounding of the coordinates is 1e-10 m */
    w = crowd(N_MAX, 0, 0.05, 0.9, 1.0e6, 0, &seed);
    rounds(w, 0.05, 0.9, 1, "far from the origin", &seed);
    rbs_world_destroy(w);
    /* both paths ran: lists kept from an earlier pass, and lists rebuilt */
    assert_true(kept_passes > 0);
    assert_true(list_passes > kept_passes);
}

static void list_too_small_takes_the_grid(void **state)
{
    uint64_t seed = 12345;
    rbs_world *w;
    (void)state;
    /* room for 16 pairs among hundreds: the grid's walk, the same set */
    w = crowd(N_MAX, 16, 0.05, 0.9, 0.0, 0, &seed);
    assert_int_equal(w->vl_cap, 16);
    grid_passes = 0;
    rounds(w, 0.05, 0.9, 0, "list of 16", &seed);
    rbs_world_destroy(w);
    assert_true(grid_passes > 0);
}

/* One sphere of a still crowd moves at d a frame, its reach grown by d (a
 * sweep's margin, as detection's): the list built at its start must be kept
 * while the sphere stays within its skin (the base 0.05 r plus four frames of
 * its motion, so more than one frame's travel although d is beyond the base
 * skin), each pass the brute force's pairs in order, and rebuilt once it
 * has travelled beyond that skin. */
static void fast_sphere_keeps_its_list(void **state)
{
    uint64_t seed = 777;
    const double r = 0.05, d = 0.1 * r; /* twice the base skin a frame */
    uint32_t n, i, frame, builds = 0, kept = 0, first_build = 0;
    rbs_world *w;
    (void)state;
    w = crowd(N_MAX, 0, r, 0.9, 0.0, 0, &seed);
    n = w->sphere_count;
    for (i = 0; i < n; ++i) {
        memcpy(&w->bp_center[3 * i], &w->pos[3 * w->spheres[i]], 3 * sizeof(double));
        w->bp_reach[i] = r; /* the others at rest: no margin */
    }
    w->bp_reach[0] = r + d;
    for (frame = 0; frame < 12; ++frame) {
        got.count = 0;
        rbs__broadphase_pairs(w, NULL, n, NULL, 0.0, record, &got);
        brute(w, n, NULL, &want);
        assert_true(w->vl_valid);
        same(&got, &want, 1, "fast sphere", (int)frame);
        if (memcmp(w->vl_pos, w->bp_center, 3 * (size_t)n * sizeof(double)) == 0) {
            builds++;
            if (frame > 0 && first_build == 0)
                first_build = frame;
        } else {
            kept++;
        }
        w->bp_center[0] += d;
    }
    /* built at frame 0; its skin, 0.05 r + 4 d = 0.45 r (under the cap of
     * half a radius), lasts while its travel k d stays within it: kept for
     * frames 1..4, rebuilt at 5 and 10 (a single skin of 0.05 r for all, as
     * before, rebuilt every frame) */
    assert_int_equal(first_build, 5);
    assert_true(kept >= 8);
    assert_true(builds <= 4);
    rbs_world_destroy(w);
}

/* Pairs of the crowd's n items closer than 2 R (the brute force, with
 * every reach R). */
static uint32_t pairs_within(rbs_world *w, uint32_t n, double R)
{
    uint32_t i;
    for (i = 0; i < n; ++i) {
        memcpy(&w->bp_center[3 * i], &w->pos[3 * w->spheres[i]], 3 * sizeof(double));
        w->bp_reach[i] = R;
    }
    brute(w, n, NULL, &want);
    return want.count;
}

/* Every item moving (reach r + d): the list with their own skins (0.05 r +
 * 4 d each) holds more pairs than the world has room for, the list with the
 * base skin alone (0.05 r) fits -- and must be the one built, not the list
 * of this pass's reaches alone (rebuilt every pass). */
static void skins_that_overflow_fall_back_to_the_base(void **state)
{
    const double r = 0.05, d = 0.1 * r;
    uint64_t seed = 4242, again = 4242;
    uint32_t n, i, base_pairs, skin_pairs, cap;
    rbs_world *w;
    (void)state;
    w = crowd(N_MAX, 0, r, 0.9, 0.0, 0, &seed);
    n = w->sphere_count;
    base_pairs = pairs_within(w, n, r + d + 0.05 * r);
    skin_pairs = pairs_within(w, n, r + d + 0.45 * r);
    rbs_world_destroy(w);
    assert_true(skin_pairs > base_pairs + 4);
    cap = base_pairs + (skin_pairs - base_pairs) / 2;
    w = crowd(N_MAX, cap, r, 0.9, 0.0, 0, &again); /* (the same crowd) */
    assert_int_equal(w->vl_cap, cap);
    for (i = 0; i < n; ++i) {
        memcpy(&w->bp_center[3 * i], &w->pos[3 * w->spheres[i]], 3 * sizeof(double));
        w->bp_reach[i] = r + d;
    }
    got.count = 0;
    rbs__broadphase_pairs(w, NULL, n, NULL, 0.0, record, &got);
    brute(w, n, NULL, &want);
    assert_true(w->vl_valid);
    same(&got, &want, 1, "skins that overflow", 0);
    for (i = 0; i < n; ++i) /* the base skin: 0.05 r beyond the reach (plus rounding's guard) */
        assert_true(w->vl_reach[i] > r + d + 0.049 * r && w->vl_reach[i] < r + d + 0.051 * r);
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(list_matches_brute_force),
        cmocka_unit_test(list_too_small_takes_the_grid),
        cmocka_unit_test(fast_sphere_keeps_its_list),
        cmocka_unit_test(skins_that_overflow_fall_back_to_the_base),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
