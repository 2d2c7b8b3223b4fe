/* common.h - small helpers shared by the core tests. */
#ifndef RBS_TEST_COMMON_H
#define RBS_TEST_COMMON_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "rbsim/rbsim.h"

#define CHECK_OK(call)                                                          \
    do {                                                                        \
        rbs_status st_ = (call);                                                \
        if (st_ != RBS_OK)                                                      \
            fail_msg("%s -> %s", #call, rbs_status_name(st_));                  \
    } while (0)

/* Body b gets a force of 1e308 N along the axis where its position is
 * nearest 0 (so that its potential f.x stays within the setter's 1e300 J:
 * b must have a coordinate within 1e-8 m of 0): the next step overflows
 * (for a small enough mass), which must be
 * RBS_E_NUMERIC with the text `what` in the message, and leave the world
 * bit for bit as it was, still at `steps` steps. */
static inline void overflow_keeps_state(rbs_world *w, rbs_body_id b, const char *what, uint64_t steps)
{
    rbs_vec3 f = {0, 0, 0};
    rbs_body_state s;
    uint64_t h;
    CHECK_OK(rbs_body_get_state(w, b, &s));
    if (fabs(s.position.x) <= fabs(s.position.y) && fabs(s.position.x) <= fabs(s.position.z))
        f.x = 1e308;
    else if (fabs(s.position.y) <= fabs(s.position.z))
        f.y = 1e308;
    else
        f.z = 1e308;
    CHECK_OK(rbs_body_set_force(w, b, f));
    h = rbs_world_hash(w);
    assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
    assert_non_null(strstr(rbs_world_last_error(w), what));
    assert_true(rbs_world_hash(w) == h);
    assert_int_equal(rbs_world_step_count(w), steps);
}

/* A world with default settings and room for n bodies. */
static inline rbs_world *make_world(uint32_t n, double dt, double gz, double e)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = n;
    d.dt = dt;
    d.gravity.z = gz;
    d.restitution = e;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* One material with the given friction, used on every body of the world. */
static inline rbs_material_id material(rbs_world *w, const char *name, double mu_s, double mu_k,
                                       double e)
{
    rbs_material_id m;
    rbs_pair_def p;
    CHECK_OK(rbs_world_add_material(w, name, &m));
    rbs_pair_def_init(&p);
    p.a = m;
    p.b = m;
    p.static_friction = mu_s;
    p.kinetic_friction = mu_k;
    p.restitution = e;
    CHECK_OK(rbs_world_set_pair(w, &p));
    return m;
}

static inline rbs_body_id floor_plane(rbs_world *w, rbs_material_id m)
{
    rbs_plane_def p;
    rbs_body_id id;
    rbs_plane_def_init(&p);
    p.material = m;
    CHECK_OK(rbs_world_add_plane(w, &p, &id));
    return id;
}

static inline rbs_body_id ball(rbs_world *w, double r, double m, double x, double y, double z,
                               double vx, double vy, double vz, rbs_material_id mat)
{
    rbs_sphere_def s;
    rbs_body_id id;
    rbs_sphere_def_init(&s);
    s.radius = r;
    s.mass = m;
    s.position.x = x; s.position.y = y; s.position.z = z;
    s.velocity.x = vx; s.velocity.y = vy; s.velocity.z = vz;
    s.material = mat;
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    return id;
}

static inline rbs_body_state state_of(const rbs_world *w, rbs_body_id id)
{
    rbs_body_state s;
    CHECK_OK(rbs_body_get_state(w, id, &s));
    return s;
}

static inline void step_n(rbs_world *w, int n)
{
    int k;
    for (k = 0; k < n; ++k) {
        rbs_status st = rbs_world_step(w, NULL);
        if (st != RBS_OK)
            fail_msg("step %d: %s: %s", k, rbs_status_name(st), rbs_world_last_error(w));
    }
}

#define ASSERT_NEAR(a, b, tol)                                                  \
    do {                                                                        \
        double a_ = (a), b_ = (b), t_ = (tol);                                  \
        if (!(fabs(a_ - b_) <= t_))                                             \
            fail_msg("%s = %.17g, expected %.17g within %.3g (off by %.3g)",     \
                     #a, a_, b_, t_, fabs(a_ - b_));                            \
    } while (0)

/* The dome of the rolling-off tests: a fixed sphere of radius R at the
 * origin and a solid 1 kg ball of radius r on its top, rolling along x at
 * v0 (spin v0 / r about y), both of material m; returns the ball. */
static inline rbs_body_id ball_on_a_dome(rbs_world *w, rbs_material_id m, double R, double r, double v0)
{
    rbs_sphere_def d;
    rbs_body_id b;
    rbs_sphere_def_init(&d);
    d.radius = R;
    d.fixed = 1;
    d.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &d, NULL));
    rbs_sphere_def_init(&d);
    d.radius = r;
    d.mass = 1.0;
    d.position.z = R + r;
    d.velocity.x = v0;
    d.angular_velocity.y = v0 / r;
    d.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &d, &b));
    return b;
}

/* The incline scene: a plane through the origin at angle th (normal
 * (-sin th, 0, cos th)) whose material has mu_s = mu_k = mu, and a solid
 * 1 kg ball of radius r set on it at rest; returns the ball. */
static inline rbs_body_id incline_ball(rbs_world *w, double th, double mu, double r)
{
    rbs_material_id m = material(w, "m", mu, mu, -1.0);
    rbs_plane_def p;
    double nx = -sin(th), nz = cos(th);
    rbs_plane_def_init(&p);
    p.normal.x = nx;
    p.normal.z = nz;
    p.material = m;
    CHECK_OK(rbs_world_add_plane(w, &p, NULL));
    return ball(w, r, 1.0, r * nx, 0, r * nz, 0, 0, 0, m);
}

/* Exact acceleration down that incline under gravity g: a solid ball rolls
 * without slipping when tan(th) <= 7/2 mu, at 5/7 g sin(th); otherwise it
 * slides at g (sin(th) - mu cos(th)). */
static inline double incline_acceleration(double th, double mu, double g)
{
    return tan(th) <= 3.5 * mu ? 5.0 / 7.0 * g * sin(th) : g * (sin(th) - mu * cos(th));
}

/* A ball's speed down the incline (the plane z = x tan(th) falls towards
 * -x: down the slope is (-cos th, 0, -sin th)) and along its normal. */
static inline void incline_speeds(rbs_body_state s, double th, double *down, double *normal)
{
    *down = -(s.velocity.x * cos(th) + s.velocity.z * sin(th));
    *normal = s.velocity.x * -sin(th) + s.velocity.z * cos(th);
}

/* A solid 1 kg ball of radius r launched sliding at v0 along x, without
 * spin, on a floor whose pair has mu_s = mu_k = mu; stepped `steps` frames.
 * Returns the time of the first frame at which it rolls (|v - w r| below
 * tol v0), -1 if none; *b: the ball. */
static inline double slide_to_roll(rbs_world *w, double v0, double mu, double r, int steps, double tol,
                                   rbs_body_id *b)
{
    rbs_material_id m = material(w, "m", mu, mu, -1.0);
    double t_seen = -1.0;
    int k;
    floor_plane(w, m);
    *b = ball(w, r, 1.0, 0, 0, r, v0, 0, 0, m);
    for (k = 0; k < steps; ++k) {
        rbs_body_state s;
        step_n(w, 1);
        s = state_of(w, *b);
        if (t_seen < 0.0 && fabs(s.velocity.x - s.angular_velocity.y * r) < tol * v0)
            t_seen = rbs_world_time(w);
    }
    return t_seen;
}

/* A solid 1 kg ball of radius r rolling at v0 along x on the floor, their
 * pair with mu = 0.5 and rolling resistance mur; returns the ball. */
static inline rbs_body_id rolling_resistance_ball(rbs_world *w, double r, double v0, double mur)
{
    rbs_material_id m;
    rbs_pair_def p;
    rbs_sphere_def s;
    rbs_body_id b;
    CHECK_OK(rbs_world_add_material(w, "m", &m));
    rbs_pair_def_init(&p);
    p.a = p.b = m;
    p.static_friction = p.kinetic_friction = 0.5;
    p.rolling = mur;
    CHECK_OK(rbs_world_set_pair(w, &p));
    floor_plane(w, m);
    rbs_sphere_def_init(&s);
    s.radius = r;
    s.position.z = r;
    s.velocity.x = v0;
    s.angular_velocity.y = v0 / r;
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, &b));
    return b;
}

/* Newton's cradle: five 0.1 m, 1 kg balls on the x axis, the first 0.1 m
 * short of the touching row and arriving at 1 m/s (no gravity or friction
 * intended: the world's settings are the caller's). */
static inline void cradle_balls(rbs_world *w, rbs_body_id b[5])
{
    int i;
    b[0] = ball(w, 0.1, 1.0, -0.5, 0, 0, 1.0, 0, 0, (rbs_material_id){0, 0});
    for (i = 1; i < 5; ++i)
        b[i] = ball(w, 0.1, 1.0, 0.2 * (i - 1), 0, 0, 0, 0, 0, (rbs_material_id){0, 0});
}

/* ... and after the impacts with e = 1: the first four at rest, the last
 * leaving at 1 m/s, within tol. */
static inline void cradle_check(const rbs_world *w, const rbs_body_id b[5], double tol)
{
    int i;
    for (i = 0; i < 4; ++i)
        ASSERT_NEAR(state_of(w, b[i]).velocity.x, 0.0, tol);
    ASSERT_NEAR(state_of(w, b[4]).velocity.x, 1.0, tol);
}

/* Galperin's billiard: a wall (the plane x = 0), a 1 kg ball of r = 0.1 m
 * at rest at x = 0.5 and a ball of `heavy` kg at x = 1 moving to the wall
 * at 1 m/s; no gravity, no friction, e = 1.  For heavy = 100^k the impacts
 * number the first k + 1 digits of pi (31, 314, 3141).  Runs `steps` steps
 * of dt with the work cap max_substeps (0: the default) and returns the
 * impacts counted (rbs_step_info.colliding) or -1 on a failed step;
 * *v_light, *v_heavy get the final velocities along x, *capped the steps
 * that hit the work cap. */
static inline long pi_billiard(rbs_method method, double heavy, double dt, int steps,
                               uint32_t max_substeps, double *v_light, double *v_heavy,
                               int *capped)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_plane_def p;
    rbs_material_id none = {0, 0};
    rbs_body_id wall, light, big;
    long impacts = 0;
    int k;
    rbs_world_def_init(&d);
    d.max_bodies = 3;
    d.dt = dt;
    d.gravity.z = 0.0;
    d.restitution = 1.0;
    d.method = method;
    if (max_substeps > 0)
        d.max_substeps = max_substeps;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_plane_def_init(&p);
    p.normal.x = 1.0;
    p.normal.z = 0.0;
    CHECK_OK(rbs_world_add_plane(w, &p, &wall));
    light = ball(w, 0.1, 1.0, 0.5, 0, 0, 0, 0, 0, none);
    big = ball(w, 0.1, heavy, 1.0, 0, 0, -1.0, 0, 0, none);
    *capped = 0;
    for (k = 0; k < steps; ++k) {
        rbs_step_info info;
        if (rbs_world_step(w, &info) != RBS_OK) {
            impacts = -1;
            break;
        }
        impacts += info.colliding;
        *capped += info.work_limit != 0;
    }
    *v_light = state_of(w, light).velocity.x;
    *v_heavy = state_of(w, big).velocity.x;
    rbs_world_destroy(w);
    return impacts;
}

#endif
