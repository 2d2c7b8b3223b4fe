/*
 * test_kernels.c - the soft step's gathered layout inside (internal: linked
 * against the library's objects, with its private headers): the row
 * kernels of every backend give the same bits, and the paths that piles
 * seldom take -- serial chunks (a body touching more than the chunker's
 * open chunks), and the serial detection (contacts beyond max_contacts)
 * -- give the exact answers; the candidate list's grid gives the same list
 * in any memory, and a soft pile leaves the world's own grid arrays
 * untouched; the warm-start table holds each contact that took an impulse
 * once, in buckets its index finds, the same on any threads, and is found
 * again in key order -- by another method's pass too (soft, Euler, soft);
 * the warm start keeps a tangent impulse in the static cone.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "busy_pile.h"

#include "core/soft.h"
#include "core/team.h"
#include "rbsim/reel.h"
#include "core/world_internal.h"

/* The warm start's tangent impulse in the static cone (rbs__warm_tangent):
 * inside the cone or on its edge it is kept bit for bit (a sliding
 * contact's stored friction lies on the edge when mu_s = mu_k); outside it
 * is scaled onto the edge, in its own direction -- exactly where the
 * numbers are exact (3-4-5), else to a rounding of the length; a cone of
 * mu_s = 0 leaves nothing, and a zero impulse stays zero. */
static void warm_tangent_kept_in_the_static_cone(void **state)
{
    v3 t;
    (void)state;
    t = rbs__warm_tangent(v3_make(0.3, 0.4, 0.0), 1.0);
    assert_true(t.x == 0.3 && t.y == 0.4 && t.z == 0.0);
    t = rbs__warm_tangent(v3_make(3.0, 4.0, 0.0), 5.0); /* on the edge */
    assert_true(t.x == 3.0 && t.y == 4.0 && t.z == 0.0);
    t = rbs__warm_tangent(v3_make(3.0, 4.0, 0.0), 2.5); /* outside: to 2.5 */
    assert_true(t.x == 1.5 && t.y == 2.0 && t.z == 0.0);
    t = rbs__warm_tangent(v3_make(0.0, -4.0, 3.0), 1.25);
    assert_true(t.x == 0.0 && t.y == -1.0 && t.z == 0.75);
    t = rbs__warm_tangent(v3_make(1.0, 2.0, 2.0), 1.0); /* length 3 to 1 */
    assert_true(fabs(t.x - 1.0 / 3.0) <= 1e-16 && fabs(t.y - 2.0 / 3.0) <= 1e-16 &&
                fabs(t.z - 2.0 / 3.0) <= 1e-16);
    assert_true(fabs(sqrt(v3_dot(t, t)) - 1.0) <= 4e-16);
    t = rbs__warm_tangent(v3_make(3.0, 4.0, 0.0), 0.0); /* mu_s = 0 */
    assert_true(t.x == 0.0 && t.y == 0.0 && t.z == 0.0);
    t = rbs__warm_tangent(v3_make(0.0, 0.0, 0.0), 0.0);
    assert_true(t.x == 0.0 && t.y == 0.0 && t.z == 0.0);
}

/* The busy pile stepped with the given kernels: its hash every 10 frames. */
static void run_kernels(const rbs__soft_kernels *k, uint64_t hashes[24])
{
    rbs_world *w = busy_pile(0.002);
    int i;
    w->soft_kernels = k;
    for (i = 0; i < 240; ++i) {
        step_n(w, 1);
        if (i % 10 == 9)
            hashes[i / 10] = rbs_world_hash(w);
    }
    rbs_world_destroy(w);
}

#if defined(RBS_HAVE_AVX_KERNELS)
/* Kernels k (named) against the plain ones' hashes, frame by frame. */
static void compare_with_plain(const char *name, const rbs__soft_kernels *k, const uint64_t *plain)
{
    static uint64_t other[24];
    int i;
    run_kernels(k, other);
    for (i = 0; i < 24; ++i)
        if (plain[i] != other[i])
            fail_msg("the %s kernels differ from the plain ones after frame %d", name, 10 * i + 10);
}
#endif

/* The plain kernels (four doubles, lane by lane) and those for AVX and
 * AVX-512VL, where this processor has them: the same bits every frame. */
static void kernels_give_the_same_bits(void **state)
{
    static uint64_t plain[24];
    (void)state;
    run_kernels(&rbs__soft_kernels_plain, plain);
#if defined(RBS_HAVE_AVX_KERNELS)
    if (__builtin_cpu_supports("avx"))
        compare_with_plain("AVX", &rbs__soft_kernels_avx, plain);
    else
        print_message("no AVX on this processor: its kernels not compared\n");
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl"))
        compare_with_plain("AVX-512VL", &rbs__soft_kernels_avx512, plain);
    else
        print_message("no AVX-512VL on this processor: its kernels not compared\n");
#else
    print_message("no AVX kernels in this build\n");
#endif
}

/* A hub: a fixed sphere of radius 1 at the origin and n balls of radius
 * 0.05 around it (points of a Fibonacci sphere), each closing on it
 * radially at v and touching it within the first frame -- n contacts on
 * one body, more than the chunker's open chunks can hold, so most of them
 * go into serial chunks.  No gravity; restitution e, friction mu. */
static void hub_bounces(const rbs__soft_kernels *kernels, int n, double v, double e, double mu)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_material_id m;
    rbs_sphere_def s;
    rbs_body_id ids[200];
    const double dt = 0.001, golden = 3.14159265358979323846 * (3.0 - sqrt(5.0));
    int i;
    rbs_world_def_init(&d);
    d.max_bodies = (uint32_t)n + 1;
    d.dt = dt;
    d.gravity.z = 0.0;
    d.method = RBS_METHOD_SOFT;
    CHECK_OK(rbs_world_create(&d, &w));
    w->soft_kernels = kernels;
    m = material(w, "m", mu, mu, e);
    rbs_sphere_def_init(&s);
    s.radius = 1.0;
    s.fixed = 1;
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    for (i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * (i + 0.5) / n, rho = sqrt(1.0 - z * z), ph = golden * i;
        double ux = rho * cos(ph), uy = rho * sin(ph), at = 1.05 + 0.5 * v * dt; /* (touches mid-frame) */
        ids[i] = ball(w, 0.05, 0.1, at * ux, at * uy, at * z, -v * ux, -v * uy, -v * z, m);
    }
    step_n(w, 3);
    /* each leaves radially at e v (the impact law with a fixed body), with
     * no tangential speed; 1e-12 of v: rounding */
    for (i = 0; i < n; ++i) {
        rbs_body_state st = state_of(w, ids[i]);
        double r = sqrt(st.position.x * st.position.x + st.position.y * st.position.y +
                        st.position.z * st.position.z);
        double vr = (st.velocity.x * st.position.x + st.velocity.y * st.position.y + st.velocity.z * st.position.z) / r;
        double v2 = st.velocity.x * st.velocity.x + st.velocity.y * st.velocity.y + st.velocity.z * st.velocity.z;
        ASSERT_NEAR(vr, e * v, 1e-12 * v);
        ASSERT_NEAR(sqrt(fabs(v2 - vr * vr)), 0.0, 1e-6 * v);
    }
    rbs_world_destroy(w);
}

static void hub_bounces_through_serial_chunks(void **state)
{
    (void)state;
    hub_bounces(&rbs__soft_kernels_plain, 60, 1.0, 0.5, 0.5);
    hub_bounces(&rbs__soft_kernels_plain, 120, 2.0, 1.0, 0.0);
    hub_bounces(rbs__soft_kernels_best(), 60, 1.0, 0.5, 0.5);
    hub_bounces(rbs__soft_kernels_best(), 120, 2.0, 0.0, 0.3);
}

/* A grid of 7 x 7 balls on the floor, 1 mm apart, all sliding at 2 m/s
 * along x: their sweeps (2 mm a frame) make every neighbouring pair a
 * contact (speculative), 84 of them besides the 49 with the floor, beyond
 * max_contacts = 60, so detection takes the serial path: the floor's
 * contacts, then the pairs while room is left (rbs__detect_swept's rule).
 * The balls keep their spacing -- no pair closes -- so each must slide and
 * come to roll exactly as a lone ball does (the same bits). */
static void overflowing_contacts_detect_serially(void **state)
{
    rbs_world_def d;
    rbs_world *w = NULL, *lone = NULL;
    rbs_material_id m, ml;
    rbs_body_id ids[49], one;
    int i, j;
    (void)state;
    rbs_world_def_init(&d);
    d.max_bodies = 50;
    d.max_contacts = 60;
    d.method = RBS_METHOD_SOFT;
    CHECK_OK(rbs_world_create(&d, &w));
    m = material(w, "m", 0.5, 0.5, 0.5);
    floor_plane(w, m);
    for (i = 0; i < 7; ++i)
        for (j = 0; j < 7; ++j)
            ids[7 * i + j] = ball(w, 0.05, 0.1, 0.101 * i, 0.101 * j, 0.05, 2.0, 0, 0, m);
    d.max_bodies = 2;
    d.max_contacts = 0;
    CHECK_OK(rbs_world_create(&d, &lone));
    ml = material(lone, "m", 0.5, 0.5, 0.5);
    floor_plane(lone, ml);
    one = ball(lone, 0.05, 0.1, 0, 0, 0.05, 2.0, 0, 0, ml);
    for (i = 0; i < 300; ++i) {
        step_n(w, 1);
        step_n(lone, 1);
        if (i == 0)
            assert_int_equal(w->contact_count, 60); /* (filled to the room: the serial rule) */
    }
    for (i = 0; i < 49; ++i) {
        rbs_body_state s = state_of(w, ids[i]), t = state_of(lone, one);
        assert_memory_equal(&s.position.z, &t.position.z, sizeof(double));
        assert_memory_equal(&s.velocity, &t.velocity, sizeof s.velocity);
        assert_memory_equal(&s.angular_velocity, &t.angular_velocity, sizeof s.angular_velocity);
    }
    /* (and it rolls by then: the slide ends at 2 v0 / (7 mu g) = 0.117 s) */
    ASSERT_NEAR(state_of(lone, one).velocity.x, 5.0 / 7.0 * 2.0, 1e-3);
    rbs_world_destroy(lone);
    rbs_world_destroy(w);
}

/* Whether the n bytes at p are all zero. */
static int all_zero(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    size_t i;
    for (i = 0; i < n; ++i)
        if (b[i] != 0)
            return 0;
    return 1;
}

/* A crowd of n spheres for the candidate list's tests and the list built
 * from the world's own arrays, kept to compare with: radii r0 to r0 + dr
 * in a cube of side L (sphere 7 of radius 0.5 m when big: past 4x the mean
 * reach, for the grid's big list), reaches 1.25 radii. */
typedef struct crowd {
    rbs_world *w;
    uint32_t n, count;
    double *C, size, rmax, rsum;
    uint32_t *pairs, *starts;
} crowd;

static crowd crowd_make(uint32_t n, uint64_t seed, double r0, double dr, double L, int big)
{
    rbs_world_def d;
    crowd c;
    uint32_t i, k;
    memset(&c, 0, sizeof c);
    c.n = n;
    c.C = malloc(3 * (size_t)n * sizeof(double));
    c.starts = malloc(((size_t)n + 1) * sizeof(uint32_t));
    assert_non_null(c.C);
    assert_non_null(c.starts);
    rbs_world_def_init(&d);
    d.max_bodies = n;
    d.method = RBS_METHOD_SOFT;
    CHECK_OK(rbs_world_create(&d, &c.w));
    for (i = 0; i < n; ++i) {
        double r = big && i == 7 ? 0.5 : r0 + dr * rnd(&seed);
        (void)ball(c.w, r, 0.1, L * rnd(&seed), L * rnd(&seed), L * rnd(&seed), 0, 0, 0, (rbs_material_id){0, 0});
    }
    for (i = 0; i < n; ++i) {
        const uint32_t a = c.w->spheres[i];
        for (k = 0; k < 3; ++k) {
            c.C[3 * i + k] = c.w->pos[3 * a + k];
            c.size = fabs(c.C[3 * i + k]) > c.size ? fabs(c.C[3 * i + k]) : c.size;
        }
        c.w->bp_reach[i] = 1.25 * c.w->radius[a];
        c.rsum += c.w->radius[a];
        c.rmax = c.w->bp_reach[i] > c.rmax ? c.w->bp_reach[i] : c.rmax;
    }
    assert_true(rbs__broadphase_build(c.w, NULL, c.C, n, 0.25, c.size, c.rmax, c.rsum));
    c.count = c.w->vl_count;
    assert_true(c.count > n / 2); /* (pairs enough to compare) */
    c.pairs = malloc(2 * (size_t)c.count * sizeof(uint32_t));
    assert_non_null(c.pairs);
    memcpy(c.pairs, c.w->vl_pair, 2 * (size_t)c.count * sizeof(uint32_t));
    memcpy(c.starts, c.w->vl_start, ((size_t)n + 1) * sizeof(uint32_t));
    return c;
}

/* The list built again in m (the list cleared first): the kept one, pair
 * for pair. */
static int crowd_same_list(crowd *c, const rbs__grid_mem *m)
{
    memset(c->w->vl_pair, 0, 2 * (size_t)c->count * sizeof(uint32_t));
    c->w->vl_valid = 0;
    return rbs__broadphase_build(c->w, m, c->C, c->n, 0.25, c->size, c->rmax, c->rsum) &&
           c->w->vl_count == c->count &&
           memcmp(c->w->vl_pair, c->pairs, 2 * (size_t)c->count * sizeof(uint32_t)) == 0 &&
           memcmp(c->w->vl_start, c->starts, ((size_t)c->n + 1) * sizeof(uint32_t)) == 0;
}

static void crowd_free(crowd *c)
{
    free(c->pairs);
    free(c->starts);
    free(c->C);
    rbs_world_destroy(c->w);
}

/* The candidate list built with the grid's arrays in a buffer of the
 * caller's (rbs__grid_mem_in) is the world's-arrays list, pair for pair;
 * a buffer a word too small is refused. */
static void grid_in_any_memory_gives_the_same_list(void **state)
{
    /* radii 0.02-0.06 m in a 1 m cube: a few pairs each, and a big one */
    crowd c = crowd_make(400, 99, 0.02, 0.04, 1.0, 1);
    rbs__grid_mem m;
    const size_t words = 6 * (size_t)c.n + 2 * (size_t)c.w->bp_table_size + 1;
    uint32_t *buf = malloc(words * sizeof(uint32_t));
    (void)state;
    assert_non_null(buf);
    assert_false(rbs__grid_mem_in(c.w, buf, (words - 1) * sizeof(uint32_t), c.n, &m));
    assert_true(rbs__grid_mem_in(c.w, buf, words * sizeof(uint32_t), c.n, &m));
    memset(buf, 0xA5, words * sizeof(uint32_t)); /* (no zeros to lean on) */
    assert_true(crowd_same_list(&c, &m));
    free(buf);
    crowd_free(&c);
}

/* A soft pile's candidate list is built in the chunks' room and its warm
 * store sorts in the records' room: the world's own grid arrays stay as
 * made (zero), so their pages are never made resident. */
static void soft_pile_leaves_the_grid_arrays_untouched(void **state)
{
    rbs_world *w = busy_pile(0.002);
    const size_t B = w->def.max_bodies, T = w->bp_table_size;
    (void)state;
    step_n(w, 60);
    assert_true(w->plan.gather);
    assert_true(w->vl_valid);
    assert_true(all_zero(w->bp_key, B * sizeof(uint32_t)));
    assert_true(all_zero(w->bp_item, B * sizeof(uint32_t)));
    assert_true(all_zero(w->bp_cell, 3 * B * sizeof(int32_t)));
    assert_true(all_zero(w->bp_start, (T + 1) * sizeof(uint32_t)));
    assert_true(all_zero(w->bp_fill, T * sizeof(uint32_t)));
    rbs_world_destroy(w);
}

/* The candidate list built on the world's threads (a buffer with room for
 * pairs: each share's pairs into its own run, counted by first item, moved
 * to their places, each item's partners sorted) against the one built on
 * the world's own grid arrays: the same list, pair for pair, on 1 to 4
 * threads; with too little room for a share's pairs (built the serial way
 * in the buffer), and with a list too small for the pairs (refused alike). */
static void list_on_threads_is_the_same_list(void **state)
{
    /* radii 0.02-0.04 m in a 1.2 m cube, no big one: a few pairs each */
    crowd c = crowd_make(3000, 7, 0.02, 0.02, 1.2, 0);
    rbs__grid_mem m;
    const size_t words = 6 * (size_t)c.n + 2 * (size_t)c.w->bp_table_size + 1;
    const size_t room = 4 * (size_t)c.count; /* pairs: ample for 8 shares */
    uint32_t *buf = malloc((words + 2 * room) * sizeof(uint32_t)), cap, t;
    int round;
    (void)state;
    assert_non_null(buf);
    assert_true(c.count > c.n);
    for (round = 0; round < 6; ++round) {
        /* rounds 0-3: 1 to 4 threads; 4: room for 2 pairs; 5: 2 threads */
        rbs_pool *pool = NULL;
        rbs_workers wk;
        int same;
        t = round < 4 ? (uint32_t)round + 1 : round == 4 ? 1 : 2;
        assert_true(rbs__grid_mem_in(c.w, buf, (words + 2 * (round == 4 ? 2 : room)) * sizeof(uint32_t), c.n, &m));
        assert_non_null(m.pairs);
        memset(buf, 0xA5, (words + 2 * room) * sizeof(uint32_t)); /* (no zeros to lean on) */
        if (t > 1) {
            CHECK_OK(rbs_pool_create(t - 1, &pool));
            rbs_workers_init(&wk);
            CHECK_OK(rbs_pool_workers(pool, &wk));
            CHECK_OK(rbs_world_set_workers(c.w, &wk));
            rbs__team_start(c.w);
        }
        same = crowd_same_list(&c, &m);
        if (t > 1) {
            rbs__team_stop(c.w);
            CHECK_OK(rbs_world_set_workers(c.w, NULL));
            rbs_pool_destroy(pool);
        }
        if (!same)
            fail_msg("round %d (%u threads): not the list of the world's own arrays", round, (unsigned)t);
    }
    /* a list with room for half the pairs: no list at all either way (the
     * skins cannot shrink: the reaches are the pass's own) */
    cap = c.w->vl_cap;
    c.w->vl_cap = c.count / 2;
    assert_false(rbs__broadphase_build(c.w, NULL, c.C, c.n, 10.0, c.size, c.rmax, c.rsum));
    assert_false(c.w->vl_valid);
    assert_true(rbs__grid_mem_in(c.w, buf, (words + 2 * room) * sizeof(uint32_t), c.n, &m));
    assert_false(rbs__broadphase_build(c.w, &m, c.C, c.n, 10.0, c.size, c.rmax, c.rsum));
    assert_false(c.w->vl_valid);
    c.w->vl_cap = cap;
    free(buf);
    crowd_free(&c);
}

static int key_less(const void *x, const void *y)
{
    const uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* The warm-start table a soft frame stores: one entry for each lane that
 * took a normal impulse (as many as the step reports resting), no key
 * twice -- so no contact twice and none lost -- each a pair of spheres or
 * a sphere and a plane that touch within a radius; each sphere's bucket of
 * each kind (its planes, its partners) in one run of entries, which
 * w->warm_at finds, and UINT32_MAX in warm_at for a sphere with none.
 * (The store used to sort each bucket into the slots before it without
 * knowing where the bucket began: an entry left there from the last frame
 * with the same sphere took the place, and in this pile the table held a
 * contact twice and lost another at frame 63.) */
static void warm_table_holds_each_contact_once(void **state)
{
    rbs_world *w = busy_pile(0.002);
    uint64_t *keys = malloc(w->warm_size * sizeof *keys);
    int frame;
    (void)state;
    assert_non_null(keys);
    for (frame = 0; frame < 150; ++frame) {
        rbs_step_info info;
        uint32_t i, k;
        CHECK_OK(rbs_world_step(w, &info));
        assert_true(w->warm_ranked && w->warm_indexed);
        if (w->warm_used != info.resting)
            fail_msg("frame %d: %u warm entries for %u resting contacts", frame, (unsigned)w->warm_used,
                     (unsigned)info.resting);
        for (i = 0; i < w->warm_used; ++i) {
            const uint64_t key = w->warm[i].key;
            const uint32_t a = (uint32_t)(key >> 32 & 0x7FFFFFFFu), b = (uint32_t)key, bucket = 2u * a + (uint32_t)(key >> 63);
            double gap;
            keys[i] = key;
            if ((i == 0 || w->warm[i - 1].key >> 32 != key >> 32) && w->warm_at[bucket] != i)
                fail_msg("frame %d: warm entry %u (%llx) begins its bucket, which warm_at puts at %u", frame,
                         (unsigned)i, (unsigned long long)key, (unsigned)w->warm_at[bucket]);
            if (key >> 63) {
                double dx = w->pos[3 * a] - w->pos[3 * b], dy = w->pos[3 * a + 1] - w->pos[3 * b + 1],
                       dz = w->pos[3 * a + 2] - w->pos[3 * b + 2];
                gap = sqrt(dx * dx + dy * dy + dz * dz) - w->radius[a] - w->radius[b];
            } else {
                gap = (w->pos[3 * a] - w->pos[3 * b]) * w->normal[3 * b] +
                      (w->pos[3 * a + 1] - w->pos[3 * b + 1]) * w->normal[3 * b + 1] +
                      (w->pos[3 * a + 2] - w->pos[3 * b + 2]) * w->normal[3 * b + 2] - w->radius[a];
            }
            if (!(w->warm[i].n > 0.0) || !(gap < w->radius[a]))
                fail_msg("frame %d: warm entry %u (%llx): force %g N, gap %g m", frame, (unsigned)i,
                         (unsigned long long)key, w->warm[i].n, gap);
        }
        /* no key twice */
        qsort(keys, w->warm_used, sizeof *keys, key_less);
        for (i = 1; i < w->warm_used; ++i)
            if (keys[i - 1] == keys[i])
                fail_msg("frame %d: the warm table holds %llx twice", frame, (unsigned long long)keys[i]);
        /* each bucket in one run: its first entry (warm_at) and the entries
         * of the bucket that follow it are all it has */
        for (k = 0; k < w->sphere_count; ++k)
            for (i = 0; i < 2u; ++i) {
                const uint32_t a = w->spheres[k], at = w->warm_at[2u * a + i];
                const uint64_t upper = (uint64_t)i << 31 | a;
                uint32_t run = 0, all = 0, j;
                for (j = at; at != UINT32_MAX && j < w->warm_used && w->warm[j].key >> 32 == upper; ++j)
                    run++;
                for (j = 0; j < w->warm_used; ++j)
                    all += w->warm[j].key >> 32 == upper;
                if (run != all || (at != UINT32_MAX && all == 0))
                    fail_msg("frame %d: sphere %u's bucket %u: %u entries, %u of them from warm_at %u", frame,
                             (unsigned)a, (unsigned)i, (unsigned)all, (unsigned)run, (unsigned)at);
            }
    }
    free(keys);
    rbs_world_destroy(w);
}

/* The table in key order (rbs__warm_sort, before another method searches it
 * by key), and an index made again from it (as after a checkpoint): every
 * entry is found by key with the same impulse, and the soft step goes on
 * with the same bits as a pile whose table stayed in its buckets. */
static void warm_table_sorted_and_indexed_again(void **state)
{
    rbs_world *a = busy_pile(0.002), *b = busy_pile(0.002);
    rbs__warm *copy;
    uint32_t i, at = 0, used;
    (void)state;
    step_n(a, 60);
    step_n(b, 60);
    used = a->warm_used;
    copy = malloc(used * sizeof *copy);
    assert_non_null(copy);
    memcpy(copy, a->warm, used * sizeof *copy);
    rbs__warm_sort(a);
    assert_false(a->warm_ranked || a->warm_indexed);
    assert_int_equal(a->warm_used, used);
    for (i = 1; i < used; ++i)
        assert_true(a->warm[i - 1].key < a->warm[i].key);
    for (i = 0; i < used; ++i) {
        const rbs__warm *m;
        at = 0;
        m = rbs__warm_find(a, copy[i].key, &at);
        assert_non_null(m);
        assert_true(m->n == copy[i].n && m->t.x == copy[i].t.x && m->t.y == copy[i].t.y && m->t.z == copy[i].t.z);
    }
    step_n(a, 60);
    step_n(b, 60);
    assert_true(rbs_world_hash(a) == rbs_world_hash(b));
    free(copy);
    rbs_world_destroy(a);
    rbs_world_destroy(b);
}

/* The warm-start table and its index are the same whatever the threads
 * that stored them (a thread stores the buckets of its own slabs): the
 * busy pile on 1, 2 and 4 threads, after 100 frames. */
static void warm_table_is_the_same_on_any_threads(void **state)
{
    rbs_world *one = busy_pile(0.002);
    uint32_t t, k;
    (void)state;
    step_n(one, 100);
    for (t = 1; t <= 3; t += 2) {
        rbs_world *w = busy_pile(0.002);
        rbs_pool *pool = NULL;
        rbs_workers wk;
        CHECK_OK(rbs_pool_create(t, &pool));
        rbs_workers_init(&wk);
        CHECK_OK(rbs_pool_workers(pool, &wk));
        CHECK_OK(rbs_world_set_workers(w, &wk));
        step_n(w, 100);
        CHECK_OK(rbs_world_set_workers(w, NULL));
        assert_int_equal(w->warm_used, one->warm_used);
        if (memcmp(w->warm, one->warm, one->warm_used * sizeof *one->warm) != 0)
            fail_msg("%u threads: another warm-start table", (unsigned)t + 1u);
        for (k = 0; k < one->sphere_count; ++k) {
            const uint32_t a = one->spheres[k];
            if (w->warm_at[2u * a] != one->warm_at[2u * a] || w->warm_at[2u * a + 1u] != one->warm_at[2u * a + 1u])
                fail_msg("%u threads: another index of sphere %u", (unsigned)t + 1u, (unsigned)a);
        }
        rbs_world_destroy(w);
        rbs_pool_destroy(pool);
    }
    rbs_world_destroy(one);
}

/* The busy pile on `threads` threads (1: none): 40 soft frames, then 5
 * frames whose pass searches the soft step's table by key (it sorts it
 * first; sort_first: the test sorts it before the switch) -- Euler's
 * (rolling 0), or the soft step's general layout, which a pair with rolling
 * resistance takes (rolling > 0: "a"/"a" gets it, and loses it again; not
 * "*"/"*", which no contact of the pile takes, every pair of its materials
 * having its own row) --
 * then 40 soft frames again (which index the key-ordered table); its hash. */
static uint64_t switching_methods(uint32_t threads, int sort_first, double rolling)
{
    rbs_pair_def pair;
    rbs_world *w = busy_pile(0.002);
    rbs_pool *pool = NULL;
    rbs_workers wk;
    uint64_t h;
    if (threads > 1) {
        CHECK_OK(rbs_pool_create(threads - 1u, &pool));
        rbs_workers_init(&wk);
        CHECK_OK(rbs_pool_workers(pool, &wk));
        CHECK_OK(rbs_world_set_workers(w, &wk));
    }
    step_n(w, 40);
    assert_true(w->warm_ranked && w->warm_used > 0);
    if (sort_first)
        rbs__warm_sort(w);
    rbs_pair_def_init(&pair);
    CHECK_OK(rbs_world_find_material(w, "a", &pair.a));
    pair.b = pair.a;
    pair.static_friction = pair.kinetic_friction = 0.5;
    if (rolling > 0.0) {
        pair.rolling = rolling;
        CHECK_OK(rbs_world_set_pair(w, &pair));
    } else {
        CHECK_OK(rbs_world_set_method(w, RBS_METHOD_EULER, 0.0));
    }
    step_n(w, 5);
    assert_false(w->warm_ranked || w->warm_indexed);
    if (rolling > 0.0) {
        pair.rolling = 0.0;
        CHECK_OK(rbs_world_set_pair(w, &pair));
    } else {
        CHECK_OK(rbs_world_set_method(w, RBS_METHOD_SOFT, 0.0));
    }
    step_n(w, 40);
    assert_true(w->warm_ranked && w->warm_indexed);
    h = rbs_world_hash(w);
    if (pool != NULL) {
        CHECK_OK(rbs_world_set_workers(w, NULL));
        rbs_pool_destroy(pool);
    }
    rbs_world_destroy(w);
    return h;
}

/* Soft, then Euler or the soft step's general layout, then soft again: the
 * table changes layout twice, and the run
 * gives the same bits on one thread and on three, and as when the table is
 * sorted before the switch (Euler's search by key finds what it would in
 * key order: a bucketed table searched by key as if sorted would not). */
static void methods_share_the_warm_table(void **state)
{
    double rolling;
    (void)state;
    for (rolling = 0.0; rolling < 0.02; rolling += 0.01) {
        const uint64_t one = switching_methods(1, 0, rolling);
        assert_true(one == switching_methods(3, 0, rolling));
        assert_true(one == switching_methods(1, 1, rolling));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(warm_tangent_kept_in_the_static_cone),
        cmocka_unit_test(kernels_give_the_same_bits),
        cmocka_unit_test(hub_bounces_through_serial_chunks),
        cmocka_unit_test(overflowing_contacts_detect_serially),
        cmocka_unit_test(grid_in_any_memory_gives_the_same_list),
        cmocka_unit_test(list_on_threads_is_the_same_list),
        cmocka_unit_test(soft_pile_leaves_the_grid_arrays_untouched),
        cmocka_unit_test(warm_table_holds_each_contact_once),
        cmocka_unit_test(warm_table_sorted_and_indexed_again),
        cmocka_unit_test(warm_table_is_the_same_on_any_threads),
        cmocka_unit_test(methods_share_the_warm_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
