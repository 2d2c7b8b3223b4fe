/* busy_pile.h - a busy pile for the soft step's tests of threads and
 * kernels: 1,100 spheres of three sizes and two materials (four
 * material-pair rows: friction, restitution 0 to 0.9), some spinning, one
 * fixed, dropped into a box of five planes -- enough spheres for four slabs
 * (soft_detect.c), so that the groups of every level of the soft step's tree
 * are used. */
#ifndef RBS_TEST_BUSY_PILE_H
#define RBS_TEST_BUSY_PILE_H

#include "common.h"

#define SPHERES 1100

/* A deterministic pseudo-random number in [0, 1) (64-bit LCG). */
static inline double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static inline rbs_world *busy_pile(double dt)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_material_id ma, mb;
    rbs_pair_def p;
    rbs_plane_def pl;
    uint64_t seed = 12345;
    int i, k;
    const double half = 0.75;
    rbs_world_def_init(&d);
    d.max_bodies = SPHERES + 8;
    d.dt = dt;
    d.restitution = 0.4;
    d.method = RBS_METHOD_SOFT;
    CHECK_OK(rbs_world_create(&d, &w));
    CHECK_OK(rbs_world_add_material(w, "a", &ma));
    CHECK_OK(rbs_world_add_material(w, "b", &mb));
    rbs_pair_def_init(&p);
    p.a = ma, p.b = ma, p.static_friction = 0.6, p.kinetic_friction = 0.4, p.restitution = 0.9;
    CHECK_OK(rbs_world_set_pair(w, &p));
    p.a = ma, p.b = mb, p.static_friction = 0.3, p.kinetic_friction = 0.2, p.restitution = 0.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    p.a = mb, p.b = mb, p.static_friction = 0.0, p.kinetic_friction = 0.0, p.restitution = 0.5;
    CHECK_OK(rbs_world_set_pair(w, &p));
    p.a = (rbs_material_id){0, 0}, p.b = (rbs_material_id){0, 0}, p.static_friction = 0.5,
    p.kinetic_friction = 0.5, p.restitution = -1.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    /* the floor and four walls */
    for (k = 0; k < 5; ++k) {
        rbs_plane_def_init(&pl);
        pl.material = k % 2 ? ma : mb;
        if (k > 0) {
            double sx = k == 1 ? 1 : k == 2 ? -1 : 0, sy = k == 3 ? 1 : k == 4 ? -1 : 0;
            pl.point.x = -sx * half, pl.point.y = -sy * half;
            pl.normal.x = sx, pl.normal.y = sy, pl.normal.z = 0.0;
        }
        CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
    }
    for (i = 0; i < SPHERES; ++i) {
        rbs_sphere_def s;
        int ix = i % 12, iy = (i / 12) % 12, iz = i / 144;
        rbs_sphere_def_init(&s);
        s.radius = i % 3 == 0 ? 0.04 : i % 3 == 1 ? 0.05 : 0.055;
        s.mass = 0.05 + 0.15 * rnd(&seed);
        s.position.x = -0.66 + 0.12 * ix + 0.01 * (rnd(&seed) - 0.5);
        s.position.y = -0.66 + 0.12 * iy + 0.01 * (rnd(&seed) - 0.5);
        s.position.z = 0.06 + 0.12 * iz + 0.01 * rnd(&seed);
        s.velocity.x = rnd(&seed) - 0.5;
        s.velocity.y = rnd(&seed) - 0.5;
        s.velocity.z = -2.0 * rnd(&seed);
        if (i % 7 == 0)
            s.angular_velocity.z = 20.0 * (rnd(&seed) - 0.5);
        s.material = i % 4 == 0 ? mb : ma;
        s.fixed = i == 40; /* one, in the bottom layer */
        if (s.fixed) {
            /* (still drawn, so the draws after it are as before) */
            memset(&s.velocity, 0, sizeof s.velocity);
            memset(&s.angular_velocity, 0, sizeof s.angular_velocity);
        }
        CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    }
    return w;
}

#endif
