/*
 * bench_methods.c - work-precision benchmark of rbsim's stepping methods.
 *
 * Every case has an exact answer (mechanics, or Kepler's equation); each
 * method that applies runs it over a sweep of frame steps dt (fixed-step
 * methods) or tolerances (adaptive), and the benchmark records the error
 * against the exact answer and the CPU time (CLOCK_PROCESS_CPUTIME_ID,
 * median of 3 runs) as CSV:
 *
 *   case,method,dt,tolerance,error,cpu_s,frames,status
 *
 * status is "ok", "unsupported" (the method is not built or refuses the
 * scene: RBS_E_UNSUPPORTED) or "failed: <reason>".  An error of exactly 0
 * is written as 0 (plots clip it).
 *
 * usage: bench_methods [--quick] [--check] [--csv PATH]
 *   --quick  three cases, a coarse sweep (a few seconds)
 *   --check  fit the order of convergence on the circular orbit and fail
 *            (exit 1) unless euler ~1, verlet ~2, rk4 ~4 (+-0.3) and the
 *            adaptive error falls at least 100x from tolerance 1e-6 to 1e-10
 * See docs/methods.md; bench/methods/run.sh runs everything and plots.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rbsim/rbsim.h"

#define PI_ 3.14159265358979323846
#define G_ 9.81
#define MAXPTS 12

/* Result of one run: error, frames stepped, status. */
typedef struct result {
    double error;
    long frames;
    rbs_status status;
    char why[160];
} result;

typedef void (*case_fn)(rbs_method m, double dt, double tol, result *out);

typedef struct bench_case {
    const char *name;
    const char *exact; /* what the error is measured against */
    case_fn run;
    double dts[MAXPTS];    /* fixed-step sweep, s; 0 ends the list */
    double adaptive_dt;    /* frame step of the adaptive sweep */
    int quick;             /* part of --quick */
} bench_case;

static const double tols_full[] = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 0};
static const double tols_quick[] = {1e-6, 1e-8, 1e-10, 0};

/* ------------------------------------------------------------------------- */
/* Helpers                                                                   */
/* ------------------------------------------------------------------------- */

static rbs_world *world(rbs_method m, double dt, double tol, double gz, double e, int mutual,
                        result *out)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = 8;
    d.dt = dt;
    d.gravity.z = gz;
    d.restitution = e;
    d.method = m;
    d.tolerance = tol;
    d.mutual_gravity = mutual;
    d.gravity_constant = 1.0;
    out->status = rbs_world_create(&d, &w);
    if (out->status != RBS_OK) {
        snprintf(out->why, sizeof out->why, "create: %s", rbs_status_string(out->status));
        return NULL;
    }
    return w;
}

static rbs_material_id material(rbs_world *w, double mu, double e)
{
    rbs_material_id m;
    rbs_pair_def p;
    rbs_world_add_material(w, "m", &m);
    rbs_pair_def_init(&p);
    p.a = p.b = m;
    p.static_friction = p.kinetic_friction = mu;
    p.restitution = e;
    rbs_world_set_pair(w, &p);
    return m;
}

static rbs_body_id sphere(rbs_world *w, double r, double mass, double x, double y, double z, double vx,
                          double vy, double vz, double wy, rbs_material_id mat)
{
    rbs_sphere_def s;
    rbs_body_id id = {0, 0};
    rbs_sphere_def_init(&s);
    s.radius = r;
    s.mass = mass;
    s.position.x = x; s.position.y = y; s.position.z = z;
    s.velocity.x = vx; s.velocity.y = vy; s.velocity.z = vz;
    s.angular_velocity.y = wy;
    s.material = mat;
    rbs_world_add_sphere(w, &s, &id);
    return id;
}

static void plane(rbs_world *w, double nx, double nz, rbs_material_id m)
{
    rbs_plane_def p;
    rbs_plane_def_init(&p);
    p.normal.x = nx;
    p.normal.z = nz;
    p.material = m;
    rbs_world_add_plane(w, &p, NULL);
}

static rbs_body_state state(const rbs_world *w, rbs_body_id id)
{
    rbs_body_state s;
    memset(&s, 0, sizeof s);
    rbs_body_get_state(w, id, &s);
    return s;
}

/* One frame; records the status and reason on failure. */
static int step(rbs_world *w, result *out, rbs_step_info *info)
{
    rbs_status st = rbs_world_step(w, info);
    if (st != RBS_OK) {
        out->status = st;
        snprintf(out->why, sizeof out->why, "%s", rbs_world_last_error(w));
        return 0;
    }
    out->frames++;
    return 1;
}

static long frames_for(double T, double dt) { return (long)(T / dt + 0.5); }

/* ------------------------------------------------------------------------- */
/* Cases                                                                     */
/* ------------------------------------------------------------------------- */

/* Bouncing ball: dropped from a gap h = 1 m, e = 0.5, frictionless.  Exact
 * apexes h e^(2n).  Error: the largest error of the apex height recovered
 * from every frame in flight (z - r + v^2 / 2g, exact for free flight) over
 * the first three flights (1.1 s). */
static void case_bounce(rbs_method m, double dt, double tol, result *out)
{
    const double h = 1.0, r = 0.1, e = 0.5;
    rbs_world *w = world(m, dt, tol, -G_, e, 0, out);
    rbs_body_id b;
    long k, n = frames_for(1.1, dt);
    int bounce = 0;
    double prev_v = 0.0;
    if (!w)
        return;
    plane(w, 0, 1, (rbs_material_id){0, 0});
    b = sphere(w, r, 1.0, 0, 0, h + r, 0, 0, 0, 0, (rbs_material_id){0, 0});
    for (k = 0; k < n; ++k) {
        rbs_body_state s;
        if (!step(w, out, NULL))
            break;
        s = state(w, b);
        if (prev_v < 0.0 && s.velocity.z > 0.0)
            bounce++;
        prev_v = s.velocity.z;
        if (s.position.z - r > 1e-3) {
            double apex = s.position.z - r + s.velocity.z * s.velocity.z / (2.0 * G_);
            double d = fabs(apex - h * pow(e, 2.0 * bounce));
            if (d > out->error)
                out->error = d;
        }
    }
    rbs_world_destroy(w);
}

/* Sliding to rolling with backspin: a solid sphere (r = 0.1 m) on a plane
 * with v0 = 3 m/s and backspin w0 = 20 rad/s, mu = 0.2.  Exact: slides with
 * deceleration mu g until t = 2 (v0 + r w0) / (7 mu g), then rolls at
 * (5 v0 - 2 r w0) / 7.  Error: |x(T) - x_exact(T)| at T = 1 s. */
static void case_backspin(rbs_method m, double dt, double tol, result *out)
{
    const double r = 0.1, v0 = 3.0, w0 = 20.0, mu = 0.2, T = 1.0;
    const double tr = 2.0 * (v0 + r * w0) / (7.0 * mu * G_), vf = (5.0 * v0 - 2.0 * r * w0) / 7.0;
    const double x_exact = v0 * tr - 0.5 * mu * G_ * tr * tr + vf * (T - tr);
    rbs_world *w = world(m, dt, tol, -G_, 0.0, 0, out);
    rbs_material_id mat;
    rbs_body_id b;
    long k, n = frames_for(T, dt);
    if (!w)
        return;
    mat = material(w, mu, 0.0);
    plane(w, 0, 1, mat);
    b = sphere(w, r, 1.0, 0, 0, r, v0, 0, 0, -w0, mat);
    for (k = 0; k < n; ++k)
        if (!step(w, out, NULL))
            break;
    if (out->status == RBS_OK)
        out->error = fabs(state(w, b).position.x - x_exact);
    rbs_world_destroy(w);
}

/* A solid ball released on a 20 degree incline: rolls (mu = 0.5, a =
 * 5/7 g sin) or slides (mu = 0.05, a = g (sin - mu cos)).  Error: distance
 * along the slope at T = 1 s against a T^2 / 2. */
static void incline(rbs_method m, double dt, double tol, double mu, result *out)
{
    const double th = 20.0 * PI_ / 180.0, r = 0.1, T = 1.0;
    const double a = tan(th) <= 3.5 * mu ? 5.0 / 7.0 * G_ * sin(th) : G_ * (sin(th) - mu * cos(th));
    rbs_world *w = world(m, dt, tol, -G_, 0.0, 0, out);
    rbs_material_id mat;
    rbs_body_id b;
    long k, n = frames_for(T, dt);
    if (!w)
        return;
    mat = material(w, mu, 0.0);
    plane(w, -sin(th), cos(th), mat);
    b = sphere(w, r, 1.0, -r * sin(th), 0, r * cos(th), 0, 0, 0, 0, mat);
    for (k = 0; k < n; ++k)
        if (!step(w, out, NULL))
            break;
    if (out->status == RBS_OK) {
        rbs_body_state s = state(w, b);
        double along = -((s.position.x + r * sin(th)) * cos(th) + (s.position.z - r * cos(th)) * sin(th));
        out->error = fabs(along - 0.5 * a * T * T);
    }
    rbs_world_destroy(w);
}

static void case_incline_roll(rbs_method m, double dt, double tol, result *out)
{
    incline(m, dt, tol, 0.5, out);
}

static void case_incline_slide(rbs_method m, double dt, double tol, result *out)
{
    incline(m, dt, tol, 0.05, out);
}

/* Newton's cradle: five equal balls touching, the first arrives at 1 m/s,
 * e = 1, no gravity.  Exact: only the last ball moves, at 1 m/s.  The first ball starts 0.3123 m away, so the contact
 * time (0.3123 s) is off every frame grid of the sweep.  Error: largest
 * velocity error (m/s) plus the last ball's position error (m) at T = 1 s. */
static void case_cradle(rbs_method m, double dt, double tol, result *out)
{
    const double T = 1.0;
    rbs_world *w = world(m, dt, tol, 0.0, 1.0, 0, out);
    rbs_body_id b[5];
    long k, n = frames_for(T, dt);
    int i;
    if (!w)
        return;
    b[0] = sphere(w, 0.1, 1.0, -0.5123, 0, 0, 1.0, 0, 0, 0, (rbs_material_id){0, 0});
    for (i = 1; i < 5; ++i)
        b[i] = sphere(w, 0.1, 1.0, 0.2 * (i - 1), 0, 0, 0, 0, 0, 0, (rbs_material_id){0, 0});
    for (k = 0; k < n; ++k)
        if (!step(w, out, NULL))
            break;
    if (out->status == RBS_OK) {
        for (i = 0; i < 5; ++i) {
            double d = fabs(state(w, b[i]).velocity.x - (i == 4 ? 1.0 : 0.0));
            if (d > out->error)
                out->error = d;
        }
        out->error += fabs(state(w, b[4]).position.x - (0.6 + (T - 0.3123)));
    }
    rbs_world_destroy(w);
}

/* Oblique impact of a solid sphere on a plane with friction, no gravity:
 * v = (2, 0, -1) m/s, no spin, e = 0.5; contact at t = 0.0537 s (off every
 * frame grid of the sweep).  Exact
 * impulse law: normal speed out e vz; the stick impulse (2/7) m vx is taken
 * if it is at most mu (1 + e) m vz (mu = 1: vx' = 5/7 vx), else the sphere
 * slides (mu = 0.2: vx' = vx - mu (1 + e) vz).  Error: position error at
 * T = 0.2 s (m). */
static void oblique(rbs_method m, double dt, double tol, double mu, result *out)
{
    const double r = 0.1, e = 0.5, vx = 2.0, vz = 1.0, tc = 0.0537, T = 0.2;
    const double stick = 2.0 / 7.0 * vx <= mu * (1.0 + e) * vz;
    const double vx1 = stick ? 5.0 / 7.0 * vx : vx - mu * (1.0 + e) * vz;
    rbs_world *w = world(m, dt, tol, 0.0, e, 0, out);
    rbs_material_id mat;
    rbs_body_id b;
    long k, n = frames_for(T, dt);
    if (!w)
        return;
    mat = material(w, mu, e);
    plane(w, 0, 1, mat);
    b = sphere(w, r, 1.0, 0, 0, r + vz * tc, vx, 0, -vz, 0, mat);
    for (k = 0; k < n; ++k)
        if (!step(w, out, NULL))
            break;
    if (out->status == RBS_OK) {
        rbs_body_state s = state(w, b);
        out->error = hypot(s.position.x - (vx * tc + vx1 * (T - tc)), s.position.z - (r + e * vz * (T - tc)));
    }
    rbs_world_destroy(w);
}

static void case_oblique_stick(rbs_method m, double dt, double tol, result *out)
{
    oblique(m, dt, tol, 1.0, out);
}

static void case_oblique_slide(rbs_method m, double dt, double tol, result *out)
{
    oblique(m, dt, tol, 0.2, out);
}

/* Two-body Kepler orbit: masses 1/2 + 1/2, G = 1, semi-major axis 1,
 * eccentricity e, from pericentre, period 2 pi.  Exact position from
 * Kepler's equation E - e sin E = t (Newton to rounding).  Error: largest
 * position error of body 1 over the frames of one period. */
static void kepler(rbs_method m, double dt, double tol, double e, result *out)
{
    const double rp = 1.0 - e, vp = sqrt((1.0 + e) / (1.0 - e));
    rbs_world *w = world(m, dt, tol, 0.0, 0.5, 1, out);
    rbs_body_id b1;
    long k, n = frames_for(2.0 * PI_, dt);
    if (!w)
        return;
    b1 = sphere(w, 0.01, 0.5, 0.5 * rp, 0, 0, 0, 0.5 * vp, 0, 0, (rbs_material_id){0, 0});
    sphere(w, 0.01, 0.5, -0.5 * rp, 0, 0, 0, -0.5 * vp, 0, 0, (rbs_material_id){0, 0});
    for (k = 0; k < n; ++k) {
        double M, E, d;
        int it;
        rbs_body_state s;
        if (!step(w, out, NULL))
            break;
        M = fmod(rbs_world_time(w), 2.0 * PI_);
        E = e < 0.8 ? M : PI_;
        for (it = 0; it < 100; ++it) {
            double c = (E - e * sin(E) - M) / (1.0 - e * cos(E));
            E -= c;
            if (fabs(c) < 1e-16)
                break;
        }
        s = state(w, b1);
        d = hypot(s.position.x - 0.5 * (cos(E) - e), s.position.y - 0.5 * sqrt(1.0 - e * e) * sin(E));
        if (d > out->error)
            out->error = d;
    }
    rbs_world_destroy(w);
}

static void case_circular(rbs_method m, double dt, double tol, result *out)
{
    kepler(m, dt, tol, 0.0, out);
}

static void case_eccentric(rbs_method m, double dt, double tol, result *out)
{
    kepler(m, dt, tol, 0.6, out);
}

/* The figure-eight three-body orbit (Chenciner & Montgomery 2000), initial
 * conditions of Simo / Moore, G = m = 1, period 6.32591398.  Error: largest
 * distance of a body from its start after one period (the data's 8-9
 * digits limit this to about 4e-8). */
#define FIG8_T 6.32591398
static void case_figure_eight(rbs_method m, double dt, double tol, result *out)
{
    static const double x[3][2] = {{0.97000436, -0.24308753}, {-0.97000436, 0.24308753}, {0.0, 0.0}};
    static const double v[3][2] = {{0.466203685, 0.43236573}, {0.466203685, 0.43236573},
                                   {-0.93240737, -0.86473146}};
    rbs_world *w = world(m, dt, tol, 0.0, 0.5, 1, out);
    rbs_body_id id[3];
    long k, n = frames_for(FIG8_T, dt);
    int i;
    if (!w)
        return;
    for (i = 0; i < 3; ++i)
        id[i] = sphere(w, 0.01, 1.0, x[i][0], x[i][1], 0, v[i][0], v[i][1], 0, 0, (rbs_material_id){0, 0});
    for (k = 0; k < n; ++k)
        if (!step(w, out, NULL))
            break;
    if (out->status == RBS_OK) {
        for (i = 0; i < 3; ++i) {
            rbs_body_state s = state(w, id[i]);
            double d = hypot(s.position.x - x[i][0], s.position.y - x[i][1]);
            if (d > out->error)
                out->error = d;
        }
    }
    rbs_world_destroy(w);
}

/* Frame steps of the orbit sweeps: the period over N frames. */
#define ORBIT(N) (2.0 * PI_ / (N))
#define FIG8(N) (FIG8_T / (N))

static const bench_case cases[] = {
    {"circular", "position over one period (exact circle)", case_circular,
     {ORBIT(50), ORBIT(100), ORBIT(200), ORBIT(400), ORBIT(800), ORBIT(1600), 0}, ORBIT(10), 1},
    {"eccentric", "position over one period (Kepler's equation, e = 0.6)", case_eccentric,
     {ORBIT(100), ORBIT(200), ORBIT(400), ORBIT(800), ORBIT(1600), ORBIT(3200), 0}, ORBIT(10), 1},
    {"figure_eight", "return to the start after one period", case_figure_eight,
     {FIG8(250), FIG8(500), FIG8(1000), FIG8(2000), FIG8(4000), FIG8(8000), 0}, FIG8(10), 0},
    {"bounce", "apex heights h e^2n, three flights", case_bounce,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 1},
    {"backspin", "position at 1 s (slide, then roll at (5 v0 - 2 r w0) / 7)", case_backspin,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
    {"incline_roll", "distance rolled in 1 s (5/7 g sin)", case_incline_roll,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
    {"incline_slide", "distance slid in 1 s (g (sin - mu cos))", case_incline_slide,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
    {"cradle", "velocities and last ball's position", case_cradle,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
    {"oblique_stick", "position after an impact that sticks", case_oblique_stick,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
    {"oblique_slide", "position after an impact that slides", case_oblique_slide,
     {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 0}, 1e-2, 0},
};

/* ------------------------------------------------------------------------- */
/* Running and timing                                                        */
/* ------------------------------------------------------------------------- */

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Run a case 3 times: the error of the first run, the median CPU time. */
static double timed(const bench_case *c, rbs_method m, double dt, double tol, result *out)
{
    double t[3];
    int k;
    for (k = 0; k < 3; ++k) {
        result r;
        double t0;
        memset(&r, 0, sizeof r);
        t0 = cpu_now();
        c->run(m, dt, tol, &r);
        t[k] = cpu_now() - t0;
        if (k == 0)
            *out = r;
        if (r.status != RBS_OK)
            return t[0];
    }
    qsort(t, 3, sizeof t[0], cmp_double);
    return t[1];
}

/* Measured points of the --check fits. */
typedef struct fit {
    double x[MAXPTS], y[MAXPTS];
    int n;
} fit;

static double slope(const fit *f)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int i;
    for (i = 0; i < f->n; ++i) {
        double lx = log(f->x[i]), ly = log(f->y[i]);
        sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly;
    }
    return (f->n * sxy - sx * sy) / (f->n * sxx - sx * sx);
}

int main(int argc, char **argv)
{
    int quick = 0, check = 0, failures = 0, i;
    const char *csv_path = NULL;
    FILE *csv = stdout;
    size_t c;
    fit fits[RBS_METHOD_COUNT];
    const rbs_method methods[] = {RBS_METHOD_EULER, RBS_METHOD_SELECTIVE, RBS_METHOD_EVENT,
                                  RBS_METHOD_VERLET, RBS_METHOD_RK4, RBS_METHOD_ADAPTIVE, RBS_METHOD_SOFT};
    memset(fits, 0, sizeof fits);
    for (i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0)
            quick = 1;
        else if (strcmp(argv[i], "--check") == 0)
            check = 1;
        else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc)
            csv_path = argv[++i];
        else {
            fprintf(stderr, "usage: %s [--quick] [--check] [--csv PATH]\nunknown argument \"%s\"\n",
                    argv[0], argv[i]);
            return 2;
        }
    }
    if (csv_path && (csv = fopen(csv_path, "w")) == NULL) {
        fprintf(stderr, "bench_methods: cannot write %s\n", csv_path);
        return 2;
    }
    fprintf(csv, "case,method,dt,tolerance,error,cpu_s,frames,status\n");
    for (c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        const bench_case *bc = &cases[c];
        size_t k;
        if (quick && !bc->quick)
            continue;
        for (k = 0; k < sizeof methods / sizeof methods[0]; ++k) {
            rbs_method m = methods[k];
            int adaptive = m == RBS_METHOD_ADAPTIVE, j, n = 0;
            double pts[MAXPTS];
            /* the sweep: dt for fixed steps, tolerance for adaptive */
            if (adaptive) {
                const double *tl = quick ? tols_quick : tols_full;
                for (j = 0; tl[j] > 0; ++j)
                    pts[n++] = tl[j];
            } else {
                for (j = 0; j < MAXPTS && bc->dts[j] > 0; ++j)
                    if (!quick || (j >= 1 && j <= 4))
                        pts[n++] = bc->dts[j];
            }
            for (j = 0; j < n; ++j) {
                double dt = adaptive ? bc->adaptive_dt : pts[j], tol = adaptive ? pts[j] : 1e-9;
                result r;
                double cpu = timed(bc, m, dt, tol, &r);
                if (r.status == RBS_E_UNSUPPORTED) {
                    fprintf(csv, "%s,%s,%.10g,%.3g,,,,unsupported\n", bc->name, rbs_method_name(m), dt,
                            adaptive ? tol : 0.0);
                    break; /* the rest of this sweep would be refused too */
                }
                if (r.status != RBS_OK) {
                    char *p;
                    for (p = r.why; *p; ++p)
                        if (*p == ',' || *p == '\n' || *p == '"')
                            *p = ' ';
                    fprintf(csv, "%s,%s,%.10g,%.3g,,,%ld,failed: %s\n", bc->name, rbs_method_name(m), dt,
                            adaptive ? tol : 0.0, r.frames, r.why);
                    continue;
                }
                fprintf(csv, "%s,%s,%.10g,%.3g,%.6e,%.6e,%ld,ok\n", bc->name, rbs_method_name(m), dt,
                        adaptive ? tol : 0.0, r.error, cpu, r.frames);
                fflush(csv);
                if (strcmp(bc->name, "circular") == 0 && fits[m].n < MAXPTS && r.error > 0.0) {
                    fits[m].x[fits[m].n] = adaptive ? tol : dt;
                    fits[m].y[fits[m].n] = r.error;
                    fits[m].n++;
                }
            }
        }
    }
    if (csv != stdout)
        fclose(csv);

    if (check) {
        /* orders on the circular orbit */
        const struct { rbs_method m; double p; } want[3] = {
            {RBS_METHOD_EULER, 1.0}, {RBS_METHOD_VERLET, 2.0}, {RBS_METHOD_RK4, 4.0}};
        for (i = 0; i < 3; ++i) {
            const fit *f = &fits[want[i].m];
            double p = f->n >= 3 ? slope(f) : NAN;
            int ok = fabs(p - want[i].p) <= 0.3;
            fprintf(stderr, "check: %s order %.3f on the circular orbit (expected %.0f +- 0.3): %s\n",
                    rbs_method_name(want[i].m), p, want[i].p, ok ? "ok" : "FAILED");
            failures += !ok;
        }
        {
            const fit *f = &fits[RBS_METHOD_ADAPTIVE];
            int ok = f->n >= 3 && f->y[f->n - 1] < 1e-2 * f->y[0] && f->x[f->n - 1] <= 1e-4 * f->x[0];
            fprintf(stderr, "check: adaptive error %.3e at tol %.0e, %.3e at tol %.0e (expected 100x "
                    "smaller): %s\n", f->n ? f->y[0] : NAN, f->n ? f->x[0] : NAN,
                    f->n ? f->y[f->n - 1] : NAN, f->n ? f->x[f->n - 1] : NAN, ok ? "ok" : "FAILED");
            failures += !ok;
        }
    }
    return failures ? 1 : 0;
}
