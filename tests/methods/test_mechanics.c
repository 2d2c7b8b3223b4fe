/*
 * test_mechanics.c - textbook answers, run under every method.
 *
 * What test_contacts.c already checks under every method (head-on impacts,
 * the time and speed of a sliding ball's roll, inclines, bouncing apexes)
 * is not repeated; these scenes run under auto and each named method and
 * are compared with their exact answers from
 * rigid-body mechanics (Goldstein, Classical Mechanics, ch. 5; any text on
 * the impact of spheres, e.g. Goldsmith, Impact, 1960, ch. 2).  Each scene
 * prints its measured error beside its bound, so a run shows the margins.
 *
 * Bounds by method class (docs/methods.md), each derived, none measured:
 *  - a constant acceleration a over n steps of h: Euler (euler, selective,
 *    and soft's sub-steps) is exact in velocity and lags in position by
 *    a h t / 2 (x_n = a h^2 n (n + 1) / 2); verlet, rk4, adaptive and event
 *    are exact for a constant acceleration up to rounding;
 *  - an impulse is exact up to rounding (1e-12 relative), but it acts at
 *    the touch as the method locates it: the rollback methods to within
 *    dt / 2^30 in time (max_halvings, rbsim.h), event exactly, adaptive
 *    where the gap is within 1e-3 of the slop (methods.md, "adaptive"),
 *    soft within the frame (it does not roll back, and "may bounce a frame
 *    late": methods.md, "auto").  And all but soft may strike it up to
 *    the slop early: a pair touches at a gap within the slop
 *    (docs/physics.md), so a sub-step that ends with the gap in that band,
 *    not overlapping, is kept and the next one strikes the pair there, a
 *    path of up to slop |v| / vn before the touch (always so for an
 *    approach slower than the slop a sub-step; the scenes here cross the
 *    band within a sub-step with an overlap, and roll back, but for the
 *    slow head-on below).  A touch found a distance d along the
 *    path off tilts a sphere-sphere normal by at most d / (r1 + r2), which
 *    turns the outgoing velocity by 2 |v| d / (r1 + r2), and shifts the
 *    positions afterwards by |v| times the time error;
 *  - soft holds a resting contact sunk by the slop plus load / (m omega^2),
 *    omega = 2 pi / dt at 3 sub-steps (methods.md, "soft"), so its heights
 *    are checked against that sink instead of the touch.
 */
#include "methods_common.h"

static const double G = 9.81;

static const rbs_method all_methods[] = {RBS_METHOD_AUTO,  RBS_METHOD_EULER, RBS_METHOD_SELECTIVE,
                                         RBS_METHOD_EVENT, RBS_METHOD_VERLET, RBS_METHOD_RK4,
                                         RBS_METHOD_ADAPTIVE, RBS_METHOD_SOFT};

/* An incline rising along +x at the angle th (sn = sin th, cs = cos th)
 * through the origin: the normal (-sin, 0, cos), up the slope (cos, 0, sin). */
static void incline_plane(rbs_world *w, double sn, double cs, rbs_material_id mat)
{
    rbs_plane_def p;
    rbs_plane_def_init(&p);
    p.normal = (rbs_vec3){-sn, 0.0, cs};
    p.material = mat;
    CHECK_OK(rbs_world_add_plane(w, &p, NULL));
}
#define N_METHODS (sizeof all_methods / sizeof *all_methods)

/* A world for method m (room for 8 bodies). */
static rbs_world *mworld(rbs_method m, double dt, double gz, double e)
{
    rbs_world *w = make_world(8, dt, gz, e);
    CHECK_OK(rbs_world_set_method(w, m, 0.0));
    return w;
}

/* Steps n times; RBS_E_UNSUPPORTED (a scene outside a method's checked
 * scope, e.g. event) returns 1 and prints why. */
static int msteps(rbs_world *w, rbs_method m, int n)
{
    int k;
    for (k = 0; k < n; ++k) {
        rbs_status st = rbs_world_step(w, NULL);
        if (st == RBS_E_UNSUPPORTED) {
            print_message("  %-9s skipped: %s\n", rbs_method_name(m), rbs_world_last_error(w));
            return 1;
        }
        if (st != RBS_OK)
            fail_msg("%s: step %d: %s: %s", rbs_method_name(m), k, rbs_status_name(st), rbs_world_last_error(w));
    }
    return 0;
}

/* Euler's position lag per unit of a t (m per m/s): h / 2 for the method's
 * Euler step h -- dt for euler, selective and auto (euler below 64 moving
 * spheres), dt / 3 for soft's sub-steps -- and 0 for the methods exact for a
 * constant acceleration. */
static double euler_lag(rbs_method m, double dt)
{
    if (m == RBS_METHOD_AUTO || m == RBS_METHOD_EULER || m == RBS_METHOD_SELECTIVE)
        return dt / 2.0;
    return m == RBS_METHOD_SOFT ? dt / 6.0 : 0.0;
}

/* How far along its path (m) method m may place a touch approached at
 * speed v (m/s) with normal speed vn, at step dt and slop (absolute, m):
 * see the header. */
static double touch_error(rbs_method m, double v, double vn, double dt, double slop)
{
    switch (m) {
    case RBS_METHOD_EVENT:
        return 1e-12 * v * dt;
    case RBS_METHOD_ADAPTIVE:
        return 1e-3 * slop * v / vn;
    case RBS_METHOD_SOFT:
        return v * dt; /* "may bounce a frame late" (methods.md, "auto") */
    default:
        return v * dt / 1073741824.0; /* 2^30 */
    }
}

/* The soft method's sink under gravity g at step dt (its omega at the
 * default 3 sub-steps is 2 pi / dt), beyond the slop. */
static double soft_sink(double g, double dt)
{
    double omega = 2.0 * PI_ / dt;
    return g / (omega * omega);
}

static void report(rbs_method m, const char *what, double err, double bound)
{
    print_message("  %-9s %-34s error %.3g (bound %.3g)\n", rbs_method_name(m), what, err, bound);
    if (!(err <= bound))
        fail_msg("%s: %s: error %.17g beyond %.3g", rbs_method_name(m), what, err, bound);
}

/* ---- a sliding ball starts rolling ------------------------------------- */

/* A solid ball (r = 0.1 m) launched at v0 = 5 m/s along x with backspin w0
 * (angular velocity -w0 about y) on a floor with mu_s = mu_k = 0.3.
 * Kinetic friction mu g decelerates it and spins it forward at
 * 5 mu g / (2 r) until v = r w, at t1 = 2 (v0 + r w0) / (7 mu g); then it
 * rolls at (5 v0 - 2 r w0) / 7 and covers v0 t1 - mu g t1^2 / 2 while
 * sliding (12 v0^2 / (49 mu g) without spin).  Run 3 s, for w0 = 0, 10
 * and 200 rad/s: at 200 (r w0 = 4 v0) the ball stops while still slipping
 * and comes back at -15/7 m/s (t1 = 2.43 s) -- friction must act through
 * v = 0, where only the slip, not the speed, vanishes.
 * (test_contacts.c's sliding_then_rolling checks the time and speed
 * without spin; new here: the backspin and the distance.)
 * Bounds: velocity and spin 1e-12 relative (constant accelerations and one
 * stick impulse); distance: Euler's lag a t1 h / 2 (euler_lag) plus the
 * slip speed over the step containing t1 (mu g dt . dt). */
static void slide_case(rbs_method m, double w0)
{
    const double v0 = 5.0, mu = 0.3, r = 0.1, dt = 1e-3, T = 3.0;
    const double a = mu * G, t1 = 2.0 * (v0 + r * w0) / (7.0 * a);
    const double vf = (5.0 * v0 - 2.0 * r * w0) / 7.0;
    const double x_exact = v0 * t1 - 0.5 * a * t1 * t1 + vf * (T - t1);
    rbs_world *w = mworld(m, dt, -G, 0.5);
    rbs_material_id mat = material(w, "m", mu, mu, -1.0);
    rbs_sphere_def s;
    rbs_body_id b;
    rbs_body_state st;
    double xb;
    floor_plane(w, mat);
    rbs_sphere_def_init(&s);
    s.radius = r;
    s.mass = 1.0;
    s.position.z = r;
    s.velocity.x = v0;
    s.angular_velocity.y = -w0;
    s.material = mat;
    CHECK_OK(rbs_world_add_sphere(w, &s, &b));
    if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
        st = state_of(w, b);
        report(m, w0 == 0.0 ? "slide->roll: speed 5/7 v0" : "backspin: speed (5v0-2Rw0)/7", fabs(st.velocity.x - vf),
               1e-12 * v0);
        report(m, "  spin v / r", fabs(st.angular_velocity.y * r - vf), 1e-12 * v0);
        xb = a * dt * dt + a * t1 * euler_lag(m, dt);
        report(m, "  distance", fabs(st.position.x - x_exact), xb + 1e-12 * x_exact);
        /* (soft: sunk by the slop, 1e-6 r, plus g / omega^2; 1e-3 of it for its
         * iterations, methods.md "soft": to 5e-7 of it at 3 sub-steps) */
        if (m == RBS_METHOD_SOFT)
            report(m, "  height: sink slop + g/w^2", fabs(r - st.position.z - (1e-6 * r + soft_sink(G, dt))),
                   1e-3 * (1e-6 * r + soft_sink(G, dt)));
        else
            report(m, "  height", fabs(st.position.z - r), 1e-12);
    }
    rbs_world_destroy(w);
}

static void sliding_ball_rolls_at_five_sevenths(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        slide_case(all_methods[i], 0.0);
        slide_case(all_methods[i], 10.0);
        slide_case(all_methods[i], 200.0);
    }
}

/* ---- oblique impacts of free spheres ---------------------------------------- */

/* (Head-on impacts for mass ratios 1 to 1e9 are test_contacts.c's
 * momentum_in_impacts, every method.) */

/* Spheres A (m1 = 3 kg, r = 0.1 m) and B (m2 = 1 kg, r = 0.15 m), no gravity,
 * restitution e, meeting obliquely: A at the origin moving at u1, B at p2
 * moving at u2.  Exact: they touch at the first t with |p2 - p1 + (u2 - u1) t|
 * = 0.25 m; along the normal n there the 1D impact law gives
 *   v1n' = (m1 v1n + m2 v2n - m2 e (v1n - v2n)) / (m1 + m2)   (and B alike),
 * and the tangential components are kept (frictionless).  Bound 1e-12 of
 * the speeds (one impulse, rounding) plus the turn of the normal where the
 * method places the touch, and the positions after 1 s that touch error
 * plus the turned velocity's drift (the header): a touch a path d off,
 * d / vrel in time, moves each body afterwards by its velocity change
 * times that, at most (1 + e) d (the change along n is (1 + e) vn times
 * the other's share of the mass).  early (0 or 1) adds the
 * header's early touch at the slop to the touch error. */
static void impact_case(rbs_method m, double e, rbs_vec3 p2, rbs_vec3 u1, rbs_vec3 u2, int early, const char *what)
{
    const double m1 = 3.0, m2 = 1.0, r1 = 0.1, r2 = 0.15, T = 1.0, dt = 1e-3;
    double dp[3] = {p2.x, p2.y, p2.z}, du[3] = {u2.x - u1.x, u2.y - u1.y, u2.z - u1.z};
    double aa = 0, bb = 0, cc = -(r1 + r2) * (r1 + r2), tc, n[3], d = 0, v1n = 0, v2n = 0, w1n, w2n;
    double v1[3], v2[3], x1[3], x2[3], err_v = 0, err_x = 0, scale;
    rbs_world *w = mworld(m, dt, 0.0, e);
    rbs_body_id a, b;
    int k;
    for (k = 0; k < 3; ++k) {
        aa += du[k] * du[k];
        bb += 2.0 * dp[k] * du[k];
        cc += dp[k] * dp[k];
    }
    tc = (-bb - sqrt(bb * bb - 4.0 * aa * cc)) / (2.0 * aa);
    {
        double u1a[3] = {u1.x, u1.y, u1.z}, u2a[3] = {u2.x, u2.y, u2.z};
        for (k = 0; k < 3; ++k) {
            n[k] = dp[k] + du[k] * tc;
            d += n[k] * n[k];
        }
        d = sqrt(d);
        for (k = 0; k < 3; ++k) {
            n[k] /= d;
            v1n += u1a[k] * n[k];
            v2n += u2a[k] * n[k];
        }
        w1n = (m1 * v1n + m2 * v2n - m2 * e * (v1n - v2n)) / (m1 + m2);
        w2n = (m1 * v1n + m2 * v2n + m1 * e * (v1n - v2n)) / (m1 + m2);
        for (k = 0; k < 3; ++k) {
            v1[k] = u1a[k] + (w1n - v1n) * n[k];
            v2[k] = u2a[k] + (w2n - v2n) * n[k];
            x1[k] = u1a[k] * tc + v1[k] * (T - tc);
            x2[k] = dp[k] + u2a[k] * tc + v2[k] * (T - tc);
        }
    }
    a = ball(w, r1, m1, 0, 0, 0, u1.x, u1.y, u1.z, (rbs_material_id){0, 0});
    b = ball(w, r2, m2, p2.x, p2.y, p2.z, u2.x, u2.y, u2.z, (rbs_material_id){0, 0});
    if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
        rbs_body_state sa = state_of(w, a), sb = state_of(w, b);
        double ga[3] = {sa.velocity.x, sa.velocity.y, sa.velocity.z}, gb[3] = {sb.velocity.x, sb.velocity.y, sb.velocity.z};
        double pa[3] = {sa.position.x, sa.position.y, sa.position.z}, pb[3] = {sb.position.x, sb.position.y, sb.position.z};
        for (k = 0; k < 3; ++k) {
            err_v = fmax(err_v, fmax(fabs(ga[k] - v1[k]), fabs(gb[k] - v2[k])));
            err_x = fmax(err_x, fmax(fabs(pa[k] - x1[k]), fabs(pb[k] - x2[k])));
        }
        double vrel = sqrt(aa), vn = fabs(w1n - w2n) / (e > 0.0 ? e : 1.0), d, tilt;
        scale = sqrt(u1.x * u1.x + u1.y * u1.y + u1.z * u1.z) + sqrt(u2.x * u2.x + u2.y * u2.y + u2.z * u2.z);
        d = touch_error(m, vrel, vn, dt, 1e-6 * r1) + (early && m != RBS_METHOD_SOFT ? 1e-6 * r1 * vrel / vn : 0.0);
        /* (head-on -- the relative path along the line of centres -- the
         * touch's place cannot tilt the normal) */
        tilt = dp[1] * du[2] - dp[2] * du[1] == 0.0 && dp[2] * du[0] - dp[0] * du[2] == 0.0 &&
                       dp[0] * du[1] - dp[1] * du[0] == 0.0
                   ? 0.0
                   : 2.0 * scale * d / (r1 + r2);
        report(m, what, err_v, 1e-12 * scale + tilt);
        report(m, "  positions after 1 s", err_x, 1e-12 + (1.0 + e) * d + tilt * T);
    }
    rbs_world_destroy(w);
}

static void oblique_impacts_keep_the_tangents(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        impact_case(m, 1.0, (rbs_vec3){1.0, 0.2, 0.1}, (rbs_vec3){2.0, 0, 0}, (rbs_vec3){-1.0, 0, 0}, 0,
                    "oblique e = 1, tangents kept");
        impact_case(m, 0.7, (rbs_vec3){1.0, 0.13, -0.07}, (rbs_vec3){2.0, 0.1, 0.05}, (rbs_vec3){-1.0, 0.2, 0}, 0,
                    "oblique e = 0.7, tangents kept");
    }
}

/* Head-on along a line at extreme speeds, e = 0.5: A (3 kg) and B (1 kg)
 * closing at 2e-6 m/s from 5e-7 m apart (five slops: they touch at
 * 0.25 s) and at 2e6 m/s from 1000 m apart (2000 m a frame, 8000 of the
 * radii's sum: they touch at 5e-4 s, inside the first frame).  The 1-D
 * impact law scales with the speed, so v' is the same fraction of it:
 * v1' = 1/4 V, v2' = 5/4 V (V = 1e-6, 1e6).  No test ran an impact at
 * these speeds (test_contacts.c's slowest_approach_in_zero_gravity meets
 * a wall or an equal ball, tests/extremes' fast_balls 1000 m/s).  Bounds
 * as impact_case's, which scale with the speeds: the impulse's rounding
 * and the touch's place -- at 1e-6 m/s the pair closes 2e-9 m a frame,
 * under the slop (1e-7 m), so every method but soft strikes it at the
 * slop, 0.05 s early (the header), and the positions after 1 s are off
 * by the slop times the velocity change over the approach, 1.1e-7 m for
 * B: the early touch is in that bound; soft, and every method at 1e6 m/s,
 * take it exactly. */
static void head_on_impacts_at_extreme_speeds(void **state)
{
    const double V[2] = {1e-6, 1e6};
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i)
        for (c = 0; c < 2; ++c) {
            const double gap = c == 0 ? 5e-7 : 1000.0 - 0.25;
            char what[64];
            snprintf(what, sizeof what, "head-on at +-%g m/s, e = 0.5", V[c]);
            impact_case(all_methods[i], 0.5, (rbs_vec3){0.25 + gap, 0, 0}, (rbs_vec3){V[c], 0, 0},
                        (rbs_vec3){-V[c], 0, 0}, c == 0, what);
        }
}

/* ---- a ball off a fixed sphere ---------------------------------------------- */

/* No gravity, e = 1, frictionless: a 1 kg ball (r = 0.1 m) from
 * (-2, 0.5, 0.3) at (3, 0, 0) m/s meets a fixed sphere of radius 1 at the
 * origin when its centre is 1.1 m from the origin, and leaves reflected
 * about the contact normal n: v' = v - 2 (v.n) n.  Bounds as for the free
 * impacts (the header): rounding plus the turn of the normal at the touch
 * as the method places it. */
static void ball_reflects_off_a_fixed_sphere(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double R = 1.0, r = 0.1, T = 1.0, dt = 1e-3, px = -2.0, py = 0.5, pz = 0.3, v = 3.0;
        /* |p + v t x| = R + r along x: (px + v t)^2 = (R + r)^2 - py^2 - pz^2 */
        double cx = -sqrt((R + r) * (R + r) - py * py - pz * pz), tc = (cx - px) / v;
        double n[3] = {cx / (R + r), py / (R + r), pz / (R + r)}, vn = v * n[0];
        double vo[3] = {v - 2.0 * vn * n[0], -2.0 * vn * n[1], -2.0 * vn * n[2]};
        double xo[3] = {cx + vo[0] * (T - tc), py + vo[1] * (T - tc), pz + vo[2] * (T - tc)};
        rbs_world *w = mworld(m, dt, 0.0, 1.0);
        rbs_sphere_def d;
        rbs_body_id b;
        rbs_sphere_def_init(&d);
        d.radius = R;
        d.fixed = 1;
        CHECK_OK(rbs_world_add_sphere(w, &d, NULL));
        b = ball(w, r, 1.0, px, py, pz, v, 0, 0, (rbs_material_id){0, 0});
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state s = state_of(w, b);
            double ev = fmax(fabs(s.velocity.x - vo[0]), fmax(fabs(s.velocity.y - vo[1]), fabs(s.velocity.z - vo[2])));
            double ex = fmax(fabs(s.position.x - xo[0]), fmax(fabs(s.position.y - xo[1]), fabs(s.position.z - xo[2])));
            double dd = touch_error(m, v, fabs(vn), dt, 1e-6 * r);
            report(m, "reflection about the normal", ev, 1e-12 * v + 2.0 * v * dd / (R + r));
            report(m, "  position after 1 s", ex, 1e-12 + dd + 2.0 * v * dd / (R + r) * T);
        }
        rbs_world_destroy(w);
    }
}

/* ---- between two walls ------------------------------------------------------ */

/* No gravity, e = 1: a ball (r = 0.1 m) between walls at x = 0 and x = 1
 * moving at 3 m/s bounces with period 2 L / v, L = 0.8 m (the free path of
 * its centre), for 10.1 s (37.9 periods, 38 impacts).  Exact: speed 3 m/s
 * (a reversal is exact in floating point), position the sawtooth.  Bound
 * on position: the touch error (header) once per impact. */
static void ball_between_walls_keeps_its_period(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double r = 0.1, v = 3.0, L = 0.8, T = 10.1, dt = 1e-3;
        rbs_world *w = mworld(m, dt, 0.0, 1.0);
        rbs_plane_def p;
        rbs_body_id b;
        double s_path, xo, vo;
        rbs_plane_def_init(&p);
        p.normal = (rbs_vec3){1, 0, 0};
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        p.point = (rbs_vec3){1, 0, 0};
        p.normal = (rbs_vec3){-1, 0, 0};
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        b = ball(w, r, 1.0, 0.5, 0, 0, v, 0, 0, (rbs_material_id){0, 0});
        /* unfold: the centre moves along a line of length 2L per period */
        s_path = fmod(0.4 + v * T, 2.0 * L);
        xo = s_path <= L ? r + s_path : r + 2.0 * L - s_path;
        vo = s_path <= L ? v : -v;
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state s = state_of(w, b);
            /* one touch error per impact: 2 v T / L impacts */
            double n_impacts = ceil(v * T / L);
            report(m, "walls: velocity after 38 periods", fabs(s.velocity.x - vo), 1e-12);
            report(m, "  position", fabs(s.position.x - xo),
                   1e-12 + n_impacts * touch_error(m, v, v, dt, 1e-6 * r));
        }
        rbs_world_destroy(w);
    }
}

/* ---- a constant torque ------------------------------------------------------ */

/* A free solid sphere (m = 2 kg, R = 0.5 m, I = 2/5 m R^2 = 0.2 kg m^2), no
 * gravity, torque 0.3 N m about z for 1 s: w = tau t / I = 1.5 rad/s
 * (a constant angular acceleration: exact in every method up to rounding,
 * 1e-12), the angle tau t^2 / (2 I) = 0.75 rad within Euler's lag
 * alpha h t / 2 (rounding for the others), read from the quaternion. */
static void constant_torque_spins_up_linearly(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double mass = 2.0, R = 0.5, tau = 0.3, T = 1.0, dt = 1e-3, I = 0.4 * mass * R * R;
        rbs_world *w = mworld(m, dt, 0.0, 0.5);
        rbs_sphere_def d;
        rbs_body_id b;
        rbs_sphere_def_init(&d);
        d.radius = R;
        d.mass = mass;
        d.torque.z = tau;
        CHECK_OK(rbs_world_add_sphere(w, &d, &b));
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state s = state_of(w, b);
            double angle = 2.0 * atan2(s.orientation.z, s.orientation.w);
            report(m, "torque: w = tau t / I", fabs(s.angular_velocity.z - tau * T / I), 1e-12);
            report(m, "  w_x, w_y stay 0", fabs(s.angular_velocity.x) + fabs(s.angular_velocity.y), 0.0);
            report(m, "  angle tau t^2 / 2I", fabs(angle - tau * T * T / (2.0 * I)),
                   tau / I * T * euler_lag(m, dt) * (1.0 + 1e-9) + 1e-12);
        }
        rbs_world_destroy(w);
    }
}

/* ---- at rest far from the origin ----------------------------------------- */

/* A ball (r = 0.1 m) at rest on a floor through (1e6, 1e6, 1e6), 10 s, with
 * friction: it must stay where it is.  The positions are held to a few ulp
 * of 1e6 (ulp = 1.16e-10 m): the contact's gap is computed from coordinates
 * of that size, so its rounding is an ulp per operation.  Bound 8 ulp. */
static void ball_rests_far_from_the_origin(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double off = 1e6, r = 0.1, ulp = 1.1641532182693481e-10;
        rbs_world *w = mworld(m, 1e-3, -G, 0.5);
        rbs_material_id mat = material(w, "m", 0.5, 0.3, -1.0);
        rbs_plane_def p;
        rbs_body_id b;
        rbs_plane_def_init(&p);
        p.point = (rbs_vec3){off, off, off};
        p.material = mat;
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        b = ball(w, r, 1.0, off, off, off + r, 0, 0, 0, mat);
        if (msteps(w, m, 10000) == 0) {
            rbs_body_state s = state_of(w, b);
            double e = fmax(fabs(s.position.x - off), fmax(fabs(s.position.y - off), fabs(s.position.z - (off + r))));
            double speed = sqrt(s.velocity.x * s.velocity.x + s.velocity.y * s.velocity.y +
                                s.velocity.z * s.velocity.z);
            if (m == RBS_METHOD_SOFT) {
                /* soft: sunk by slop + g / omega^2 (as at the origin), and its
                 * push answers a gap error of an ulp at its bias rate
                 * omega / (2 zeta + h omega), zeta = 10, h = dt / 3
                 * (methods.md, "soft"): a reported speed up to that */
                double sink = 1e-6 * r + soft_sink(G, 1e-3), omega = 2.0 * PI_ / 1e-3;
                s.position.z += sink;
                e = fmax(fabs(s.position.x - off), fmax(fabs(s.position.y - off), fabs(s.position.z - (off + r))));
                report(m, "rest at 1e6 m: displacement - sink", e, 8.0 * ulp);
                report(m, "  speed", speed, 2.0 * ulp * omega / (20.0 + 1e-3 / 3.0 * omega));
            } else {
                report(m, "rest at 1e6 m: displacement", e, 8.0 * ulp);
                report(m, "  speed", speed, 0.0);
            }
        }
        rbs_world_destroy(w);
    }
}

/* ---- dropped far from the origin, it comes to rest ------------------------- */

/* A ball (r = 0.1 m, 1 kg) dropped from a gap of 0.1 m onto a floor
 * through (off, off, off), e = 0.5, mu_s = 0.5, mu_k = 0.4, at off = 1e7 m
 * and 1e9 m (coordinates there round in steps of s = 1.9e-9 and 1.2e-7 m;
 * the slop, 1e-7 m, is still above half a step up to 1.1e9 m, so no method
 * refuses: docs/physics.md, "coordinate rounding").  Its bounces end at
 * t_inf = 3 sqrt(2 h / g) = 0.43 s (Zeno, e = 1/2: test
 * bouncing_ball_comes_to_rest); from 1 s to 2 s it must be at rest, as at
 * the origin.  Measured over that second: the largest speed, exactly 0 (a
 * resting ball's speed is 0, and so is soft's here); the steps counted in
 * rbs_world_rounded_steps, 0 (nothing moves); the height above off + r,
 * within the slop plus one step s of rounding of the contact's gap (soft:
 * less its sink slop + g / omega^2, two steps for its push).  Before
 * session 52 euler, selective and auto rested 4.3e-8 m past the slop at
 * 1e9 m still falling at 4.3e-5 m/s (2.1e-7 m/s at 1e7 m), every frame one
 * of the rounded steps: the resting pass asked the contact to close a gap
 * that x + v h could not, as it rounds back to x. */
static void ball_dropped_far_from_the_origin_rests(void **state)
{
    const double offs[2] = {1e7, 1e9};
    size_t i;
    int c, k;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        for (c = 0; c < 2; ++c) {
            const double off = offs[c], r = 0.1, dt = 1e-3, slop = 1e-6 * r;
            const double s_off = ldexp(1.0, ilogb(off) - 52);
            const int soft = m == RBS_METHOD_SOFT;
            rbs_world *w = mworld(m, dt, -G, 0.5);
            rbs_material_id mat = material(w, "m", 0.5, 0.4, -1.0);
            rbs_plane_def p;
            rbs_body_id b;
            uint64_t rounded = 0;
            double speed = 0.0, height = 0.0;
            char what[64];
            rbs_plane_def_init(&p);
            p.point = (rbs_vec3){off, off, off};
            p.material = mat;
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            b = ball(w, r, 1.0, off, off, off + r + 0.1, 0, 0, 0, mat);
            if (msteps(w, m, 1000) != 0) {
                rbs_world_destroy(w);
                continue;
            }
            rounded = rbs_world_rounded_steps(w);
            for (k = 0; k < 1000; ++k) {
                rbs_body_state st;
                if (msteps(w, m, 1) != 0)
                    break;
                st = state_of(w, b);
                speed = fmax(speed, sqrt(st.velocity.x * st.velocity.x + st.velocity.y * st.velocity.y +
                                         st.velocity.z * st.velocity.z));
                height = fmax(height, fabs(st.position.z - (off + r) + (soft ? slop + soft_sink(G, dt) : 0.0)));
            }
            snprintf(what, sizeof what, "dropped at %g m: speed at rest", off);
            report(m, what, speed, 0.0);
            report(m, "  rounded steps at rest", (double)(rbs_world_rounded_steps(w) - rounded), 0.0);
            report(m, "  height over the floor", height, soft ? 2.0 * s_off + slop : slop + s_off);
            rbs_world_destroy(w);
        }
    }
}

/* ---- a small ball on a big one, dropped together ---------------------------- */

/* A big ball (M = 1 kg, R = 0.2 m) with a small one (m, r = 0.05 m) resting
 * on its top, dropped together from a gap h = 1 m onto a floor, e = 1
 * everywhere, frictionless.  Both reach the floor at v = sqrt(2 g h).  The
 * methods resolve simultaneous impacts pair by pair (docs/physics.md,
 * "Simultaneous impacts are resolved pair by pair"): the floor reverses
 * the big ball, which then meets the small one at 2 v, and the 1-D impact
 * law sends the small ball up at u_s = (3 M - m) / (M + m) v and the big
 * one at u_B = (M - 3 m) / (M + m) v (the textbook's "about 3 v" for
 * m << M; Kerwin, Am. J. Phys. 40, 1972).  That is the limit of a gap
 * between the balls going to zero, and what a real pair does when the big
 * ball's contact with the floor is much shorter than the balls' own.  A
 * simultaneous model (every contact aiming at e times its own approach
 * before the impact: the pair's is 0) would send both up together at v.
 * Measured: the launch speeds from the state 0.3 s after the impact,
 * |u| = sqrt(v^2 + 2 g (z - z_c)) (exact for free flight; z_c the centre
 * at the impact, the big ball's bounces on the floor keep it), for
 * m = 0.01 and 0.1 kg (u_B < 0: the big ball bounces off the floor again).
 * Bounds: the exact integrators (event, verlet, rk4, adaptive) reach the
 * floor within the slop, 1e-6 R, of the touch, which changes the speeds
 * by at most g slop / v and the launch height by the slop: 1e-6 relative.
 * Euler (euler, selective, auto) reaches the floor g dt / 2 slow (its fall
 * loses g^2 dt^2 of v^2 + 2 g z a step), which the impacts pass on times
 * (3 M - m) / (M + m) < 3, and loses g^2 dt t / (2 u) of u in flight t:
 * 1.5 g dt + g^2 dt t / (2 u).  soft is excluded from the law: it cannot
 * pass an impulse through touching bodies (docs/methods.md, soft, "What
 * it does not do"; it gives neither answer, 8.75 and 8.08 m/s); checked:
 * the small ball leaves no faster than the sequential law and no slower
 * than the simultaneous one, and the energy is not gained. */
static void stacked_drop_case(rbs_method m, double ms)
{
    const double M = 1.0, R = 0.2, r = 0.05, h = 1.0, dt = 1e-3, t_after = 0.3;
    const double v = sqrt(2.0 * G * h), us = (3.0 * M - ms) / (M + ms) * v, uB = fabs(M - 3.0 * ms) / (M + ms) * v;
    const double ti = sqrt(2.0 * h / G);
    rbs_world *w = mworld(m, dt, -G, 1.0);
    rbs_material_id mat = material(w, "m", 0.0, 0.0, 1.0);
    rbs_body_id big, small;
    rbs_energy e0, e1;
    floor_plane(w, mat);
    big = ball(w, R, M, 0, 0, R + h, 0, 0, 0, mat);
    small = ball(w, r, ms, 0, 0, 2.0 * R + r + h, 0, 0, 0, mat);
    CHECK_OK(rbs_world_energy(w, &e0));
    if (msteps(w, m, (int)((ti + t_after) / dt)) == 0) {
        rbs_body_state sb = state_of(w, big), ss = state_of(w, small);
        double ls = sqrt(ss.velocity.z * ss.velocity.z + 2.0 * G * (ss.position.z - (2.0 * R + r)));
        double lb = sqrt(sb.velocity.z * sb.velocity.z + 2.0 * G * (sb.position.z - R));
        CHECK_OK(rbs_world_energy(w, &e1));
        if (m == RBS_METHOD_SOFT) {
            report(m, "stacked drop: small <= sequential", fmax(ls - us, 0.0), 0.0);
            report(m, "  small >= simultaneous", fmax(v - ls, 0.0), 0.0);
            report(m, "  energy not gained (J)", fmax(e1.total - e0.total, 0.0), 1e-9 * e0.total);
        } else {
            double lag = euler_lag(m, dt) > 0.0;
            double bs = lag ? 1.5 * G * dt + G * G * dt * t_after / (2.0 * us) : 1e-6 * us;
            double bb = lag ? 1.5 * G * dt + G * G * dt * t_after / (2.0 * uB) : 1e-6 * us;
            report(m, "stacked drop: small (3M-m)/(M+m) v", fabs(ls - us), bs);
            report(m, "  big |M-3m|/(M+m) v", fabs(lb - uB), bb);
        }
    }
    rbs_world_destroy(w);
}

static void stacked_drop_follows_sequential_impacts(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        stacked_drop_case(all_methods[i], 0.01);
        stacked_drop_case(all_methods[i], 0.1);
    }
}

/* ---- Newton's cradles of 3 to 5, one and two strikers -------------------- */

/* The sequential-impact model (docs/physics.md: impacts "pair by pair,
 * swept until no contact approaches") on a line of n equal balls, the
 * first k at 1 m/s, the rest at rest, restitution e: every approaching
 * neighbour pair (j, j + 1), left to right, takes the 1-D impact of equal
 * masses, v_j, v_j+1 = c -+ e a / 2 (c their mean, a their approach), until
 * no pair approaches.  For e = 1/2, 3/4, 9/10 and 1, n <= 5, k <= 2 it
 * ends after at most four sweeps, and in the same state swept right to
 * left (checked in exact rational arithmetic; not so for small e -- 1/4
 * at n = 5, 1/8 at n = 4 -- where the sweeps go on for ever towards the
 * common speed k / n), so the order
 * the methods take the pairs in, or the order their impacts happen in
 * across gaps, does not matter.  For
 * n = 3, k = 1: (1 - e)/2, (1 + e)/2, 0, then (1 - e)/2, (1 - e^2)/4,
 * (1 + e)^2/4, then (1 - e)(3 + e^2)/8, (1 - e^2)(3 - e)/8, (1 + e)^2/4,
 * the end for e > 3 - 2 sqrt 2 (e = 1/2: 13/64, 15/64, 36/64).  With e
 * 1/2 or 3/4 every value is a dyadic fraction of at most 40 bits, so the
 * sums here are exact in doubles; e = 1 is the textbook cradle (k balls
 * leave at 1 m/s, the rest stay).  Writes v[0..n-1]. */
static void sequential_chain(int n, int k, double e, double *v)
{
    int j, sweep, any = 1;
    for (j = 0; j < n; ++j)
        v[j] = j < k ? 1.0 : 0.0;
    for (sweep = 0; sweep < 64 && any; ++sweep)
        for (any = 0, j = 0; j + 1 < n; ++j) {
            const double a = v[j] - v[j + 1], c = 0.5 * (v[j] + v[j + 1]);
            if (a > 0.0) {
                v[j] = c - 0.5 * e * a;
                v[j + 1] = c + 0.5 * e * a;
                any = 1;
            }
        }
    if (any)
        fail_msg("sequential_chain(%d, %d, %g) did not end", n, k, e);
}

/* n equal balls (1 kg, r = 0.1 m) in a line, no gravity, restitution e,
 * frictionless; the first k (1 or 2) move at 1 m/s into the others, all
 * touching or spaced 1e-4 m.  Exact: the sequential-impact model above
 * (for e = 1, Herrmann & Seitz, Am. J. Phys. 50, 1982; exact for the
 * spaced line, where the impacts are separate, and what the methods take
 * for touching balls).  (test_contacts.c's newtons_cradle checks five
 * touching balls with one striker at e = 1.)  Bound: the impulses'
 * rounding, 1e-12 m/s.  soft is excluded: it cannot pass an impulse down a
 * chain (docs/methods.md, soft, "What it does not do"; at e < 1 it is off
 * by up to 0.44 m/s touching, 0.19 spaced); checked for it: momentum kept
 * (no other force acts) and energy not gained. */
static void cradle_case(rbs_method m, int n, int k, double gap, double e)
{
    rbs_world *w = mworld(m, 1e-3, 0.0, e);
    rbs_body_id b[5];
    rbs_energy e0, e1;
    double v[5];
    int j;
    sequential_chain(n, k, e, v);
    for (j = 0; j < n; ++j)
        b[j] = ball(w, 0.1, 1.0, (0.2 + gap) * j - (j < k ? 0.3 : 0.0), 0, 0, j < k ? 1.0 : 0.0, 0, 0,
                    (rbs_material_id){0, 0});
    CHECK_OK(rbs_world_energy(w, &e0));
    if (msteps(w, m, 1000) == 0) {
        double err = 0.0, p = 0.0;
        char what[128];
        for (j = 0; j < n; ++j) {
            double vx = state_of(w, b[j]).velocity.x;
            err = fmax(err, fabs(vx - v[j]));
            p += vx;
        }
        CHECK_OK(rbs_world_energy(w, &e1));
        if (m == RBS_METHOD_SOFT) {
            snprintf(what, sizeof what, "cradle %d, %d in, gap %g, e %g: momentum", n, k, gap, e);
            report(m, what, fabs(p - k), 1e-12);
            report(m, "  energy not gained (J)", fmax(e1.total - e0.total, 0.0), 1e-12);
        } else {
            snprintf(what, sizeof what, "cradle %d, %d in, gap %g, e %g", n, k, gap, e);
            report(m, what, err, 1e-12);
        }
    }
    rbs_world_destroy(w);
}

static void cradles_pass_one_and_two_strikers(void **state)
{
    const double es[3] = {1.0, 0.75, 0.5};
    size_t i;
    int n;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        for (n = 3; n <= 5; ++n) {
            int k, e;
            for (e = 0; e < 3; ++e)
                for (k = 1; k <= 2; ++k) {
                    cradle_case(all_methods[i], n, k, 0.0, es[e]);
                    cradle_case(all_methods[i], n, k, 1e-4, es[e]);
                }
        }
    }
}

/* ---- a spinning projectile ----------------------------------------------- */

/* A ball (r = 0.1 m, 1 kg) launched from a frictionless floor (e = 0) at
 * (3, 0, 4) m/s spinning at (5, -7, 11) rad/s: no air, so the spin is
 * untouched (an isotropic torque-free sphere: every method turns it by the
 * exact rotation, and a frictionless contact has no lever on it), the
 * orientation turns by |w| t about w (1e-15 a step of rounding), the
 * apex is r + vz^2 / (2 g), the flight lasts T = 2 vz / g and the range is
 * 3 T; after landing (e = 0) it slides on at 3 m/s.  Bounds: spin 0
 * (nothing may change it); apex from the frames about it,
 * z + vz^2 / (2 g) (exact in free flight), exact for the constant
 * acceleration methods (1e-12), Euler's v^2 + 2 g z loses g^2 h^2 a step
 * h: g h t / 2 for the frame after the apex, t <= vz / g + dt; the landing found in the frame holding T, for Euler
 * up to one step h early (its flight is 2 vz / g - h: the lag g h t / 2
 * closes the gap early), soft up to a frame late ("may bounce a frame
 * late"); after landing, x = 3 t to rounding, z = r (soft: its sink). */
static void spinning_projectile_keeps_its_spin(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double r = 0.1, dt = 1e-3, vx = 3.0, vz = 4.0, T = 2.0 * vz / G, Tend = 1.2;
        const double om[3] = {5.0, -7.0, 11.0}, wn = sqrt(25.0 + 49.0 + 121.0);
        const double apex = r + vz * vz / (2.0 * G);
        rbs_world *w = mworld(m, dt, -G, 0.0);
        rbs_material_id mat = material(w, "m", 0.0, 0.0, 0.0);
        rbs_sphere_def d;
        rbs_body_id b;
        double prev_vz = vz, apex_err = -1.0, t_land = -1.0, werr = 0.0, qerr = 0.0;
        int k, n = (int)(Tend / dt + 0.5), failed = 0;
        floor_plane(w, mat);
        rbs_sphere_def_init(&d);
        d.radius = r;
        d.mass = 1.0;
        d.position.z = r;
        d.velocity.x = vx;
        d.velocity.z = vz;
        d.angular_velocity = (rbs_vec3){om[0], om[1], om[2]};
        d.material = mat;
        CHECK_OK(rbs_world_add_sphere(w, &d, &b));
        for (k = 1; k <= n && !failed; ++k) {
            rbs_body_state s;
            double t = k * dt, ang = wn * t, qe[4];
            failed = msteps(w, m, 1);
            if (failed)
                break;
            s = state_of(w, b);
            if (prev_vz > 0.0 && s.velocity.z <= 0.0)
                apex_err = fabs(s.position.z + s.velocity.z * s.velocity.z / (2.0 * G) - apex);
            if (t_land < 0.0 && prev_vz < 0.0 && s.velocity.z >= 0.0)
                t_land = t;
            prev_vz = s.velocity.z;
            werr = fmax(werr, fabs(s.angular_velocity.x - om[0]) + fabs(s.angular_velocity.y - om[1]) +
                                  fabs(s.angular_velocity.z - om[2]));
            qe[0] = cos(ang / 2.0);
            qe[1] = sin(ang / 2.0) * om[0] / wn;
            qe[2] = sin(ang / 2.0) * om[1] / wn;
            qe[3] = sin(ang / 2.0) * om[2] / wn;
            qerr = fmax(qerr, fmax(fmax(fabs(s.orientation.w - qe[0]), fabs(s.orientation.x - qe[1])),
                                   fmax(fabs(s.orientation.y - qe[2]), fabs(s.orientation.z - qe[3]))));
        }
        if (!failed) {
            rbs_body_state s = state_of(w, b);
            double lag = euler_lag(m, dt), early = lag > 0.0 ? 2.0 * lag : 0.0;
            double late = m == RBS_METHOD_SOFT ? 2.0 * dt : dt;
            report(m, "projectile: spin unchanged", werr, 0.0);
            report(m, "  orientation exp(w t)", qerr, 1e-15 * n);
            report(m, "  apex r + vz^2/2g", apex_err, G * lag * (vz / G + dt) + 1e-12);
            report(m, "  landing frame - T (early)", fmax(T - t_land, 0.0), early);
            report(m, "  landing frame - T (late)", fmax(t_land - T, 0.0), late);
            report(m, "  range: x = 3 t after landing", fabs(s.position.x - vx * Tend), 1e-12);
            report(m, "  at rest on the floor: |vz|", fabs(s.velocity.z), m == RBS_METHOD_SOFT ? 1e-9 : 0.0);
            report(m, "  height", fabs(s.position.z - r),
                   m == RBS_METHOD_SOFT ? 1e-6 * r + soft_sink(G, dt) * (1.0 + 1e-3) : 1e-6 * r);
        }
        rbs_world_destroy(w);
    }
}

/* ---- a bouncing ball comes to rest ------------------------------------------ */

/* A frictionless ball (r = 0.1 m) dropped from a gap h = 1 m, e = 0.5:
 * it meets the floor at t_1 = t0 = sqrt(2 h / g) and leaves the k-th
 * impact at e^k v0 (v0 = g t0), so t_(k+1) = t_k + 2 e^k t0, and the
 * bounces end at t_inf = t0 (1 + e) / (1 - e) (a geometric series; e.g.
 * Mirtich 1996, Zeno behaviour).  Measured: the first five impact times and
 * launch speeds, from the frame after each bounce (u = sqrt(v^2 + 2 g
 * (z - r)), t_k = t - (u - v) / g: exact for free flight); the time from
 * which it stays at rest; and after that, to 5 s: no bounce, no sinking or
 * rising beyond the slop, and no energy gained.
 * Bounds, each derived:
 *  - event, verlet, rk4, adaptive fly exactly; an impact is taken at a
 *    gap within the slop s = 1e-6 r, which moves its time by s / v_k and the
 *    launch height by s: every later time by up to 4 s / v_j summed over
 *    the impacts so far, the speeds by g s / v_k;
 *  - Euler (euler, selective, auto) steps h = dt: v^2 + 2 g z loses g^2 h^2
 *    a step, so the fall arrives g h / 2 slow and h / 2 early, and each
 *    flight from u lasts 2 u / g - h and arrives g h slower: the k-th
 *    launch speed is off by up to e g h (1/2 + 1/(1 - e)) and the k-th time
 *    by h / 2 + (k - 1) h (1 + 2 e (1/2 + 1/(1 - e)));
 *  - soft flies exactly (since session 37) but bounces at the frame's end
 *    from the surface, at e times the frame's start approach speed
 *    (docs/methods.md, soft: "up to e g dt slower than the impact speed",
 *    "up to a frame late"): the k-th launch speed is off by up to
 *    e (its approach's error + g dt), and the k-th impact up to dt late
 *    after a flight 2 / g times that error short;
 *  - the rest: approaches slower than g dt are resting, so the cascade is
 *    cut where e^(k-1) v0 < g dt, which leaves out 2 e v_k / (g (1 - e)) <
 *    2 e dt / (1 - e) of it; rest is seen at the frame's end (dt) and late
 *    by the sum of the per-flight errors above over the n flights with
 *    e^n v0 > g dt (n = 9 here);
 *  - at rest: speed within 1e-12 m/s (the resting pass's residual of the
 *    g dt it cancels every step: 2.9e-15 measured with euler) and the
 *    height r within the slop; after rest, no frame off it and the energy
 *    not above its value at rest beyond 1e-12 J.  soft's contact settles
 *    into its sink, slop + g / omega^2, at its bias rate beta = omega /
 *    (2 zeta + h omega) (zeta = 10, h = dt / 3; docs/methods.md, soft), so
 *    its rest is a speed within beta times the sink, the height between r
 *    and the sink (1e-3 beyond), and at 5 s speed 1e-12 and the sink to
 *    1e-3 of it, as the sliding ball's above. */
static void bouncing_ball_comes_to_rest(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const double r = 0.1, h = 1.0, e = 0.5, dt = 1e-3, T = 5.0, slop = 1e-6 * r;
        const double t0 = sqrt(2.0 * h / G), v0 = G * t0, t_inf = t0 * (1.0 + e) / (1.0 - e);
        const int soft = m == RBS_METHOD_SOFT, euler = euler_lag(m, dt) > 0.0 && !soft;
        const double z_rest = soft ? r - slop - soft_sink(G, dt) : r;
        const double per_flight = dt * (1.0 + 2.0 * e * (0.5 + 1.0 / (1.0 - e)));
        const double omega = 2.0 * PI_ / dt, beta = omega / (20.0 + dt / 3.0 * omega);
        rbs_world *w = mworld(m, dt, -G, e);
        rbs_material_id mat = material(w, "m", 0.0, 0.0, e);
        rbs_body_id b;
        rbs_energy en;
        double prev_vz = 0.0, t_k = t0, u_k = v0, t_rest = -1.0, e_rest = 0.0, sum_s = 0.0;
        double terr = 0.0, uerr = 0.0, tb = 0.0, ub = 0.0, after = 0.0, e_gain = 0.0;
        int k, n = (int)(T / dt + 0.5), bounce = 0, flights = 0, failed = 0, bounced_after = 0;
        floor_plane(w, mat);
        b = ball(w, r, 1.0, 0, 0, r + h, 0, 0, 0, mat);
        for (k = 1; k <= n; ++k) {
            rbs_body_state s;
            double t = k * dt;
            int at_rest;
            if ((failed = msteps(w, m, 1)) != 0)
                break;
            s = state_of(w, b);
            if (soft) /* settling into its sink at its bias rate */
                at_rest = fabs(s.velocity.z) <= beta * (r - z_rest) && s.position.z <= r + 1e-15 &&
                          s.position.z >= z_rest - 1e-3 * (r - z_rest);
            else
                at_rest = fabs(s.velocity.z) <= 1e-12 && fabs(s.position.z - z_rest) <= slop + 1e-15;
            if (prev_vz < 0.0 && s.velocity.z > 0.0) {
                flights++;
                if (t_rest >= 0.0)
                    bounced_after = 1;
                if (bounce < 5) {
                    double u = sqrt(s.velocity.z * s.velocity.z + 2.0 * G * (s.position.z - r));
                    double tk = t - (u - s.velocity.z) / G;
                    bounce++;
                    u_k *= e;
                    sum_s += 4.0 * slop / (u_k / e);
                    terr = fmax(terr, fabs(tk - t_k));
                    uerr = fmax(uerr, fabs(u - u_k));
                    if (euler) {
                        tb = dt / 2.0 + (bounce - 1) * per_flight;
                        ub = e * G * dt * (0.5 + 1.0 / (1.0 - e));
                    } else if (soft) {
                        /* the flight before was 2 ub / g short, then a frame late */
                        tb += dt + 2.0 * ub / G;
                        ub = e * (ub + G * dt);
                    } else {
                        tb = sum_s;
                        ub = G * slop / u_k;
                    }
                    t_k += 2.0 * u_k / G;
                }
            }
            if (at_rest && t_rest < 0.0) {
                t_rest = t;
                CHECK_OK(rbs_world_energy(w, &en));
                e_rest = en.total;
            } else if (!at_rest && t_rest >= 0.0) {
                /* a frame off rest after rest was reached: record how far */
                after = fmax(after, fabs(s.velocity.z) + fabs(s.position.z - z_rest));
            }
            if (t_rest >= 0.0) {
                CHECK_OK(rbs_world_energy(w, &en));
                e_gain = fmax(e_gain, en.total - e_rest);
            }
            prev_vz = s.velocity.z;
        }
        if (!failed) {
            double cut = 2.0 * e * dt / (1.0 - e);
            double late = euler ? dt / 2.0 + flights * per_flight : soft ? flights * dt : 0.0;
            report(m, "bounces: impact times t_k", terr, tb);
            report(m, "  launch speeds e^k v0", uerr, ub);
            report(m, "  rest from t_inf - early", fmax(t_inf - t_rest, 0.0), cut + late);
            report(m, "  rest from t_inf - late", fmax(t_rest - t_inf, 0.0), dt + late);
            report(m, "  no bounce after rest", bounced_after, 0.0);
            report(m, "  off rest after rest (m/s + m)", after, 0.0);
            report(m, "  energy gained after rest (J)", e_gain, 1e-12);
            if (soft) {
                rbs_body_state s = state_of(w, b);
                report(m, "  at 5 s: speed", fabs(s.velocity.z), 1e-12);
                report(m, "  at 5 s: sunk by slop + g/w^2", fabs(s.position.z - z_rest), 1e-3 * (r - z_rest));
            }
        }
        rbs_world_destroy(w);
    }
}

/* ---- a rolling ball into a wall ---------------------------------------------- */

/* No gravity: a ball (1 kg, R = 0.1 m, I = 2/5 m R^2) moving at (vx, 0, vz)
 * spinning at w_y = 20 rad/s (rolling, for vx = 2 m/s on a floor below it)
 * meets a wall x = 1 (normal -x), e = 0.5.  Impulse-momentum (Stronge,
 * Impact Mechanics, 2000, ch. 5; the core's law, docs/physics.md):
 * Jn = (1 + e) m vx; the contact point slips along z at u = vz - w_y R,
 * and a tangential impulse J along z changes it by J (1/m + R^2 / I) =
 * 3.5 J / m; the slip stops (J = -m u / 3.5) if that is within mu_k Jn,
 * else J = -sign(u) mu_k Jn (kinetic while slipping).  Then vx' = -e vx,
 * vz' = vz + J / m, w_y' = w_y - R J / I.  Cases: head-on (vz = 0) with
 * mu_k = 0.3 (sticks: 2/7 <= mu_k (1 + e)) and 0.1 (slides); and vz = 1
 * m/s (sticks).  Bounds: velocities one impulse's rounding, 1e-12 of the
 * speeds; positions after 1 s the touch error (the header) times the
 * change of velocity over the speed, plus 1e-12. */
static void rolling_ball_into_a_wall(void **state)
{
    const double R = 0.1, e = 0.5, wy0 = 20.0, dt = 1e-3, T = 1.0, I = 0.4 * R * R;
    const double cases[3][3] = {{2.0, 0.0, 0.3}, {2.0, 0.0, 0.1}, {2.0, 1.0, 0.3}};
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        for (c = 0; c < 3; ++c) {
            const double vx = cases[c][0], vz = cases[c][1], muk = cases[c][2];
            const double jn = (1.0 + e) * vx, u = vz - wy0 * R, stop = -u / 3.5;
            const double jt = fabs(stop) <= muk * jn ? stop : (u > 0.0 ? -muk * jn : muk * jn);
            const double vx1 = -e * vx, vz1 = vz + jt, wy1 = wy0 - R * jt / I, tc = (0.9 - 0.5) / vx;
            rbs_world *w = mworld(m, dt, 0.0, e);
            rbs_material_id mat = material(w, "m", muk * 1.5, muk, e);
            rbs_plane_def p;
            rbs_sphere_def d;
            rbs_body_id b;
            rbs_plane_def_init(&p);
            p.point.x = 1.0;
            p.normal = (rbs_vec3){-1.0, 0.0, 0.0};
            p.material = mat;
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            rbs_sphere_def_init(&d);
            d.radius = R;
            d.mass = 1.0;
            d.position.x = 0.5;
            d.velocity = (rbs_vec3){vx, 0.0, vz};
            d.angular_velocity.y = wy0;
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                rbs_body_state s = state_of(w, b);
                double sp0 = hypot(vx, vz), sp1 = hypot(vx1, vz1), dv = hypot(vx1 - vx, vz1 - vz);
                double dd = touch_error(m, sp0, vx, dt, 1e-6 * R);
                double ev = fmax(fmax(fabs(s.velocity.x - vx1), fabs(s.velocity.z - vz1)), fabs(s.velocity.y));
                double ex = fmax(fabs(s.position.x - (0.9 + vx1 * (T - tc))),
                                 fmax(fabs(s.position.z - (vz * tc + vz1 * (T - tc))), fabs(s.position.y)));
                char what[64];
                snprintf(what, sizeof what, "wall, vz %g, mu_k %g: %s", vz, muk, jt == stop ? "sticks" : "slides");
                report(m, what, ev, 1e-12 * (sp0 + sp1));
                report(m, "  spin w_y' = w_y - R J / I", fabs(s.angular_velocity.y - wy1) +
                       fabs(s.angular_velocity.x) + fabs(s.angular_velocity.z), 1e-12 * wy0);
                report(m, "  position after 1 s", ex, 1e-12 + dd * dv / sp0);
            }
            rbs_world_destroy(w);
        }
    }
}

/* The same ball rolling on a floor (mu_s = mu_k = mu, e = 0.5 for both
 * planes) under gravity at 2 m/s into the wall, touching it at
 * tc = 0.2003 s: the wall's friction lifts it (vz' = J / m > 0), so the
 * floor's contact opens in the impact and takes no impulse, and the
 * answer is the wall's alone: vx' = -e v, w_y' = w_y - R J / I, and
 * vz = J / m - g (t - tc) in the frame after.  mu = 0.3 sticks
 * (J = 2/7 m v), 0.1 slides (J = mu (1 + e) m v).  Bounds: vx and w_y an
 * impulse's rounding, 1e-12 of v; vz that plus g times the touch's time
 * error (touch_error / v; soft's frame late is in t - tc already: it
 * bounces at the frame's end, so 1e-12 as well -- measured exact).
 * selective takes the frame's Euler step first and strikes with velocities
 * that carry the gravity of the frame's part after the touch, which the
 * floor no longer supports: the slip the wall stops is off by up to g dt,
 * so J by m g dt / 3.5, w_y by R m g dt / (3.5 I) and vz by g dt (first
 * order: 0.049 rad/s of 5.71 at dt = 1 ms, 4.9e-3 at 0.1 ms, 4.9e-4 at
 * 0.01 ms, touching 0.3 dt into a frame; a probe of session 50).  soft
 * likewise: its impacts take the frame's velocities, gravity and the
 * floor's support included ("restitution at the frame's end",
 * docs/methods.md), and its w_y is off by the whole R m g dt / (3.5 I). */
static void rolling_ball_on_a_floor_into_a_wall(void **state)
{
    const double R = 0.1, e = 0.5, v = 2.0, dt = 1e-3, I = 0.4 * R * R, x0 = 0.9 - 0.2003 * v;
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        for (c = 0; c < 2; ++c) {
            const double mu = c == 0 ? 0.3 : 0.1, jn = (1.0 + e) * v, stop = v / 3.5;
            const double jt = stop <= mu * jn ? stop : mu * jn, tc = (0.9 - x0) / v;
            rbs_world *w = mworld(m, dt, -G, e);
            rbs_material_id mat = material(w, "m", mu, mu, e);
            rbs_plane_def p;
            rbs_sphere_def d;
            rbs_body_id b;
            rbs_body_state s;
            int k, failed = 0;
            floor_plane(w, mat);
            rbs_plane_def_init(&p);
            p.point.x = 1.0;
            p.normal = (rbs_vec3){-1.0, 0.0, 0.0};
            p.material = mat;
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            rbs_sphere_def_init(&d);
            d.radius = R;
            d.mass = 1.0;
            d.position = (rbs_vec3){x0, 0.0, R};
            d.velocity.x = v;
            d.angular_velocity.y = v / R;
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            for (k = 1; k <= 400 && !failed; ++k) {
                failed = msteps(w, m, 1);
                s = state_of(w, b);
                if (s.velocity.x < 0.0)
                    break;
            }
            if (!failed) {
                const double tau = k * dt - tc, terr = touch_error(m, v, v, dt, 1e-6 * R) / v;
                const double sel = m == RBS_METHOD_SELECTIVE || m == RBS_METHOD_SOFT ? 1.0 : 0.0;
                report(m, mu == 0.3 ? "wall, on a floor: sticks" : "wall, on a floor: slides",
                       fabs(s.velocity.x + e * v), 1e-12 * v);
                report(m, "  vz = J/m - g (t - tc)", fabs(s.velocity.z - (jt - G * tau)),
                       1e-12 * v + G * terr + sel * G * dt);
                report(m, "  w_y' = v/R - R J / I", fabs(s.angular_velocity.y - (v / R - R * jt / I)),
                       1e-12 * v / R + sel * R * G * dt / (3.5 * I));
            }
            rbs_world_destroy(w);
        }
    }
}

/* ---- sliding up an incline, rolling back --------------------------------- */

/* A ball (r = 0.1 m, 1 kg) launched without spin at v0 = 3 m/s up a
 * 20-degree incline, mu_s = mu_k = 0.2 (tan th = 0.364 <= 3.5 mu: it can
 * roll).  It slides up, friction down the slope: a = -g (sin th + mu cos th),
 * spin growing at 5 mu g cos th / (2 r), until v = r w at t1 = v0 /
 * (g sin th + 7/2 mu g cos th); then it rolls up at -5/7 g sin th, stops at
 * t2 and rolls back down (static friction, the same 2/7 m g sin th, holds
 * through v = 0).  Its angular momentum about the contact line, m r v +
 * I w, changes only by gravity's torque, -m g r sin th, whatever friction
 * does, so once rolling v(T) = 5/7 (v0 - g sin th T) -- exact for every
 * method whatever step the switch falls in (bound 1e-12 of v0, the
 * constant accelerations' and the stick impulse's rounding).  Position:
 * the two parabolas; Euler's sum of end-of-step speeds lags by
 * h/2 (v(T) - v0) (euler_lag; measured 2.2259e-3 m of the bound's
 * 2.2307e-3 at dt = 1 ms) plus the kink's h^2 (a1 - a2); the switch found
 * within a step adds the slip over it, mu g cos th dt^2 (as the level
 * floor's, above).  soft: its speeds exact too (measured), the sink of its
 * contact, slop + g cos th / omega^2, under the height. */
static void sliding_up_an_incline_rolls_back(void **state)
{
    const double r = 0.1, v0 = 3.0, mu = 0.2, th = 20.0 * PI_ / 180.0, dt = 1e-3, T = 1.5;
    const double sn = sin(th), cs = cos(th), a1 = G * (sn + mu * cs), a2 = 5.0 / 7.0 * G * sn;
    const double t1 = v0 / (G * sn + 3.5 * mu * G * cs), v1 = v0 - a1 * t1;
    const double s_exact = v0 * t1 - a1 * t1 * t1 / 2.0 + v1 * (T - t1) - a2 * (T - t1) * (T - t1) / 2.0;
    const double vT = 5.0 / 7.0 * (v0 - G * sn * T);
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const int soft = m == RBS_METHOD_SOFT;
        rbs_world *w = mworld(m, dt, -G, 0.0);
        rbs_material_id mat = material(w, "m", mu, mu, 0.0);
        rbs_body_id b;
        incline_plane(w, sn, cs, mat);
        b = ball(w, r, 1.0, -r * sn, 0.0, r * cs, v0 * cs, 0.0, v0 * sn, mat);
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state st = state_of(w, b);
            double up = (st.position.x + r * sn) * cs + (st.position.z - r * cs) * sn;
            double normal = -(st.position.x + r * sn) * sn + (st.position.z - r * cs) * cs;
            double v_up = st.velocity.x * cs + st.velocity.z * sn, v_n = -st.velocity.x * sn + st.velocity.z * cs;
            double sink = soft ? 1e-6 * r + G * cs * dt * dt / (4.0 * PI_ * PI_) : 0.0;
            double xb = euler_lag(m, dt) * fabs(vT - v0) + (a1 - a2) * dt * dt + mu * G * cs * dt * dt + 1e-12;
            report(m, "up the incline: v(T) = 5/7 (v0 - g sin T)", fabs(v_up - vT) + fabs(v_n) + fabs(st.velocity.y),
                   1e-12 * v0);
            /* (rolling up the slope along +x turns about +y) */
            report(m, "  rolling: r w = v", fabs(r * st.angular_velocity.y - v_up), 1e-12 * v0);
            report(m, "  distance, two parabolas", fabs(up - s_exact), xb);
            report(m, "  height over the plane", fabs(normal + sink), soft ? 1e-9 : 1e-12);
        }
        rbs_world_destroy(w);
    }
}

/* ---- an incline at the rolling threshold ------------------------------------ */

/* soft's bound on the distance lost while a contact on an incline of th
 * (r, dt, 3 sub-steps, default slop) sinks to its fixed point with mu_s
 * above rolling's need but below mu_s* / ms: (N1 + N2) e1 (see
 * incline_at_the_rolling_threshold); rounding, 1e-12, when the solve holds. */
static double sink_slide(double r, double dt, double th, double mstar, double mus, double muk)
{
    const double h = dt / 3.0, hw = 2.0 * PI_ / 3.0, a = hw * (20.0 + hw), ms = a / (1.0 + a), is = 1.0 / (1.0 + a);
    const double gc = G * cos(th), slop = 1e-6 * r;
    const double e1 = (mstar - muk * ms) * gc * h * h;
    double n1, n2;
    if (mus * ms >= mstar)
        return 1e-12;
    n1 = ceil(slop / (is * gc * h * h));
    n2 = ceil(log((1.0 - mstar / mus) / is) / log(1.0 - is * hw * hw));
    return (n1 + n2) * e1;
}

/* A ball (r = 0.1 m, 1 kg) from rest on a 30-degree incline (normal
 * (-sin, 0, cos)): it rolls at a = 5/7 g sin th (spin a t / r) if
 * tan th <= 7/2 mu_s, else slides at g (sin th - mu_k cos th), spinning up
 * at 5 mu_k g cos th / (2 r) (Goldstein; Meriam & Kraige).  The threshold is
 * mu_s* = tan th / 3.5 = 0.16496; cases mu_s = 1.0001 mu_s* (rolls: friction
 * at 99.99 % of its static limit), 0.9999 mu_s* (slides), mu_k = 0.8 mu_s,
 * and mu_s = mu_k = 5 (rolls: a sphere never stays put on an incline,
 * however rough).  The same for a hollow ball (I = 2/3 m r^2; k = I /
 * (m r^2) in general): it rolls at a = g sin th / (1 + k) = 3/5 g sin th
 * if tan th <= (1 + k) / k mu_s = 5/2 mu_s, else slides, spinning up at
 * mu_k g cos th / (k r) = 3/2 mu_k g cos th / r; mu_s* = tan th / 2.5
 * (no test rolled a hollow ball down an incline; soft's bounds below take
 * its mu_s*, the sink and sliding the same).
 * (test_contacts.c's oblique_incline_closed_form checks
 * both regimes far from the threshold.)  Bounds as there: the speed and
 * spin after 1 s exact to 1e-11 (a constant acceleration); the distance
 * a T^2 / 2 plus each method's lag a T (euler_lag), to 1e-12; the height
 * 1e-12.
 * soft rolls and slides as the others do, from the same margin (session
 * 50: before, its relax rows over-relaxed this lone contact while it sank
 * into its spring, and a ball with mu_s up to 1.00095 mu_s* slid for good;
 * soft.h, RBS__SOFT_OVER), in its gathered layout and, with spinning
 * resistance 1e-3 m (no torque on a ball rolling straight down), in its
 * general one.  Its velocities and spin are as exact; its
 * distance is not while the contact sinks to its fixed point, slop +
 * g cos th / omega^2: there the solve's soft row carries less than the load
 * (ms L within the slop, L (ms + is x / x*) at x of the sink x* beyond it;
 * ms = a / (1 + a), is = 1 / (1 + a), a = h omega (2 zeta + h omega),
 * h omega = 2 pi / 3, zeta = 10: docs/methods.md, "soft"), so while that is
 * under the need mu_s* L / mu_s the solve's friction slides at mu_k, and the
 * position takes the solve's velocity for the sub-step before the relax
 * sticks again.  A sub-step then takes the ball further by at most
 * e1 = (mu_s* - mu_k ms) g cos th h^2; the slop takes N1 = slop /
 * (is g cos th h^2) sub-steps (the solve sinks it at is g cos th h), and the
 * spring N2 = ln((1 - mu_s* / mu_s) / is) / ln(1 - is (h omega)^2) more (x*
 * - x shrinks by that factor a sub-step), each rounded up: the distance's
 * bound (N1 + N2) e1, 2.06e-6 m (61 sub-steps; measured 1.91e-6; at
 * 1.001 mu_s* 1.28e-6, 38 sub-steps, measured 1.19e-6).  From
 * mu_s = mu_s* / ms (1.0216 mu_s*) the solve holds too and the distance is
 * exact (3e-14 at 1.022).  The sliding case's distance bound is mu_k times
 * the sink (oblique_incline_closed_form) within 1e-7, the heights the sink
 * to 1e-9.  (The measured values: a probe of session 50.)
 * height the sink to 1e-9. */
static void incline_at_the_rolling_threshold(void **state)
{
    const double r = 0.1, dt = 1e-3, th = PI_ / 6.0, sn = sin(th), cs = cos(th);
    const int steps = 1000;
    const double T = steps * dt;
    size_t i;
    int c, hollow;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const int soft = m == RBS_METHOD_SOFT;
        const double margin = 1e-4;
        for (hollow = 0; hollow < 2; ++hollow) {
            /* k = I / (m r^2): 2/5 solid, 2/3 hollow; rolling needs
             * mu_s >= tan th k / (1 + k) */
            const double k = hollow ? 2.0 / 3.0 : 0.4, mstar = tan(th) * k / (1.0 + k);
            const double mus[4] = {(1.0 + margin) * mstar, (1.0 - margin) * mstar, 5.0, (1.0 + margin) * mstar};
            const double muk[4] = {0.8 * mus[0], 0.8 * mus[1], 5.0, 0.8 * mus[3]};
            /* (soft also runs the solid ball's first case in its general
             * layout: spinning resistance, which a ball rolling straight
             * down never meets) */
            for (c = 0; c < (soft && !hollow ? 4 : 3); ++c) {
                const int rolls = mus[c] >= mstar;
                const double a = rolls ? G * sn / (1.0 + k) : G * (sn - muk[c] * cs);
                const double wdot = rolls ? a / r : muk[c] * G * cs / (k * r);
                const double sink = soft ? 1e-6 * r + G * cs * dt * dt / (4.0 * PI_ * PI_) : 0.0;
                rbs_world *w = mworld(m, dt, -G, 0.0);
                rbs_material_id mat = material(w, "m", mus[c], muk[c], 0.0);
                rbs_sphere_def d;
                rbs_body_id b;
                if (c == 3) {
                    rbs_pair_def pd;
                    rbs_pair_def_init(&pd);
                    pd.a = pd.b = mat;
                    pd.static_friction = mus[c];
                    pd.kinetic_friction = muk[c];
                    pd.restitution = 0.0;
                    pd.spinning = 1e-3;
                    CHECK_OK(rbs_world_set_pair(w, &pd));
                }
                incline_plane(w, sn, cs, mat);
                rbs_sphere_def_init(&d);
                d.radius = r;
                d.mass = 1.0;
                d.inertia_kind = hollow ? RBS_INERTIA_HOLLOW : RBS_INERTIA_SOLID;
                d.position = (rbs_vec3){-r * sn, 0.0, r * cs};
                d.material = mat;
                CHECK_OK(rbs_world_add_sphere(w, &d, &b));
                if (msteps(w, m, steps) == 0) {
                    rbs_body_state s = state_of(w, b);
                    /* down the slope d = (-cos, 0, -sin); the spin about n x d = (0, -1, 0) */
                    double along = -(s.position.x + r * sn) * cs - (s.position.z - r * cs) * sn;
                    double normal = -(s.position.x + r * sn) * sn + (s.position.z - r * cs) * cs;
                    double v_along = -s.velocity.x * cs - s.velocity.z * sn;
                    double v_normal = -s.velocity.x * sn + s.velocity.z * cs;
                    double x_exact = a * T * (T / 2.0 + euler_lag(m, dt));
                    double xb = !soft ? 1e-12
                                : rolls && c != 2 ? sink_slide(r, dt, th, mstar, mus[c], muk[c])
                                                  : 1e-7;
                    char what[64];
                    snprintf(what, sizeof what, "incline %s mu_s %.4f mu_s*: %s%s", hollow ? "hollow" : "solid",
                             mus[c] / mstar, rolls ? "rolls" : "slides", c == 3 ? " (general)" : "");
                    report(m, what, fabs(v_along - a * T) + fabs(v_normal) + fabs(s.velocity.y), 1e-11);
                    report(m, "  spin", fabs(-s.angular_velocity.y - wdot * T) + fabs(s.angular_velocity.x) +
                           fabs(s.angular_velocity.z), 1e-11 / r);
                    report(m, "  distance a T^2/2 + lag", fabs(along - x_exact), xb);
                    report(m, "  height over the plane", fabs(normal + sink), soft ? 1e-9 : 1e-12);
                }
                rbs_world_destroy(w);
            }
        }
    }
}

/* ---- a ball leaves a fixed sphere ------------------------------------------- */

/* A ball (m = 1 kg, r = 0.1 m; solid, and hollow rolling) released at rest
 * a hair off the top of a fixed sphere (R = 1 m): its centre at th0 = 0.01 rad from the vertical
 * on the circle of radius L = R + r.  While the contact holds,
 * m v^2 / L = m g cos th - N, energy gives v^2, and the ball leaves where
 * N = 0 (the particle on a hemisphere of any mechanics text, e.g. Kleppner
 * & Kolenkow, An Introduction to Mechanics, 1973, ch. 4; the rolling sphere
 * in Routh, Dynamics of a System of Rigid Bodies, elementary part):
 *   frictionless: v^2 = 2 g L (c0 - c), so c* = cos th* = 2/3 c0;
 *   rolling (v = r w, kinetic energy (1 + k) m v^2 / 2, k = I / (m r^2)):
 *   (1 + k) v^2 / 2 = g L (c0 - c), c* = 2 c0 / (3 + k) -- 10/17 c0 for a
 *   solid ball (k = 2/5), 6/11 c0 for a hollow one (k = 2/3) -- and it
 *   leaves at v*^2 = g L c* spinning at v* / r.
 * Rolling needs friction k / (1 + k) m g sin th over N = m g ((3 + k) c -
 * 2 c0) / (1 + k), mu_s >= k sin th / ((3 + k) c - 2 c0), unbounded as
 * N -> 0: with mu = 1e6 the ball slips only where c - c* < k sin th /
 * ((3 + k) mu) (9.5e-8 solid, 1.5e-7 hollow), far inside the bounds below.
 * Measured: cos th at the end of the last frame with a normal impulse
 * (rbs_step_info.resting counts the contacts whose impulse is > 0); that
 * the ball leaves once (no frame without an impulse before that one); and
 * in the flight after it, which keeps both: frictionless, the horizontal
 * speed v* c* = sqrt(g L) c*^(3/2); rolling, the spin v* / r.
 * Bounds, first order in dt for every method (a contact's sub-steps are
 * first order, docs/physics.md: "all five converge at first order"), in
 * units of the frame's turn at the departure, e = s* v* dt / L
 * (s* = sin th*):
 *  - the true departure lies within the frame after the last impulse: e;
 *  - semi-implicit Euler's positions lag its velocities by half a step
 *    along the path, so N = 0 is met up to e / 2 off;
 *  - its energy, by its modified energy H + (h / 2) p . grad V (Hairer,
 *    Lubich & Wanner, Geometric Numerical Integration, 2006, ch. IX), is
 *    off by at most (h / 2) m g v* s*, which moves c* by e / 3;
 * 2 e in all.  The flight checks take what that moves: rolling,
 * v*^2 = 2 g L (c0 - c) / (1 + k), so |dv*| <= g L dc / ((1 + k) v*);
 * frictionless, v* c* = sqrt(2 g L (c0 - c)) c is stationary at c* (its
 * horizontal force N sin th vanishes there), so it is off by the energy's
 * g dt s* c* / 2 plus the second order, half its second derivative in c
 * times dc^2.
 * dt = 1 and 0.1 ms; soft at 0.1 ms only: at 1 ms its rows keep the
 * frame's tangent plane once the gap a frame comes in with is past the
 * slop (docs/methods.md, "A contact with a fixed sphere turns"), and the
 * ball, held on one frame of two or three from th = 0.72 rad (rolling;
 * N = 0.4 m g there), hops off early: at th = 0.82 rad frictionless (exact
 * 0.84) and 0.93 rolling (0.94), 1.1e-3 and 8.2e-3 m/s too fast in flight
 * (a probe of session 51).  At 0.1 ms soft leaves where the others do, but
 * its contact takes energy out while the ball slides over the sphere
 * (6.9e-4 J of 10.8 by the departure, growing with the speed; 7.3e-3 J at
 * 1 ms: first order), so its flight speed is checked one way only: not
 * faster than v* c* (no energy gained).  event refuses a ball held on a
 * sphere. */
static void leave_case(rbs_method m, int rolling, double dt)
{
    const double R = 1.0, r = 0.1, L = R + r, th0 = 0.01, c0 = cos(th0), k1 = rolling == 2 ? 5.0 / 3.0 : 1.4;
    const double cs = rolling ? 2.0 * c0 / (2.0 + k1) : 2.0 / 3.0 * c0, ss = sqrt(1.0 - cs * cs), vs = sqrt(G * L * cs);
    const double bc = 2.0 * ss * vs * dt / L;
    rbs_world *w = mworld(m, dt, -G, 0.0);
    rbs_material_id mat = rolling ? material(w, "m", 1e6, 1e6, 0.0) : (rbs_material_id){0, 0};
    rbs_sphere_def d;
    rbs_body_id b;
    rbs_body_state s;
    double c_last = -2.0;
    int k, n = (int)(4.0 / dt + 0.5), off = 0, hops = 0;
    char what[64];
    memset(&s, 0, sizeof s); /* (GCC -O2 with the sanitizers cannot see that the loop sets it) */
    rbs_sphere_def_init(&d);
    d.radius = R;
    d.fixed = 1;
    d.material = mat;
    CHECK_OK(rbs_world_add_sphere(w, &d, NULL));
    rbs_sphere_def_init(&d);
    d.radius = r;
    d.inertia_kind = rolling == 2 ? RBS_INERTIA_HOLLOW : RBS_INERTIA_SOLID;
    d.position = (rbs_vec3){L * sin(th0), 0.0, L * c0};
    d.material = mat;
    CHECK_OK(rbs_world_add_sphere(w, &d, &b));
    for (k = 0; k < n; ++k) {
        rbs_step_info info;
        rbs_status st = rbs_world_step(w, &info);
        if (st == RBS_E_UNSUPPORTED) {
            print_message("  %-9s skipped: %s\n", rbs_method_name(m), rbs_world_last_error(w));
            rbs_world_destroy(w);
            return;
        }
        if (st != RBS_OK)
            fail_msg("%s: step %d: %s: %s", rbs_method_name(m), k, rbs_status_name(st), rbs_world_last_error(w));
        s = state_of(w, b);
        if (info.resting > 0) {
            hops += off;
            off = 0;
            c_last = s.position.z / sqrt(s.position.x * s.position.x + s.position.z * s.position.z);
        } else if (c_last > -2.0) {
            off = 1;
            if (s.position.z < 0.0)
                break; /* below the sphere's centre: in flight for good */
        }
    }
    if (k == n)
        fail_msg("%s: the ball did not leave the sphere in %g s", rbs_method_name(m), n * dt);
    snprintf(what, sizeof what, "leaves a sphere %s, dt %g: cos",
             rolling == 2 ? "hollow, rolling" : rolling ? "rolling" : "frictionless", dt);
    report(m, what, fabs(c_last - cs), bc);
    report(m, "  leaves once: hops before", hops, 0.0);
    if (rolling) {
        report(m, "  flight: spin r w = v*", fabs(s.angular_velocity.y * r - vs), G * L * bc / (k1 * vs));
    } else {
        const double f2 = 1.0 / sqrt(c0 - cs) + cs / (4.0 * pow(c0 - cs, 1.5));
        const double second = 0.5 * f2 * sqrt(2.0 * G * L) * bc * bc;
        if (m == RBS_METHOD_SOFT)
            report(m, "  flight: v_x <= v* c* (no gain)", fmax(s.velocity.x - vs * cs, 0.0), second + 1e-12);
        else
            report(m, "  flight: v_x = v* c*", fabs(s.velocity.x - vs * cs), G * dt * ss * cs / 2.0 + second);
    }
    rbs_world_destroy(w);
}

static void ball_leaves_a_fixed_sphere(void **state)
{
    size_t i;
    int rolling;
    (void)state;
    for (i = 0; i < N_METHODS; ++i)
        for (rolling = 0; rolling < 3; ++rolling) {
            if (all_methods[i] != RBS_METHOD_SOFT)
                leave_case(all_methods[i], rolling, 1e-3);
            leave_case(all_methods[i], rolling, 1e-4);
        }
}

/* ---- a rolling ball strikes a resting one ------------------------------------ */

/* Billiards (r = 0.05 m, m = 0.17 kg): a cue ball rolling at v = 1 m/s along
 * x (spin v / r about y) strikes an equal object ball at rest, e = 1 and no
 * friction between the balls, mu = 0.2 (static = kinetic) with the cloth,
 * at a cut angle a: the line of centres at the touch, n = (cos a, sin a, 0),
 * is a off the cue ball's path (impact parameter 2 r sin a).  Exact
 * (Coriolis, Theorie mathematique des effets du jeu de billard, 1835;
 * D. G. Alciatore, The Illustrated Principles of Pool and Billiards, 2004):
 *  - the impact (no friction between the balls; the cloth's normal, across
 *    the impulse, takes none, so neither does its friction) swaps the
 *    normal components: the object ball leaves at v cos a n without spin,
 *    the cue ball keeps v_t = v sin a (sin a, -cos a) and its spin;
 *  - each then slips on the cloth, the object ball at its velocity, the
 *    cue ball at v_t - (v, 0) = -v cos a n.  Kinetic friction mu m g
 *    against the slip is a constant force whose slip falls at 7/2 mu g along
 *    a fixed direction (a centred solid sphere), so both roll from
 *    t1 = 2 v cos a / (7 mu g) after the touch (head-on: 2 v / (7 mu g));
 *  - the angular momentum about the contact point is kept while sliding,
 *    so they roll on at 5/7 v cos a n (object) and 5/7 v_t + 2/7 (v, 0)
 *    (cue): head-on (a = 0) the striker stops, keeps its spin v / r and
 *    rolls on at 2/7 v, the struck ball at 5/7 v; a cut turns the cue
 *    ball off its line by atan(sin a cos a / (sin^2 a + 2/5)), 33.7 degrees
 *    at a half-ball hit (a = 30: the "30-degree rule").
 * Cases a = 0, 30 and 60 degrees, the touch at tc = 0.1003 s, run to 1 s.
 * Bounds:
 *  - velocities: the impulses' rounding, 1e-12 v (they do not depend on
 *    when the slides end), plus the normal's tilt where the method places
 *    the touch, 2 v d / (2 r) (d = touch_error, as impact_case); soft:
 *    mu g dt more (its impact and the cloth's
 *    friction share the frame's passes, docs/physics.md: "a cue ball ...
 *    1.00065 times too hard");
 *  - the first frame in which each ball rolls again: the one holding
 *    tc + t1, or for selective and soft up to a frame later (selective
 *    strikes after the frame's Euler step, so the struck balls miss the
 *    cloth's friction for the rest of that frame -- measured: a frame late
 *    at 1 ms, on time at 0.1 ms; soft may strike a frame late);
 *  - positions: Euler's lag of the slide, mu g t1 euler_lag, the slide
 *    on past t1 to the frame's end, mu g dt^2, the touch error (header);
 *    selective its missed friction, mu g dt (t1 + dt); soft a frame late,
 *    v dt, and its velocity error over the run, mu g dt T. */
static void cue_case(rbs_method m, double a_deg)
{
    const double r = 0.05, mass = 0.17, v = 1.0, mu = 0.2, dt = 1e-3, T = 1.0, tc = 0.1003;
    const double a = a_deg * PI_ / 180.0, ca = cos(a), sa = sin(a), amu = mu * G, t1 = 2.0 * v * ca / (7.0 * amu);
    const int soft = m == RBS_METHOD_SOFT, sel = m == RBS_METHOD_SELECTIVE;
    /* after the impact (0) and rolling (1); object o, cue c; friction
     * along -n on o, +n on c */
    const double vo0[2] = {v * ca * ca, v * ca * sa}, vc0[2] = {v * sa * sa, -v * sa * ca};
    const double vo1[2] = {5.0 / 7.0 * vo0[0], 5.0 / 7.0 * vo0[1]};
    const double vc1[2] = {vc0[0] + 2.0 / 7.0 * v * ca * ca, vc0[1] + 2.0 / 7.0 * v * ca * sa};
    const double pc[2] = {-2.0 * r * ca, -2.0 * r * sa}, n[2] = {ca, sa};
    double xo[2], xc[2];
    rbs_world *w = mworld(m, dt, -G, 1.0);
    rbs_material_id cloth, bm;
    rbs_pair_def p;
    rbs_plane_def pl;
    rbs_sphere_def d;
    rbs_body_id ob, cb;
    double t_roll[2] = {-1.0, -1.0};
    int slipped[2] = {0, 0}, k, j, failed = 0;
    for (j = 0; j < 2; ++j) {
        xo[j] = vo0[j] * t1 - 0.5 * amu * n[j] * t1 * t1 + vo1[j] * (T - tc - t1);
        xc[j] = pc[j] + vc0[j] * t1 + 0.5 * amu * n[j] * t1 * t1 + vc1[j] * (T - tc - t1);
    }
    CHECK_OK(rbs_world_add_material(w, "cloth", &cloth));
    CHECK_OK(rbs_world_add_material(w, "ball", &bm));
    rbs_pair_def_init(&p);
    p.a = cloth;
    p.b = bm;
    p.static_friction = p.kinetic_friction = mu;
    p.restitution = 0.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    p.a = bm;
    p.static_friction = p.kinetic_friction = 0.0;
    p.restitution = 1.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    rbs_plane_def_init(&pl);
    pl.material = cloth;
    CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
    rbs_sphere_def_init(&d);
    d.radius = r;
    d.mass = mass;
    d.position = (rbs_vec3){pc[0] - v * tc, pc[1], r};
    d.velocity.x = v;
    d.angular_velocity.y = v / r;
    d.material = bm;
    CHECK_OK(rbs_world_add_sphere(w, &d, &cb));
    ob = ball(w, r, mass, 0.0, 0.0, r, 0, 0, 0, bm);
    for (k = 1; k <= (int)(T / dt + 0.5) && !failed; ++k) {
        failed = msteps(w, m, 1);
        for (j = 0; j < 2 && !failed; ++j) {
            rbs_body_state s = state_of(w, j == 0 ? ob : cb);
            /* the contact point's slip: v + w x (-r z) */
            double slip = hypot(s.velocity.x - r * s.angular_velocity.y, s.velocity.y + r * s.angular_velocity.x);
            if (slip > 1e-6 * v)
                slipped[j] = 1;
            else if (slipped[j] && t_roll[j] < 0.0 && slip <= 1e-12 * v)
                t_roll[j] = k * dt;
        }
    }
    if (!failed) {
        rbs_body_state so = state_of(w, ob), sc = state_of(w, cb);
        const double late = (sel || soft ? 2.0 : 1.0) * dt, dd = touch_error(m, v, v * ca, dt, 1e-6 * r);
        const double xb = amu * t1 * euler_lag(m, dt) + amu * dt * dt + dd + (sel ? amu * dt * (t1 + dt) : 0.0) +
                          (soft ? v * dt + amu * dt * T : 0.0) + 1e-12;
        const double bv = 1e-12 * v + 2.0 * v * dd / (2.0 * r) + (soft ? amu * dt : 0.0);
        char what[64];
        snprintf(what, sizeof what, "cut %g deg: object rolls at 5/7 v cos a n", a_deg);
        report(m, what, fmax(fabs(so.velocity.x - vo1[0]), fabs(so.velocity.y - vo1[1])), bv);
        report(m, "  cue at 5/7 v_t + 2/7 v", fmax(fabs(sc.velocity.x - vc1[0]), fabs(sc.velocity.y - vc1[1])), bv);
        report(m, "  object rolls from tc + t1: frames late", t_roll[0] - (tc + t1), late);
        report(m, "  (early)", fmax(tc + t1 - t_roll[0], 0.0), 0.0);
        report(m, "  cue rolls from tc + t1: frames late", t_roll[1] - (tc + t1), late);
        report(m, "  (early)", fmax(tc + t1 - t_roll[1], 0.0), 0.0);
        report(m, "  object's position", fmax(fabs(so.position.x - xo[0]), fabs(so.position.y - xo[1])), xb);
        report(m, "  cue's position", fmax(fabs(sc.position.x - xc[0]), fabs(sc.position.y - xc[1])), xb);
    }
    rbs_world_destroy(w);
}

static void rolling_ball_strikes_a_resting_one(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        cue_case(all_methods[i], 0.0);
        cue_case(all_methods[i], 30.0);
        cue_case(all_methods[i], 60.0);
    }
}

/* ---- equal masses leave at right angles ------------------------------------- */

/* No gravity, frictionless, e = 1: a ball (m = 1 kg, r = 0.1 m) at v = 2 m/s
 * along x strikes an equal ball at rest with impact parameter b = 2 r sin a.
 * At the touch the line of centres n = (cos a, sin a) is a off the path; the
 * impulse along n swaps the normal components: the target leaves along n
 * at v cos a, the striker along the tangent at v sin a, at right angles
 * (momentum v = v1 + v2 and energy v^2 = v1^2 + v2^2 give v1 . v2 = 0 for
 * any normal: Marion & Thornton, Classical Dynamics of Particles and
 * Systems, ch. 9, elastic collisions in the laboratory system).  a = 10, 45,
 * 80 and 89 degrees.  Bounds: the right angle (the cosine between the
 * velocities), rounding, 1e-12 -- it holds whatever normal the method
 * takes; the velocities, rounding plus the normal's tilt where the method
 * places the touch, 2 v d / (2 r) with d = touch_error at the normal
 * approach v cos a (as impact_case). */
static void equal_masses_leave_at_right_angles(void **state)
{
    const double r = 0.1, v = 2.0, dt = 1e-3, degs[4] = {10.0, 45.0, 80.0, 89.0};
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i)
        for (c = 0; c < 4; ++c) {
            rbs_method m = all_methods[i];
            const double a = degs[c] * PI_ / 180.0, ca = cos(a), sa = sin(a);
            rbs_world *w = mworld(m, dt, 0.0, 1.0);
            rbs_body_id s1, s2;
            s1 = ball(w, r, 1.0, -0.5, 0.0, 0.0, v, 0, 0, (rbs_material_id){0, 0});
            s2 = ball(w, r, 1.0, 0.0, 2.0 * r * sa, 0.0, 0, 0, 0, (rbs_material_id){0, 0});
            if (msteps(w, m, 500) == 0) {
                rbs_body_state a1 = state_of(w, s1), a2 = state_of(w, s2);
                /* exact: the target along n = (ca, sa) at v ca; the striker v - that */
                const double t2[2] = {v * ca * ca, v * ca * sa}, t1[2] = {v - t2[0], -t2[1]};
                const double q1 = hypot(a1.velocity.x, a1.velocity.y), q2 = hypot(a2.velocity.x, a2.velocity.y);
                const double dd = touch_error(m, v, v * ca, dt, 1e-6 * r);
                char what[64];
                snprintf(what, sizeof what, "equal masses, a = %g deg: cos(angle)", degs[c]);
                report(m, what, fabs(a1.velocity.x * a2.velocity.x + a1.velocity.y * a2.velocity.y) / (q1 * q2), 1e-12);
                report(m, "  speeds v sin a, v cos a", fmax(fabs(q1 - v * sa), fabs(q2 - v * ca)),
                       1e-12 * v + 2.0 * v * dd / (2.0 * r));
                report(m, "  velocities", fmax(fmax(fabs(a1.velocity.x - t1[0]), fabs(a1.velocity.y - t1[1])),
                                               fmax(fabs(a2.velocity.x - t2[0]), fabs(a2.velocity.y - t2[1]))),
                       1e-12 * v + 2.0 * v * dd / (2.0 * r));
            }
            rbs_world_destroy(w);
        }
}

/* ---- a spinning ball bounces ----------------------------------------------- */

/* A solid ball (m = 1 kg, r = 0.1 m, I = 2/5 m r^2) dropped from a gap
 * h = 0.2 m, spinning, onto a floor with e = 0.5, mu_s = 0.9, mu_k = 0.2.
 * It meets the floor at vn = sqrt(2 g h), its contact point slipping at
 * u = (vx - r wy, vy + r wx); Jn = (1 + e) m vn.  Coulomb's law through the
 * impact (Stronge, Impact Mechanics, 2000, ch. 5; Brach, Mechanical Impact
 * Dynamics, 1991): while the point slips, kinetic friction mu_k dJn
 * against the slip, whose direction stays fixed for a centred sphere of
 * isotropic inertia (K_tt = 3.5 / m times the identity); the tangential
 * impulse that stops the slip is m |u| / 3.5.  So if m |u| / 3.5 <=
 * mu_k Jn the slip stops within the impact and the ball leaves rolling
 * (it sticks: Jt = -m u / 3.5; static friction then has nothing to hold),
 * otherwise it slides throughout, Jt = -mu_k Jn u / |u|; mu_s does not
 * enter, as docs/physics.md ("Collisions") claims: a contact that comes in
 * slipping more than mu_k Jn can stop takes mu = mu_k.  Then
 * v_t' = v_t + Jt / m, w' = w + (r / I) (Jt_y, -Jt_x, 0), vz' = e vn.
 * Cases (vx, vy, wx, wy): backspin -40 rad/s (slides, and leaves backwards
 * at -0.594 m/s), -10 (sticks: rolls back at 2/7 r w), -25 (needs more
 * than mu_k Jn but less than mu_s Jn: slides), a diagonal slip (0, 0.5,
 * 15, -20: slides along u) and a rolling ball (1, 0, 0, 10: no slip, no
 * friction).  Measured at 0.35 s, in the flight after the bounce (which
 * keeps the horizontal velocity and the spin; the launch speed is
 * sqrt(vz^2 + 2 g (z - r))).  Bounds: sticking and rolling, rounding,
 * 1e-12; sliding, mu_k (1 + e) times the error of the approach speed:
 * event 0 (rounding); verlet, rk4 and adaptive touch within the slop s of
 * the floor, g s / vn; Euler (euler, selective, auto), whose fall keeps
 * v^2 + 2 g z less g^2 h^2 a step h, meets it at v^2 = 2 g h - g^2 (t_n dt
 * + x^2) (t_n <= vn / g the frames before, x <= dt the sub-step that
 * reaches it: about g dt / 2 slow); soft's impact takes the frame's
 * velocities, up to g dt ("restitution at the frame's end",
 * docs/methods.md).  The spin's bound is r / I times the velocity's.  The
 * launch speed e vn: the slop's height, g s / u, plus e times that error
 * -- for Euler, whose flight then loses g^2 dt^2 of u^2 a frame, u less
 * sqrt((u - e dvn)^2 - n g^2 dt^2) over the n frames after the impact. */
static void spinning_ball_bounces_by_coulomb(void **state)
{
    const double r = 0.1, h = 0.2, e = 0.5, mus = 0.9, muk = 0.2, I = 0.4 * r * r, dt = 1e-3, T = 0.35;
    const double cs[5][4] = {{0, 0, 0, -40}, {0, 0, 0, -10}, {0, 0, 0, -25}, {0, 0.5, 15, -20}, {1, 0, 0, 10}};
    const double vn = sqrt(2.0 * G * h), jn = (1.0 + e) * vn, ti = vn / G, slop = 1e-6 * r, u1 = e * vn;
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i)
        for (c = 0; c < 5; ++c) {
            rbs_method m = all_methods[i];
            const int euler = euler_lag(m, dt) == dt / 2.0, soft = m == RBS_METHOD_SOFT;
            const double ux = cs[c][0] - r * cs[c][3], uy = cs[c][1] + r * cs[c][2], un = hypot(ux, uy);
            const double stop = un / 3.5, sticks = stop <= muk * jn, jt = sticks ? stop : muk * jn;
            const double jx = un > 0.0 ? -jt * ux / un : 0.0, jy = un > 0.0 ? -jt * uy / un : 0.0;
            const double v1[2] = {cs[c][0] + jx, cs[c][1] + jy}, w1[2] = {cs[c][2] + r / I * jy, cs[c][3] - r / I * jx};
            const double dvn = m == RBS_METHOD_EVENT ? 0.0
                               : euler ? vn - sqrt(vn * vn - G * G * (ti * dt + dt * dt))
                               : soft  ? G * dt
                                       : G * slop / vn;
            const double nf = ceil((T - ti) / dt) + 1.0, ul = u1 - e * dvn;
            const double bv = 1e-12 + (sticks || un == 0.0 ? 0.0 : muk * (1.0 + e) * dvn);
            const double bu = 1e-12 + G * slop / u1 + (euler ? u1 - sqrt(ul * ul - nf * G * G * dt * dt) : e * dvn);
            rbs_world *w = mworld(m, dt, -G, e);
            rbs_material_id mat = material(w, "m", mus, muk, e);
            rbs_sphere_def d;
            rbs_body_id b;
            floor_plane(w, mat);
            rbs_sphere_def_init(&d);
            d.radius = r;
            d.mass = 1.0;
            d.position.z = r + h;
            d.velocity = (rbs_vec3){cs[c][0], cs[c][1], 0.0};
            d.angular_velocity = (rbs_vec3){cs[c][2], cs[c][3], 0.0};
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                rbs_body_state s = state_of(w, b);
                char what[64];
                snprintf(what, sizeof what, "spin (%g, %g) on a floor: %s", cs[c][2], cs[c][3],
                         un == 0.0 ? "rolls" : sticks ? "sticks" : "slides");
                report(m, what, fmax(fabs(s.velocity.x - v1[0]), fabs(s.velocity.y - v1[1])), bv);
                report(m, "  spin w + (r / I) z x Jt", fmax(fmax(fabs(s.angular_velocity.x - w1[0]),
                                                                  fabs(s.angular_velocity.y - w1[1])),
                                                             fabs(s.angular_velocity.z)),
                       r / I * bv);
                report(m, "  launch speed e vn",
                       fabs(sqrt(s.velocity.z * s.velocity.z + 2.0 * G * (s.position.z - r)) - u1), bu);
            }
            rbs_world_destroy(w);
        }
}

/* ---- rolling across an incline, spinning about its normal ------------------ */

/* A ball (r = 0.1 m, 1 kg) on a 20-degree incline (normal n = (-sin, 0,
 * cos), mu = 0.5) launched across the slope (along y) at v0 = 1.5 m/s,
 * rolling (w = n x v / r), and spinning at wn = 30 rad/s about n.  Exact
 * (a sphere on a rough inclined plane: Routh, Dynamics of a System of Rigid
 * Bodies, advanced part): the friction F at the contact point, lever -r n,
 * has no moment about n, so wn stays; rolling, v = r w x n, with
 * I dw/dt = -r n x F gives F = -2/7 m g_t (g_t gravity along the plane),
 * so the centre moves as a projectile under 5/7 g sin th down the slope,
 * a parabola, whatever wn (for a sphere the spin about the normal does not
 * couple).  It needs 2/7 g sin th <= mu g cos th: tan th <= 3.5 mu.  After
 * T = 1 s: v = (5/7 g sin th T down the slope, v0 across),
 * w = n x v / r + wn n, the distance down 5/14 g sin th T^2 plus each
 * method's lag (euler_lag), across v0 T.  Bounds: velocities and spins
 * 1e-11 (constant accelerations: rounding), positions 1e-12 beyond the lag
 * (soft: its sink, slop + g cos th / omega^2, under the height, to 1e-9). */
static void rolling_across_an_incline_with_normal_spin(void **state)
{
    const double r = 0.1, th = 20.0 * PI_ / 180.0, v0 = 1.5, wn = 30.0, mu = 0.5, dt = 1e-3, T = 1.0;
    const double sn = sin(th), cs = cos(th), a = 5.0 / 7.0 * G * sn;
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const int soft = m == RBS_METHOD_SOFT;
        rbs_world *w = mworld(m, dt, -G, 0.0);
        rbs_material_id mat = material(w, "m", mu, mu, 0.0);
        rbs_sphere_def d;
        rbs_body_id b;
        incline_plane(w, sn, cs, mat);
        rbs_sphere_def_init(&d);
        d.radius = r;
        d.mass = 1.0;
        d.position = (rbs_vec3){-r * sn, 0.0, r * cs};
        d.velocity.y = v0;
        /* n x (0, v0, 0) / r = v0 / r (-cos, 0, -sin), plus wn n */
        d.angular_velocity = (rbs_vec3){-cs * v0 / r - wn * sn, 0.0, -sn * v0 / r + wn * cs};
        d.material = mat;
        CHECK_OK(rbs_world_add_sphere(w, &d, &b));
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state s = state_of(w, b);
            /* down the slope dn = (-cos, 0, -sin); n x dn = (0, -1, 0) */
            const double along = -(s.position.x + r * sn) * cs - (s.position.z - r * cs) * sn;
            const double normal = -(s.position.x + r * sn) * sn + (s.position.z - r * cs) * cs;
            const double v_al = -s.velocity.x * cs - s.velocity.z * sn, v_n = -s.velocity.x * sn + s.velocity.z * cs;
            const double w_n = -s.angular_velocity.x * sn + s.angular_velocity.z * cs;
            const double wx = -cs * v0 / r - wn * sn, wy = -a * T / r, wz = -sn * v0 / r + wn * cs;
            const double sink = soft ? 1e-6 * r + G * cs * dt * dt / (4.0 * PI_ * PI_) : 0.0;
            report(m, "across an incline: v = (5/7 g sin T, v0)",
                   fabs(v_al - a * T) + fabs(s.velocity.y - v0) + fabs(v_n), 1e-11);
            report(m, "  spin about n kept", fabs(w_n - wn), 1e-11 / r);
            report(m, "  rolling: w = n x v / r + wn n",
                   fabs(s.angular_velocity.x - wx) + fabs(s.angular_velocity.y - wy) + fabs(s.angular_velocity.z - wz),
                   1e-11 / r);
            report(m, "  down the slope a T^2/2 + lag", fabs(along - a * T * (T / 2.0 + euler_lag(m, dt))), 1e-12);
            report(m, "  across v0 T", fabs(s.position.y - v0 * T), 1e-12);
            report(m, "  height over the plane", fabs(normal + sink), soft ? 1e-9 : 1e-12);
        }
        rbs_world_destroy(w);
    }
}

/* ---- an oblique impact with friction between spinning spheres --------------- */

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* No gravity: a solid sphere 1 (m1 = 2 kg, r1 = 0.15 m) at v1 = (3, 0, 0)
 * m/s spinning at (0, 5, 20) rad/s meets sphere 2 (m2 = 0.5 kg, r2 =
 * 0.08 m) at rest at (1, 0.12, 0.05) m spinning at (-10, 0, 0) rad/s,
 * e = 0.8, mu_s = mu_k = mu.  At the touch (the first t with
 * |p2 - v1 t| = r1 + r2) the contact points, r1 n and -r2 n from the
 * centres (n from 1 to 2), move apart at u = v1 + w1 x r1 n - w2 x (-r2 n);
 * Jn = (1 + e) (u . n) / (1/m1 + 1/m2).  A tangential impulse P (on 1,
 * -P on 2) changes the tangential slip u_t by P (1/m1 + 1/m2 + r1^2 / I1 +
 * r2^2 / I2) = 3.5 (1/m1 + 1/m2) P (solid spheres, r^2 / I = 5 / (2 m)),
 * isotropic, so the slip keeps its direction (Stronge, Impact Mechanics,
 * 2000, ch. 5 -- the two-sphere case of spinning_ball_bounces_by_coulomb's
 * law): it stops (P = -u_t / K_t) if that is within mu Jn, else
 * P = -mu Jn u_t / |u_t|.  Then v1 += (P - Jn n) / m1, v2 -= (P - Jn n) /
 * m2, w1 += r1 n x P / I1, w2 += r2 n x P / I2 (the normal part has no
 * lever).  mu = 0.1 slides (the stop needs 0.243 N s of mu Jn = 0.178),
 * 0.3 and 0.6 stick.  Bounds after 1 s: rounding, 1e-12 of the scale
 * s = |v1| + |w1| r1 + |w2| r2 (the fastest contact-point speed), plus the
 * normal's tilt where the method places the touch, d / (r1 + r2)
 * (d = touch_error), which turns the normal and the tangential impulse by
 * at most 2 s d / (r1 + r2) (1 + mu); the spins 2.5 / r times that (an
 * impulse error m dv turns a sphere by r m dv / I). */
static void spinning_spheres_meet_with_friction(void **state)
{
    const double m1 = 2.0, r1 = 0.15, m2 = 0.5, r2 = 0.08, e = 0.8, dt = 1e-3, T = 1.0, mus[3] = {0.1, 0.3, 0.6};
    const double v1[3] = {3.0, 0.0, 0.0}, w1[3] = {0.0, 5.0, 20.0};
    const double p2[3] = {1.0, 0.12, 0.05}, w2[3] = {-10.0, 0.0, 0.0};
    const double I1 = 0.4 * m1 * r1 * r1, I2 = 0.4 * m2 * r2 * r2, L = r1 + r2, Kt = 3.5 * (1.0 / m1 + 1.0 / m2);
    const double scale = 3.0 + r1 * sqrt(425.0) + r2 * 10.0;
    /* the touch along x at 3 m/s: (p2x - 3 t)^2 + p2y^2 + p2z^2 = L^2 */
    const double tc = (p2[0] - sqrt(L * L - p2[1] * p2[1] - p2[2] * p2[2])) / 3.0;
    const double n[3] = {(p2[0] - 3.0 * tc) / L, p2[1] / L, p2[2] / L};
    double u[3], a1[3], a2[3], rn1[3], rn2[3], un = 0.0, ut[3], utn = 0.0;
    size_t i;
    int c, k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        rn1[k] = r1 * n[k];
        rn2[k] = -r2 * n[k];
    }
    cross3(w1, rn1, a1);
    cross3(w2, rn2, a2);
    for (k = 0; k < 3; ++k) {
        u[k] = v1[k] + a1[k] - a2[k];
        un += u[k] * n[k];
    }
    for (k = 0; k < 3; ++k) {
        ut[k] = u[k] - un * n[k];
        utn += ut[k] * ut[k];
    }
    utn = sqrt(utn);
    for (i = 0; i < N_METHODS; ++i)
        for (c = 0; c < 3; ++c) {
            rbs_method m = all_methods[i];
            const double mu = mus[c], jn = (1.0 + e) * un / (1.0 / m1 + 1.0 / m2);
            const int sticks = utn / Kt <= mu * jn;
            double P[3], nP[3], t1[3], t2[3], V1[3], V2[3], W1[3], W2[3];
            rbs_world *w = mworld(m, dt, 0.0, e);
            rbs_material_id mat = material(w, "m", mu, mu, e);
            rbs_sphere_def d;
            rbs_body_id a, b;
            for (k = 0; k < 3; ++k) {
                P[k] = -(sticks ? 1.0 / Kt : mu * jn / utn) * ut[k];
                nP[k] = -P[k];
            }
            cross3(rn1, P, t1);
            cross3(rn2, nP, t2);
            for (k = 0; k < 3; ++k) {
                V1[k] = v1[k] + (P[k] - jn * n[k]) / m1;
                V2[k] = -(P[k] - jn * n[k]) / m2;
                W1[k] = w1[k] + t1[k] / I1;
                W2[k] = w2[k] + t2[k] / I2;
            }
            rbs_sphere_def_init(&d);
            d.radius = r1;
            d.mass = m1;
            d.velocity = (rbs_vec3){v1[0], v1[1], v1[2]};
            d.angular_velocity = (rbs_vec3){w1[0], w1[1], w1[2]};
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &a));
            rbs_sphere_def_init(&d);
            d.radius = r2;
            d.mass = m2;
            d.position = (rbs_vec3){p2[0], p2[1], p2[2]};
            d.angular_velocity = (rbs_vec3){w2[0], w2[1], w2[2]};
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                rbs_body_state sa = state_of(w, a), sb = state_of(w, b);
                const double ga[3] = {sa.velocity.x, sa.velocity.y, sa.velocity.z};
                const double gb[3] = {sb.velocity.x, sb.velocity.y, sb.velocity.z};
                const double ha[3] = {sa.angular_velocity.x, sa.angular_velocity.y, sa.angular_velocity.z};
                const double hb[3] = {sb.angular_velocity.x, sb.angular_velocity.y, sb.angular_velocity.z};
                const double dd = touch_error(m, 3.0, un, dt, 1e-6 * r2);
                const double bv = 1e-12 * scale + 2.0 * scale * dd / L * (1.0 + mu);
                double ev = 0.0, ew1 = 0.0, ew2 = 0.0;
                char what[64];
                for (k = 0; k < 3; ++k) {
                    ev = fmax(ev, fmax(fabs(ga[k] - V1[k]), fabs(gb[k] - V2[k])));
                    ew1 = fmax(ew1, fabs(ha[k] - W1[k]));
                    ew2 = fmax(ew2, fabs(hb[k] - W2[k]));
                }
                snprintf(what, sizeof what, "spinning spheres, mu %g: %s", mu, sticks ? "sticks" : "slides");
                report(m, what, ev, bv);
                report(m, "  spin of 1", ew1, 2.5 / r1 * bv);
                report(m, "  spin of 2", ew2, 2.5 / r2 * bv);
            }
            rbs_world_destroy(w);
        }
}

/* ---- a sliding ball swerves ---------------------------------------------------- */

/* A solid ball (r = 0.1 m, 1 kg) launched on a floor (mu_s = mu_k = 0.3)
 * at v0 = (3, 0, 0) m/s spinning at w0 = (20, 10, 5) rad/s: its contact
 * point slips at s0 = (vx - r wy, vy + r wx) = (2, 2) m/s, across its
 * path.  Kinetic friction mu m g against the slip decelerates it at
 * mu g and spins it so that the slip falls at 7/2 mu g along a fixed
 * direction (a centred solid sphere), so the ball swerves on a parabola
 * under -mu g s0 / |s0| until it rolls at t1 = 2 |s0| / (7 mu g); the spin
 * about the normal has no lever and stays.  The angular momentum about the
 * contact point, I w + m r z x v, is kept (friction acts there, gravity and
 * the normal force through it), so it rolls on at
 * v1 = 5/7 v0 + 2/7 r (w0 x z) = (2.4286, -0.5714) m/s (Coriolis 1835;
 * the masse shot of billiards; the one-dimensional case is
 * sliding_ball_rolls_at_five_sevenths).  Bounds as there: velocity and
 * spin 1e-12 (constant accelerations, one stick impulse); the distance
 * after 2 s Euler's lag a t1 euler_lag plus the slip over the stick's
 * frame, a dt^2. */
static void sliding_ball_swerves(void **state)
{
    const double r = 0.1, mu = 0.3, dt = 1e-3, T = 2.0, v0 = 3.0, w0[3] = {20.0, 10.0, 5.0};
    const double s0[2] = {v0 - r * w0[1], r * w0[0]}, sn = hypot(s0[0], s0[1]), a = mu * G;
    const double t1 = 2.0 * sn / (7.0 * a), v1[2] = {5.0 / 7.0 * v0 + 2.0 / 7.0 * r * w0[1], -2.0 / 7.0 * r * w0[0]};
    const double x1[2] = {v0 * t1 - 0.5 * a * s0[0] / sn * t1 * t1 + v1[0] * (T - t1),
                          -0.5 * a * s0[1] / sn * t1 * t1 + v1[1] * (T - t1)};
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        rbs_world *w = mworld(m, dt, -G, 0.0);
        rbs_material_id mat = material(w, "m", mu, mu, 0.0);
        rbs_sphere_def d;
        rbs_body_id b;
        floor_plane(w, mat);
        rbs_sphere_def_init(&d);
        d.radius = r;
        d.mass = 1.0;
        d.position.z = r;
        d.velocity.x = v0;
        d.angular_velocity = (rbs_vec3){w0[0], w0[1], w0[2]};
        d.material = mat;
        CHECK_OK(rbs_world_add_sphere(w, &d, &b));
        if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
            rbs_body_state s = state_of(w, b);
            report(m, "swerve: rolls at 5/7 v0 + 2/7 r w0 x z",
                   fmax(fabs(s.velocity.x - v1[0]), fabs(s.velocity.y - v1[1])) + fabs(s.velocity.z), 1e-12 * v0);
            /* rolling: w = z x v / r, and w_z kept */
            report(m, "  spin (-vy, vx) / r, w_z kept",
                   fabs(s.angular_velocity.x + v1[1] / r) + fabs(s.angular_velocity.y - v1[0] / r) +
                       fabs(s.angular_velocity.z - w0[2]), 1e-12 * v0 / r);
            report(m, "  distance on the parabola", fmax(fabs(s.position.x - x1[0]), fabs(s.position.y - x1[1])),
                   a * t1 * euler_lag(m, dt) + a * dt * dt + 1e-12);
        }
        rbs_world_destroy(w);
    }
}

/* ---- rolling down a V-groove ---------------------------------------------------- */

/* A solid ball (r = 0.1 m, 1 kg, k = I / (m r^2) = 2/5) from rest in a
 * V-groove of two planes whose line falls at phi = 10 degrees (along
 * u = (cos phi, 0, -sin phi)), each plane's normal b off the groove's
 * vertical plane: n = cos b w +- sin b y, w = (sin phi, 0, cos phi).
 * Each contact is at -r n; rolling on both (v u + w x (-r n) = 0) takes
 * w = v / (r cos b) about y: the ball rolls on a circle of radius
 * r cos b, its kinetic energy m v^2 (1 + k / cos^2 b) / 2, so it rolls
 * down at a = g sin phi / (1 + k / cos^2 b) (the ball on two rails: Routh,
 * Dynamics of a System of Rigid Bodies, elementary part).  Each contact
 * bears N = m g cos phi / (2 cos b) and needs friction (m g sin phi - m a)
 * / 2 along u, so it rolls iff mu >= mu* = tan phi k cos b / (k +
 * cos^2 b); below, both contact points slip at (v - r cos b w) u and
 * kinetic friction gives a = g sin phi - mu g cos phi / cos b and
 * dw/dt = mu g cos phi / (k r) (the torques of the two about y add, about
 * z they cancel).  Cases b = 45 and 70 degrees, mu = 2 mu* (rolls) and
 * 0.9 mu* (slides).  Bounds after 1 s: velocity and spin 1e-11 (constant
 * accelerations, rounding); the distance a T^2 / 2 within each method's
 * lag (euler_lag) + 1e-12 (soft: 1e-7, its contacts sinking to the
 * spring's fixed point, as incline_at_the_rolling_threshold's sliding
 * case).  soft sliding: its first frame starts cold, and one solve and one
 * relax pass a sub-step, each contact's friction row taken alone, do not
 * find the two contacts' shared sliding friction (the rows of the two
 * stop the one slip; one at a time each takes what it alone would need):
 * that frame takes less than its friction, up to the whole frame's,
 * mu g cos phi / cos b dt in velocity and mu g cos phi / (k r) dt in
 * spin, and later frames, warm, keep it (measured: 4.4e-5 m/s, 6.5 % of
 * a frame's friction, at b = 45; 4.5e-4, 38 %, at b = 70; a probe of
 * session 51); the distance that velocity times T more.  soft rolling: the
 * same cold frame may let the ball slip ahead, by at most (g sin phi - a)
 * dt^2, before the next, warm, rolls it again at the exact speed (the
 * angular momentum about the contact line does not care); measured
 * 7.0e-8 and 3.8e-7 m.  event refuses a ball held by two planes.
 * Nearer mu* the sliding ball is not exact: at mu = 0.999 and 0.9999 mu*
 * (b = 70) the resting pass ends at max_sweeps in the first 41 and 69
 * frames and leaves it sliding 7.5e-6 and 1.7e-5 m/s fast and 6.5e-5 and
 * 1.4e-4 rad/s slow after 1 s (dt 1 ms; 1.7e-6 at 0.1 ms; 3.6e-9 with
 * max_sweeps 2000; b = 45: 1.6e-6 m/s; a probe of session 51). */
static void rolling_down_a_v_groove(void **state)
{
    const double r = 0.1, k = 0.4, phi = 10.0 * PI_ / 180.0, dt = 1e-3, T = 1.0;
    const double degs[2] = {45.0, 70.0}, f[2] = {2.0, 0.9};
    const double u[3] = {cos(phi), 0.0, -sin(phi)}, wv[3] = {sin(phi), 0.0, cos(phi)};
    size_t i;
    int c, j, sg;
    (void)state;
    for (i = 0; i < N_METHODS; ++i)
        for (c = 0; c < 2; ++c)
            for (j = 0; j < 2; ++j) {
                rbs_method m = all_methods[i];
                const double b = degs[c] * PI_ / 180.0, cb = cos(b), d = r / cb;
                const double need = tan(phi) * k * cb / (k + cb * cb), mu = f[j] * need, rolls = mu >= need;
                const double a = rolls ? G * sin(phi) / (1.0 + k / (cb * cb)) : G * sin(phi) - mu * G * cos(phi) / cb;
                const double wy = rolls ? a * T / (r * cb) : mu * G * cos(phi) / (k * r) * T;
                rbs_world *w = mworld(m, dt, -G, 0.0);
                rbs_material_id mat = material(w, "m", mu, mu, 0.0);
                rbs_body_id ball_id;
                for (sg = -1; sg <= 1; sg += 2) {
                    rbs_plane_def p;
                    rbs_plane_def_init(&p);
                    p.normal = (rbs_vec3){cb * wv[0], sg * sin(b), cb * wv[2]};
                    p.material = mat;
                    CHECK_OK(rbs_world_add_plane(w, &p, NULL));
                }
                ball_id = ball(w, r, 1.0, d * wv[0], 0.0, d * wv[2], 0, 0, 0, mat);
                if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                    rbs_body_state s = state_of(w, ball_id);
                    const double vu = s.velocity.x * u[0] + s.velocity.z * u[2];
                    const double vw = s.velocity.x * wv[0] + s.velocity.z * wv[2];
                    const double su = (s.position.x - d * wv[0]) * u[0] + (s.position.z - d * wv[2]) * u[2];
                    const int cold = m == RBS_METHOD_SOFT && !rolls;
                    const double bv = 1e-11 + (cold ? mu * G * cos(phi) / cb * dt : 0.0);
                    char what[64];
                    snprintf(what, sizeof what, "V-groove b %g, mu %g mu*: %s", degs[c], f[j],
                             rolls ? "rolls" : "slides");
                    report(m, what, fabs(vu - a * T) + fabs(vw) + fabs(s.velocity.y), bv);
                    report(m, "  spin about y", fabs(s.angular_velocity.y - wy) + fabs(s.angular_velocity.x) +
                           fabs(s.angular_velocity.z), 1e-11 / r + (cold ? mu * G * cos(phi) / (k * r) * dt : 0.0));
                    report(m, "  distance a T^2/2 + lag", fabs(su - a * T * (T / 2.0 + euler_lag(m, dt))),
                           m != RBS_METHOD_SOFT ? 1e-12
                           : rolls             ? 1e-7 + (G * sin(phi) - a) * dt * dt
                                               : 1e-7 + (bv - 1e-11) * T);
                }
                rbs_world_destroy(w);
            }
}

/* ---- rolling and spinning resistance ------------------------------------------- */

/* A solid ball (r = 0.1 m, 1 kg, I = 2/5 m r^2) rolling on a floor at
 * v0 = 2 m/s and spinning about the vertical at 20 rad/s, mu_s 0.5,
 * mu_k 0.4, rolling resistance mu_r = 0.1 (a torque up to mu_r r N
 * against the rolling) and spinning resistance mu_sp = 0.01 m (up to
 * mu_sp N against the spin about the normal; docs/physics.md, "Resting
 * contact").  Rolling, m dv/dt = -F and I dw/dt = F r - mu_r r m g with
 * v = r w give dv/dt = -mu_r g / (1 + I / (m r^2)) = -5/7 mu_r g (Meriam &
 * Kraige's rolling resistance, the friction F keeping it rolling), so it
 * stops at ts = v0 / (5/7 mu_r g) = 2.854 s after v0^2 / (10/7 mu_r g),
 * and stays (mu_r r N holds what is left; on a level floor nothing is
 * left); the spin falls at mu_sp m g / I = 24.5 rad/s^2 and stops at
 * 0.8155 s.  Bounds: the speed and spin at 0.5 s 1e-12 (constant
 * decelerations); each stopped from the end of the frame holding its exact
 * time on, to the rounding of the speeds, 1e-12 v0 and 1e-12 w0 (measured:
 * the rigid methods 0 to 1e-34; soft's relax leaves 2.6e-15 m/s of slip,
 * shrinking by -1/4 a frame); the distance: Euler's sum of end-of-frame
 * speeds, v0 N h - a h^2 N (N + 1) / 2 over the N = floor(ts / h) frames
 * before the stop, is short by a h^2 ((ts/h - N)^2 + N) / 2 <= a ts h / 2 +
 * a h^2 / 2 (euler_lag, h = dt, dt / 3 for soft), the exact integrators
 * by a frame's a dt^2.  event refuses a ball with a resistance
 * (skipped). */
static void rolling_and_spinning_resistance_stop_the_ball(void **state)
{
    const double r = 0.1, v0 = 2.0, wz0 = 20.0, mur = 0.1, musp = 0.01, dt = 1e-3, t1 = 0.5;
    const double a = 5.0 / 7.0 * mur * G, ts = v0 / a, al = musp * G / (0.4 * r * r), tsp = wz0 / al;
    size_t i;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        rbs_world *w = mworld(m, dt, -G, 0.0);
        rbs_material_id mat;
        rbs_pair_def p;
        rbs_sphere_def d;
        rbs_body_id b;
        double e1 = -1.0, after_v = 0.0, after_w = 0.0;
        int k, failed = 0, n = (int)(3.5 / dt + 0.5);
        CHECK_OK(rbs_world_add_material(w, "m", &mat));
        rbs_pair_def_init(&p);
        p.a = p.b = mat;
        p.static_friction = 0.5;
        p.kinetic_friction = 0.4;
        p.restitution = 0.0;
        p.rolling = mur;
        p.spinning = musp;
        CHECK_OK(rbs_world_set_pair(w, &p));
        floor_plane(w, mat);
        rbs_sphere_def_init(&d);
        d.radius = r;
        d.mass = 1.0;
        d.position.z = r;
        d.velocity.x = v0;
        d.angular_velocity = (rbs_vec3){0.0, v0 / r, wz0};
        d.material = mat;
        CHECK_OK(rbs_world_add_sphere(w, &d, &b));
        for (k = 1; k <= n && !failed; ++k) {
            rbs_body_state s;
            failed = msteps(w, m, 1);
            if (failed)
                break;
            s = state_of(w, b);
            if (k == (int)(t1 / dt + 0.5))
                e1 = fabs(s.velocity.x - (v0 - a * t1)) + fabs(s.angular_velocity.z - (wz0 - al * t1));
            if (k * dt >= ts) /* (from the end of the frame holding ts) */
                after_v = fmax(after_v, fabs(s.velocity.x) + fabs(s.angular_velocity.y) * r);
            if (k * dt >= tsp)
                after_w = fmax(after_w, fabs(s.angular_velocity.z));
        }
        if (!failed) {
            rbs_body_state s = state_of(w, b);
            report(m, "resistance: v, w_z at 0.5 s", e1, 1e-12 * v0 + 1e-12 * wz0);
            report(m, "  stopped from the frame of v0/(5/7 mu_r g)", after_v, 1e-12 * v0);
            report(m, "  spin stopped from the frame of I w/(mu_sp m g)", after_w, 1e-12 * wz0);
            report(m, "  distance v0^2 / (10/7 mu_r g)", fabs(s.position.x - v0 * v0 / (2.0 * a)),
                   a * ts * euler_lag(m, dt) + a * dt * dt);
        }
        rbs_world_destroy(w);
    }
}

/* ---- a ball pushed or twisted on a floor --------------------------------- */

/* A solid ball (m = 2 kg, r = 0.1 m, I = 2/5 m r^2) at rest on a floor
 * (mu_s = 0.3, mu_k = 0.2, g = 9.81), driven for 1 s by a constant
 * horizontal force F along x at its centre, or by a constant torque tau
 * about +y (which rolls it along +x).  Newton's laws for the centre and
 * about it with the friction f at the contact (Meriam & Kraige, Dynamics,
 * plane motion of a rolling wheel; the rolling ball of any mechanics text):
 *  - force: rolling (v = r w) needs f = 2 F / 7 against F, a = 5 F / (7 m),
 *    so it rolls iff F <= 7/2 mu_s m g; else it slides, a = F / m - mu_k g,
 *    w' = 5 mu_k g / (2 r), and stays sliding (slip speed grows at
 *    F / m - 7/2 mu_k g > 0);
 *  - torque: rolling needs f = 5 tau / (7 r) along +x, a = 5 tau / (7 m r),
 *    so it rolls iff tau <= 7/5 mu_s m g r; else its contact slips back,
 *    a = mu_k g, w' = (tau - mu_k m g r) / I.
 * Cases at 0.9 and 1.1 of each threshold.  (The inclines' rolling and
 * sliding, where gravity drives the ball, are incline_at_the_rolling_
 * threshold; spinning up under constant_torque_spins_up_linearly is free.)
 * Bounds as for the incline: speed and spin after 1 s exact to 1e-11 (one
 * constant acceleration; 1e-11 / r for the spin), nothing else moves
 * (1e-12), the distance a T^2/2 plus each method's lag a T (euler_lag)
 * to 1e-12, the height r to 1e-12; soft's
 * contact sinks by the slop plus g / omega^2 (soft_sink; the load is the
 * ball's weight on m_eff = m, 1e-9 for its settling), and while it sinks
 * it bears less than the weight: the normal impulse it lacks, integrated
 * twice, is m times the depth d it sank (the ball ends at rest in z), so
 * a sliding ball's kinetic friction, mu_k N, moves it mu_k d further
 * (force) or less far (torque) than the exact answer: 7.0e-8 m, bound
 * mu_k d (1 + 1e-3); a rolling ball's friction is within its cone and
 * does not care (1e-12). */
static void pushed_and_twisted_balls_roll_or_slide(void **state)
{
    const double mass = 2.0, r = 0.1, mus = 0.3, muk = 0.2, dt = 1e-3, T = 1.0, I = 0.4 * mass * r * r;
    const double f_star = 3.5 * mus * mass * G, t_star = 1.4 * mus * mass * G * r;
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const int soft = m == RBS_METHOD_SOFT;
        for (c = 0; c < 4; ++c) {
            const int torque = c >= 2;
            const double q = (c % 2 ? 1.1 : 0.9) * (torque ? t_star : f_star);
            const int rolls = c % 2 == 0;
            double a, wdot;
            rbs_world *w = mworld(m, dt, -G, 0.0);
            rbs_material_id mat = material(w, "m", mus, muk, 0.0);
            rbs_sphere_def d;
            rbs_body_id b;
            if (!torque) {
                a = rolls ? 5.0 * q / (7.0 * mass) : q / mass - muk * G;
                wdot = rolls ? a / r : muk * mass * G * r / I;
            } else {
                a = rolls ? 5.0 * q / (7.0 * mass * r) : muk * G;
                wdot = rolls ? a / r : (q - muk * mass * G * r) / I;
            }
            floor_plane(w, mat);
            rbs_sphere_def_init(&d);
            d.radius = r;
            d.mass = mass;
            d.position.z = r;
            d.material = mat;
            if (torque)
                d.torque.y = q;
            else
                d.force.x = q;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                rbs_body_state s = state_of(w, b);
                const double x_exact = a * T * (T / 2.0 + euler_lag(m, dt));
                const double sink = soft ? 1e-6 * r + soft_sink(G, dt) : 0.0;
                char what[64];
                snprintf(what, sizeof what, "%s %.1f of the limit: %s", torque ? "torque" : "force",
                         c % 2 ? 1.1 : 0.9, rolls ? "rolls" : "slides");
                report(m, what, fabs(s.velocity.x - a * T), 1e-11);
                report(m, "  spin", fabs(s.angular_velocity.y - wdot * T), 1e-11 / r);
                report(m, "  nothing else moves", fabs(s.velocity.y) + fabs(s.velocity.z) +
                       fabs(s.angular_velocity.x) + fabs(s.angular_velocity.z) + fabs(s.position.y), 1e-12);
                report(m, "  distance a T^2/2 + lag", fabs(s.position.x - x_exact),
                       soft && !rolls ? muk * sink * (1.0 + 1e-3) : 1e-12);
                report(m, "  height r", fabs(s.position.z - r + sink), soft ? 1e-9 : 1e-12);
            }
            rbs_world_destroy(w);
        }
    }
}

/* ---- a ball pressed to a wall rolls down it -------------------------------- */

/* A solid ball (1 kg, r = 0.1 m) pressed against a wall x = 0 (normal +x)
 * by a constant force F along -x at its centre, gravity g down the wall,
 * mu_s = 0.5, mu_k = 0.4: the wall's load is the applied force, not
 * gravity.  As on an incline (incline_at_the_rolling_threshold, with
 * g sin th -> g and m g cos th -> F): it rolls down at a = 5/7 g (spin
 * a / r) iff 2/7 m g <= mu_s F, else slides at a = g - mu_k F / m,
 * spinning up at 5 mu_k F / (2 m r).  Cases F = 1.1 and 0.9 of 2/7 m g /
 * mu_s.  Bounds as for the pushed ball (pushed_and_twisted_balls_roll_or_
 * slide): speed and spin exact to 1e-11 (1e-11 / r), the distance a T^2/2
 * plus each method's lag to 1e-12, x = r to 1e-12; soft sinks into the
 * wall by the slop plus (F / m) / omega^2, and slides mu_k times that less
 * far (its contact bears less than F while it sinks). */
static void ball_pressed_to_a_wall_rolls_down(void **state)
{
    const double mass = 1.0, r = 0.1, mus = 0.5, muk = 0.4, dt = 1e-3, T = 1.0, z0 = 10.0;
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < N_METHODS; ++i) {
        rbs_method m = all_methods[i];
        const int soft = m == RBS_METHOD_SOFT;
        for (c = 0; c < 2; ++c) {
            const double F = (c ? 0.9 : 1.1) * (2.0 / 7.0) * mass * G / mus;
            const int rolls = c == 0;
            const double a = rolls ? 5.0 / 7.0 * G : G - muk * F / mass;
            const double wdot = rolls ? a / r : 2.5 * muk * F / (mass * r);
            const double sink = soft ? 1e-6 * r + soft_sink(F / mass, dt) : 0.0;
            rbs_world *w = mworld(m, dt, -G, 0.0);
            rbs_material_id mat = material(w, "m", mus, muk, 0.0);
            rbs_plane_def p;
            rbs_sphere_def d;
            rbs_body_id b;
            rbs_plane_def_init(&p);
            p.normal = (rbs_vec3){1, 0, 0};
            p.material = mat;
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            rbs_sphere_def_init(&d);
            d.radius = r;
            d.mass = mass;
            d.position = (rbs_vec3){r, 0.0, z0};
            d.force.x = -F;
            d.material = mat;
            CHECK_OK(rbs_world_add_sphere(w, &d, &b));
            if (msteps(w, m, (int)(T / dt + 0.5)) == 0) {
                rbs_body_state s = state_of(w, b);
                const double down = a * T * (T / 2.0 + euler_lag(m, dt));
                char what[64];
                snprintf(what, sizeof what, "pressed to a wall by %.2f N: %s", F, rolls ? "rolls" : "slides");
                /* rolling down the wall (-z) with the contact at -r x:
                 * v_z + r w_y = 0, so w_y = a t / r > 0 */
                report(m, what, fabs(s.velocity.z + a * T) + fabs(s.velocity.x) + fabs(s.velocity.y), 1e-11);
                report(m, "  spin", fabs(s.angular_velocity.y - wdot * T) + fabs(s.angular_velocity.x) +
                       fabs(s.angular_velocity.z), 1e-11 / r);
                report(m, "  distance a T^2/2 + lag", fabs(z0 - s.position.z - down),
                       soft && !rolls ? muk * sink * (1.0 + 1e-3) : 1e-12);
                report(m, "  off the wall", fabs(s.position.x - r + sink), soft ? 1e-9 : 1e-12);
            }
            rbs_world_destroy(w);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sliding_ball_rolls_at_five_sevenths),
        cmocka_unit_test(oblique_impacts_keep_the_tangents),
        cmocka_unit_test(head_on_impacts_at_extreme_speeds),
        cmocka_unit_test(ball_reflects_off_a_fixed_sphere),
        cmocka_unit_test(ball_between_walls_keeps_its_period),
        cmocka_unit_test(constant_torque_spins_up_linearly),
        cmocka_unit_test(ball_rests_far_from_the_origin),
        cmocka_unit_test(ball_dropped_far_from_the_origin_rests),
        cmocka_unit_test(stacked_drop_follows_sequential_impacts),
        cmocka_unit_test(cradles_pass_one_and_two_strikers),
        cmocka_unit_test(spinning_projectile_keeps_its_spin),
        cmocka_unit_test(bouncing_ball_comes_to_rest),
        cmocka_unit_test(rolling_ball_into_a_wall),
        cmocka_unit_test(rolling_ball_on_a_floor_into_a_wall),
        cmocka_unit_test(incline_at_the_rolling_threshold),
        cmocka_unit_test(sliding_up_an_incline_rolls_back),
        cmocka_unit_test(ball_leaves_a_fixed_sphere),
        cmocka_unit_test(rolling_ball_strikes_a_resting_one),
        cmocka_unit_test(equal_masses_leave_at_right_angles),
        cmocka_unit_test(spinning_ball_bounces_by_coulomb),
        cmocka_unit_test(rolling_across_an_incline_with_normal_spin),
        cmocka_unit_test(spinning_spheres_meet_with_friction),
        cmocka_unit_test(sliding_ball_swerves),
        cmocka_unit_test(rolling_down_a_v_groove),
        cmocka_unit_test(rolling_and_spinning_resistance_stop_the_ball),
        cmocka_unit_test(pushed_and_twisted_balls_roll_or_slide),
        cmocka_unit_test(ball_pressed_to_a_wall_rolls_down),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
