/*
 * test_order.c - each fixed-step method's measured order of convergence and
 * its conservation on smooth cases with exact answers (mutual gravity:
 * two-body circular orbit, figure-eight three-body orbit).
 *
 * Order: the position error after a quarter period of the circular orbit
 * (exact: a rotation by pi/2) for 4 step sizes in ratio 2, fitted as
 * log(error) against log(dt).  The quarter period is used because at a full
 * period the first-order error of semi-implicit Euler (a radial velocity
 * offset of a h / 2, which leaves the energy and hence the period unchanged
 * to first order) cancels and Euler looks second order.  The step sizes keep
 * every error far above rounding (RK4's smallest is ~3e-11).  Accepted:
 * within +-0.3 of the theoretical order (the fit of an asymptotic C h^p
 * with higher-order terms).
 */
#include "methods_common.h"

static void measure_order(rbs_method m, const int *n, double expect)
{
    double dt[4], err[4], p;
    int i;
    for (i = 0; i < 4; ++i) {
        dt[i] = 1.0 / n[i];
        err[i] = circular_error(m, n[i], 0.25, 1e-9);
    }
    p = fit_slope(dt, err, 4);
    print_message("%s: errors %.3e %.3e %.3e %.3e, order %.3f\n", rbs_method_name(m), err[0], err[1],
                  err[2], err[3], p);
    ASSERT_NEAR(p, expect, 0.3);
}

static void euler_is_first_order(void **state)
{
    const int n[4] = {50, 100, 200, 400};
    (void)state;
    measure_order(RBS_METHOD_EULER, n, 1.0);
}

static void verlet_is_second_order(void **state)
{
    const int n[4] = {50, 100, 200, 400};
    (void)state;
    measure_order(RBS_METHOD_VERLET, n, 2.0);
}

static void rk4_is_fourth_order(void **state)
{
    const int n[4] = {25, 50, 100, 200};
    (void)state;
    measure_order(RBS_METHOD_RK4, n, 4.0);
}

/* After one period T = 2 pi sqrt(a^3 / (G (m1 + m2))) the bodies are back
 * where they started.  Bounds: the methods' error constants at 400 steps
 * per period (measured orders above; Euler's full-period error is second
 * order, see the top): Euler and Verlet within 1e-2 (ah^2-size, a = 1),
 * RK4 within 2e-8 (ten times the leading RK4 phase error of a linear
 * oscillator over one period, 2 pi (w h)^4 / 120 * r = 1.6e-9). */
static void circular_orbit_period(void **state)
{
    (void)state;
    assert_true(circular_error(RBS_METHOD_EULER, 400, 1.0, 1e-9) < 1e-2);
    assert_true(circular_error(RBS_METHOD_VERLET, 400, 1.0, 1e-9) < 1e-2);
    assert_true(circular_error(RBS_METHOD_RK4, 400, 1.0, 1e-9) < 2e-8);
}

/* Energy over 10 periods at 100 steps per period.  Euler (semi-implicit,
 * symplectic) and Verlet (symplectic) have no secular drift: the largest
 * deviation over 10 periods is at most 1.5 times the largest over the
 * first.  RK4 drifts, but by O(h^4): below 1e-5 of |E| (h w = 0.063,
 * (h w)^4 = 1.6e-5). */
static void energy_per_method(void **state)
{
    const rbs_method ms[3] = {RBS_METHOD_EULER, RBS_METHOD_VERLET, RBS_METHOD_RK4};
    int k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        const int n = 100;
        rbs_body_id a, b;
        rbs_world *w = circular_orbit(ms[k], circular_period() / n, 1e-9, &a, &b);
        rbs_energy e0, e;
        double first = 0.0, all = 0.0;
        int i;
        CHECK_OK(rbs_world_energy(w, &e0));
        for (i = 0; i < 10 * n; ++i) {
            double d;
            CHECK_OK(rbs_world_step(w, NULL));
            CHECK_OK(rbs_world_energy(w, &e));
            d = fabs(e.total - e0.total);
            if (i < n && d > first)
                first = d;
            if (d > all)
                all = d;
        }
        print_message("%s: energy deviation, first period %.3e, ten periods %.3e (E = %.3f)\n",
                      rbs_method_name(ms[k]), first, all, e0.total);
        if (ms[k] == RBS_METHOD_RK4)
            assert_true(all < 1e-5 * fabs(e0.total));
        else
            assert_true(all <= 1.5 * first);
        rbs_world_destroy(w);
    }
}

/* The figure-eight returns to its start after one period.  The initial
 * conditions and the period are given to 8-9 digits, so the orbit itself
 * closes only to a few 1e-8; bounds: RK4 (2000 steps, h^4 error ~1e-10)
 * within 2e-7; Verlet (16000 steps, O(h^2)) within 1e-6; Euler (16000 steps,
 * O(h)) within 2e-3. */
static void figure_eight_closes(void **state)
{
    (void)state;
    assert_true(figure_eight_error(RBS_METHOD_RK4, 2000, 1e-9) < 2e-7);
    assert_true(figure_eight_error(RBS_METHOD_VERLET, 16000, 1e-9) < 1e-6);
    assert_true(figure_eight_error(RBS_METHOD_EULER, 16000, 1e-9) < 2e-3);
}

/* Momentum and angular momentum of the isolated three-body system are
 * conserved by every method (pairwise-equal forces: rounding only, 1e-12). */
static void figure_eight_momentum(void **state)
{
    const rbs_method ms[3] = {RBS_METHOD_EULER, RBS_METHOD_VERLET, RBS_METHOD_RK4};
    int k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        rbs_body_id id[3];
        rbs_world *w = figure_eight(ms[k], FIG8_T / 1000, 1e-9, id);
        rbs_vec3 p0, l0, p1, l1;
        CHECK_OK(rbs_world_momentum(w, &p0, &l0));
        step_n(w, 1000);
        CHECK_OK(rbs_world_momentum(w, &p1, &l1));
        ASSERT_NEAR(p1.x, p0.x, 1e-12);
        ASSERT_NEAR(p1.y, p0.y, 1e-12);
        ASSERT_NEAR(l1.z, l0.z, 1e-12);
        rbs_world_destroy(w);
    }
}


/* A free asymmetric top (principal moments 1, 2, 2.5 g m^2, spinning mostly
 * about the intermediate axis, no gravity) keeps its angular momentum and
 * rotational energy exactly; the methods' largest relative errors over T s
 * measure their rotational accuracy.  Returns the largest relative error of
 * E and |L - L0| / |L0|, or -1 if the method is not built. */
static double top_error_over(rbs_method m, double dt, double w0, double T)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_sphere_def s;
    rbs_energy e0, e;
    rbs_vec3 L0, L;
    double worst = 0.0;
    int f;
    rbs_world_def_init(&d);
    d.gravity.z = 0.0;
    d.dt = dt;
    d.method = m;
    d.tolerance = 1e-10;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_sphere_def_init(&s);
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = 1e-3; s.inertia.y = 2e-3; s.inertia.z = 2.5e-3;
    s.angular_velocity.x = 0.1 * w0; s.angular_velocity.y = w0; s.angular_velocity.z = 0.1 * w0;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    CHECK_OK(rbs_world_energy(w, &e0));
    CHECK_OK(rbs_world_momentum(w, NULL, &L0));
    for (f = 0; f < (int)(T / dt + 0.5); ++f) {
        double dE, dL;
        CHECK_OK(rbs_world_step(w, NULL));
        CHECK_OK(rbs_world_energy(w, &e));
        CHECK_OK(rbs_world_momentum(w, NULL, &L));
        dE = fabs(e.total - e0.total) / e0.total;
        dL = sqrt((L.x - L0.x) * (L.x - L0.x) + (L.y - L0.y) * (L.y - L0.y) + (L.z - L0.z) * (L.z - L0.z)) /
             sqrt(L0.x * L0.x + L0.y * L0.y + L0.z * L0.z);
        if (dE > worst) worst = dE;
        if (dL > worst) worst = dL;
    }
    rbs_world_destroy(w);
    return worst;
}

/* The same over 2 s. */
static double top_error(rbs_method m, double dt, double w0)
{
    return top_error_over(m, dt, w0, 2.0);
}

/* Euler (and soft, whose sub-steps turn as Euler's) turns an anisotropic
 * body by the angular velocity of the sub-step's middle, a fixed point
 * iterated to convergence: a symmetric rule, whose energy error is O((w
 * h)^2) and oscillates without drifting.  Measured (the largest error of
 * E and L) over 1e5 steps (100 s) at w = 100 rad/s, dt = 1 ms: euler
 * 2.5e-4 (w h = 0.1), soft 2.8e-5 (its sub-steps: h = dt / 3).  Accepted:
 * 0.1 (w h)^2 -- 1e-3 and 1.1e-4 -- 4 times those.  With two rounds of the
 * fixed point (before session 47) the rule was not symmetric and the
 * energy fell steadily: euler 3.7e-2, soft 9.8e-4 at 100 s (a top at 1e3
 * rad/s lost 56 % in 0.5 s, ending about its axis of most inertia). */
static void euler_spin_energy_does_not_drift(void **state)
{
    double ee, es;
    (void)state;
    ee = top_error_over(RBS_METHOD_EULER, 1e-3, 100.0, 100.0);
    es = top_error_over(RBS_METHOD_SOFT, 1e-3, 100.0, 100.0);
    print_message("top over 100 s at w dt = 0.1: euler %.2e, soft %.2e\n", ee, es);
    assert_true(ee < 0.1 * (100.0 * 1e-3) * (100.0 * 1e-3));
    assert_true(es < 0.1 * (100.0 * 1e-3 / 3.0) * (100.0 * 1e-3 / 3.0));
}

/* Rotation converges at the method's order: fit over dt = 10, 5, 2.5,
 * 1.25 ms at w = 10 rad/s (w dt <= 0.1): verlet 2, rk4 4 (+-0.3). */
static void rotation_orders(void **state)
{
    const double dts[4] = {1e-2, 5e-3, 2.5e-3, 1.25e-3};
    double ev[4], er[4];
    int i;
    (void)state;
    for (i = 0; i < 4; ++i) {
        ev[i] = top_error(RBS_METHOD_VERLET, dts[i], 10.0);
        er[i] = top_error(RBS_METHOD_RK4, dts[i], 10.0);
    }
    print_message("top: verlet %.2e .. %.2e order %.3f; rk4 %.2e .. %.2e order %.3f\n", ev[0], ev[3],
                  fit_slope(dts, ev, 4), er[0], er[3], fit_slope(dts, er, 4));
    ASSERT_NEAR(fit_slope(dts, ev, 4), 2.0, 0.3);
    ASSERT_NEAR(fit_slope(dts, er, 4), 4.0, 0.3);
}

/* A torqued symmetric top with an exact answer: I = diag(1, 1, 2) g m^2,
 * w0 = (5, 0, 5) rad/s (L0 = (5, 0, 10) mN m s), under the constant world
 * torque tau = L0 / (2 s), parallel to L0.  Then L = L0 (1 + t / 2 s) keeps
 * its direction; the symmetry axis e3 keeps its angle to L (d(L.e3)/dt =
 * tau.e3 and d|L|/dt = |tau|, as L.(w x e3) = 0 for a symmetric top) and
 * turns about L at |L| / I1 (e3' = w x e3 = (L / I1) x e3): by
 * phi = (|L0| t + |tau| t^2 / 2) / I1; the energy is
 * |L|^2 (sin^2 th / I1 + cos^2 th / I3) / 2 (Landau & Lifshitz, Mechanics,
 * sec. 33 and 36).  Error: the larger of |e3 - e3_exact| and the relative
 * energy error after 2 s (|L| doubles; phi = 33.5 rad). */
static double torqued_top_error(rbs_method m, double dt)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_sphere_def s;
    rbs_body_id id;
    rbs_state_view v;
    rbs_energy e;
    const double I1 = 1e-3, I3 = 2e-3, T = 2.0, L0[3] = {5e-3, 0.0, 1e-2};
    const double l0 = sqrt(L0[0] * L0[0] + L0[2] * L0[2]), k[3] = {L0[0] / l0, 0.0, L0[2] / l0};
    const double c = k[2], lt = l0 * (1.0 + 0.5 * T), phi = (l0 * T + 0.25 * l0 * T * T) / I1;
    const double te = 0.5 * lt * lt * ((1.0 - c * c) / I1 + c * c / I3);
    double ex[3], e3[3], err, de;
    const double *q;
    int f;
    rbs_world_def_init(&d);
    d.gravity.z = 0.0;
    d.dt = dt;
    d.method = m;
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_sphere_def_init(&s);
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = I1; s.inertia.y = I1; s.inertia.z = I3;
    s.angular_velocity.x = 5.0; s.angular_velocity.z = 5.0;
    s.torque.x = 0.5 * L0[0]; s.torque.z = 0.5 * L0[2];
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    for (f = 0; f < (int)(T / dt + 0.5); ++f)
        CHECK_OK(rbs_world_step(w, NULL));
    CHECK_OK(rbs_world_state(w, &v));
    CHECK_OK(rbs_world_energy(w, &e));
    q = &v.orientation[4 * id.index];
    /* e3 = R(q) z; the exact one: z turned about k by phi (Rodrigues) */
    e3[0] = 2.0 * (q[1] * q[3] + q[0] * q[2]);
    e3[1] = 2.0 * (q[2] * q[3] - q[0] * q[1]);
    e3[2] = 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2]);
    ex[0] = k[0] * c * (1.0 - cos(phi)) + k[1] * sin(phi);
    ex[1] = -k[0] * sin(phi) + k[1] * c * (1.0 - cos(phi));
    ex[2] = cos(phi) + k[2] * c * (1.0 - cos(phi));
    err = sqrt((e3[0] - ex[0]) * (e3[0] - ex[0]) + (e3[1] - ex[1]) * (e3[1] - ex[1]) +
               (e3[2] - ex[2]) * (e3[2] - ex[2]));
    de = fabs(e.total - te) / te;
    rbs_world_destroy(w);
    return err > de ? err : de;
}

/* The torqued top converges at the method's order: dt = 10, 5, 2.5,
 * 1.25 ms (|w| dt <= 0.22 rad: one rotation part a step, so the fit sees
 * the method, not a changing part count): verlet 2, rk4 4 (+-0.3, as
 * above). */
static void torqued_rotation_orders(void **state)
{
    const double dts[4] = {1e-2, 5e-3, 2.5e-3, 1.25e-3};
    double ev[4], er[4];
    int i;
    (void)state;
    for (i = 0; i < 4; ++i) {
        ev[i] = torqued_top_error(RBS_METHOD_VERLET, dts[i]);
        er[i] = torqued_top_error(RBS_METHOD_RK4, dts[i]);
    }
    print_message("torqued top: verlet %.2e .. %.2e order %.3f; rk4 %.2e .. %.2e order %.3f\n", ev[0], ev[3],
                  fit_slope(dts, ev, 4), er[0], er[3], fit_slope(dts, er, 4));
    ASSERT_NEAR(fit_slope(dts, ev, 4), 2.0, 0.3);
    ASSERT_NEAR(fit_slope(dts, er, 4), 4.0, 0.3);
}

/* Spinning fast relative to the step (w dt = 1 rad) the higher-order methods
 * stay stable and bounded, their rotation being sub-stepped to 1/4 rad:
 * verlet within 1e-2 (its error constant, 2.5e-2 (w dt)^2 as measured above,
 * at 1/4 rad: 1.6e-3), rk4 within 1e-4, adaptive within 1e-8 (100 x its
 * tolerance 1e-10). */
static void fast_spin_stays_bounded(void **state)
{
    (void)state;
    assert_true(top_error(RBS_METHOD_VERLET, 1e-2, 100.0) < 1e-2);
    assert_true(top_error(RBS_METHOD_RK4, 1e-2, 100.0) < 1e-4);
    assert_true(top_error(RBS_METHOD_ADAPTIVE, 1e-2, 100.0) < 1e-8);
}

/* A weightless world for method m with the given work budget. */
static rbs_world *spin_world(rbs_method m, uint32_t max_substeps)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.gravity.z = 0.0;
    d.method = m;
    d.max_substeps = max_substeps;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* A torque-free solid sphere spinning at w about a tilted axis turns by
 * exactly w t: its orientation after 10 steps of 1 ms at w = 1e6 rad/s
 * (1000 rad per step) is the rotation by w t, to 1e-9 in each quaternion
 * component (rounding of ~10^4 rad angles: 1e4 * 1e-16 * a few).  One
 * rotation per step is exact here, so it needs none of the rotation
 * sub-steps (4000 a step at 1/4 rad) that the budget of max_substeps = 2
 * (512) would refuse. */
static void free_spin_is_exact(void **state)
{
    const rbs_method methods[2] = {RBS_METHOD_VERLET, RBS_METHOD_RK4};
    int k;
    (void)state;
    for (k = 0; k < 2; ++k) {
        rbs_world *w = spin_world(methods[k], 2); /* one sub-step, 512 rotation sub-steps */
        rbs_sphere_def s;
        rbs_body_id id;
        rbs_state_view v;
        rbs_step_info info;
        const double om = 1e6, n[3] = {0.0, 0.6, 0.8}, t = 10e-3;
        double half, qe[4];
        int f;
        rbs_sphere_def_init(&s);
        s.angular_velocity.y = om * n[1];
        s.angular_velocity.z = om * n[2];
        CHECK_OK(rbs_world_add_sphere(w, &s, &id));
        for (f = 0; f < 10; ++f) {
            CHECK_OK(rbs_world_step(w, &info));
            assert_int_equal(info.work_limit, 0);
        }
        rbs_world_state(w, &v);
        half = 0.5 * om * t;
        qe[0] = cos(half), qe[1] = 0.0, qe[2] = sin(half) * n[1], qe[3] = sin(half) * n[2];
        /* q and -q are the same rotation */
        if (qe[0] * v.orientation[4 * id.index] < 0.0)
            qe[0] = -qe[0], qe[2] = -qe[2], qe[3] = -qe[3];
        for (f = 0; f < 4; ++f)
            ASSERT_NEAR(v.orientation[4 * id.index + f], qe[f], 1e-9);
        rbs_world_destroy(w);
    }
}

/* A torqued asymmetric body spinning at 1e9 rad/s would need 4e6 rotation
 * sub-steps of 1/4 rad per 1 ms step: more than the step's budget
 * (max_substeps * 256), so the step takes what the budget allows, finishes
 * with finite numbers and says so in work_limit. */
static void spin_work_is_bounded(void **state)
{
    const rbs_method methods[2] = {RBS_METHOD_VERLET, RBS_METHOD_RK4};
    int k;
    (void)state;
    for (k = 0; k < 2; ++k) {
        rbs_world *w = spin_world(methods[k], 16); /* budget: 4096 rotation sub-steps */
        rbs_sphere_def s;
        rbs_step_info info;
        rbs_sphere_def_init(&s);
        s.inertia_kind = RBS_INERTIA_PRINCIPAL;
        s.inertia.x = 1e-3; s.inertia.y = 2e-3; s.inertia.z = 2.5e-3;
        s.angular_velocity.x = 1e9;
        s.torque.z = 1.0;
        CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
        CHECK_OK(rbs_world_step(w, &info));
        assert_int_equal(info.work_limit, 1);
        rbs_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(euler_is_first_order),
        cmocka_unit_test(verlet_is_second_order),
        cmocka_unit_test(rk4_is_fourth_order),
        cmocka_unit_test(circular_orbit_period),
        cmocka_unit_test(energy_per_method),
        cmocka_unit_test(figure_eight_closes),
        cmocka_unit_test(figure_eight_momentum),
        cmocka_unit_test(rotation_orders),
        cmocka_unit_test(torqued_rotation_orders),
        cmocka_unit_test(fast_spin_stays_bounded),
        cmocka_unit_test(euler_spin_energy_does_not_drift),
        cmocka_unit_test(free_spin_is_exact),
        cmocka_unit_test(spin_work_is_bounded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
