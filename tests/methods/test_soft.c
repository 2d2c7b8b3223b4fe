/*
 * test_soft.c - the soft method (RBS_METHOD_SOFT) against exact answers.
 *
 * The soft step is Euler on sub-steps of h = dt / n with contacts that are
 * springs of frequency omega = 2 pi (1/3) / h and damping ratio 10 beyond the
 * slop, rigid Coulomb friction, and a restitution pass at the end of each
 * frame that uses the approach speed of the frame's start (docs/methods.md).
 * So its exact answers are those of mechanics plus that model's own,
 * stated ones: a load L on a contact of effective mass m_eff sinks by
 * L / (m_eff omega^2); a bounce leaves with e times the approach speed of
 * the frame's start, up to g dt away from the speed at impact.  Each test
 * says which, and why its tolerance.
 */
#include "common.h"
#include "raw_state.h"

#define G 9.81
#define PI_ 3.14159265358979323846

static rbs_world *soft_world(uint32_t n, double dt, double gz, double e, uint32_t substeps)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = n;
    d.dt = dt;
    d.gravity.z = gz;
    d.restitution = e;
    d.method = RBS_METHOD_SOFT;
    d.soft_substeps = substeps;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* omega of the soft contacts for dt and n sub-steps, 1/s. */
static double soft_omega(double dt, uint32_t n) { return 2.0 * PI_ * n / (3.0 * dt); }

/* The defaults: 3 sub-steps, and validation of the setting's range. */
static void substeps_default_and_range(void **state)
{
    rbs_world_def d;
    char msg[256];
    (void)state;
    rbs_world_def_init(&d);
    assert_int_equal(d.soft_substeps, 3);
    assert_string_equal(rbs_method_name(RBS_METHOD_SOFT), "soft");
    d.soft_substeps = 0;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "soft_substeps must be in [1, 1000], got 0"));
    d.soft_substeps = 1001;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    d.soft_substeps = 1000;
    CHECK_OK(rbs_world_def_validate(&d, msg, sizeof msg));
}

/* A ball set down touching the floor sinks to the spring's static
 * deflection and stays: slop r + g / omega^2, for 1, 4 and 16 sub-steps
 * (the deflection falls with h^2).  The steady state of the soft row is
 * exact (warm start, then a solve that changes nothing), so after 1 s
 * (about 30 time constants of the overdamped spring) the depth matches to
 * 1e-6 of itself, and over the next 9 s the ball moves less than 1e-12 m. */
static void resting_ball_sinks_to_the_static_deflection(void **state)
{
    const uint32_t ns[3] = {1, 4, 16};
    const double r = 0.1, dt = 1e-3;
    int i;
    (void)state;
    for (i = 0; i < 3; ++i) {
        rbs_world *w = soft_world(4, dt, -G, 0.5, ns[i]);
        rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
        double om = soft_omega(dt, ns[i]), sink = 1e-6 * r + G / (om * om), z1;
        rbs_body_id b;
        floor_plane(w, m);
        b = ball(w, r, 1.0, 0, 0, r, 0, 0, 0, m);
        step_n(w, 1000);
        z1 = state_of(w, b).position.z;
        ASSERT_NEAR(r - z1, sink, 1e-6 * sink);
        step_n(w, 9000);
        ASSERT_NEAR(state_of(w, b).position.z, z1, 1e-12);
        ASSERT_NEAR(state_of(w, b).position.x, 0.0, 1e-15);
        rbs_world_destroy(w);
    }
}

/* A stack of 10 equal balls on the floor holds, each contact sinking by its
 * load over its effective mass: the floor's (m_eff = m) 10 g / omega^2, the
 * contact under ball k (m_eff = m / 2, carrying 10 - k balls) 2 (10 - k)
 * g / omega^2.  The top ball's drop is their sum plus ten slops, within
 * 1e-6 of itself, and no ball moves sideways. */
static void stack_sinks_by_its_loads(void **state)
{
    enum { N = 10 };
    const double r = 0.1, dt = 1e-3;
    rbs_world *w = soft_world(N + 1, dt, -G, 0.3, 4);
    rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
    rbs_body_id b[N];
    double om = soft_omega(dt, 4), loads = N, drop;
    int k;
    (void)state;
    floor_plane(w, m);
    for (k = 0; k < N; ++k)
        b[k] = ball(w, r, 1.0, 0, 0, r + 2.0 * r * k, 0, 0, 0, m);
    for (k = 1; k < N; ++k)
        loads += 2.0 * (N - k);
    drop = N * 1e-6 * r + loads * G / (om * om);
    step_n(w, 3000);
    ASSERT_NEAR(r + 2.0 * r * (N - 1) - state_of(w, b[N - 1]).position.z, drop, 1e-6 * drop);
    for (k = 0; k < N; ++k)
        ASSERT_NEAR(state_of(w, b[k]).position.x, 0.0, 1e-12);
    rbs_world_destroy(w);
}

/* The push limit never stops a load being held.  1 % of the smaller radius
 * a sub-step is below the push that holds a resting load once g dt^2 >
 * about 4.2 r (3 sub-steps): a ball of r = 1 mm at dt = 0.03 s sank through
 * the floor at a steady 0.3 mm a frame.  Now it rests at the static
 * deflection g / omega^2 = 0.224 mm (22 % of its radius, the model's own
 * answer at so coarse a step), and a stack of 5 such balls of r = 5 mm
 * sinks by its loads (as stack_sinks_by_its_loads), each to 1e-6 of
 * itself after 20 s (about 30 time constants), and then stays within
 * 1e-12 m. */
static void coarse_steps_still_hold_loads(void **state)
{
    enum { N = 5 };
    const double dt = 0.03, om = soft_omega(dt, 3);
    (void)state;
    {
        const double r = 1e-3, sink = 1e-6 * r + G / (om * om);
        rbs_world *w = soft_world(4, dt, -G, 0.5, 3);
        rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
        rbs_body_id b;
        double z1;
        floor_plane(w, m);
        b = ball(w, r, 1e-3, 0, 0, r, 0, 0, 0, m);
        step_n(w, 700);
        z1 = state_of(w, b).position.z;
        ASSERT_NEAR(r - z1, sink, 1e-6 * sink);
        step_n(w, 300);
        ASSERT_NEAR(state_of(w, b).position.z, z1, 1e-12);
        rbs_world_destroy(w);
    }
    {
        const double r = 5e-3;
        rbs_world *w = soft_world(N + 1, dt, -G, 0.3, 3);
        rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
        rbs_body_id b[N];
        double loads = N, drop, z1;
        int k;
        floor_plane(w, m);
        for (k = 0; k < N; ++k)
            b[k] = ball(w, r, 1e-3, 0, 0, r + 2.0 * r * k, 0, 0, 0, m);
        for (k = 1; k < N; ++k)
            loads += 2.0 * (N - k);
        drop = N * 1e-6 * r + loads * G / (om * om);
        step_n(w, 700);
        z1 = state_of(w, b[N - 1]).position.z;
        ASSERT_NEAR(r + 2.0 * r * (N - 1) - z1, drop, 1e-6 * drop);
        step_n(w, 300);
        ASSERT_NEAR(state_of(w, b[N - 1]).position.z, z1, 1e-12);
        for (k = 0; k < N; ++k)
            ASSERT_NEAR(state_of(w, b[k]).position.x, 0.0, 1e-12);
        rbs_world_destroy(w);
    }
}

/* A heavy ball on a light one settles to rounding (|v| < 1e-12 m/s over
 * the 21st second) up to the mass ratios docs/methods.md states: 10^4 at 3
 * sub-steps (measured 6e-14 m/s; at 10^5 the pair keeps a limit cycle of
 * 8 mm/s, the documented limit, not asserted).  Before session 45's
 * over-relaxed relax rows (tall_column_settles_and_holds_its_loads) the
 * limit was 70 at 3 sub-steps and 100 at 6: at 100 with 3 the top ball
 * kept moving at 0.03 m/s, at 1,000 at 0.13 m/s. */
static void heavy_on_light_settles_within_the_stated_ratios(void **state)
{
    static const struct {
        double ratio;
        uint32_t substeps;
    } cases[] = {{10, 3}, {70, 3}, {100, 6}, {100, 3}, {1000, 3}, {1e4, 3}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        rbs_world *w = soft_world(4, 1e-3, -G, 0.5, cases[i].substeps);
        rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
        rbs_body_id lo, hi;
        double vmax = 0.0;
        int k;
        floor_plane(w, m);
        lo = ball(w, 0.1, 1.0, 0, 0, 0.1, 0, 0, 0, m);
        hi = ball(w, 0.1, cases[i].ratio, 0, 0, 0.3, 0, 0, 0, m);
        step_n(w, 20000);
        for (k = 0; k < 1000; ++k) {
            rbs_body_state a, b;
            step_n(w, 1);
            a = state_of(w, lo);
            b = state_of(w, hi);
            vmax = fmax(vmax, fmax(fabs(a.velocity.z), fabs(b.velocity.z)));
        }
        if (!(vmax < 1e-12))
            fail_msg("ratio %g, %u sub-steps: still moving at %.3g m/s", cases[i].ratio,
                     (unsigned)cases[i].substeps, vmax);
        rbs_world_destroy(w);
    }
}

/* Two free spheres meeting head on, no gravity, masses m1, m2 and
 * restitution e: the 1-D impact law gives
 *   v1' = (m1 v1 + m2 v2 - e m2 (v1 - v2)) / (m1 + m2),
 *   v2' = (m1 v1 + m2 v2 + e m1 (v1 - v2)) / (m1 + m2).
 * With no force the approach speed at the frame's start is the speed at
 * impact, so the restitution pass gives these to rounding (1e-12 of the
 * speeds), for mass ratios 1 to 1e6 and e = 0, 0.5, 1; momentum to 1e-12. */
static void head_on_impacts_follow_the_impact_law(void **state)
{
    const double ratios[4] = {1.0, 3.0, 1e3, 1e6}, es[3] = {0.0, 0.5, 1.0};
    int i, j;
    (void)state;
    for (i = 0; i < 4; ++i)
        for (j = 0; j < 3; ++j) {
            const double m1 = 1.0, m2 = ratios[i], v1 = 2.0, v2 = -1.0, e = es[j];
            rbs_world *w = soft_world(4, 1e-3, 0.0, e, 4);
            rbs_body_id a = ball(w, 0.1, m1, -0.5, 0, 0, v1, 0, 0, (rbs_material_id){0, 0});
            rbs_body_id b = ball(w, 0.1, m2, 0.5, 0, 0, v2, 0, 0, (rbs_material_id){0, 0});
            double p0 = m1 * v1 + m2 * v2;
            double u1 = (p0 - e * m2 * (v1 - v2)) / (m1 + m2), u2 = (p0 + e * m1 * (v1 - v2)) / (m1 + m2);
            step_n(w, 500);
            ASSERT_NEAR(state_of(w, a).velocity.x, u1, 1e-12 * 3.0);
            ASSERT_NEAR(state_of(w, b).velocity.x, u2, 1e-12 * 3.0);
            ASSERT_NEAR(m1 * state_of(w, a).velocity.x + m2 * state_of(w, b).velocity.x, p0,
                        1e-12 * (m1 + m2) * 3.0);
            rbs_world_destroy(w);
        }
}

/* a + s b */
static rbs_vec3 vmad_(rbs_vec3 a, rbs_vec3 b, double s)
{
    rbs_vec3 r = {a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
    return r;
}
static double vdot_(rbs_vec3 a, rbs_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static rbs_vec3 vcross_(rbs_vec3 a, rbs_vec3 b)
{
    rbs_vec3 r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return r;
}
static double vdiff_(rbs_vec3 a, rbs_vec3 b)
{
    return fmax(fabs(a.x - b.x), fmax(fabs(a.y - b.y), fabs(a.z - b.z)));
}

/* One oblique impact of two spheres (a: r 0.1 m, 1 kg; b: r 0.03 m, m_b),
 * both moving, without forces, set up so that they touch T = (5 + frac) dt
 * into the run with the line of centres n (unit, b to a) th off +x in the
 * x-y plane and tilted 20 degrees out of it; u = v_a - v_b = (-v, 0, 0). */
typedef struct oblique_pair {
    rbs_world *w;
    rbs_body_id a, b;
    double ra, rb, ma, mb;
    rbs_vec3 va, vb, u, n;
} oblique_pair;

/* A sphere of material mat; general: with anisotropic principal moments
 * (0.3, 0.4, 0.5) m r^2 (the soft step's general rows), else solid. */
static rbs_body_id impact_sphere(rbs_world *w, rbs_material_id mat, double r, double m, rbs_vec3 p, rbs_vec3 v,
                                 int general)
{
    rbs_sphere_def s;
    rbs_body_id id;
    rbs_vec3 moments = {0.3 * m * r * r, 0.4 * m * r * r, 0.5 * m * r * r};
    rbs_sphere_def_init(&s);
    s.material = mat;
    s.radius = r;
    s.mass = m;
    s.position = p;
    s.velocity = v;
    if (general) {
        s.inertia_kind = RBS_INERTIA_PRINCIPAL;
        s.inertia = moments;
    }
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    return id;
}

/* A single column of balls on the floor settles and holds its loads
 * (session 45).  Before, a column of more than about 21 balls never
 * settled: the one relax pass a sub-step, the only pass that takes energy
 * out of the column's slow modes, reached them less the longer the column,
 * while the solve's soft rows built their force there only through the
 * accumulated impulse, many passes late, and the column rocked in a limit
 * cycle (kinetic energy up to 0.09 J at 50 balls of 1 kg, 0.8 J at 100,
 * with e = 0 too).  Now a contact that comes in loaded over-relaxes its
 * relax rows (RBS__SOFT_OVER).  Cases: 50 equal balls (1 kg, r = 0.1 m,
 * dt = 1 ms) with e = 0; 100 with e = 0.5; 50 alternating 1 kg of r = 0.1 m
 * and 3 kg of r = 0.05 m, e = 0.5; 50 on one sub-step; 50 in the general
 * layout (anisotropic inertia: the general rows).  After T s the kinetic
 * energy over one more second stays below 1e-12 J (measured: 1e-21 J or
 * less; the column settles to rounding in 2 to 6 s), no ball moves
 * sideways, and each contact sinks by its load over m_eff omega^2 beyond
 * the slop (the soft row's fixed point, as stack_sinks_by_its_loads), to
 * 1e-6 of itself (measured 3e-9: rounding in positions up to 20 m). */
static void tall_column_settles_and_holds_its_loads(void **state)
{
    static const struct {
        int n;
        double e;
        double heavy, small; /* the odd balls' mass (kg) and radius (m) */
        uint32_t substeps;
        int general;
        int seconds;
    } cases[] = {{50, 0.0, 1.0, 0.1, 3, 0, 5},
                 {100, 0.5, 1.0, 0.1, 3, 0, 8},
                 {50, 0.5, 3.0, 0.05, 3, 0, 5},
                 {50, 0.0, 1.0, 0.1, 1, 0, 6},
                 {50, 0.0, 1.0, 0.1, 3, 1, 5}};
    const double dt = 1e-3;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        enum { MAX = 100 };
        const int n = cases[i].n;
        const double om = soft_omega(dt, cases[i].substeps);
        rbs_world *w = soft_world((uint32_t)n + 1u, dt, -G, cases[i].e, cases[i].substeps);
        rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
        rbs_body_id b[MAX];
        double r[MAX], mass[MAX], z = 0.0, kmax = 0.0, load = 0.0;
        int k;
        floor_plane(w, m);
        for (k = 0; k < n; ++k) {
            r[k] = k % 2 ? cases[i].small : 0.1;
            mass[k] = k % 2 ? cases[i].heavy : 1.0;
            b[k] = impact_sphere(w, m, r[k], mass[k], (rbs_vec3){0, 0, z + r[k]}, (rbs_vec3){0, 0, 0},
                                 cases[i].general);
            z += 2.0 * r[k];
        }
        step_n(w, 1000 * cases[i].seconds);
        for (k = 0; k < 1000; ++k) {
            rbs_energy en;
            step_n(w, 1);
            CHECK_OK(rbs_world_energy(w, &en));
            kmax = fmax(kmax, en.kinetic);
        }
        if (!(kmax < 1e-12))
            fail_msg("%d balls (case %d): kinetic energy up to %.3g J over the last second", n, (int)i, kmax);
        /* the contact under ball k carries the balls k .. n - 1 */
        for (k = n - 1; k >= 0; --k) {
            const rbs_body_state s = state_of(w, b[k]);
            const double below = k > 0 ? state_of(w, b[k - 1]).position.z + r[k - 1] : 0.0;
            const double meff = k > 0 ? 1.0 / (1.0 / mass[k] + 1.0 / mass[k - 1]) : mass[k];
            const double rmin = k > 0 ? fmin(r[k], r[k - 1]) : r[k];
            double sink;
            load += mass[k] * G;
            sink = 1e-6 * rmin + load / (meff * om * om);
            ASSERT_NEAR(below - (s.position.z - r[k]), sink, 1e-6 * sink);
            ASSERT_NEAR(s.position.x, 0.0, 1e-12);
            ASSERT_NEAR(s.position.y, 0.0, 1e-12);
        }
        rbs_world_destroy(w);
    }
}

/* Flight is exact in both layouts: a projectile launched at (3, 0, 4) m/s
 * from z = 10 m is at x = 3 T, z = 10 + 4 T - g T^2 / 2 after T = 1 s, for
 * 1, 3 and 4 sub-steps at dt = 1 ms and 1 and 3 at 10 ms: to 1e-12 m, a few
 * roundings a frame (measured 1e-14).  In the gathered layout (every pile)
 * a body that no contact touches flies each frame at once, x += (v0 + v1)
 * dt / 2 with v1 = v0 + a dt (stage_free).  In the general layout --
 * reached by anisotropic inertia, and by a pair with rolling resistance
 * (here with a floor 1000 m below, out of reach: rows are judged by
 * materials, rbs_world_explain names it) -- it is semi-implicit Euler on
 * the sub-steps, whose lead a dt h / 2 (h = dt / n) is taken back at the
 * frame's end (fly_free); before session 47 it lagged by g T h / 2 (1.6e-3
 * m at 1 ms and 3 sub-steps), which this test then held. */
static void flight_is_exact_in_both_layouts(void **state)
{
    static const struct { double dt; uint32_t n; } cases[5] = {
        {1e-3, 1}, {1e-3, 3}, {1e-3, 4}, {1e-2, 1}, {1e-2, 3}};
    const double T = 1.0;
    int i, general;
    (void)state;
    for (general = 0; general < 3; ++general)
        for (i = 0; i < 5; ++i) {
            rbs_world *w = soft_world(2, cases[i].dt, -G, 0.5, cases[i].n);
            rbs_material_id m = {0, 0};
            rbs_body_id b;
            rbs_body_state st;
            char text[4096];
            if (general == 2) {
                /* a resistance row, for a floor no sphere reaches */
                rbs_pair_def p;
                rbs_plane_def pl;
                CHECK_OK(rbs_world_add_material(w, "m", &m));
                rbs_pair_def_init(&p);
                p.a = p.b = m;
                p.static_friction = 0.5;
                p.kinetic_friction = 0.4;
                p.rolling = 0.01;
                CHECK_OK(rbs_world_set_pair(w, &p));
                rbs_plane_def_init(&pl);
                pl.point.z = -1000.0;
                pl.material = m;
                CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
            }
            b = impact_sphere(w, m, 0.1, 1.0, (rbs_vec3){0, 0, 10.0}, (rbs_vec3){3.0, 0, 4.0}, general == 1);
            CHECK_OK(rbs_world_explain(w, text, sizeof text, NULL));
            assert_true((strstr(text, "the general rows") != NULL) == (general != 0));
            step_n(w, (uint32_t)(T / cases[i].dt + 0.5));
            st = state_of(w, b);
            ASSERT_NEAR(st.position.x, 3.0 * T, 1e-12);
            ASSERT_NEAR(st.position.z, 10.0 + 4.0 * T - 0.5 * G * T * T, 1e-12);
            ASSERT_NEAR(st.velocity.z, 4.0 - G * T, 1e-12);
            rbs_world_destroy(w);
        }
}

/* The pair of oblique_pair's comment in a soft world of dt, restitution e,
 * friction mu (static and kinetic), stepped 12 frames (past the touch). */
static oblique_pair oblique_impact(double th, double mb, double e, double mu, double dt, double frac, double v,
                                   int general)
{
    const double tilt = 20.0 * PI_ / 180.0;
    oblique_pair q;
    rbs_material_id m;
    rbs_vec3 pb = {0.0, 0.0, 1.0}, pa, n = {cos(th) * cos(tilt), sin(th) * cos(tilt), sin(tilt)};
    q.ra = 0.1;
    q.rb = 0.03;
    q.ma = 1.0;
    q.mb = mb;
    q.vb.x = 0.3 * v;
    q.vb.y = -0.2 * v;
    q.vb.z = 0.1 * v;
    q.va = q.vb;
    q.va.x -= v;
    q.u = vmad_(q.va, q.vb, -1.0);
    q.n = n;
    /* a starts back along the relative path from the touch (b's frame) */
    pa = vmad_(vmad_(pb, n, q.ra + q.rb), q.u, -(5.0 + frac) * dt);
    q.w = soft_world(4, dt, 0.0, e, 4);
    m = material(q.w, "m", mu, mu, -1.0);
    q.a = impact_sphere(q.w, m, q.ra, q.ma, pa, q.va, general);
    q.b = impact_sphere(q.w, m, q.rb, q.mb, pb, q.vb, general);
    step_n(q.w, 12);
    return q;
}

/* Two spheres meet obliquely, without forces or friction: the impulse acts
 * along the line of centres at the moment of touch, n = (d + u t*) / R
 * (u = v_a - v_b, R = r_a + r_b), and the impact law gives
 * v_a' = v_a + J n / m_a, v_b' = v_b - J n / m_b with
 * J = -(1 + e) (u . n) / (1/m_a + 1/m_b) (Goldsmith, "Impact", 1960, ch. 2).
 * The swept detection takes the normal of the touch on the straight paths,
 * and a pair due to touch just after a frame's end is left to the next
 * frame, so the soft step meets this to rounding (1e-12 of |u|; measured
 * 1e-15 gathered, 1e-13 general) wherever the touch falls in its frame
 * (early, middle, late), with 20 to 88 degrees between the approach and
 * the line of centres (head-on: the test above), both bodies moving, for
 * mass ratios 1e-3 to 1e3, e = 0, 0.5 and 1, dt = 1 and 10 ms, 0.5 and
 * 20 m/s, in both layouts (anisotropic inertia: the general rows).  With
 * the frame-start normal, a 30-degree hit at 2 m/s and dt = 1 ms was 2e-3
 * of the speed off, and glancing hits at dt = 10 ms a third. */
static void oblique_sphere_impacts_follow_the_impact_law(void **state)
{
    const double angles[5] = {0.0, 30.0, 60.0, 80.0, 88.0}, ratios[3] = {1e-3, 1.0, 1e3};
    const double es[3] = {0.0, 0.5, 1.0}, dts[2] = {1e-3, 1e-2}, fracs[3] = {0.05, 0.5, 0.97};
    const double speeds[2] = {0.5, 20.0};
    int ia, im, ie, id, ifr, iv, general;
    (void)state;
    for (ia = 0; ia < 5; ++ia)
        for (im = 0; im < 3; ++im)
            for (ie = 0; ie < 3; ++ie)
                for (id = 0; id < 2; ++id)
                    for (ifr = 0; ifr < 3; ++ifr)
                        for (iv = 0; iv < 2; ++iv)
                            for (general = 0; general < 2; ++general) {
                                oblique_pair q = oblique_impact(angles[ia] * PI_ / 180.0, ratios[im], es[ie], 0.0,
                                                                dts[id], fracs[ifr], speeds[iv], general);
                                double J = -(1.0 + es[ie]) * vdot_(q.u, q.n) / (1.0 / q.ma + 1.0 / q.mb), err;
                                err = fmax(vdiff_(state_of(q.w, q.a).velocity, vmad_(q.va, q.n, J / q.ma)),
                                           vdiff_(state_of(q.w, q.b).velocity, vmad_(q.vb, q.n, -J / q.mb)));
                                rbs_world_destroy(q.w);
                                if (!(err <= 1e-12 * speeds[iv]))
                                    fail_msg("%.0f deg in-plane (20 tilted), m_b %g, e %g, dt %g, touch at %.2f "
                                             "of a frame, %g m/s, %s layout: velocities %.3g m/s off the impact law",
                                             angles[ia], ratios[im], es[ie], dts[id], fracs[ifr], speeds[iv],
                                             general ? "general" : "gathered", err);
                            }
}

/* The same oblique impacts with Coulomb friction (mu_s = mu_k = mu),
 * solid spheres without spin: the tangential effective mass is
 * 1/K_t = 1 / (7/2 (1/m_a + 1/m_b)) (r^2 / I = 5 / (2 m) for each), the
 * normal impulse J_n = -(1 + e) (u . n) / (1/m_a + 1/m_b), and the slip
 * u_t = u - (u . n) n keeps its direction through the impact, so it sticks
 * when mu J_n >= |u_t| / K_t (J_t = |u_t| / K_t) and slides otherwise
 * (J_t = mu J_n), J = J_n n - J_t u_t / |u_t| (the two-sphere form of the
 * floor's law below; Brach, "Mechanical Impact Dynamics", 1991).  Spins
 * follow from the levers -r_a n and r_b n.  Exact to rounding in the soft
 * step (1e-12 of v and of v / r; measured 1.5e-14), sticking and sliding;
 * with the frame-start normal it was up to 0.14 m/s off at 2 m/s. */
static void oblique_sphere_impacts_with_friction_follow_the_impact_law(void **state)
{
    const double mus[3] = {0.05, 0.2, 1.0}, angles[4] = {20.0, 45.0, 70.0, 88.0}, es[3] = {0.0, 0.5, 1.0};
    const double ratios[3] = {1e-3, 1.0, 1e3}, v = 2.0;
    int im, ia, ie, ir, sticks = 0, slides = 0;
    (void)state;
    for (im = 0; im < 3; ++im)
        for (ia = 0; ia < 4; ++ia)
            for (ie = 0; ie < 3; ++ie)
                for (ir = 0; ir < 3; ++ir) {
                    const double mu = mus[im], e = es[ie];
                    oblique_pair q = oblique_impact(angles[ia] * PI_ / 180.0, ratios[ir], e, mu, 1e-3, 0.5, v, 0);
                    const double kn = 1.0 / q.ma + 1.0 / q.mb, un = vdot_(q.u, q.n), jn = -(1.0 + e) * un / kn;
                    const rbs_vec3 ut = vmad_(q.u, q.n, -un);
                    const double slip = sqrt(vdot_(ut, ut)), stick = slip / (3.5 * kn);
                    const double jt = mu * jn >= stick ? stick : mu * jn;
                    const rbs_vec3 zero = {0.0, 0.0, 0.0}, J = vmad_(vmad_(zero, q.n, jn), ut, -jt / slip);
                    /* spins: lever x impulse / I, lever -r_a n with J for a, r_b n with -J for b */
                    const rbs_vec3 nj = vcross_(q.n, J);
                    const rbs_vec3 wa = vmad_(zero, nj, -q.ra / (0.4 * q.ma * q.ra * q.ra));
                    const rbs_vec3 wb = vmad_(zero, nj, -q.rb / (0.4 * q.mb * q.rb * q.rb));
                    rbs_body_state sa = state_of(q.w, q.a), sb = state_of(q.w, q.b);
                    double err = fmax(fmax(vdiff_(sa.velocity, vmad_(q.va, J, 1.0 / q.ma)) / v,
                                           vdiff_(sb.velocity, vmad_(q.vb, J, -1.0 / q.mb)) / v),
                                      fmax(vdiff_(sa.angular_velocity, wa) * q.ra / v,
                                           vdiff_(sb.angular_velocity, wb) * q.rb / v));
                    rbs_world_destroy(q.w);
                    if (!(err <= 1e-12))
                        fail_msg("mu %g, %.0f deg in-plane (20 tilted), e %g, m_b %g (%s): %.3g of the speed off "
                                 "the impact law",
                                 mu, angles[ia], e, ratios[ir], mu * jn >= stick ? "sticks" : "slides", err);
                    if (mu * jn >= stick)
                        sticks++;
                    else
                        slides++;
                }
    /* (the set takes both branches of the law) */
    assert_true(sticks > 0 && slides > 0);
}

/* A ball (no spin, no gravity) meets the floor obliquely, at vx along it
 * and vz into it, e = 0.5.  The impact law (Coulomb friction through the
 * whole impulse, e.g. Brach, "Mechanical Impact Dynamics", 1991): when
 * 7/2 mu (1 + e) vz < vx it slides throughout, vx' = vx - mu (1 + e) vz;
 * otherwise it sticks and leaves rolling, vx' = 5/7 vx; and vz' = e vz.
 * Without forces the approach speed of the frame's start is the impact
 * speed, and the restitution row's friction keeps the cone of the whole
 * normal impulse: exact to rounding (1e-12 of the speeds). */
static void oblique_bounce_follows_the_impact_law(void **state)
{
    const double vx = 2.0, vz = 1.0, e = 0.5, r = 0.1, mus[2] = {0.2, 0.8};
    int i;
    (void)state;
    for (i = 0; i < 2; ++i) {
        rbs_world *w = soft_world(4, 1e-3, 0.0, e, 4);
        rbs_material_id m = material(w, "m", mus[i], mus[i], -1.0);
        rbs_body_id b;
        double slides = 3.5 * mus[i] * (1.0 + e) * vz < vx;
        rbs_body_state st;
        floor_plane(w, m);
        b = ball(w, r, 1.0, 0, 0, r + 0.0123, vx, 0, -vz, m);
        step_n(w, 100);
        st = state_of(w, b);
        ASSERT_NEAR(st.velocity.z, e * vz, 1e-12);
        ASSERT_NEAR(st.velocity.x, slides ? vx - mus[i] * (1.0 + e) * vz : 5.0 / 7.0 * vx, 1e-12);
        if (!slides)
            ASSERT_NEAR(st.angular_velocity.y * r, st.velocity.x, 1e-12);
        rbs_world_destroy(w);
    }
}

/* A ball dropped from h onto the floor with e = 0.5: its rebound speeds are
 * e^n sqrt(2 g h) and its apexes h e^(2n) (rigid contact, exact).  The soft
 * method stops the ball within the sub-step of impact and sends it back at
 * the frame's end with e times the speed of the frame's start, so each
 * rebound speed is low by at most e g dt and each flight lasts up to a frame
 * longer: apex n is off by at most 2 v_n g dt / g = 2 v_n dt (v_n the
 * rebound speed) plus the previous bounces' losses carried on, which stays
 * below 4 sqrt(2 g h) dt = 0.018 m for h = 1 m.  The first rebound speed
 * is checked to e g dt. */
static void bouncing_ball_apexes(void **state)
{
    const double h = 1.0, r = 0.1, e = 0.5, dt = 1e-3, v0 = sqrt(2.0 * G * h);
    rbs_world *w = soft_world(4, dt, -G, e, 4);
    rbs_material_id m = material(w, "m", 0.0, 0.0, -1.0);
    rbs_body_id b;
    double apex = 0.0, last_vz = 0.0, first_up = -1.0;
    int n = 0, k;
    (void)state;
    floor_plane(w, m);
    b = ball(w, r, 1.0, 0, 0, r + h, 0, 0, 0, m);
    for (k = 0; k < 2500 && n < 3; ++k) {
        rbs_body_state s;
        step_n(w, 1);
        s = state_of(w, b);
        if (first_up < 0.0 && s.velocity.z > 0.0)
            first_up = s.velocity.z;
        if (last_vz > 0.0 && s.velocity.z <= 0.0) {
            n++;
            ASSERT_NEAR(apex - r, h * pow(e, 2.0 * n), 4.0 * v0 * dt);
        }
        if (s.position.z > apex || s.velocity.z < 0.0)
            apex = s.velocity.z < 0.0 ? 0.0 : s.position.z;
        last_vz = s.velocity.z;
    }
    assert_int_equal(n, 3);
    ASSERT_NEAR(first_up, e * v0, e * G * dt);
    rbs_world_destroy(w);
}

/* With e = 1 a bouncing ball never gains energy: the rebound takes the
 * approach speed of the frame's start, reached higher up, so each bounce
 * can only lose (about m g v dt).  50 bounces' worth (20 s); energy never
 * above its start by more than rounding (1e-12 J). */
static void elastic_bounce_never_gains_energy(void **state)
{
    rbs_world *w = soft_world(4, 1e-3, -G, 1.0, 4);
    rbs_material_id m = material(w, "m", 0.0, 0.0, -1.0);
    rbs_energy e0, e;
    int k;
    (void)state;
    floor_plane(w, m);
    ball(w, 0.1, 1.0, 0, 0, 0.6, 0, 0, 0, m);
    CHECK_OK(rbs_world_energy(w, &e0));
    for (k = 0; k < 20000; ++k) {
        step_n(w, 1);
        CHECK_OK(rbs_world_energy(w, &e));
        if (e.total > e0.total + 1e-12)
            fail_msg("step %d: energy %.17g above the start's %.17g", k, e.total, e0.total);
    }
    rbs_world_destroy(w);
}

/* |v|, m/s. */
static double speed(rbs_vec3 v) { return sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

/* A frictionless ball in a narrow V-groove: two planes whose normals are
 * tilted th from vertical, walls 0.1 and 1 degree off vertical (th = 89.9,
 * 89 degrees), the ball set at rest touching both -- an equilibrium, each
 * wall holding m g / (2 cos th), 286 and 29 times its weight.  Its two
 * rows, one after the other, cannot hold it (the mode in which it sinks
 * into both is 1 / (2 cos^2 th) times heavier than either row's mass), and
 * the warm-started soft rows gained energy: at 0.1 degrees it rattled at
 * up to 1.0 m/s after 20 s, 0.3 J gained, at 1 degree for good at 0.06 m/s.
 * Solved as one block (soft_rows.h, row_wedge) it sinks as a ball on a
 * floor: each wall's overlap beyond the slop is cos th g / omega^2, the
 * ball g / omega^2 lower, plus the slop r 1e-6 / cos th, which the steady
 * state gives to rounding (1e-9 of the sink, 5.8e-5 m at 0.1 degrees, and
 * the ball's speed under 1e-12 m/s over the last 10 s, at rest to rounding).
 * Dropped 5 cm into the groove (a vertical impact at v = sqrt(2 g 0.05))
 * it bounces as off a floor, the restitution rows a block too: up at e
 * times the frame-start speed, between e (v - g dt) and e v (to 1e-12 m/s,
 * rounding; one row after the other met it plastically), never has more
 * energy than at the start (1e-9 J: rounding of the 0.5 J it falls) and
 * comes to rest as well. */
static void ball_in_a_narrow_wedge_settles(void **state)
{
    const double tilt[2] = {89.9, 89.0}, r = 0.1, dt = 1e-3;
    int i, drop;
    (void)state;
    for (drop = 0; drop < 2; ++drop)
        for (i = 0; i < 2; ++i) {
            rbs_world *w = soft_world(4, dt, -G, 0.5, 3);
            rbs_material_id m = material(w, "m", 0.0, 0.0, 0.5);
            const double th = tilt[i] * PI_ / 180.0, c = cos(th), om = soft_omega(dt, 3);
            const double z0 = r / c, sink = 1e-6 * r / c + G / (om * om);
            rbs_plane_def p;
            rbs_body_id b, id;
            rbs_energy e0, e;
            double vmax = 0.0, up = 0.0, v = sqrt(2.0 * G * 0.05);
            int k;
            rbs_plane_def_init(&p);
            p.material = m;
            p.normal.x = sin(th);
            p.normal.z = c;
            CHECK_OK(rbs_world_add_plane(w, &p, &id));
            p.normal.x = -sin(th);
            CHECK_OK(rbs_world_add_plane(w, &p, &id));
            b = ball(w, r, 1.0, 0, 0, z0 + 0.05 * drop, 0, 0, 0, m);
            CHECK_OK(rbs_world_energy(w, &e0));
            for (k = 0; k < 20000; ++k) {
                rbs_body_state s;
                step_n(w, 1);
                CHECK_OK(rbs_world_energy(w, &e));
                if (e.total > e0.total + 1e-9)
                    fail_msg("tilt %g, drop %d, step %d: energy %.17g above the start's %.17g", tilt[i], drop, k,
                             e.total, e0.total);
                s = state_of(w, b);
                if (s.velocity.z > up)
                    up = s.velocity.z;
                if (k >= 10000 && speed(s.velocity) > vmax)
                    vmax = speed(s.velocity);
            }
            if (vmax > 1e-12)
                fail_msg("tilt %g, drop %d: still moving at %.3g m/s in the last 10 s", tilt[i], drop, vmax);
            if (drop && (up < 0.5 * (v - G * dt) - 1e-12 || up > 0.5 * v + 1e-12))
                fail_msg("tilt %g: bounced up at %.17g m/s, not e times the approach %.17g", tilt[i], up, v);
            ASSERT_NEAR(z0 - state_of(w, b).position.z, sink, 1e-9 * sink);
            ASSERT_NEAR(state_of(w, b).position.x, 0.0, 1e-12);
            rbs_world_destroy(w);
        }
}

/* A solid sphere launched sliding at v0 with mu_k rolls from t = 2 v0 /
 * (7 mu g) at 5/7 v0.  Kinetic friction is a constant deceleration, which
 * Euler integrates exactly on the sub-steps, and the switch is a stick
 * impulse: 5/7 v0 within 1e-9 of v0 (the contact's spring leaves the ball
 * rounding-level normal motion), rolling (v = w r) to the same, and the
 * switch seen within a frame of the exact time. */
static void sliding_sphere_starts_rolling(void **state)
{
    const double v0 = 5.0, mu = 0.3, r = 0.1, dt = 1e-3;
    const double t_roll = 2.0 * v0 / (7.0 * mu * G);
    rbs_world *w = soft_world(4, dt, -G, 0.5, 4);
    rbs_body_id b;
    double t_seen = slide_to_roll(w, v0, mu, r, 3000, 1e-9, &b);
    (void)state;
    assert_true(t_seen >= t_roll - dt && t_seen <= t_roll + dt);
    ASSERT_NEAR(state_of(w, b).velocity.x, 5.0 / 7.0 * v0, 1e-9 * v0);
    ASSERT_NEAR(state_of(w, b).angular_velocity.y * r, 5.0 / 7.0 * v0, 1e-9 * v0);
    rbs_world_destroy(w);
}

/* On an incline of angle theta a solid ball rolls without slipping when
 * tan(theta) <= 7/2 mu_s, at a = 5/7 g sin(theta), and otherwise slides at
 * a = g (sin(theta) - mu_k cos(theta)).  Constant accelerations after the
 * first frames' settling into the spring: 1e-6 m/s after 1 s. */
static void incline_rolls_or_slides(void **state)
{
    const double th = 20.0 * PI_ / 180.0, r = 0.1, T = 1.0;
    const double mus[2] = {0.5, 0.05};
    int i;
    (void)state;
    for (i = 0; i < 2; ++i) {
        rbs_world *w = soft_world(4, 1e-3, -G, 0.0, 4);
        rbs_body_id b = incline_ball(w, th, mus[i], r);
        double down, normal;
        step_n(w, 1000);
        incline_speeds(state_of(w, b), th, &down, &normal);
        ASSERT_NEAR(down, incline_acceleration(th, mus[i], G) * T, 1e-6);
        ASSERT_NEAR(normal, 0.0, 1e-6);
        rbs_world_destroy(w);
    }
}

/* Rolling resistance mu_r (the general rows: resistance is not in the
 * gathered layout) decelerates a rolling ball at 5/7 mu_r g: 1e-6 m/s
 * after 1 s, as for the incline. */
static void rolling_resistance_decelerates(void **state)
{
    const double r = 0.1, v0 = 2.0, mur = 0.02, T = 1.0;
    rbs_world *w = soft_world(4, 1e-3, -G, 0.0, 4);
    rbs_body_id b = rolling_resistance_ball(w, r, v0, mur);
    (void)state;
    step_n(w, (int)(T / 1e-3 + 0.5));
    ASSERT_NEAR(state_of(w, b).velocity.x, v0 - 5.0 / 7.0 * mur * G * T, 1e-6);
    rbs_world_destroy(w);
}

/* A ball on a 20 degree slope whose rolling resistance stops it turning
 * (mu_r = 10 tan) is held by static friction when mu_s >= tan: at rest
 * (|v| < 1e-12 m/s after 2 s, at most the spring's sink off its start),
 * for mu_s 1.05 tan (mu_k 0.5 tan) and 10 tan (mu_k the same); below,
 * mu_s 0.9 tan, it slides without turning at g (sin - mu_k cos), to first
 * order in h (g h = 3.3e-3 m/s at 3 sub-steps of 1 ms over 2 s: 1e-2 m/s).
 * The friction and rolling rows taken one each a pass let it slide away
 * at 3 m/s in the first case and creep at 2.4e-4 m/s in the second. */
static void rolling_resistance_holds_a_ball_on_a_slope(void **state)
{
    const double th = 20.0 * PI_ / 180.0, t = tan(th), r = 0.1, T = 2.0;
    static const double mus[3] = {1.05, 10.0, 0.9}, muk[3] = {0.5, 10.0, 0.5};
    int i;
    (void)state;
    for (i = 0; i < 3; ++i) {
        rbs_world *w = soft_world(4, 1e-3, -G, 0.0, 3);
        rbs_material_id m;
        rbs_pair_def pd;
        rbs_plane_def pl;
        rbs_body_id b;
        rbs_body_state st;
        double down, normal;
        CHECK_OK(rbs_world_add_material(w, "m", &m));
        rbs_pair_def_init(&pd);
        pd.a = pd.b = m;
        pd.static_friction = mus[i] * t;
        pd.kinetic_friction = muk[i] * t;
        pd.rolling = 10.0 * t;
        CHECK_OK(rbs_world_set_pair(w, &pd));
        rbs_plane_def_init(&pl);
        pl.normal.x = -sin(th);
        pl.normal.z = cos(th);
        pl.material = m;
        CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
        b = ball(w, r, 1.0, -r * sin(th), 0, r * cos(th), 0, 0, 0, m);
        step_n(w, (int)(T / 1e-3 + 0.5));
        st = state_of(w, b);
        incline_speeds(st, th, &down, &normal);
        if (i < 2) {
            ASSERT_NEAR(down, 0.0, 1e-12);
            ASSERT_NEAR(st.position.x, -r * sin(th), 1e-6);
        } else {
            ASSERT_NEAR(down, G * (sin(th) - muk[i] * t * cos(th)) * T, 1e-2);
        }
        ASSERT_NEAR(st.angular_velocity.y, 0.0, 1e-9);
        rbs_world_destroy(w);
    }
}

/* No tunnelling: a ball crossing 10 radii a step stops at a plane, and two
 * crossing 5 radii a step each meet instead of passing (the swept margins
 * |v| dt make them contacts a frame ahead).  e = 0: after the impact the
 * ball lies on the plane within its spring's reach (1e-6 m), the pair
 * moves together at the mean velocity (momentum, 1e-12). */
static void fast_bodies_do_not_tunnel(void **state)
{
    const double r = 0.01, dt = 1e-3;
    rbs_world *w = soft_world(4, dt, 0.0, 0.0, 4);
    rbs_body_id a, b;
    (void)state;
    floor_plane(w, (rbs_material_id){0, 0});
    a = ball(w, r, 1.0, 0, 0, 0.5, 0, 0, -100.0, (rbs_material_id){0, 0});
    step_n(w, 20);
    ASSERT_NEAR(state_of(w, a).position.z, r, 1e-6);
    assert_true(state_of(w, a).velocity.z > -1e-9);
    rbs_world_destroy(w);

    w = soft_world(4, dt, 0.0, 0.0, 4);
    a = ball(w, r, 1.0, -0.3, 0, 0, 50.0, 0, 0, (rbs_material_id){0, 0});
    b = ball(w, r, 2.0, 0.3, 0, 0, -50.0, 0, 0, (rbs_material_id){0, 0});
    step_n(w, 20);
    assert_true(state_of(w, a).position.x < state_of(w, b).position.x);
    ASSERT_NEAR(state_of(w, a).velocity.x, -50.0 / 3.0, 1e-12 * 50.0);
    ASSERT_NEAR(state_of(w, b).velocity.x, -50.0 / 3.0, 1e-12 * 50.0);
    rbs_world_destroy(w);
}

/* A ball (r = 0.1 m) between two walls 2 m apart (its centre between x =
 * -0.9 and 0.9), e = 1, no gravity, dt = 1 ms, at 6e3, 1.2e4, 3e4 and 1e5
 * m/s: 6 to 100 m a frame, more than the 1.8 m between the walls within a
 * sub-step (v h, h = dt / n) for 1, 3 and 8 sub-steps at all but the
 * slowest.  The soft step meets at most one impact a frame (docs/methods.md),
 * so its exact answer is: each frame ends at the wall it turned at (after
 * frame k at +0.9 for k odd, -0.9 for k even, from x0 = 0.0123 moving to
 * +x), leaving at exactly the speed it came with (a plane's elastic row
 * reverses the normal velocity: 1e-12 of v, rounding), one impact
 * restituted a frame; checked at every frame's end, to the slop (1e-7 m: a
 * contact may overlap by it, and the speculative row closes the gap to
 * rounding), with the step's max_overlap under the slop too.  Before
 * session 51 the next sub-step's warm start gave back the impulse that had
 * stopped the ball at one wall and the other wall's speculative row, solved
 * first, took part of it: the ball ended frames 0.4 % of its radius inside
 * a wall at 6e3 m/s and left the box from about 1.2e4 (soft_rows.h,
 * row_lanes).  Both layouts (the general one: principal moments).
 * The same between two bodies that never move where either or both is a
 * fixed sphere (R = 1 m, centre 2 m from the middle, so its surface is
 * where the wall was): the ball moves along the line of the centres, so a
 * fixed sphere meets it as the wall did, with the same exact answer, and no
 * motion off the line (exactly 0: every normal lies along x).  Before
 * session 51's second fix the ball's contacts with fixed
 * spheres, in different chunks (or anywhere in the general layout's
 * contacts), were taken in the chunks' order, not touching first: the
 * impulse that stopped it at one body, given back by the next sub-step's
 * warm start, was taken by the other's speculative row, and it ended
 * frames 0.4 % of its radius inside a fixed sphere at 6e3 m/s (3
 * sub-steps) and passed through one at 3e4 (soft_rows.h, pass_stage). */
static void ball_between_walls_or_fixed_spheres_stays_inside(void **state)
{
    const double speeds[] = {6e3, 1.2e4, 3e4, 1e5}, r = 0.1, dt = 1e-3, slop = 1e-7;
    const uint32_t subs[] = {1, 3, 8};
    const char *const names[] = {"two walls", "two fixed spheres", "a fixed sphere left, a wall right",
                                 "a wall left, a fixed sphere right"};
    size_t iv, is;
    int general, kind, side;
    (void)state;
    for (kind = 0; kind < 4; ++kind)
        for (iv = 0; iv < sizeof speeds / sizeof speeds[0]; ++iv)
            for (is = 0; is < sizeof subs / sizeof subs[0]; ++is)
                for (general = 0; general < 2; ++general) {
                    const double v = speeds[iv];
                    rbs_world *w = soft_world(4, dt, 0.0, 1.0, subs[is]);
                    rbs_body_id b;
                    int k;
                    for (side = -1; side <= 1; side += 2) {
                        /* kind 0: walls; 1: spheres both sides; 2: the left; 3: the right */
                        if (kind == 1 || (kind == 2 && side < 0) || (kind == 3 && side > 0)) {
                            rbs_sphere_def f;
                            rbs_sphere_def_init(&f);
                            f.radius = 1.0;
                            f.fixed = 1;
                            f.position.x = 2.0 * side;
                            CHECK_OK(rbs_world_add_sphere(w, &f, NULL));
                        } else {
                            rbs_plane_def p;
                            rbs_body_id id;
                            rbs_plane_def_init(&p);
                            p.point.x = 1.0 * side;
                            p.normal = (rbs_vec3){-1.0 * side, 0.0, 0.0};
                            CHECK_OK(rbs_world_add_plane(w, &p, &id));
                        }
                    }
                    b = impact_sphere(w, (rbs_material_id){0, 0}, r, 1.0, (rbs_vec3){0.0123, 0, 0},
                                      (rbs_vec3){v, 0, 0}, general);
                    for (k = 1; k <= 100; ++k) {
                        rbs_step_info info;
                        rbs_body_state s;
                        const double at = k % 2 ? 0.9 : -0.9;
                        CHECK_OK(rbs_world_step(w, &info));
                        s = state_of(w, b);
                        if (!(fabs(s.position.x - at) <= slop) || !(info.max_overlap <= slop) ||
                            !(fabs(s.velocity.x + (k % 2 ? v : -v)) <= 1e-12 * v) || s.velocity.y != 0.0 ||
                            s.velocity.z != 0.0 || s.position.y != 0.0 || s.position.z != 0.0 ||
                            info.colliding != 1u)
                            fail_msg("%s, %g m/s, %u sub-steps, %s layout, frame %d: x %.17g (the surface at %g), "
                                     "max_overlap %.3g m, v (%.17g, %g, %g), %u impacts",
                                     names[kind], v, (unsigned)subs[is], general ? "general" : "gathered", k,
                                     s.position.x, at, info.max_overlap, s.velocity.x, s.velocity.y, s.velocity.z,
                                     (unsigned)info.colliding);
                    }
                    rbs_world_destroy(w);
                }
}

/* The same ball in a groove whose walls are tilted from parallel by t
 * (0.001, 1 and 5 degrees; normals (cos t, 0, sin t) at x = -1 and
 * (-cos t, 0, sin t) at x = 1, nearly opposed: a wedge, whose two rows the
 * soft step solves as one block, soft_rows.h, row_wedge), frictionless,
 * e = 1, no gravity, from x0 = 0.0123 at v along x, 1e3 to 1e5 m/s: each
 * wall's contact is within the frame's reach of the other's, and each
 * bounce sends the ball up the groove.  Exact: it stays inside both walls
 * and keeps its speed (a frictionless plane's elastic row reverses the
 * normal velocity and keeps the tangential one).  Checked at every frame's
 * end, 100 frames: each wall's overlap at most the slop (1e-7 m) and |v|
 * to 1e-12 of v (rounding).  Before session 51 the block's two lanes, the
 * wall ahead to close and the wall behind to open, both came out pulling;
 * the wall ahead let go first, and at 1e3 m/s (0.001 degrees) the ball
 * went 0.2 m into it. */
static void ball_in_a_tilted_groove_stays_inside(void **state)
{
    const double speeds[] = {1e3, 6e3, 1.2e4, 1e5}, tilts[] = {0.001, 1.0, 5.0}, r = 0.1, dt = 1e-3;
    const double slop = 1e-7;
    size_t iv, it;
    (void)state;
    for (iv = 0; iv < sizeof speeds / sizeof speeds[0]; ++iv)
        for (it = 0; it < sizeof tilts / sizeof tilts[0]; ++it) {
            const double v = speeds[iv], t = tilts[it] * PI_ / 180.0, c = cos(t), sn = sin(t);
            rbs_world *w = soft_world(4, dt, 0.0, 1.0, 3);
            rbs_plane_def p;
            rbs_body_id id, b;
            int k;
            rbs_plane_def_init(&p);
            p.point.x = -1.0;
            p.normal = (rbs_vec3){c, 0.0, sn};
            CHECK_OK(rbs_world_add_plane(w, &p, &id));
            p.point.x = 1.0;
            p.normal = (rbs_vec3){-c, 0.0, sn};
            CHECK_OK(rbs_world_add_plane(w, &p, &id));
            b = ball(w, r, 1.0, 0.0123, 0, 0, v, 0, 0, (rbs_material_id){0, 0});
            for (k = 1; k <= 100; ++k) {
                rbs_body_state s;
                double da, db;
                step_n(w, 1);
                s = state_of(w, b);
                /* each wall's overlap: r less the centre's distance from it */
                da = r - ((s.position.x + 1.0) * c + s.position.z * sn);
                db = r - (-(s.position.x - 1.0) * c + s.position.z * sn);
                if (!(da <= slop) || !(db <= slop) || !(fabs(speed(s.velocity) - v) <= 1e-12 * v))
                    fail_msg("%g m/s, walls %g degrees from parallel, frame %d: %.3g m into the left wall, %.3g m "
                             "into the right, speed %.17g",
                             v, tilts[it], k, da, db, speed(s.velocity));
            }
            rbs_world_destroy(w);
        }
}

/* A line of n equal balls of radius r along x, the gaps between them gap,
 * the first moving at v towards the rest (e = 1, no gravity), in a soft
 * world of dt: each ball's slot into b. */
static rbs_world *ball_line(int n, double r, double gap, double v, double dt, int general, rbs_body_id *b)
{
    rbs_world *w = soft_world((uint32_t)n, dt, 0.0, 1.0, 4);
    int i;
    for (i = 0; i < n; ++i) {
        rbs_vec3 p = {i * (2.0 * r + gap), 0.0, 0.0}, u = {i == 0 ? v : 0.0, 0.0, 0.0};
        b[i] = impact_sphere(w, (rbs_material_id){0, 0}, r, 1.0, p, u, general);
    }
    return w;
}

/* A spaced Newton's cradle: equal balls apart by gaps under a frame's
 * travel, struck by the first at v with e = 1.  The impacts come one after
 * another, and each passes the whole velocity on (the impact law for equal
 * masses), so at the end the last ball leaves at v and the others rest.
 * The soft step meets each impact whole in its own frame -- the struck
 * ball's next pair is no contact of the frame it is struck in, since a
 * kick of less than RBS__GUARD_DEPTH of the radius makes no guard (guards
 * acting at 1 % of it gave errors of up to 0.6 v) -- so the answer
 * is exact to rounding: 1e-12 of v, for 3, 5 and 8 balls, gaps of 1e-3 to
 * 1.5 of v dt, 0.5 to 20 m/s (up to 0.4 of a radius a frame) and both
 * layouts. */
static void spaced_cradle_passes_the_velocity_down_the_line(void **state)
{
    const int ns[] = {3, 5, 8};
    const double fracs[] = {1e-3, 0.1, 0.5, 0.99, 1.5}, r = 0.05;
    const struct {
        double v, dt;
    } runs[] = {{0.5, 1e-3}, {2.0, 1e-3}, {20.0, 1e-3}, {0.5, 1e-2}, {2.0, 1e-2}};
    size_t in, ifr, ir;
    int general;
    (void)state;
    for (in = 0; in < sizeof ns / sizeof ns[0]; ++in)
        for (ifr = 0; ifr < sizeof fracs / sizeof fracs[0]; ++ifr)
            for (ir = 0; ir < sizeof runs / sizeof runs[0]; ++ir)
                for (general = 0; general < 2; ++general) {
                    const int n = ns[in];
                    const double v = runs[ir].v, dt = runs[ir].dt, gap = fracs[ifr] * v * dt;
                    rbs_body_id b[8];
                    rbs_world *w = ball_line(n, r, gap, v, dt, general, b);
                    int i;
                    /* (n impacts of at most two frames each, and the gaps) */
                    step_n(w, (int)(n * (gap / v / dt + 3.0)) + 5);
                    for (i = 0; i < n; ++i) {
                        double got = state_of(w, b[i]).velocity.x, want = i == n - 1 ? v : 0.0;
                        if (!(fabs(got - want) <= 1e-12 * v))
                            fail_msg("%d balls, gaps %g of v dt, %g m/s, dt %g, %s layout: ball %d at %.17g m/s, "
                                     "not %g",
                                     n, fracs[ifr], v, dt, general ? "general" : "gathered", i, got, want);
                    }
                    rbs_world_destroy(w);
                }
}

/* A ball struck within a frame faster than its gap to the next one a frame
 * goes into that one, which no frame-start margin took as a contact: at
 * 20 m/s and dt = 10 ms (4 radii a frame) a line of five went 1.43 radii
 * deep and came out with 8 % more energy than it had (27 % at its most;
 * e = 1).  The guard the kick makes a contact stops the struck ball at
 * RBS__GUARD_DEPTH = half of the radius (measured 0.503 gathered and 0.614
 * general: 0.7 allows the sub-steps' Gauss-Seidel slack), the line keeps
 * its momentum to rounding (1e-12 of m v) and never gains energy (1e-12):
 * the soft step, which cannot pass an impulse down a chain within a frame,
 * may only lose (it ends with about half of it; this is not the exact
 * answer, which euler and event give). */
static void kicked_ball_stops_at_the_guard_depth(void **state)
{
    const double r = 0.05, v = 20.0, dt = 1e-2;
    int general;
    (void)state;
    for (general = 0; general < 2; ++general) {
        rbs_body_id b[5];
        rbs_world *w = ball_line(5, r, 0.1 * v * dt, v, dt, general, b);
        rbs_energy e0, e;
        rbs_vec3 p;
        double deepest = 0.0;
        int k, i;
        CHECK_OK(rbs_world_energy(w, &e0));
        for (k = 0; k < 40; ++k) {
            step_n(w, 1);
            for (i = 0; i < 4; ++i) {
                double over = 2.0 * r - (state_of(w, b[i + 1]).position.x - state_of(w, b[i]).position.x);
                deepest = over > deepest ? over : deepest;
            }
            CHECK_OK(rbs_world_energy(w, &e));
            assert_true(e.total <= e0.total * (1.0 + 1e-12));
        }
        assert_true(deepest <= 0.7 * r);
        CHECK_OK(rbs_world_momentum(w, &p, NULL));
        ASSERT_NEAR(p.x, v, 1e-12 * v);
        rbs_world_destroy(w);
    }
}

/* A ball shot at 100 m/s (2 radii a frame) into a grid of 8 x 8 resting
 * balls on the floor, e = 1: the struck balls are kicked within the frame
 * into their neighbours.  Without guards they went 0.97 radii deep and the
 * grid came out with 19 % more energy than the shot brought; with them no
 * pair overlaps by more than 0.7 of a radius (measured 0.50) and the
 * energy never grows (1e-9 of it, for rounding: the grid settling into
 * the floor's springs only gives energy up). */
static void shot_into_a_grid_gains_no_energy(void **state)
{
    const double r = 0.05;
    rbs_world *w = soft_world(66, 1e-3, -G, 1.0, 4);
    rbs_body_id b[65];
    rbs_energy e0, e;
    double deepest = 0.0;
    int i, j, k;
    (void)state;
    floor_plane(w, (rbs_material_id){0, 0});
    for (i = 0; i < 64; ++i)
        b[i] = ball(w, r, 0.1, (i / 8) * 2.02 * r, (i % 8) * 2.02 * r, r, 0, 0, 0, (rbs_material_id){0, 0});
    b[64] = ball(w, r, 0.1, -0.3, 3.3 * 2.02 * r, r, 100.0, 0, 0, (rbs_material_id){0, 0});
    CHECK_OK(rbs_world_energy(w, &e0));
    for (k = 0; k < 300; ++k) {
        step_n(w, 1);
        CHECK_OK(rbs_world_energy(w, &e));
        assert_true(e.total <= e0.total * (1.0 + 1e-9));
        for (i = 0; i < 65; ++i)
            for (j = i + 1; j < 65; ++j) {
                rbs_vec3 p = state_of(w, b[i]).position, q = state_of(w, b[j]).position;
                double d = sqrt((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y) + (p.z - q.z) * (p.z - q.z));
                deepest = 2.0 * r - d > deepest ? 2.0 * r - d : deepest;
            }
    }
    assert_true(deepest <= 0.7 * r);
    rbs_world_destroy(w);
}

/* A crowd of 64 balls in a box with no gravity, random velocities, e = 1
 * and no friction: every impulse is internal or against a wall, so with the
 * walls away (they take none here: the balls are far from them) the total
 * momentum is conserved to rounding (1e-12 of the largest |m v|) over 2 s
 * of collisions, and no energy is created (the soft step can only lose). */
static void crowd_conserves_momentum(void **state)
{
    enum { N = 64 };
    rbs_world *w = soft_world(N, 1e-3, 0.0, 1.0, 4);
    rbs_body_id b[N];
    rbs_energy e0, e1;
    double px = 0.0, py = 0.0, pz = 0.0, qx = 0.0, qy = 0.0, qz = 0.0;
    uint64_t x = 12345;
    int i;
    (void)state;
    for (i = 0; i < N; ++i) {
        double v[3];
        int k;
        for (k = 0; k < 3; ++k) {
            x = x * 6364136223846793005ull + 1442695040888963407ull;
            v[k] = ((double)(x >> 11) / 9007199254740992.0 - 0.5) * 0.4;
        }
        b[i] = ball(w, 0.05, 1.0 + i % 3, 0.12 * (i % 4), 0.12 * ((i / 4) % 4), 0.12 * (i / 16), v[0], v[1],
                    v[2], (rbs_material_id){0, 0});
        px += (1.0 + i % 3) * v[0];
        py += (1.0 + i % 3) * v[1];
        pz += (1.0 + i % 3) * v[2];
    }
    CHECK_OK(rbs_world_energy(w, &e0));
    step_n(w, 2000);
    CHECK_OK(rbs_world_energy(w, &e1));
    for (i = 0; i < N; ++i) {
        rbs_body_state s = state_of(w, b[i]);
        qx += s.mass * s.velocity.x;
        qy += s.mass * s.velocity.y;
        qz += s.mass * s.velocity.z;
    }
    ASSERT_NEAR(qx, px, 1e-12 * 0.6 * N);
    ASSERT_NEAR(qy, py, 1e-12 * 0.6 * N);
    ASSERT_NEAR(qz, pz, 1e-12 * 0.6 * N);
    assert_true(e1.total <= e0.total + 1e-12);
    rbs_world_destroy(w);
}

/* The largest energy rise over 3 s of a ball whose centre of mass is 3 cm
 * off-centre, set down on the floor with its mass to one side (it rocks),
 * e = 0, with n sub-steps: the general rows (not the gathered layout). */
static double rocking_rise(uint32_t n)
{
    rbs_world *w = soft_world(4, 1e-3, -G, 0.0, n);
    rbs_material_id m = material(w, "m", 0.8, 0.6, -1.0);
    rbs_sphere_def s;
    rbs_energy e0, e;
    double most = 0.0;
    int k;
    floor_plane(w, m);
    rbs_sphere_def_init(&s);
    s.radius = 0.1;
    s.position.z = 0.1;
    s.center_of_mass.x = 0.03;
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    CHECK_OK(rbs_world_energy(w, &e0));
    for (k = 0; k < 3000; ++k) {
        step_n(w, 1);
        CHECK_OK(rbs_world_energy(w, &e));
        most = e.total - e0.total > most ? e.total - e0.total : most;
    }
    rbs_world_destroy(w);
    return most;
}

/* An anisotropic ball set down on the floor takes the general rows too and
 * rests like a round one: it sinks by slop r + g / omega^2 (1e-6 of it) and
 * its energy never rises by more than the push that restores that sink can
 * lift it, m g (slop r + g / omega^2).
 * A rocking off-centre ball (e = 0) should lose energy; the soft step makes
 * it gain a little, at first order in h (the pushes that restore the
 * spring's changing deflection under a rocking load lift it without taking
 * the energy from anything; docs/methods.md): the largest rise in 3 s falls
 * by at least 3x from 4 to 16 sub-steps (4x when first order; measured
 * 3.6e-4 -> 9.4e-5 J), and stays below 2e-4 J at 16. */
static void general_rows_rest(void **state)
{
    rbs_world *w = soft_world(4, 1e-3, -G, 0.0, 4);
    rbs_material_id m = material(w, "m", 0.8, 0.6, -1.0);
    rbs_sphere_def s;
    rbs_body_id a;
    rbs_energy e0, e;
    double om = soft_omega(1e-3, 4), sink = 1e-7 + G / (om * om), r4, r16;
    int k;
    (void)state;
    floor_plane(w, m);
    rbs_sphere_def_init(&s);
    s.radius = 0.1;
    s.position.z = 0.1;
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = 0.004;
    s.inertia.y = 0.005;
    s.inertia.z = 0.006;
    s.angular_velocity.z = 0.5; /* spinning about the vertical: the gyroscopic path */
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, &a));
    CHECK_OK(rbs_world_energy(w, &e0));
    for (k = 0; k < 2000; ++k) {
        step_n(w, 1);
        CHECK_OK(rbs_world_energy(w, &e));
        if (e.total > e0.total + G * sink * (1.0 + 1e-6))
            fail_msg("step %d: energy rose by %.3g J (bound %.3g J)", k, e.total - e0.total, G * sink);
    }
    ASSERT_NEAR(0.1 - state_of(w, a).position.z, sink, 1e-6 * sink);
    rbs_world_destroy(w);
    r4 = rocking_rise(4);
    r16 = rocking_rise(16);
    if (!(r16 * 3.0 <= r4) || !(r16 < 2e-4))
        fail_msg("rocking ball's energy rise: %.3g J at 4 sub-steps, %.3g J at 16", r4, r16);
}

/* Three balls resting on a floor and a "hot" ball of mass m in the air at
 * x = -0.5 m, z = 0.3 m: centred isotropic (the gathered layout), or with
 * anisotropic inertia (the general layout) when general. */
static rbs_world *hot_ball_world(int general, double m, rbs_body_id *hot)
{
    rbs_world *w = soft_world(8, 1e-3, -G, 0.5, 4);
    rbs_sphere_def s;
    int i;
    floor_plane(w, (rbs_material_id){0, 0});
    for (i = 0; i < 3; ++i)
        ball(w, 0.1, 1.0, 0.3 * i, 0, 0.1, 0, 0, 0, (rbs_material_id){0, 0});
    rbs_sphere_def_init(&s);
    s.name = "hot";
    s.radius = 0.1;
    s.mass = m;
    s.position.x = -0.5;
    s.position.z = 0.3;
    if (general) {
        s.inertia_kind = RBS_INERTIA_PRINCIPAL;
        s.inertia.x = 0.4 * m * 0.01;
        s.inertia.y = 0.5 * m * 0.01;
        s.inertia.z = 0.6 * m * 0.01;
    }
    CHECK_OK(rbs_world_add_sphere(w, &s, hot));
    return w;
}

/* A step that overflows (a = 1e313 from a huge force) is RBS_E_NUMERIC and
 * leaves the world bit for bit at its last good state, in both layouts:
 * the gathered one saves nothing at the frame's start and writes the world
 * only once the whole frame is finite; the general one (an anisotropic
 * ball) restores its save.  The overflowing body is named. */
static void overflow_keeps_last_good_state(void **state)
{
    int general;
    (void)state;
    for (general = 0; general <= 1; ++general) {
        rbs_body_id b;
        rbs_world *w = hot_ball_world(general, 1e-5, &b);
        step_n(w, 50);
        overflow_keeps_state(w, b, "(\"hot\") became NaN or infinite", 50);
        rbs_world_destroy(w);
    }
}

/* A spin too fast to turn: 1e157 rad/s about each axis turns a ball by a
 * finite 1e154 rad about each in a frame, whose length overflows, so the
 * turn is NaN.  The step is RBS_E_NUMERIC and leaves the world bit for bit
 * as it was, in both layouts (the gathered one checks the new orientation
 * before it writes anything; the fuzzer found it writing the NaN). */
static void spin_overflow_keeps_last_good_state(void **state)
{
    int general;
    (void)state;
    for (general = 0; general <= 1; ++general) {
        rbs_body_id b;
        rbs_world *w = hot_ball_world(general, 1.0, &b);
        rbs_vec3 spin = {1e157, 1e157, 1e157};
        uint64_t h;
        step_n(w, 5);
        raw_set(w, b, RAW_ANGULAR_VELOCITY, spin); /* (beyond the setter's limit) */
        h = rbs_world_hash(w);
        assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
        assert_non_null(strstr(rbs_world_last_error(w), "(\"hot\") became NaN or infinite"));
        assert_true(rbs_world_hash(w) == h);
        assert_int_equal(rbs_world_step_count(w), 5);
        rbs_world_destroy(w);
    }
}

/* A heap of n balls (3 per row, touching layers) on a floor, in a world
 * with room for one more body. */
static rbs_world *soft_heap(int n, rbs_body_id *ids)
{
    rbs_world *w = soft_world((uint32_t)n + 2, 1e-3, -G, 0.5, 4);
    rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
    int i;
    floor_plane(w, m);
    for (i = 0; i < n; ++i)
        ids[i] = ball(w, 0.05, 0.1, 0.1 * (i % 3) + 0.01 * (i % 2), 0.1 * ((i / 3) % 3), 0.06 + 0.1 * (i / 9),
                      0.2 * (i % 4), 0, 0, m);
    return w;
}

/* Without applied forces the gathered layout shares one velocity increment
 * among all bodies (and detection computes their accelerations itself);
 * with a force on any body it keeps a table of them.  Both must give the
 * same bits: the heap stepped alone, and beside a far-away ball held up by
 * a force (which makes the world take the table), ends the same. */
static void shared_increment_is_the_table(void **state)
{
    enum { N = 27 };
    rbs_body_id ia[N], ib[N], far;
    rbs_world *a = soft_heap(N, ia), *b = soft_heap(N, ib);
    rbs_vec3 up = {0, 0, 0.1 * G};
    int i;
    (void)state;
    far = ball(b, 0.05, 0.1, 100.0, 0.0, 50.0, 0, 0, 0, (rbs_material_id){0, 0});
    CHECK_OK(rbs_body_set_force(b, far, up));
    step_n(a, 400);
    step_n(b, 400);
    for (i = 0; i < N; ++i) {
        rbs_body_state sa = state_of(a, ia[i]), sb = state_of(b, ib[i]);
        assert_memory_equal(&sa.position, &sb.position, sizeof sa.position);
        assert_memory_equal(&sa.velocity, &sb.velocity, sizeof sa.velocity);
        assert_memory_equal(&sa.angular_velocity, &sb.angular_velocity, sizeof sa.angular_velocity);
    }
    ASSERT_NEAR(state_of(b, far).position.z, 50.0, 1e-9); /* (held: the force is its weight) */
    rbs_world_destroy(a);
    rbs_world_destroy(b);
}

/* A heap of 30 balls (r 0.05 m, 0.1 kg) in three layers of 5 x 3 over a
 * floor, of material m (mu_s 0.5, mu_k 0.4), all moving at vx along x;
 * the material through *m. */
static rbs_world *heap_world(double e, double vx, rbs_material_id *m)
{
    rbs_world *w = soft_world(40, 1e-3, -G, e, 4);
    int i;
    *m = material(w, "m", 0.5, 0.4, -1.0);
    floor_plane(w, *m);
    for (i = 0; i < 30; ++i)
        ball(w, 0.05, 0.1, 0.11 * (i % 5), 0.11 * ((i / 5) % 3), 0.06 + 0.11 * (i / 15), vx, 0, 0, *m);
    return w;
}

/* Checkpoints: a soft run stopped half-way and resumed from its checkpoint
 * continues bit for bit (the warm-start table is in the world's block). */
static void checkpoint_resumes_bit_for_bit(void **state)
{
    rbs_material_id m;
    rbs_world *w = heap_world(0.5, 0.0, &m), *c = NULL;
    static unsigned char buf[1 << 20];
    size_t n = 0;
    int i;
    (void)state;
    step_n(w, 300);
    assert_true(rbs_world_checkpoint_size(w) <= sizeof buf);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, sizeof buf, &n));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &c));
    step_n(w, 300);
    step_n(c, 300);
    for (i = 0; i < 40; ++i) {
        rbs_body_id id;
        if (rbs_world_body_at(w, (uint32_t)i, &id) != RBS_OK)
            continue;
        rbs_body_state s1 = state_of(w, id), s2 = state_of(c, id);
        assert_memory_equal(&s1.position, &s2.position, sizeof s1.position);
        assert_memory_equal(&s1.velocity, &s2.velocity, sizeof s1.velocity);
    }
    rbs_world_destroy(c);
    rbs_world_destroy(w);
}

/* The layout follows the world: the plan keeps whether the records can be
 * gathered, so a change that rules them out -- here rolling resistance set
 * on a pair mid-run, which only the general rows apply -- must take the
 * general layout from the next step.  The twin is the same world written to
 * a checkpoint just after the change and read back, so its plan is made
 * afresh: the two agree bit for bit only if the running world's plan was
 * remade (with the stale plan the gathered rows ignore the resistance, and
 * the balls roll further). */
static void layout_follows_changes(void **state)
{
    rbs_material_id m;
    rbs_world *w = heap_world(0.3, 0.5, &m), *c = NULL;
    static unsigned char buf[1 << 20];
    rbs_pair_def p;
    size_t n = 0;
    int i;
    (void)state;
    step_n(w, 100);
    rbs_pair_def_init(&p);
    p.a = p.b = m;
    p.static_friction = 0.5;
    p.kinetic_friction = 0.4;
    p.rolling = 0.05;
    CHECK_OK(rbs_world_set_pair(w, &p));
    CHECK_OK(rbs_world_checkpoint_write(w, buf, sizeof buf, &n));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &c));
    for (i = 0; i < 200; ++i) {
        CHECK_OK(rbs_world_step(w, NULL));
        CHECK_OK(rbs_world_step(c, NULL));
        if (rbs_world_hash(w) != rbs_world_hash(c))
            fail_msg("step %d after the change: the running world and its fresh twin differ", i + 1);
    }
    rbs_world_destroy(c);
    rbs_world_destroy(w);
}

/* soft_tolerance: default 0 (every frame takes soft_substeps), and the
 * range [0, 1] checked with a message that names it. */
static void tolerance_default_and_range(void **state)
{
    rbs_world_def d;
    char msg[256];
    (void)state;
    rbs_world_def_init(&d);
    assert_true(d.soft_tolerance == 0.0);
    d.soft_tolerance = -0.1;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "soft_tolerance must be in [0, 1] (a fraction of the radius), got -0.1"));
    d.soft_tolerance = 1.5;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    d.soft_tolerance = NAN;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "soft_tolerance"));
    d.soft_tolerance = 1.0;
    CHECK_OK(rbs_world_def_validate(&d, msg, sizeof msg));
}

/* A world of soft_substeps n and soft_tolerance tol (else soft_world's). */
static rbs_world *tolerant_world(uint32_t bodies, double gz, uint32_t n, double tol)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = bodies;
    d.dt = 1e-3;
    d.gravity.z = gz;
    d.restitution = 0.5;
    d.method = RBS_METHOD_SOFT;
    d.soft_substeps = n;
    d.soft_tolerance = tol;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* The frame's sub-steps follow the rule (rbsim.h, soft_tolerance): a ball
 * of radius r = 0.1 m a gap of 1e-4 m over the floor, approaching it at v
 * with no gravity, can reach an overlap of v dt - 1e-4 m in the frame; of
 * r, over tol = 0.01, that is q = 0.9, 0.4 and 0.1 for v = 1, 0.5 and 0.2
 * m/s, so of 4 sub-steps the frame takes 4 (q >= 1/2), 2 (q < 1/2) and 1
 * (q < 1/4) -- far from the thresholds, so the detected gap's rounding
 * cannot move them.  Each bounce still follows the soft step's impact law,
 * v' = e v (the approach of the frame's start, no force), to rounding. */
static void tolerance_sets_the_substeps(void **state)
{
    const double vs[3] = {1.0, 0.5, 0.2};
    const uint32_t want[3] = {4, 2, 1};
    int i;
    (void)state;
    for (i = 0; i < 3; ++i) {
        rbs_world *w = tolerant_world(2, 0.0, 4, 0.01);
        rbs_body_id b;
        rbs_step_info info;
        floor_plane(w, (rbs_material_id){0, 0});
        b = ball(w, 0.1, 1.0, 0, 0, 0.1 + 1e-4, 0, 0, -vs[i], (rbs_material_id){0, 0});
        CHECK_OK(rbs_world_step(w, &info));
        assert_int_equal(info.substeps, want[i]);
        ASSERT_NEAR(state_of(w, b).velocity.z, 0.5 * vs[i], 1e-12);
        CHECK_OK(rbs_world_step(w, &info)); /* (leaving: nothing can overlap) */
        assert_int_equal(info.substeps, 1);
        rbs_world_destroy(w);
    }
}

/* With a tolerance a ball resting on the floor takes one sub-step a frame
 * (its reachable overlap, the static deflection, is about 4e-5 of r, far
 * under tol / 4), and so sinks to the deflection of h = dt:
 * slop r + g / omega(dt, 1)^2, to 1e-6 of itself as in
 * resting_ball_sinks_to_the_static_deflection.  A ball in free fall beside
 * it still flies exactly (to 1e-12 m as in
 * flight_is_exact_in_both_layouts) and ends bit for
 * bit as it does with no tolerance: the tolerance concerns contacts only. */
static void tolerance_rests_on_one_substep_and_keeps_free_flight(void **state)
{
    const double r = 0.1, dt = 1e-3, T = 1.0;
    rbs_world *w = tolerant_world(4, -G, 4, 0.01), *z = tolerant_world(4, -G, 4, 0.0);
    rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
    double om = soft_omega(dt, 1), sink = 1e-6 * r + G / (om * om);
    rbs_body_id rest, fly, fz;
    rbs_step_info info;
    rbs_body_state a, b;
    (void)state;
    floor_plane(w, m);
    rest = ball(w, r, 1.0, 0, 0, r, 0, 0, 0, m);
    fly = ball(w, r, 1.0, 5.0, 0, 10.0, 0, 0, 0, m);
    fz = ball(z, r, 1.0, 5.0, 0, 10.0, 0, 0, 0, (rbs_material_id){0, 0});
    step_n(w, 999);
    step_n(z, 1000);
    CHECK_OK(rbs_world_step(w, &info));
    assert_int_equal(info.substeps, 1);
    ASSERT_NEAR(r - state_of(w, rest).position.z, sink, 1e-6 * sink);
    a = state_of(w, fly);
    b = state_of(z, fz);
    ASSERT_NEAR(a.position.z, 10.0 - 0.5 * G * T * T, 1e-12);
    assert_memory_equal(&a.position, &b.position, sizeof a.position);
    assert_memory_equal(&a.velocity, &b.velocity, sizeof a.velocity);
    rbs_world_destroy(w);
    rbs_world_destroy(z);
}

/* A falling heap of 27 balls with tol = 0.01: the rule reads only the state
 * at the frame's start, so a run resumed from a checkpoint continues bit for
 * bit; the settled heap takes fewer than 4 sub-steps a frame on average
 * over its last 200 frames, and no overlap (info.max_overlap, the deepest
 * of each frame) ever exceeds 1 % of the radius, the tolerance's scale. */
static void tolerance_heap_resumes_and_settles(void **state)
{
    enum { N = 27 };
    rbs_body_id ids[N];
    rbs_world *w = tolerant_world(N + 2, -G, 4, 0.01), *c = NULL;
    rbs_material_id m = material(w, "m", 0.5, 0.4, -1.0);
    static unsigned char buf[1 << 20];
    size_t n = 0;
    uint32_t late = 0;
    double deepest = 0.0;
    int i;
    (void)state;
    floor_plane(w, m);
    for (i = 0; i < N; ++i)
        ids[i] = ball(w, 0.05, 0.1, 0.1 * (i % 3) + 0.01 * (i % 2), 0.1 * ((i / 3) % 3), 0.06 + 0.1 * (i / 9),
                      0.2 * (i % 4), 0, 0, m);
    step_n(w, 300);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, sizeof buf, &n));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &c));
    for (i = 0; i < 1700; ++i) {
        rbs_step_info info;
        CHECK_OK(rbs_world_step(w, &info));
        if (info.max_overlap > deepest)
            deepest = info.max_overlap;
        if (i >= 1500)
            late += info.substeps;
    }
    step_n(c, 1700);
    for (i = 0; i < N; ++i) {
        rbs_body_state s1 = state_of(w, ids[i]), s2 = state_of(c, ids[i]);
        assert_memory_equal(&s1.position, &s2.position, sizeof s1.position);
        assert_memory_equal(&s1.velocity, &s2.velocity, sizeof s1.velocity);
    }
    assert_true(late < 4 * 200);
    assert_true(deepest < 0.01 * 0.05);
    rbs_world_destroy(c);
    rbs_world_destroy(w);
}

/* Friction in an impact that starts with slip: kinetic until the slip is
 * gone (Coulomb).  A solid ball (1 kg, r = 0.1 m, no spin) strikes a floor
 * at vz = -1 with slip vx0, e = 0.5, mu_s = 0.5, mu_k = 0.1, no gravity:
 * Jn = 1.5 N s, and stopping the slip needs m vx0 / 3.5 (K_tt = 3.5 / m).
 * Up to mu_k Jn = 0.15 N s (vx0 <= 0.525) the ball leaves rolling at 5/7
 * vx0; beyond, sliding at vx0 - 0.15 with wy = 0.15 r / I = 3.75 rad/s.
 * Both layouts (mutual gravity, which no body here feels, takes the
 * general one).  Before session 41 the gathered layout stuck up to a need
 * of about 0.31 Jn (vx' 21 % low at vx0 = 1.6): each sub-step's cone held
 * mu_s times its share of the impulse.  One impact's rounding: 1e-12. */
static void impact_with_slip_is_kinetic(void **state)
{
    const double r = 0.1, vx0[] = {0.4, 0.5, 0.6, 1.0, 1.6, 2.2, 2.8};
    size_t i;
    int general;
    (void)state;
    for (general = 0; general < 2; ++general) {
        for (i = 0; i < sizeof vx0 / sizeof vx0[0]; ++i) {
            rbs_world_def d;
            rbs_world *w = NULL;
            rbs_material_id m;
            rbs_body_id b;
            rbs_body_state s;
            double vx, wy;
            int k;
            rbs_world_def_init(&d);
            d.max_bodies = 4;
            d.dt = 1e-3;
            d.gravity.z = 0.0;
            d.restitution = 0.5;
            d.method = RBS_METHOD_SOFT;
            d.mutual_gravity = general;
            CHECK_OK(rbs_world_create(&d, &w));
            m = material(w, "m", 0.5, 0.1, 0.5);
            floor_plane(w, m);
            b = ball(w, r, 1.0, 0, 0, r + 0.0003, vx0[i], 0, -1.0, m);
            for (k = 0; k < 40; ++k)
                CHECK_OK(rbs_world_step(w, NULL));
            s = state_of(w, b);
            vx = vx0[i] / 3.5 <= 0.15 ? 5.0 / 7.0 * vx0[i] : vx0[i] - 0.15;
            wy = vx0[i] / 3.5 <= 0.15 ? vx / r : 0.15 * r / (0.4 * r * r);
            if (fabs(s.velocity.x - vx) > 1e-12 || fabs(s.angular_velocity.y - wy) > 1e-11 ||
                fabs(s.velocity.z - 0.5) > 1e-12)
                fail_msg("%s layout, vx0 %g: v (%.15g, %.15g), wy %.15g; exact (%.15g, 0.5), %.15g",
                         general ? "general" : "gathered", vx0[i], s.velocity.x, s.velocity.z,
                         s.angular_velocity.y, vx, wy);
            rbs_world_destroy(w);
        }
    }
}

/* A solid ball (r 0.1 m, 1 kg) rolling off the top of a fixed sphere (R =
 * 1 m) at v0 = 5 cm/s, mu_s 0.5, mu_k 0.2, e = 0: the scene of
 * test_contacts.c's ball_rolling_off_a_dome (exact: it slips at theta =
 * 0.730 rad, 1.74588 s, leaves at 1.83358 s, and at 2.134 s is at x =
 * 1.342861, z = -0.378298 m, omega_y = 20.71310 rad/s).  The contact's
 * normal was the frame's, fixed at detection, and its separation linear in
 * the displacements: the rows held the ball on the tangent plane of the
 * frame's start, off the dome by v^2 t^2 / (2 L), so each frame's first
 * sub-steps flew (the curve fell away faster than g cos(theta) h^2 / 2
 * once v^2 / L > g cos(theta) / 9) and the next carried their friction on
 * a normal impulse of the frame's right total but bunched late: the static
 * cone gave way at 0.60 rad, where rolling needs 0.56 of mu_s N, whatever
 * dt (x 1.3e-2, z 2.5e-2 m, omega_y -1.66 rad/s off at 0.1 and 0.01 ms;
 * with the curved separation alone, 0.711 rad and 4.9e-3 m, -0.33 rad/s).
 * A contact with a fixed sphere now takes the normal and separation of now
 * at each row (docs/methods.md, "soft").  Measured at dt = 0.1 ms: gathered 4.5e-4
 * m, 1.0e-3 rad/s (0.01 ms: 4.6e-5 m, 1e-4 rad/s), general 5.8e-5 m,
 * 3e-4 rad/s; bounds 1.5e-3 m and 5e-3 rad/s, first order in dt. */
static void ball_rolls_off_a_dome(void **state)
{
    const double R = 1.0, r = 0.1, v0 = 0.05;
    int general;
    (void)state;
    for (general = 0; general < 2; ++general) {
        rbs_world_def d;
        rbs_world *w = NULL;
        rbs_material_id m;
        rbs_body_id b;
        rbs_body_state s;
        rbs_world_def_init(&d);
        d.max_bodies = 4;
        d.dt = 1e-4;
        d.gravity.z = -G;
        d.restitution = 0.0;
        d.method = RBS_METHOD_SOFT;
        d.mutual_gravity = general; /* (the general layout; G 6.7e-11: nothing) */
        CHECK_OK(rbs_world_create(&d, &w));
        m = material(w, "m", 0.5, 0.2, 0.0);
        b = ball_on_a_dome(w, m, R, r, v0);
        step_n(w, 21340);
        s = state_of(w, b);
        print_message("%s: x %.6f, z %.6f m, wy %.5f rad/s\n", general ? "general" : "gathered", s.position.x,
                      s.position.z, s.angular_velocity.y);
        ASSERT_NEAR(s.position.x, 1.342861, 1.5e-3);
        ASSERT_NEAR(s.position.z, -0.378298, 1.5e-3);
        ASSERT_NEAR(s.angular_velocity.y, 20.71310, 5e-3);
        rbs_world_destroy(w);
    }
}

/* A ball spinning at 10 rad/s about the vertical, dropped 0.3 m onto a
 * floor (e = 0, spinning resistance mu_sp = 0.002 m): the landing is an
 * impact, which in the model takes friction only (docs/physics.md), and
 * then the spin decays at alpha = mu_sp m g / I = 4.905 rad/s^2, so
 * w(t) = 10 - alpha (t - t1), t1 = sqrt(2 h / g) -- euler, verlet, rk4 and
 * adaptive converge to it.  The soft step bounded its spinning row by the
 * landing's normal impulse too and took mu_sp m v1 / I = 1.21 rad/s off at
 * once, at every dt (session 46).  Tolerance: first order, alpha dt (a
 * frame's decay; measured 1.5e-3 rad/s at dt = 1 ms, 4.8e-5 at 0.01 ms).
 * The rolling case likewise (mu_r = 0.02, down a 20-degree incline onto
 * the floor, rolling on at 5/7 mu_r g less: its exact speed was 9.7e-3
 * m/s off) is covered by the same bound. */
static void spinning_ball_lands_keeping_its_spin(void **state)
{
    const double r = 0.1, h = 0.3, msp = 0.002, dt = 1e-3, I = 0.4 * r * r;
    const double t1 = sqrt(2.0 * h / G), alpha = msp * G / I;
    rbs_world *w = soft_world(4, dt, -G, 0.0, 3);
    rbs_material_id m;
    rbs_pair_def p;
    rbs_sphere_def sd;
    rbs_body_id b;
    rbs_body_state st;
    int n = (int)((t1 + 0.2) / dt);
    (void)state;
    CHECK_OK(rbs_world_add_material(w, "m", &m));
    rbs_pair_def_init(&p);
    p.a = p.b = m;
    p.static_friction = p.kinetic_friction = 0.5;
    p.restitution = 0.0;
    p.spinning = msp;
    CHECK_OK(rbs_world_set_pair(w, &p));
    floor_plane(w, m);
    rbs_sphere_def_init(&sd);
    sd.radius = r;
    sd.mass = 1.0;
    sd.position.z = r + h;
    sd.angular_velocity.z = 10.0;
    sd.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &b));
    step_n(w, n);
    st = state_of(w, b);
    print_message("w_z %.9f rad/s, exact %.9f\n", st.angular_velocity.z, 10.0 - alpha * (n * dt - t1));
    ASSERT_NEAR(st.angular_velocity.z, 10.0 - alpha * (n * dt - t1), alpha * dt);
    rbs_world_destroy(w);

    /* e = 0.5: the bounces' impulses are no load either (the restitution
     * pass's, and what the last sub-step's impulse holds of the impact):
     * the spin decays only from t_inf = 3 t1, where the Zeno cascade ends
     * (t1 (1 + e) / (1 - e)), to w(2 s) = 10 - alpha (2 - t_inf).  Like
     * euler's, the cascade ends early by first order's loss at each bounce
     * (docs/physics.md): 0.016 rad/s low at dt = 0.1 ms, as euler's
     * (0.093 and 0.107 at 1 ms); tolerance 0.05.  Counting the last
     * sub-step's impulse as load, the first bounce took 0.96 rad/s. */
    w = soft_world(4, 1e-4, -G, 0.5, 3);
    CHECK_OK(rbs_world_add_material(w, "m", &m));
    p.restitution = 0.5;
    CHECK_OK(rbs_world_set_pair(w, &p));
    floor_plane(w, m);
    CHECK_OK(rbs_world_add_sphere(w, &sd, &b));
    step_n(w, 20000);
    st = state_of(w, b);
    print_message("e = 0.5: w_z %.9f rad/s, exact %.9f\n", st.angular_velocity.z, 10.0 - alpha * (2.0 - 3.0 * t1));
    ASSERT_NEAR(st.angular_velocity.z, 10.0 - alpha * (2.0 - 3.0 * t1), 0.05);
    rbs_world_destroy(w);
}

/* A frictionless 1 kg ball on three fixed balls of r = 0.05 m touching each
 * other (docs/methods.md, soft, after the wedges: not blocked).  Up to twice
 * their radius it rests to rounding (|v| < 1e-13 m/s over the 21st second,
 * measured 2e-14) and at 1 radius each contact sinks by its load
 * L = m g / (3 cos phi) over m omega^2 beyond the slop (m_eff = m: the
 * others are fixed), to 1e-6 of it (measured 5e-7: the normals tilt as it
 * sinks).  From about 2.2 times the one-row-at-a-time passes lag on the
 * mode that sinks into all three and it rattles for good: at 3 times,
 * 0.64-0.72 mm/s (a probe; this test); the test holds it under 2 mm/s,
 * so that a change making it worse is seen (one that settles it passes). */
static void ball_on_three_fixed_balls(void **state)
{
    static const double ratios[3] = {1.0, 2.0, 3.0};
    const double R = 0.05, dt = 1e-3, d = 2.0 * R / sqrt(3.0);
    int i, k;
    (void)state;
    for (i = 0; i < 3; ++i) {
        rbs_world *w = soft_world(4, dt, -G, 0.0, 3);
        rbs_material_id m = material(w, "m", 0.0, 0.0, 0.0);
        const double r = ratios[i] * R, z = sqrt((R + r) * (R + r) - d * d);
        double vmax = 0.0, om = soft_omega(dt, 3), load = G / (3.0 * z / (R + r));
        rbs_body_id b;
        rbs_body_state s;
        for (k = 0; k < 3; ++k) {
            rbs_sphere_def f;
            rbs_sphere_def_init(&f);
            f.radius = R;
            f.fixed = 1;
            f.material = m;
            f.position.x = d * cos(2.0 * PI_ * k / 3.0);
            f.position.y = d * sin(2.0 * PI_ * k / 3.0);
            CHECK_OK(rbs_world_add_sphere(w, &f, NULL));
        }
        b = ball(w, r, 1.0, 0, 0, z, 0, 0, 0, m);
        step_n(w, 20000);
        s = state_of(w, b);
        for (k = 0; k < 1000; ++k) {
            double v;
            step_n(w, 1);
            s = state_of(w, b);
            v = sqrt(s.velocity.x * s.velocity.x + s.velocity.y * s.velocity.y + s.velocity.z * s.velocity.z);
            if (v > vmax)
                vmax = v;
        }
        print_message("ratio %g: largest speed over the 21st second %.3g m/s\n", ratios[i], vmax);
        if (i < 2) {
            assert_true(vmax < 1e-13);
        } else {
            /* (not promised to rest: bounded, so that worse is seen; a fix
             * that settles it passes too, and the docs are updated) */
            assert_true(vmax < 2e-3);
        }
        if (i == 0) {
            double sink = 1e-6 * R + load / (om * om), dx = s.position.x - d, dist;
            dist = sqrt(dx * dx + s.position.y * s.position.y + s.position.z * s.position.z);
            ASSERT_NEAR(R + r - dist, sink, 1e-6 * sink);
        }
        rbs_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(substeps_default_and_range),
        cmocka_unit_test(resting_ball_sinks_to_the_static_deflection),
        cmocka_unit_test(stack_sinks_by_its_loads),
        cmocka_unit_test(coarse_steps_still_hold_loads),
        cmocka_unit_test(heavy_on_light_settles_within_the_stated_ratios),
        cmocka_unit_test(tall_column_settles_and_holds_its_loads),
        cmocka_unit_test(flight_is_exact_in_both_layouts),
        cmocka_unit_test(head_on_impacts_follow_the_impact_law),
        cmocka_unit_test(oblique_sphere_impacts_follow_the_impact_law),
        cmocka_unit_test(oblique_sphere_impacts_with_friction_follow_the_impact_law),
        cmocka_unit_test(oblique_bounce_follows_the_impact_law),
        cmocka_unit_test(bouncing_ball_apexes),
        cmocka_unit_test(elastic_bounce_never_gains_energy),
        cmocka_unit_test(ball_in_a_narrow_wedge_settles),
        cmocka_unit_test(sliding_sphere_starts_rolling),
        cmocka_unit_test(incline_rolls_or_slides),
        cmocka_unit_test(rolling_resistance_decelerates),
        cmocka_unit_test(rolling_resistance_holds_a_ball_on_a_slope),
        cmocka_unit_test(fast_bodies_do_not_tunnel),
        cmocka_unit_test(ball_between_walls_or_fixed_spheres_stays_inside),
        cmocka_unit_test(ball_in_a_tilted_groove_stays_inside),
        cmocka_unit_test(spaced_cradle_passes_the_velocity_down_the_line),
        cmocka_unit_test(kicked_ball_stops_at_the_guard_depth),
        cmocka_unit_test(shot_into_a_grid_gains_no_energy),
        cmocka_unit_test(crowd_conserves_momentum),
        cmocka_unit_test(general_rows_rest),
        cmocka_unit_test(checkpoint_resumes_bit_for_bit),
        cmocka_unit_test(overflow_keeps_last_good_state),
        cmocka_unit_test(shared_increment_is_the_table),
        cmocka_unit_test(spin_overflow_keeps_last_good_state),
        cmocka_unit_test(layout_follows_changes),
        cmocka_unit_test(tolerance_default_and_range),
        cmocka_unit_test(tolerance_sets_the_substeps),
        cmocka_unit_test(tolerance_rests_on_one_substep_and_keeps_free_flight),
        cmocka_unit_test(tolerance_heap_resumes_and_settles),
        cmocka_unit_test(impact_with_slip_is_kinetic),
        cmocka_unit_test(ball_rolls_off_a_dome),
        cmocka_unit_test(spinning_ball_lands_keeping_its_spin),
        cmocka_unit_test(ball_on_three_fixed_balls),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
