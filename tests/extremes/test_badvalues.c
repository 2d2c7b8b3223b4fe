/*
 * test_badvalues.c - bad values at run time, for every method.
 *
 * A NaN or infinite value arriving through the API is refused (RBS_E_NUMERIC
 * or RBS_E_INVALID) and leaves the world bit-identical; a step whose result
 * overflows returns RBS_E_NUMERIC and leaves the world at its last good state
 * (same hash, same step count, every state value finite), and keeps doing so
 * when stepped again; NaN never reaches an output (state view, body state,
 * energy, momentum, checkpoint).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "rbsim/rbsim.h"
#include "core/world_internal.h" /* (add_ball: the layout of rbs_world) */

#define CHECK_OK(call)                                                          \
    do {                                                                        \
        rbs_status st_ = (call);                                                \
        if (st_ != RBS_OK)                                                      \
            fail_msg("%s -> %s", #call, rbs_status_name(st_));                  \
    } while (0)

static rbs_world *new_world(rbs_method m, double gz, int mutual)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_status st;
    rbs_world_def_init(&d);
    d.max_bodies = 8;
    d.gravity.z = gz;
    d.restitution = 1.0;
    d.mutual_gravity = mutual;
    d.gravity_constant = 1.0;
    CHECK_OK(rbs_world_create(&d, &w));
    st = rbs_world_set_method(w, m, 0.0);
    if (st == RBS_E_UNSUPPORTED) {
        rbs_world_destroy(w);
        return NULL;
    }
    CHECK_OK(st);
    return w;
}

/* A ball at p with velocity v and force f, written into the world's arrays
 * after it is added: rbs_world_add_sphere refuses a sphere whose energy at
 * the start is beyond 1e300 J, and since session 50 so do the setters
 * (their argument held to the same limits), but stepping can carry a world
 * into such states (and a checkpoint keep them), and they are what these
 * tests drive the world into.  Written as the setters wrote them before
 * (the same arrays, the plan marked stale); the values are finite. */
static rbs_body_id add_ball(rbs_world *w, double r, double mass, rbs_vec3 p, rbs_vec3 v, rbs_vec3 f)
{
    rbs_sphere_def s;
    rbs_body_id id;
    rbs_sphere_def_init(&s);
    s.radius = r;
    s.mass = mass;
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    assert_true(isfinite(p.x) && isfinite(p.y) && isfinite(p.z) && isfinite(v.x) && isfinite(v.y) &&
                isfinite(v.z) && isfinite(f.x) && isfinite(f.y) && isfinite(f.z));
    w->pos[3 * id.index] = p.x; w->pos[3 * id.index + 1] = p.y; w->pos[3 * id.index + 2] = p.z;
    w->vel[3 * id.index] = v.x; w->vel[3 * id.index + 1] = v.y; w->vel[3 * id.index + 2] = v.z;
    w->force[3 * id.index] = f.x; w->force[3 * id.index + 1] = f.y; w->force[3 * id.index + 2] = f.z;
    w->plan_dirty = 1;
    return id;
}

static rbs_vec3 V(double x, double y, double z)
{
    rbs_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

/* Every double of the state is finite; with diagnostics, energy and
 * momentum are an error or a number, never NaN. */
static void assert_outputs_clean_ex(const rbs_world *w, const char *where, int diagnostics)
{
    rbs_state_view v;
    rbs_energy e;
    rbs_vec3 p, l;
    uint32_t i;
    int k;
    CHECK_OK(rbs_world_state(w, &v));
    for (i = 0; i < v.slots; ++i) {
        for (k = 0; k < 3; ++k)
            if (!isfinite(v.position[3 * i + k]) || !isfinite(v.velocity[3 * i + k]) ||
                !isfinite(v.angular_velocity[3 * i + k]))
                fail_msg("%s: state view slot %u holds a non-finite value", where, (unsigned)i);
        for (k = 0; k < 4; ++k)
            if (!isfinite(v.orientation[4 * i + k]))
                fail_msg("%s: orientation of slot %u is not finite", where, (unsigned)i);
    }
    if (!diagnostics)
        return;
    /* diagnostics: an error or a number, never NaN */
    if (rbs_world_energy(w, &e) == RBS_OK && (isnan(e.kinetic) || isnan(e.potential) || isnan(e.total)))
        fail_msg("%s: rbs_world_energy returned RBS_OK with NaN (kinetic %g, potential %g, total %g)", where,
                 e.kinetic, e.potential, e.total);
    if (rbs_world_momentum(w, &p, &l) == RBS_OK &&
        (isnan(p.x) || isnan(p.y) || isnan(p.z) || isnan(l.x) || isnan(l.y) || isnan(l.z)))
        fail_msg("%s: rbs_world_momentum returned RBS_OK with NaN (P %g %g %g, L %g %g %g)", where, p.x, p.y,
                 p.z, l.x, l.y, l.z);
}

static void assert_outputs_clean(const rbs_world *w, const char *where)
{
    assert_outputs_clean_ex(w, where, 1);
}

/* Step up to n times.  Each step is RBS_OK or RBS_E_NUMERIC; a failing step
 * leaves hash and step count as they were, repeats the failure when stepped
 * again, and names the body.  Returns the number of failed steps seen (the
 * loop stops at the first). */
static int unnamed_errors; /* test-local tally: errors that name no body */

static int step_guarded(rbs_world *w, int n, const char *what)
{
    int k;
    for (k = 0; k < n; ++k) {
        uint64_t h = rbs_world_hash(w), c = rbs_world_step_count(w);
        rbs_status st = rbs_world_step(w, NULL);
        if (st == RBS_OK) {
            assert_outputs_clean_ex(w, what, 0); /* diagnostics: see diagnostics_never_nan */
            continue;
        }
        if (st == RBS_E_UNSUPPORTED) {
            print_message("[ SKIP     ] %s: %s\n", what, rbs_world_last_error(w));
            return -1;
        }
        if (st != RBS_E_NUMERIC)
            fail_msg("%s: step %d returned %s (%s), expected OK or E_NUMERIC", what, k + 1, rbs_status_name(st),
                     rbs_world_last_error(w));
        if (rbs_world_hash(w) != h || rbs_world_step_count(w) != c)
            fail_msg("%s: failed step %d changed the world", what, k + 1);
        if (strstr(rbs_world_last_error(w), "body") == NULL) {
            print_error("%s: error text does not name the body: \"%s\"\n", what, rbs_world_last_error(w));
            unnamed_errors++;
        }
        assert_outputs_clean_ex(w, what, 0);
        /* stepping again fails again, the world still unchanged */
        assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
        assert_true(rbs_world_hash(w) == h);
        return 1;
    }
    return 0;
}

static const double bad_values[] = {NAN, INFINITY, -INFINITY};

/* Setters and definitions refuse NaN and infinity; the world is unchanged. */
static void setters_refuse_non_finite(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        rbs_world *w = new_world((rbs_method)m, -9.81, 0);
        rbs_body_id b;
        rbs_sphere_def s;
        rbs_plane_def p;
        rbs_pair_def pd;
        rbs_quat q;
        size_t k;
        uint64_t h;
        if (!w)
            continue;
        b = add_ball(w, 0.1, 1.0, V(0, 0, 1), V(1, 0, 0), V(0, 0, 0));
        CHECK_OK(rbs_world_step(w, NULL));
        h = rbs_world_hash(w);
        for (k = 0; k < sizeof bad_values / sizeof bad_values[0]; ++k) {
            double x = bad_values[k];
            int c;
            for (c = 0; c < 3; ++c) {
                rbs_vec3 v = V(0, 0, 0);
                if (c == 0) v.x = x; else if (c == 1) v.y = x; else v.z = x;
                assert_int_equal(rbs_body_set_position(w, b, v), RBS_E_NUMERIC);
                assert_int_equal(rbs_body_set_velocity(w, b, v), RBS_E_NUMERIC);
                assert_int_equal(rbs_body_set_angular_velocity(w, b, v), RBS_E_NUMERIC);
                assert_int_equal(rbs_body_set_force(w, b, v), RBS_E_NUMERIC);
                assert_int_equal(rbs_body_set_torque(w, b, v), RBS_E_NUMERIC);
            }
            q.w = x; q.x = 0; q.y = 0; q.z = 0;
            assert_true(rbs_body_set_orientation(w, b, q) != RBS_OK);
            assert_true(rbs_world_set_dt(w, x) != RBS_OK);
            /* definitions */
            rbs_sphere_def_init(&s);
            s.radius = x;
            assert_true(rbs_world_add_sphere(w, &s, NULL) != RBS_OK);
            rbs_sphere_def_init(&s);
            s.mass = x;
            assert_true(rbs_world_add_sphere(w, &s, NULL) != RBS_OK);
            rbs_sphere_def_init(&s);
            s.position.y = x;
            assert_true(rbs_world_add_sphere(w, &s, NULL) != RBS_OK);
            rbs_sphere_def_init(&s);
            s.angular_velocity.x = x;
            assert_true(rbs_world_add_sphere(w, &s, NULL) != RBS_OK);
            rbs_sphere_def_init(&s);
            s.density = x;
            assert_true(rbs_world_add_sphere(w, &s, NULL) != RBS_OK);
            rbs_plane_def_init(&p);
            p.normal.z = x;
            assert_true(rbs_world_add_plane(w, &p, NULL) != RBS_OK);
            rbs_plane_def_init(&p);
            p.point.x = x;
            assert_true(rbs_world_add_plane(w, &p, NULL) != RBS_OK);
            rbs_pair_def_init(&pd);
            pd.static_friction = x;
            assert_true(rbs_world_set_pair(w, &pd) != RBS_OK);
            /* (restitution -inf is "negative: the world's", accepted by design) */
            rbs_pair_def_init(&pd);
            pd.restitution = x;
            assert_true(rbs_world_set_pair(w, &pd) != RBS_OK || x < 0.0);
            assert_true(rbs_world_set_method(w, (rbs_method)m, x) != RBS_OK || isinf(x));
        }
        assert_true(rbs_world_hash(w) == h);
        assert_int_equal(rbs_world_step_count(w), 1);
        CHECK_OK(rbs_world_step(w, NULL));
        assert_outputs_clean(w, "after refused setters");
        rbs_world_destroy(w);
    }
}

/* Overflow inside a step: huge force, huge speed, tiny mass, 1e308
 * positions, a collision at 1e308 m/s, mutual gravity across 2e308 m. */
static void overflow_restores_last_good_state(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        rbs_world *w;
        char what[96];
        const char *name = rbs_method_name((rbs_method)m);

        /* 1e308 N on 1 kg: v grows by 1e305 m/s per step, x overflows */
        if ((w = new_world((rbs_method)m, 0.0, 0)) == NULL) {
            print_message("[ SKIP     ] %s: method not available\n", name);
            continue;
        }
        add_ball(w, 0.1, 1.0, V(0, 0, 0), V(0, 0, 0), V(1e308, 0, 0));
        snprintf(what, sizeof what, "%s: huge force", name);
        if (step_guarded(w, 3000, what) == 0)
            fail_msg("%s: never overflowed", what);
        rbs_world_destroy(w);

        /* 1e308 m/s from x = 1e308: x overflows after ~800 steps */
        w = new_world((rbs_method)m, 0.0, 0);
        add_ball(w, 0.1, 1.0, V(1e308, 0, 0), V(1e308, 0, 0), V(0, 0, 0));
        snprintf(what, sizeof what, "%s: huge speed", name);
        if (step_guarded(w, 3000, what) == 0)
            fail_msg("%s: never overflowed", what);
        rbs_world_destroy(w);

        /* 1e-300 kg pushed by 1e10 N: a = 1e310 m/s^2 is infinite at once */
        w = new_world((rbs_method)m, 0.0, 0);
        add_ball(w, 0.1, 1e-300, V(0, 0, 0), V(0, 0, 0), V(1e10, 0, 0));
        snprintf(what, sizeof what, "%s: tiny mass", name);
        if (step_guarded(w, 10, what) == 0)
            fail_msg("%s: never overflowed", what);
        rbs_world_destroy(w);

        /* two balls at +-1e308 m/s meet: the relative speed overflows */
        w = new_world((rbs_method)m, 0.0, 0);
        add_ball(w, 0.1, 1.0, V(-0.11, 0, 0), V(1e308, 0, 0), V(0, 0, 0));
        add_ball(w, 0.1, 1.0, V(0.11, 0, 0), V(-1e308, 0, 0), V(0, 0, 0));
        snprintf(what, sizeof what, "%s: collision at 1e308 m/s", name);
        step_guarded(w, 10, what);
        rbs_world_destroy(w);

        /* mutual gravity between bodies 2e308 m apart (the distance is inf) */
        w = new_world((rbs_method)m, 0.0, 1);
        if (w) {
            add_ball(w, 0.1, 1.0, V(-1e308, 0, 0), V(0, 0, 0), V(0, 0, 0));
            add_ball(w, 0.1, 1.0, V(1e308, 0, 0), V(0, 0, 0), V(0, 0, 0));
            snprintf(what, sizeof what, "%s: mutual gravity across 2e308 m", name);
            step_guarded(w, 10, what);
            rbs_world_destroy(w);
        }

        /* a ball at 1e308 m resting on a plane through it under gravity */
        w = new_world((rbs_method)m, -9.81, 0);
        {
            rbs_plane_def p;
            rbs_plane_def_init(&p);
            p.point = V(1e308, 1e308, 1e308);
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        }
        add_ball(w, 0.1, 1.0, V(1e308, 1e308, 1e308), V(0, 0, 0), V(0, 0, 0));
        snprintf(what, sizeof what, "%s: resting at 1e308 m", name);
        step_guarded(w, 100, what);
        rbs_world_destroy(w);
    }
    if (unnamed_errors)
        fail_msg("%d overflow errors do not say which body overflowed", unnamed_errors);
}

/* A ball placed 1.8e308 m behind a tilted plane: pushing the overlap apart
 * overflows.  The step must then fail with RBS_E_NUMERIC and leave the
 * world unchanged (or succeed with a finite state), for every method. */
static void separation_overflow(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        rbs_world *w = new_world((rbs_method)m, 0.0, 0);
        rbs_plane_def p;
        char what[96];
        if (!w)
            continue;
        rbs_plane_def_init(&p);
        p.normal = V(1e-7, -1.0, 1e-7);
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        add_ball(w, 1e-3, 1.0, V(0, 1.7976931348623157e308, -1.7976931348623157e308), V(0, 0, 0), V(0, 0, 0));
        snprintf(what, sizeof what, "%s: separation from 1.8e308 m behind a plane", rbs_method_name((rbs_method)m));
        step_guarded(w, 3, what);
        rbs_world_destroy(w);
    }
}

/* Large but finite states must not turn diagnostics into NaN: a ball far
 * below the origin (z = -1e308) moving fast (1e155 m/s, so v^2 overflows)
 * has infinite kinetic and minus infinite potential energy; the sum is NaN
 * unless the library guards it.  Likewise momentum of 1e200 kg at 1e200 m/s
 * at x = 1 (0 * inf in the cross product). */
static void diagnostics_never_nan(void **state)
{
    rbs_world *w = new_world(RBS_METHOD_EULER, -9.81, 0);
    rbs_body_id b;
    (void)state;
    b = add_ball(w, 0.1, 1.0, V(0, 0, -1e308), V(0, 0, -1e155), V(0, 0, 0));
    (void)b;
    assert_outputs_clean(w, "energy at z = -1e308, v = 1e155");
    rbs_world_destroy(w);
    w = new_world(RBS_METHOD_EULER, 0.0, 0);
    add_ball(w, 0.1, 1e200, V(1, 0, 0), V(1e200, 0, 0), V(0, 0, 0));
    assert_outputs_clean(w, "momentum of 1e200 kg at 1e200 m/s");
    rbs_world_destroy(w);
    /* the state a huge force drives a ball into, one step before overflow */
    w = new_world(RBS_METHOD_EULER, 0.0, 0);
    add_ball(w, 0.1, 1.0, V(0, 0, 0), V(0, 0, 0), V(1e308, 0, 0));
    while (rbs_world_step(w, NULL) == RBS_OK)
        ;
    assert_outputs_clean(w, "last good state under a 1e308 N force");
    rbs_world_destroy(w);
}

/* A checkpoint of an extreme (finite) state restores it bit for bit, and
 * the restored world fails the overflowing step the same way. */
static void checkpoint_of_extreme_state(void **state)
{
    rbs_world *w = new_world(RBS_METHOD_EULER, 0.0, 0), *b = NULL;
    size_t n;
    unsigned char *buf;
    (void)state;
    add_ball(w, 1e-100, 1e-100, V(1.7976931348623157e308, -1.7e308, 4.9e-324), V(1e308, 0, -1e-310), V(0, 0, 0));
    add_ball(w, 1e100, 1e100, V(0, 0, 0), V(0, 0, 0), V(0, 0, 0));
    n = rbs_world_checkpoint_size(w);
    buf = malloc(n);
    assert_non_null(buf);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, n, NULL));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &b));
    assert_true(rbs_world_hash(w) == rbs_world_hash(b));
    assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
    assert_int_equal(rbs_world_step(b, NULL), RBS_E_NUMERIC);
    assert_true(rbs_world_hash(w) == rbs_world_hash(b));
    free(buf);
    rbs_world_destroy(w);
    rbs_world_destroy(b);
}

/* Far from the origin, where coordinates round by more than a contact's
 * slop (half their spacing: 1e10 m rounds in steps of 1.9e-6 m, against
 * 1e-6 of a 0.1 m radius = 1e-7 m), a contact's gap is rounding: the
 * methods that decide by the slop (rollback: euler, verlet, rk4, adaptive;
 * events: event) refuse the step with RBS_E_NUMERIC, naming both bodies and
 * the distance, and leave the world as it was -- where before they rolled
 * back without end, froze a ball above the floor or let it fall through
 * (the probe of session 38) -- while soft and selective, whose contacts do
 * not hang on the slop, hold the ball within their own tolerance.  At 1e8 m
 * (steps of 1.5e-8 m) every method holds it.  At 1e12 m (steps of 1.2e-4
 * m) soft and selective refuse too: the falling ball's own move, before it
 * lands, as its coordinates round by more than 1 % of what it moves a frame
 * (the rule for free motion, which also stops euler, verlet, rk4 and
 * adaptive there before the contact does; see
 * far_motion_refused_where_it_would_be_rounding).  A ball
 * resting on the floor and one dropped onto it from 5 cm, 300 steps of 1 ms. */
static void far_contacts_refused_where_coordinates_are_coarse(void **state)
{
    static const double offs[] = {1e8, 1e10, 1e12};
    size_t o;
    int m;
    (void)state;
    for (o = 0; o < sizeof offs / sizeof offs[0]; ++o) {
        const double off = offs[o];
        for (m = 0; m < RBS_METHOD_COUNT; ++m) {
            const int holds = off < 1e9 || ((m == RBS_METHOD_SOFT || m == RBS_METHOD_SELECTIVE ||
                                              m == RBS_METHOD_AUTO) && off < 1e11);
                              /* (auto takes euler here: checked below) */
            rbs_world *w = new_world((rbs_method)m, -9.81, 0);
            rbs_plane_def p;
            rbs_body_id rest;
            rbs_body_state bs;
            char what[64];
            int k, failed = 0;
            if (!w)
                continue;
            snprintf(what, sizeof what, "%s at %g m", rbs_method_name((rbs_method)m), off);
            rbs_plane_def_init(&p);
            p.point = V(off, -off, off);
            p.normal = V(0, 0, 1);
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            rest = add_ball(w, 0.1, 1.0, V(off, -off, off + 0.1), V(0, 0, 0), V(0, 0, 0));
            (void)add_ball(w, 0.1, 1.0, V(off + 1.0, -off, off + 0.15), V(0, 0, 0), V(0, 0, 0));
            for (k = 0; k < 300 && !failed; ++k) {
                uint64_t h = rbs_world_hash(w), c = rbs_world_step_count(w);
                rbs_status st = rbs_world_step(w, NULL);
                if (st == RBS_OK)
                    continue;
                failed = 1;
                if (st != RBS_E_NUMERIC)
                    fail_msg("%s: step %d returned %s (%s)", what, k + 1, rbs_status_name(st), rbs_world_last_error(w));
                if (strstr(rbs_world_last_error(w), "from the origin") == NULL ||
                    (strstr(rbs_world_last_error(w), "touches") == NULL &&
                     (off < 1e11 || strstr(rbs_world_last_error(w), "lost to rounding") == NULL)))
                    fail_msg("%s: the error does not name the contact and the distance: \"%s\"", what,
                             rbs_world_last_error(w));
                if (rbs_world_hash(w) != h || rbs_world_step_count(w) != c)
                    fail_msg("%s: the failed step changed the world", what);
            }
            if (m == RBS_METHOD_AUTO) {
                /* two spheres: auto is euler, which refuses beyond 1e9 m */
                if (failed != (off > 1e9))
                    fail_msg("%s: %s", what, failed ? rbs_world_last_error(w) : "no error where euler refuses");
            } else if (holds && failed) {
                fail_msg("%s: %s", what, rbs_world_last_error(w));
            } else if (!holds && !failed) {
                fail_msg("%s: 300 steps without an error", what);
            }
            if (!failed) {
                /* the resting ball held: its drop at most the soft step's sink
                 * g / omega^2 = 0.25 um (1 um) plus 4 roundings */
                CHECK_OK(rbs_body_get_state(w, rest, &bs));
                if (!(fabs(bs.position.z - (off + 0.1)) <= 1e-6 + 4.0 * off * 2.3e-16))
                    fail_msg("%s: the resting ball moved to %.17g (from %.17g)", what, bs.position.z, off + 0.1);
            }
            rbs_world_destroy(w);
        }
    }
}

/* The same refusal for a ball dropped from 1 m onto a floor at 1e12 m (a
 * friction row on the pair, one ball): adaptive did not refuse, but hung
 * the ball 0.1 mm over the floor -- its event search put it back at its
 * last rounded place before the floor, again and again -- while gravity
 * went on adding to its speed (-5.9 m/s at 0.6 s), each frame slower than
 * the last (a probe of session 40).  Every method that decides by the slop
 * refuses within the 0.45 s the fall takes and a few frames more. */
static void far_drop_refused_by_every_slop_method(void **state)
{
    static const rbs_method ms[] = {RBS_METHOD_EULER, RBS_METHOD_EVENT, RBS_METHOD_VERLET, RBS_METHOD_RK4,
                                    RBS_METHOD_ADAPTIVE};
    const double off = 1e12;
    size_t m;
    (void)state;
    for (m = 0; m < sizeof ms / sizeof ms[0]; ++m) {
        rbs_world *w = new_world(ms[m], -9.81, 0);
        rbs_plane_def p;
        rbs_pair_def pr;
        int k, failed = 0;
        rbs_plane_def_init(&p);
        p.point = V(0, 0, off);
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        rbs_pair_def_init(&pr); /* (a and b null: "*" with "*") */
        CHECK_OK(rbs_world_set_pair(w, &pr));
        (void)add_ball(w, 0.1, 1.0, V(0, 0, off + 1.1), V(0, 0, 0), V(0, 0, 0));
        for (k = 0; k < 600 && !failed; ++k) {
            uint64_t h = rbs_world_hash(w);
            rbs_status st = rbs_world_step(w, NULL);
            if (st == RBS_OK)
                continue;
            failed = 1;
            if (st != RBS_E_NUMERIC || strstr(rbs_world_last_error(w), "from the origin") == NULL)
                fail_msg("%s: step %d: %s: %s", rbs_method_name(ms[m]), k + 1, rbs_status_name(st),
                         rbs_world_last_error(w));
            if (rbs_world_hash(w) != h)
                fail_msg("%s: the failed step changed the world", rbs_method_name(ms[m]));
        }
        if (!failed)
            fail_msg("%s: 600 steps (0.6 s) without an error", rbs_method_name(ms[m]));
        rbs_world_destroy(w);
    }
}

/* Free motion far from the origin: x + v h rounds back to x once the
 * spacing of coordinates passes the move, and bodies froze while their
 * speeds went on (a probe of session 40: at 1e15 m, steps of 0.125 m, a
 * ball launched at 1 m/s stayed put with every method and two balls closing
 * at 1 m/s never met; at 1e12 m a slide came out 2.4 % long).  Every method
 * now refuses the step (RBS_E_NUMERIC, the world unchanged) where a body
 * moving more than a thousandth of its radius a frame would move by less
 * than 100 roundings; at 1e10 m (rounding 1e-3 of a 1 mm move) a ball flies
 * 1000 frames within those roundings of x0 + v t. */
static void far_motion_refused_where_it_would_be_rounding(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        static const double offs[] = {1e15, 1e12, 1e10};
        size_t o;
        for (o = 0; o < sizeof offs / sizeof offs[0]; ++o) {
            const double off = offs[o];
            rbs_world *w = new_world((rbs_method)m, 0.0, 0);
            rbs_body_id a;
            rbs_body_state bs;
            char what[64];
            int k;
            if (!w)
                continue;
            snprintf(what, sizeof what, "%s at %g m", rbs_method_name((rbs_method)m), off);
            a = add_ball(w, 0.1, 1.0, V(off, 0, 0), V(1.0, 0, 0), V(0, 0, 0));
            (void)add_ball(w, 0.1, 1.0, V(off + 1.0, 0, 0), V(-1.0, 0, 0), V(0, 0, 0));
            if (off > 1e11) {
                uint64_t h = rbs_world_hash(w);
                rbs_status st = rbs_world_step(w, NULL);
                if (st != RBS_E_NUMERIC || strstr(rbs_world_last_error(w), "lost to rounding") == NULL ||
                    strstr(rbs_world_last_error(w), "from the origin along x") == NULL)
                    fail_msg("%s: %s: %s", what, rbs_status_name(st), rbs_world_last_error(w));
                if (rbs_world_hash(w) != h || rbs_world_step_count(w) != 0)
                    fail_msg("%s: the refused step changed the world", what);
            } else {
                for (k = 0; k < 400; ++k) {
                    rbs_status st = rbs_world_step(w, NULL);
                    if (st != RBS_OK)
                        fail_msg("%s: step %d: %s", what, k + 1, rbs_world_last_error(w));
                }
                /* (0.4 s: 0.4 m each, still 0.2 m apart) */
                CHECK_OK(rbs_body_get_state(w, a, &bs));
                if (!(fabs(bs.position.x - (off + 0.4)) <= 400 * 0.5 * 1.9073486328125e-06))
                    fail_msg("%s: x = %.17g, expected %.17g within 400 half spacings", what, bs.position.x,
                             off + 0.4);
            }
            rbs_world_destroy(w);
        }
    }
}

/* Directions of any finite size are directions: a plane normal of
 * (0, 0, 1e-310) was scaled by 1 / 1e-310 = inf and stored as NaN (the ball
 * then fell through that floor with soft and event, and euler blamed the
 * ball), and rbs_body_set_orientation took sqrt of the sum of squares as it
 * came: it refused (1e300, 0, 0, 0) and (5e-324, 0, 0, 0) as "zero" and
 * stored |q| = 0.954 for (3e-162, 0, 0, 0), while add_sphere took them (a
 * probe of session 40).  Exact: the unit normal (0, 0, 1) and the identity
 * (or 90 degrees about x for (1e308, 1e308, 0, 0)) to rounding.  And the
 * time: dt = 1e308 makes the second step's time inf, which is refused. */
static void tiny_and_huge_directions(void **state)
{
    static const double tiny[] = {1e-310, 4e-320, 5e-324, 1e-300, 1e300, 1.7976931348623157e308};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof tiny / sizeof tiny[0]; ++k) {
        rbs_world *w = new_world(RBS_METHOD_SOFT, -9.81, 0);
        rbs_plane_def p;
        rbs_body_id f, b;
        rbs_body_state bs;
        rbs_quat q;
        rbs_plane_def_init(&p);
        p.normal = V(0, 0, tiny[k]);
        CHECK_OK(rbs_world_add_plane(w, &p, &f));
        CHECK_OK(rbs_body_get_state(w, f, &bs));
        if (!(bs.normal.x == 0.0 && bs.normal.y == 0.0 && bs.normal.z == 1.0))
            fail_msg("normal (0, 0, %g) stored as (%g, %g, %g)", tiny[k], bs.normal.x, bs.normal.y, bs.normal.z);
        b = add_ball(w, 0.1, 1.0, V(0, 0, 0.5), V(0, 0, 0), V(0, 0, 0));
        q.w = tiny[k]; q.x = q.y = q.z = 0.0;
        CHECK_OK(rbs_body_set_orientation(w, b, q));
        CHECK_OK(rbs_body_get_state(w, b, &bs));
        if (!(bs.orientation.w == 1.0 && bs.orientation.x == 0.0))
            fail_msg("orientation (%g, 0, 0, 0) stored as (%.17g, %g, %g, %g)", tiny[k], bs.orientation.w,
                     bs.orientation.x, bs.orientation.y, bs.orientation.z);
        q.w = q.x = tiny[k];
        CHECK_OK(rbs_body_set_orientation(w, b, q));
        CHECK_OK(rbs_body_get_state(w, b, &bs));
        if (!(fabs(bs.orientation.w - sqrt(0.5)) <= 2.3e-16 && fabs(bs.orientation.x - sqrt(0.5)) <= 2.3e-16))
            fail_msg("orientation (%g, %g, 0, 0) stored as (%.17g, %.17g, ...)", tiny[k], tiny[k],
                     bs.orientation.w, bs.orientation.x);
        q.w = q.x = 0.0;
        assert_int_equal(rbs_body_set_orientation(w, b, q), RBS_E_INVALID);
        {
            /* (e = 1: it bounces on the floor, never below it by more than
             * soft's overlaps, a few mm at an impact of 2.8 m/s) */
            int i;
            for (i = 0; i < 1000; ++i) {
                CHECK_OK(rbs_world_step(w, NULL));
                CHECK_OK(rbs_body_get_state(w, b, &bs));
                if (!(bs.position.z > 0.09))
                    fail_msg("normal (0, 0, %g): the ball is at z = %g at step %d, through the floor", tiny[k],
                             bs.position.z, i + 1);
            }
        }
        rbs_world_destroy(w);
    }
    {
        rbs_world *w = new_world(RBS_METHOD_EULER, 0.0, 0);
        rbs_plane_def p;
        rbs_plane_def_init(&p);
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        CHECK_OK(rbs_world_set_dt(w, 1e308));
        CHECK_OK(rbs_world_step(w, NULL));
        assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
        assert_non_null(strstr(rbs_world_last_error(w), "beyond the largest double"));
        assert_true(rbs_world_time(w) == 1e308 && rbs_world_step_count(w) == 1);
        rbs_world_destroy(w);
    }
}

/* A fast impact near the origin is not "far": a 1 mm ball at 1e8 m/s
 * meets a fixed ball (or a wall) 1 m away within a frame of dt = 1 s.  The
 * trial step put it at 1e8 m, and euler, verlet and rk4 refused the frame
 * as a contact "1e+08 m from the origin" where coordinates are coarse (a
 * probe of session 45), though the impact is at 1 m: the rule for coarse
 * contacts now takes the positions at the start of the sub-step, where a
 * rollback goes back to.  Exact (e = 1, the target fixed): the ball comes
 * back at -1e8 m/s from its touching point x1 (0.998 m, or 0.999 m for the
 * wall), so it ends at 2 x1 - 1e8 m; to 1e-12 of the speed and to 1e-6 m,
 * a few roundings of the positions it passes through (1.5e-8 m at 1e8 m).
 * At the rollback floor (dt / 2^30 = 9.3e-10 s, 0.093 m at that speed)
 * the ball then went through the other ball, reported only as a floor hit,
 * and came back from the wall 2.5 cm off: a floor sub-step is now taken in
 * two parts that meet at the first touch.  Every method. */
static void fast_impact_near_the_origin_is_not_far(void **state)
{
    int m, wall;
    (void)state;
    for (wall = 0; wall < 2; ++wall)
        for (m = 0; m < RBS_METHOD_COUNT; ++m) {
            rbs_world *w = new_world((rbs_method)m, 0.0, 0);
            rbs_body_id a;
            rbs_body_state bs;
            char what[64];
            rbs_status st;
            rbs_step_info si;
            const double r = 1e-3, x1 = wall ? 1.0 - r : 1.0 - 2.0 * r;
            if (!w)
                continue;
            snprintf(what, sizeof what, "%s, %s", rbs_method_name((rbs_method)m), wall ? "wall" : "ball");
            CHECK_OK(rbs_world_set_dt(w, 1.0));
            a = add_ball(w, r, 1.0, V(0, 0, 0), V(1e8, 0, 0), V(0, 0, 0));
            if (wall) {
                rbs_plane_def p;
                rbs_plane_def_init(&p);
                p.point = V(1.0, 0, 0);
                p.normal = V(-1.0, 0, 0);
                CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            } else {
                rbs_sphere_def s;
                rbs_sphere_def_init(&s);
                s.radius = r;
                s.mass = 1.0;
                s.fixed = 1;
                s.position = V(1.0, 0, 0);
                CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
            }
            st = rbs_world_step(w, &si);
            if (st != RBS_OK)
                fail_msg("%s: %s: %s", what, rbs_status_name(st), rbs_world_last_error(w));
            if (si.floor_hits != 0 || si.work_limit != 0)
                fail_msg("%s: %u floor hits, work limit %u", what, (unsigned)si.floor_hits, (unsigned)si.work_limit);
            CHECK_OK(rbs_body_get_state(w, a, &bs));
            if (m == RBS_METHOD_SOFT) {
                /* (soft bounces a frame late, as documented: only that it
                 * does bounce, at the speed it came) */
                if (!(fabs(bs.velocity.x + 1e8) <= 1e-4))
                    fail_msg("%s: v = %.17g, expected -1e8", what, bs.velocity.x);
            } else if (!(fabs(bs.velocity.x + 1e8) <= 1e-4) || !(fabs(bs.position.x - (2 * x1 - 1e8)) <= 1e-6)) {
                fail_msg("%s: x = %.17g, v = %.17g; expected %.17g, -1e8", what, bs.position.x, bs.velocity.x,
                         2 * x1 - 1e8);
            }
            rbs_world_destroy(w);
        }
}

/* Slow motion far from the origin: a move under a thousandth of the
 * radius a frame is not refused (a bounce passes through such moves at its
 * top), but where rounding changes it by more than 1 % (and by more than
 * 1e-9 of the radius) the step is counted in rbs_world_rounded_steps.  A
 * 0.1 m ball at 0.05 m/s (5e-5 m a frame) froze at 1e12 m (steps of 1.2e-4
 * m) and came out 0.8 % short at 1e10 m (1.9e-6 m), both unreported (a
 * probe of session 45): every step of those is counted now, with every
 * method.  Not counted: the same at 1e6 m (rounding 1.2e-10 m, 2e-4 % of
 * the move), and a ball bouncing on a floor near the origin or at 1e6 m
 * (its top's slow moves lose at most 6e-11 m, under 1e-9 of the radius),
 * nor a ball resting on a floor. */
static void slow_far_motion_counted(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        static const struct { double off, v, gz; int counted; } cs[] = {
            {1e12, 0.05, 0.0, 1}, {1e10, 0.05, 0.0, 1}, {1e6, 0.05, 0.0, 0},
            {0.0, 0.0, -9.81, 0}, {1e6, 0.0, -9.81, 0}, {0.0, -1e-3, -9.81, 0}};
        size_t k;
        for (k = 0; k < sizeof cs / sizeof cs[0]; ++k) {
            rbs_world *w = new_world((rbs_method)m, cs[k].gz, 0);
            char what[96];
            int i;
            uint64_t counted;
            if (!w)
                continue;
            snprintf(what, sizeof what, "%s at %g m, v %g, g %g", rbs_method_name((rbs_method)m), cs[k].off,
                     cs[k].v, cs[k].gz);
            if (cs[k].gz != 0.0) {
                rbs_plane_def p;
                rbs_plane_def_init(&p);
                p.point = V(0, 0, cs[k].off);
                CHECK_OK(rbs_world_add_plane(w, &p, NULL));
                /* resting (v 0) or dropped from 5 cm (v < 0: e = 1, bounces) */
                (void)add_ball(w, 0.1, 1.0, V(0, 0, cs[k].off + (cs[k].v < 0.0 ? 0.15 : 0.1)), V(0, 0, 0),
                               V(0, 0, 0));
            } else {
                (void)add_ball(w, 0.1, 1.0, V(cs[k].off, 0, 0), V(cs[k].v, 0, 0), V(0, 0, 0));
            }
            for (i = 0; i < 1000; ++i) {
                rbs_status st = rbs_world_step(w, NULL);
                if (st != RBS_OK)
                    fail_msg("%s: step %d: %s", what, i + 1, rbs_world_last_error(w));
            }
            counted = rbs_world_rounded_steps(w);
            if (cs[k].counted ? counted != 1000 : counted != 0)
                fail_msg("%s: %llu of 1000 steps counted", what, (unsigned long long)counted);
            rbs_world_destroy(w);
        }
    }
    assert_true(rbs_world_rounded_steps(NULL) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(setters_refuse_non_finite),
        cmocka_unit_test(overflow_restores_last_good_state),
        cmocka_unit_test(checkpoint_of_extreme_state),
        cmocka_unit_test(separation_overflow),
        cmocka_unit_test(diagnostics_never_nan),
        cmocka_unit_test(far_contacts_refused_where_coordinates_are_coarse),
        cmocka_unit_test(far_drop_refused_by_every_slop_method),
        cmocka_unit_test(far_motion_refused_where_it_would_be_rounding),
        cmocka_unit_test(tiny_and_huge_directions),
        cmocka_unit_test(fast_impact_near_the_origin_is_not_far),
        cmocka_unit_test(slow_far_motion_counted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
