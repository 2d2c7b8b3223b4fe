/*
 * test_clock.c - the simulated clock over long runs, for every method.
 *
 * rbs_world_time is the step count times dt (each run of steps with the dt
 * it was taken with), one product, not a running sum: after n steps it must
 * be n dt correctly rounded, |t - n dt| <= half an ulp of t.  A running sum
 * of 1e7 steps of 1 ms would be off by up to 1e7 half-ulps of the sum's
 * size (1e-6 s at 1e4 s), 1e6 times that bound.  The residual n dt - t is
 * taken exactly with fma (the error of a rounded product is a double).
 */
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

static double half_ulp(double t) { return 0.5 * (nextafter(t, INFINITY) - t); }

/* A world with one ball flying at 1 m/s along x, no gravity. */
static rbs_world *flyer(rbs_method m, double dt, rbs_body_id *b)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_sphere_def s;
    rbs_world_def_init(&d);
    d.max_bodies = 2;
    d.dt = dt;
    d.gravity.z = 0.0;
    d.method = m;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_sphere_def_init(&s);
    s.velocity.x = 1.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, b));
    return w;
}

/* For every method, 1e6 steps of 1 ms (1e7 for the default, auto; 2e5 for
 * adaptive and soft, whose steps cost 5-10 times more here): the
 * time is n dt to half an ulp after every 1000th step and at the end, and
 * the ball, x = v t exactly in real numbers, is within n half-ulps of its
 * largest x (one rounding of x + v dt a step; soft: 3 sub-steps a step):
 * 1e6 x 5.7e-14 = 5.7e-8 m at 1000 m. */
static void time_is_n_dt(void **state)
{
    int m;
    (void)state;
    for (m = 0; m < RBS_METHOD_COUNT; ++m) {
        const double dt = 1e-3;
        const long n = m == RBS_METHOD_AUTO                                ? 10000000L
                       : m == RBS_METHOD_ADAPTIVE || m == RBS_METHOD_SOFT ? 200000L
                                                                          : 1000000L;
        rbs_body_id b;
        rbs_world *w = flyer((rbs_method)m, dt, &b);
        rbs_body_state s;
        long k;
        double t = 0.0, xbound;
        for (k = 1; k <= n; ++k) {
            rbs_status st = rbs_world_step(w, NULL);
            if (st != RBS_OK)
                fail_msg("%s: step %ld: %s", rbs_method_name((rbs_method)m), k, rbs_world_last_error(w));
            if (k % 1000 == 0 || k == n) {
                t = rbs_world_time(w);
                if (!(fabs(fma((double)k, dt, -t)) <= half_ulp(t)))
                    fail_msg("%s: after %ld steps of %g s the time is %.17g, off by %.3g s (> half an ulp, "
                             "%.3g)", rbs_method_name((rbs_method)m), k, dt, t, fma((double)k, dt, -t),
                             half_ulp(t));
            }
        }
        assert_true(rbs_world_step_count(w) == (uint64_t)n);
        CHECK_OK(rbs_body_get_state(w, b, &s));
        xbound = (double)n * (m == RBS_METHOD_SOFT ? 3.0 : 1.0) * half_ulp(t);
        if (!(fabs(s.position.x - t) <= xbound))
            fail_msg("%s: x = %.17g after %.17g s at 1 m/s: off by %.3g m (bound %.3g m)",
                     rbs_method_name((rbs_method)m), s.position.x, t, s.position.x - t, xbound);
        rbs_world_destroy(w);
    }
}

/* rbs_world_set_dt keeps the time so far and counts on from it: 1000 steps
 * of 1 ms, then 3 steps of 1/3 s, then 1e5 of 1e-7 s: t = 1 + 1 + 0.01 s,
 * each part one rounded product and one rounded sum: within 2 ulps of 2.01
 * (a running sum of the 101,003 steps: up to 1e5 half-ulps of 2). */
static void set_dt_keeps_the_time(void **state)
{
    rbs_body_id b;
    rbs_world *w = flyer(RBS_METHOD_EULER, 1e-3, &b);
    long k;
    double t;
    (void)state;
    for (k = 0; k < 1000; ++k)
        CHECK_OK(rbs_world_step(w, NULL));
    CHECK_OK(rbs_world_set_dt(w, 1.0 / 3.0));
    for (k = 0; k < 3; ++k)
        CHECK_OK(rbs_world_step(w, NULL));
    CHECK_OK(rbs_world_set_dt(w, 1e-7));
    for (k = 0; k < 100000; ++k)
        CHECK_OK(rbs_world_step(w, NULL));
    t = rbs_world_time(w);
    if (!(fabs(t - 2.01) <= 4.0 * half_ulp(2.01)))
        fail_msg("time after 1000 x 1 ms, 3 x 1/3 s, 1e5 x 1e-7 s: %.17g (exact 2.01)", t);
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(time_is_n_dt),
        cmocka_unit_test(set_dt_keeps_the_time),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
