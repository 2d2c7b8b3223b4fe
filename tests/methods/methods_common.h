/* methods_common.h - scenes shared by the method tests (orbits, fits). */
#ifndef RBS_TEST_METHODS_COMMON_H
#define RBS_TEST_METHODS_COMMON_H

#include "common.h"

#define PI_ 3.14159265358979323846

/* Body-frame v = R(q)^T v for the unit quaternion q = [w x y z]. */
static inline void to_body(const double *q, const double *v, double *out)
{
    const double w = q[0], x = -q[1], y = -q[2], z = -q[3];
    const double tx = 2.0 * (y * v[2] - z * v[1]), ty = 2.0 * (z * v[0] - x * v[2]),
                 tz = 2.0 * (x * v[1] - y * v[0]);
    out[0] = v[0] + w * tx + (y * tz - z * ty);
    out[1] = v[1] + w * ty + (z * tx - x * tz);
    out[2] = v[2] + w * tz + (x * ty - y * tx);
}

/* A world for method m with no uniform gravity and mutual gravity of
 * constant G on. */
static inline rbs_world *orbit_world(rbs_method m, double dt, double G, double tol)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = 8;
    d.dt = dt;
    d.gravity.z = 0.0;
    d.method = m;
    d.tolerance = tol;
    d.mutual_gravity = 1;
    d.gravity_constant = G;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

static inline rbs_body_id point_mass(rbs_world *w, double m, double x, double y, double vx, double vy)
{
    return ball(w, 0.01, m, x, y, 0.0, vx, vy, 0.0, (rbs_material_id){0, 0});
}

/* Two equal masses m = 1 at distance a = 1 on a circular orbit, G = 1:
 * omega^2 = G (m1 + m2) / a^3, period 2 pi sqrt(a^3 / (G (m1 + m2))). */
static inline double circular_period(void) { return 2.0 * PI_ * sqrt(1.0 / 2.0); }

static inline rbs_world *circular_orbit(rbs_method m, double dt, double tol, rbs_body_id *a, rbs_body_id *b)
{
    rbs_world *w = orbit_world(m, dt, 1.0, tol);
    double v = 0.5 * sqrt(2.0); /* omega a / 2 */
    *a = point_mass(w, 1.0, 0.5, 0.0, 0.0, v);
    *b = point_mass(w, 1.0, -0.5, 0.0, 0.0, -v);
    return w;
}

/* Position error of body a after a fraction f of the circular orbit's period
 * taken in n steps, against the exact position 0.5 (cos wt, sin wt). */
static inline double circular_error(rbs_method m, int n, double f, double tol)
{
    rbs_body_id a, b;
    double T = circular_period(), th = 2.0 * PI_ * f;
    rbs_world *w = circular_orbit(m, f * T / n, tol, &a, &b);
    rbs_body_state s;
    step_n(w, n);
    s = state_of(w, a);
    rbs_world_destroy(w);
    return sqrt((s.position.x - 0.5 * cos(th)) * (s.position.x - 0.5 * cos(th)) +
                (s.position.y - 0.5 * sin(th)) * (s.position.y - 0.5 * sin(th)) +
                s.position.z * s.position.z);
}

/* Least-squares slope of log(err) against log(x). */
static inline double fit_slope(const double *x, const double *err, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int i;
    for (i = 0; i < n; ++i) {
        double lx = log(x[i]), ly = log(err[i]);
        sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/* The figure-eight three-body orbit (Chenciner & Montgomery 2000) with the
 * initial conditions of Simo / Moore, G = m = 1:
 *   x1 = -x2 = (0.97000436, -0.24308753), x3 = 0,
 *   v3 = (-0.93240737, -0.86473146), v1 = v2 = -v3 / 2,
 * period T = 6.32591398 (given to 9 digits, so the orbit closes only to
 * about 1e-8 of its size). */
#define FIG8_T 6.32591398
static const double fig8_x[3][2] = {{0.97000436, -0.24308753}, {-0.97000436, 0.24308753}, {0.0, 0.0}};
static const double fig8_v[3][2] = {{0.466203685, 0.43236573}, {0.466203685, 0.43236573},
                                    {-0.93240737, -0.86473146}};

static inline rbs_world *figure_eight(rbs_method m, double dt, double tol, rbs_body_id *id)
{
    rbs_world *w = orbit_world(m, dt, 1.0, tol);
    int k;
    for (k = 0; k < 3; ++k)
        id[k] = point_mass(w, 1.0, fig8_x[k][0], fig8_x[k][1], fig8_v[k][0], fig8_v[k][1]);
    return w;
}

/* Largest distance of a body from its start after one period in n steps. */
static inline double figure_eight_error(rbs_method m, int n, double tol)
{
    rbs_body_id id[3];
    rbs_world *w = figure_eight(m, FIG8_T / n, tol, id);
    double worst = 0.0;
    int k;
    step_n(w, n);
    for (k = 0; k < 3; ++k) {
        rbs_body_state s = state_of(w, id[k]);
        double e = hypot(s.position.x - fig8_x[k][0], s.position.y - fig8_x[k][1]);
        if (e > worst)
            worst = e;
    }
    rbs_world_destroy(w);
    return worst;
}

/* A two-body Kepler orbit: masses 1/2 and 1/2, G = 1 (mu = G (m1 + m2) = 1),
 * semi-major axis 1, eccentricity e, starting at pericentre; period 2 pi.
 * Body 1 sits at +r/2 of the relative vector, body 2 at -r/2. */
static inline rbs_world *kepler_orbit(rbs_method m, double e, double dt, double tol, rbs_body_id *b1,
                                      rbs_body_id *b2)
{
    rbs_world *w = orbit_world(m, dt, 1.0, tol);
    double rp = 1.0 - e, vp = sqrt((1.0 + e) / (1.0 - e));
    *b1 = point_mass(w, 0.5, 0.5 * rp, 0.0, 0.0, 0.5 * vp);
    *b2 = point_mass(w, 0.5, -0.5 * rp, 0.0, 0.0, -0.5 * vp);
    return w;
}

/* Exact position of body 1 at time t: Kepler's equation E - e sin E = t
 * (mean motion 1) solved by Newton's method to rounding, then
 * r = (cos E - e, sqrt(1 - e^2) sin E) and body 1 at r / 2. */
static inline void kepler_position(double e, double t, double *x, double *y)
{
    double M = fmod(t, 2.0 * PI_), E = e < 0.8 ? M : PI_;
    int k;
    for (k = 0; k < 100; ++k) {
        double d = (E - e * sin(E) - M) / (1.0 - e * cos(E));
        E -= d;
        if (fabs(d) < 1e-16)
            break;
    }
    *x = 0.5 * (cos(E) - e);
    *y = 0.5 * sqrt(1.0 - e * e) * sin(E);
}

/* Largest position error of body 1 over n frames per period, one period. */
static inline double kepler_error(rbs_method m, double e, int n, double tol)
{
    rbs_body_id b1, b2;
    rbs_world *w = kepler_orbit(m, e, 2.0 * PI_ / n, tol, &b1, &b2);
    double worst = 0.0;
    int k;
    for (k = 1; k <= n; ++k) {
        rbs_body_state s;
        double x, y, d;
        step_n(w, 1);
        s = state_of(w, b1);
        kepler_position(e, rbs_world_time(w), &x, &y);
        d = hypot(s.position.x - x, s.position.y - y);
        if (d > worst)
            worst = d;
    }
    rbs_world_destroy(w);
    return worst;
}

#endif
