/*
 * step_event.c - exact event-driven stepping (RBS_METHOD_EVENT).
 *
 * Between events every moving sphere has constant linear and angular
 * acceleration, so its motion is integrated in closed form:
 *   x(s) = x + v s + a s^2/2,  v(s) = v + a s,  w(s) = w + alpha s.
 * A sphere is either free (gravity + applied force and torque) or on one
 * plane, where it rolls (the friction that keeps the contact point still is
 * at most mu_s N) or slides (friction mu_k N against the slip).
 *
 * Events, processed in time order within each frame [t, t + dt]:
 *  - impact: the earliest time a gap function crosses zero while closing:
 *    sphere-plane gap(s) is a quadratic, sphere-sphere |d(s)|^2 - R^2 a
 *    quartic.  Its roots are bracketed between the roots of its derivative
 *    (GSL's gsl_poly_solve_quadratic / gsl_poly_solve_cubic), so grazing
 *    (near-double) roots are found, then polished by safeguarded Newton.
 *  - a sliding sphere's slip reaches zero: it starts to roll.
 * At an event, contacts are resolved with the core's impulse law (the same
 * restitution and Coulomb friction as the other methods).  A contact that
 * approaches slower than the speed one frame of the applied forces builds
 * (|a_rel . n| dt) is made plastic, so a bouncing ball's Zeno cascade ends in
 * resting contact after finitely many events.
 *
 * Scope (checked; anything else is RBS_E_UNSUPPORTED with the reason): spheres
 * with isotropic inertia and a centred mass, uniform gravity and constant
 * applied forces, no mutual gravity, no rolling or spinning resistance, and
 * resting contact with at most one plane per sphere (no stacks, corners or
 * spheres pressed together).  Orientation is exact when a sphere's angular
 * acceleration is zero or parallel to its angular velocity, and second order
 * otherwise (sub-segments of at most dt/16).
 */
#include <string.h>

#include <gsl/gsl_poly.h>

#include "core/world_internal.h"

enum { EV_FREE = 0, EV_ROLL = 1, EV_SLIDE = 2 };

/* Events per step: at most max_substeps * EV_EVENTS_PER_SUBSTEP (1,048,576
 * at the default max_substeps), the same bound on a step's work as the
 * other methods' sub-steps. */
#define EV_EVENTS_PER_SUBSTEP 256u
#define EV_MAX_STALLED 1000u

/* ------------------------------------------------------------------------- */
/* Roots                                                                     */
/* ------------------------------------------------------------------------- */

static double poly_eval(const double *c, int deg, double s)
{
    double r = c[deg];
    int k;
    for (k = deg - 1; k >= 0; --k)
        r = r * s + c[k];
    return r;
}

static double poly_deriv(const double *c, int deg, double s)
{
    double r = deg * c[deg];
    int k;
    for (k = deg - 1; k >= 1; --k)
        r = r * s + k * c[k];
    return r;
}

/* Root of f in [lo, hi] where f(lo) > 0 >= f(hi) and f is monotone:
 * Newton steps kept inside the bracket, bisection when they leave it. */
static double bracketed_root(const double *c, int deg, double lo, double hi)
{
    double s = hi, flo = poly_eval(c, deg, lo);
    int it;
    (void)flo;
    s = 0.5 * (lo + hi);
    for (it = 0; it < 200; ++it) {
        double f = poly_eval(c, deg, s), d, next;
        if (f > 0.0)
            lo = s;
        else
            hi = s;
        d = poly_deriv(c, deg, s);
        next = d != 0.0 ? s - f / d : 0.5 * (lo + hi);
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        if (next == s || hi - lo <= 4.0 * 2.220446049250313e-16 * hi)
            break;
        s = next;
    }
    /* the earliest time the gap is closed: the bracket's upper end */
    return hi;
}

/* Earliest s in (0, smax] where the polynomial (degree <= 4, c[0] = f(0))
 * crosses from > 0 to <= 0.  Returns smax + 1 if none. */
static double first_closing(const double *c, int deg, double smax)
{
    double crit[4] = {0, 0, 0, 0}, pts[6], d[4];
    int n = 0, k, m = 0;
    while (deg > 0 && c[deg] == 0.0)
        deg--;
    if (deg == 0)
        return smax + 1.0;
    /* critical points: roots of the derivative */
    for (k = 1; k <= deg; ++k)
        d[k - 1] = k * c[k];
    if (deg == 2) {
        crit[n++] = -d[0] / d[1];
    } else if (deg == 3) {
        n = gsl_poly_solve_quadratic(d[2], d[1], d[0], &crit[0], &crit[1]);
    } else if (deg == 4) {
        n = gsl_poly_solve_cubic(d[2] / d[3], d[1] / d[3], d[0] / d[3], &crit[0], &crit[1], &crit[2]);
    }
    pts[m++] = 0.0;
    for (k = 0; k < n; ++k)
        if (crit[k] > 0.0 && crit[k] < smax)
            pts[m++] = crit[k];
    pts[m++] = smax;
    /* sort the few points */
    for (k = 1; k < m; ++k) {
        double x = pts[k];
        int j = k - 1;
        while (j >= 0 && pts[j] > x) {
            pts[j + 1] = pts[j];
            --j;
        }
        pts[j + 1] = x;
    }
    for (k = 0; k + 1 < m; ++k) {
        double lo = pts[k], hi = pts[k + 1];
        double flo = poly_eval(c, deg, lo), fhi = poly_eval(c, deg, hi);
        if (hi <= lo)
            continue;
        if (flo > 0.0 && fhi <= 0.0)
            return bracketed_root(c, deg, lo, hi);
    }
    return smax + 1.0;
}

/* ------------------------------------------------------------------------- */
/* Motion between events                                                     */
/* ------------------------------------------------------------------------- */

static int zero3(v3 a) { return a.x == 0.0 && a.y == 0.0 && a.z == 0.0; }

/* Check the scene is within the method's scope. */
static rbs_status check_scope(rbs_world *w)
{
    uint32_t k;
    int32_t row;
    if (w->plan.mutual_acts) /* (on, but with nothing to act on, it is not in the scene) */
        return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
            "method \"event\": mutual gravity is not a constant force; use \"adaptive\"");
    /* (only a row some contact can take: one on no body's materials is
     * not in the scene) */
    if ((row = rbs__row_in_use(w, 1)) >= 0) {
        const rbs__pair *r = &w->pair[row];
        return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
            "method \"event\": rolling and spinning resistance are not supported (pair \"%s\"/\"%s\"); use "
            "\"euler\"", r->a ? w->material_name[r->a - 1] : "*", r->b ? w->material_name[r->b - 1] : "*");
    }
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        if (w->fixed[i])
            continue;
        if (!w->isotropic[i] || !zero3(v3_load(&w->com_body[3 * i])))
            return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
                "method \"event\": sphere %u (\"%s\") has anisotropic inertia or an off-centre mass; use \"euler\"",
                (unsigned)i, w->name[i]);
    }
    return RBS_OK;
}

/* Friction on a sphere on plane p with normal n: the row of its pair. */
static void pair_friction(const rbs_world *w, uint32_t i, uint32_t p, double *mu_s, double *mu_k)
{
    uint32_t n = w->def.max_materials + 1;
    int32_t row = w->pair_table[w->material[i] * n + w->material[p]];
    *mu_s = row >= 0 ? w->pair[row].mu_s : 0.0;
    *mu_k = row >= 0 ? w->pair[row].mu_k : 0.0;
}

/* How long body i's acceleration (as classify left it) lasts at most,
 * within dt: a sliding sphere's lasts until its slip stops (straight: the
 * exact time; curving: re-evaluated after dt/16, as the event search does);
 * any other's all of dt (until an event changes it). */
static double accel_lasts(const rbs_world *w, uint32_t i, double dt)
{
    uint32_t p;
    v3 n, u, du, cr;
    double uu, ud, s;
    if (w->fixed[i] || w->ev_mode[i] != EV_SLIDE)
        return dt;
    p = w->ev_plane[i];
    n = v3_load(&w->normal[3 * p]);
    u = v3_sub(v3_load(&w->vel[3 * i]), v3_scale(v3_cross(v3_load(&w->avel[3 * i]), n), w->radius[i]));
    du = v3_sub(v3_load(&w->acc[3 * i]), v3_scale(v3_cross(v3_load(&w->ev_alpha[3 * i]), n), w->radius[i]));
    uu = v3_dot(u, u);
    ud = v3_dot(u, du);
    if (!(ud < 0.0))
        return dt;
    s = -uu / ud;
    cr = v3_cross(u, du);
    if (v3_dot(cr, cr) > 1e-24 * uu * v3_dot(du, du) && dt / 16.0 < s)
        s = dt / 16.0;
    return s < dt ? s : dt;
}

/* Decide each moving sphere's mode and its constant accelerations (w->acc,
 * w->ev_alpha).  Returns an error for configurations out of scope. */
static rbs_status classify(rbs_world *w, double dt)
{
    rbs__coarse coarse;
    uint32_t k, q, j;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k], plane = UINT32_MAX;
        v3 a, tau, x, v, alpha;
        double r = w->radius[i], m = w->mass[i], I = rbs__inertia_xx(w, i), invI = rbs__inv_inertia_xx(w, i);
        if (w->fixed[i])
            continue;
        rbs__accelerations(w, i, &a, &tau);
        x = v3_load(&w->pos[3 * i]);
        v = v3_load(&w->vel[3 * i]);
        /* planes it rests on: touching, pressed by the forces, and not
         * leaving (up to rounding: 1e-9 of the speed one frame of them
         * builds, the resting threshold).  A departure slower than that
         * threshold is a bounce's, which flies: only approaches below it
         * are plastic (resolve_contacts); taken as rest, it made a 4 m/s
         * impact with e = 0.1 at dt = 0.05 s dead (a probe of session 39) */
        for (q = 0; q < w->plane_count; ++q) {
            uint32_t p = w->planes[q];
            v3 n = v3_load(&w->normal[3 * p]);
            double gap = v3_dot(v3_sub(x, v3_load(&w->pos[3 * p])), n) - r;
            double an = v3_dot(a, n), vn = v3_dot(v, n);
            /* (touching where its coordinates cannot resolve the slop:
             * far from the origin) */
            if (rbs__coarse_touch(w, i, p, gap, w->def.slop * r, &coarse))
                return rbs__coarse_error(w, &coarse);
            if (gap > w->def.slop * r || !(an < 0.0) || vn > -an * dt * 1e-9)
                continue;
            if (plane != UINT32_MAX) {
                char tb[40];
                return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
                    "method \"event\": sphere %u (\"%s\") rests on two planes at t = %s; use \"euler\"",
                    (unsigned)i, w->name[i], rbs__shortest(tb, rbs_world_time(w)));
            }
            plane = p;
        }
        w->ev_plane[i] = plane;
        if (plane == UINT32_MAX) {
            w->ev_mode[i] = EV_FREE;
            v3_store(&w->acc[3 * i], a);
            v3_store(&w->ev_alpha[3 * i], v3_scale(tau, invI));
            continue;
        }
        {
            v3 n = v3_load(&w->normal[3 * plane]), om = v3_load(&w->avel[3 * i]);
            double an = v3_dot(a, n), N = -m * an, mu_s, mu_k, kk = 1.0 / m + r * r / I;
            v3 gt = v3_mad(a, n, -an), u, f, tn = v3_cross(tau, n);
            /* resting normal: cancel the small approach or departure */
            v = v3_mad(v, n, -v3_dot(v, n));
            v3_store(&w->vel[3 * i], v);
            pair_friction(w, i, plane, &mu_s, &mu_k);
            u = v3_sub(v, v3_scale(v3_cross(om, n), r)); /* contact point velocity */
            /* Rolling: the slip within rounding of the speeds -- and of
             * what the slip can change in a frame (the drive and the
             * kinetic friction): at a slip's stop that finds the sphere
             * nearly still (a large inertia stops it as it rolls), the speeds
             * are as small as the slip's rounding, and by them alone it was
             * taken as sliding, on a direction of rounding (a probe of
             * session 38: I = 1e9 m r^2 up an incline slid back down). */
            const double du = v3_len(v3_sub(gt, v3_scale(tn, r / I))) + mu_k * N * kk;
            if (v3_len(u) <= 1e-12 * (v3_len(v) + r * v3_len(om) + du * dt) + 1e-300) {
                /* the slip stopped: remove its rounding, so that rolling is
                 * exact, and a slide starts from a slip of exactly 0 (left,
                 * it pointed anywhere, and at the top of a frictionless
                 * slide up an incline its stop was due again at once, event
                 * after event, until the step gave up -- a probe of session
                 * 39) */
                if (!zero3(u)) {
                    v3 jimp = v3_scale(u, -1.0 / kk);
                    v = v3_mad(v, jimp, 1.0 / m);
                    om = v3_add(om, v3_scale(v3_cross(v3_scale(n, -r), jimp), invI));
                    v3_store(&w->vel[3 * i], v);
                    v3_store(&w->avel[3 * i], om);
                }
                /* rolls if the friction that keeps it rolling is available */
                f = v3_scale(v3_sub(v3_scale(tn, r / I), gt), 1.0 / kk);
                if (v3_len(f) <= mu_s * N) {
                    w->ev_mode[i] = EV_ROLL;
                } else {
                    /* starts to slide along the drive c = g_t - (r/I) tau x n */
                    v3 c = v3_sub(gt, v3_scale(tn, r / I));
                    double cl = v3_len(c);
                    f = cl > 0.0 ? v3_scale(c, -mu_k * N / cl) : v3_make(0, 0, 0);
                    w->ev_mode[i] = EV_SLIDE;
                }
            } else {
                f = v3_scale(u, -mu_k * N / v3_len(u));
                w->ev_mode[i] = EV_SLIDE;
            }
            a = v3_mad(gt, f, 1.0 / m);
            alpha = v3_scale(v3_sub(tau, v3_scale(v3_cross(n, f), r)), invI);
            v3_store(&w->acc[3 * i], a);
            v3_store(&w->ev_alpha[3 * i], alpha);
        }
    }
    /* spheres pressed together by their accelerations are out of scope */
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 x = v3_load(&w->pos[3 * i]), v = v3_load(&w->vel[3 * i]);
        v3 a = w->fixed[i] ? v3_make(0, 0, 0) : v3_load(&w->acc[3 * i]);
        double r = w->radius[i], lasts = accel_lasts(w, i, dt);
        for (j = k + 1; j < w->sphere_count; ++j) {
            uint32_t b = w->spheres[j];
            v3 d, ab;
            double dist, rel_an, vn, rb = w->radius[b];
            if (w->fixed[i] && w->fixed[b])
                continue;
            d = v3_sub(x, v3_load(&w->pos[3 * b]));
            dist = v3_len(d);
            if (rbs__coarse_touch(w, i, b, dist - r - rb, w->def.slop * (r < rb ? r : rb), &coarse))
                return rbs__coarse_error(w, &coarse);
            if (dist - r - rb > w->def.slop * (r < rb ? r : rb) || dist == 0.0)
                continue;
            d = v3_scale(d, 1.0 / dist);
            ab = w->fixed[b] ? v3_make(0, 0, 0) : v3_load(&w->acc[3 * b]);
            rel_an = v3_dot(v3_sub(a, ab), d);
            vn = v3_dot(v3_sub(v, v3_load(&w->vel[3 * b])), d);
            /* pressed: the accelerations bring the pair back together, or
             * hold it, within the time they last -- a sliding sphere's
             * friction stops with its slip (a ball rolling at 1 mm/s into
             * a resting one with mu = 0.5 left it sliding for 58 us, its
             * friction pressing the pair that whole time against a whole
             * frame's worth: refused, though they part; a probe of
             * session 43).  A relative acceleration within rounding of
             * the two accelerations (1e-12 of them, as the slip's test in
             * classify) is none: two balls rolling together down an
             * incline, each at 5/7 g_t whatever its size, were refused as
             * a stack or not by the sign of that rounding, by which of
             * them was ahead (a probe of session 47) */
            if (rel_an < -1e-12 * (v3_len(a) + v3_len(ab)) &&
                vn <= -rel_an * fmin(lasts, accel_lasts(w, b, dt))) {
                char tb[40];
                return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
                    "method \"event\": spheres %u and %u are pressed together at t = %s (a stack or "
                    "a pile); use \"euler\"", (unsigned)i, (unsigned)b, rbs__shortest(tb, rbs_world_time(w)));
            }
        }
    }
    return RBS_OK;
}

/* Rotate q by the motion w(t) = w0 + alpha t over s seconds. */
static quat rotate_over(quat q, v3 w0, v3 alpha, double s, double dt)
{
    v3 c = v3_cross(w0, alpha);
    if (zero3(alpha) || (v3_dot(c, c) <= 1e-30 * v3_dot(w0, w0) * v3_dot(alpha, alpha))) {
        /* fixed axis: rotate by the integral w0 s + alpha s^2 / 2, exactly */
        v3 turn = v3_mad(v3_scale(w0, s), alpha, 0.5 * s * s);
        if (zero3(turn))
            return q;
        return q_normalize(q_mul(q_from_rotation(turn, 1.0), q));
    } else {
        /* changing axis: midpoint rotations over sub-segments <= dt/16 */
        double m = ceil(s / (dt / 16.0)), h;
        int n, k;
        /* s <= dt within a frame, so at most 16 pieces; a denormal dt can
         * make the ratio infinite: clamp before converting */
        n = m >= 1.0 && m <= 16.0 ? (int)m : (m > 16.0 ? 16 : 1);
        h = s / n;
        for (k = 0; k < n; ++k) {
            v3 wm = v3_mad(w0, alpha, (k + 0.5) * h);
            q = q_normalize(q_mul(q_from_rotation(wm, h), q));
        }
        return q;
    }
}

static void advance(rbs_world *w, double s, double dt)
{
    uint32_t k;
    if (s <= 0.0)
        return;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 x, v, a, om, al;
        if (w->fixed[i])
            continue;
        x = v3_load(&w->pos[3 * i]);
        v = v3_load(&w->vel[3 * i]);
        a = v3_load(&w->acc[3 * i]);
        om = v3_load(&w->avel[3 * i]);
        al = v3_load(&w->ev_alpha[3 * i]);
        v3_store(&w->pos[3 * i], v3_add(x, v3_mad(v3_scale(v, s), a, 0.5 * s * s)));
        v3_store(&w->vel[3 * i], v3_mad(v, a, s));
        if (!zero3(om) || !zero3(al)) {
            q_store(&w->orient[4 * i], rotate_over(q_load(&w->orient[4 * i]), om, al, s, dt));
            v3_store(&w->avel[3 * i], v3_mad(om, al, s));
        }
    }
}

/* Earliest next event within (0, smax]; smax + 1 if none. */
static double next_event(const rbs_world *w, double smax, double dt)
{
    double best = smax + 1.0;
    uint32_t k, q, j;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 x = v3_load(&w->pos[3 * i]), v = v3_load(&w->vel[3 * i]), a = v3_load(&w->acc[3 * i]);
        double r = w->radius[i];
        int moves = !w->fixed[i];
        if (moves) {
            if (w->fixed[i])
                a = v3_make(0, 0, 0);
            for (q = 0; q < w->plane_count; ++q) {
                uint32_t p = w->planes[q];
                v3 n;
                double c[3], s;
                if (w->ev_mode[i] != EV_FREE && w->ev_plane[i] == p)
                    continue;
                n = v3_load(&w->normal[3 * p]);
                c[0] = v3_dot(v3_sub(x, v3_load(&w->pos[3 * p])), n) - r;
                c[1] = v3_dot(v, n);
                c[2] = 0.5 * v3_dot(a, n);
                s = first_closing(c, 2, best < smax ? best : smax);
                if (s < best)
                    best = s;
            }
            if (w->ev_mode[i] == EV_SLIDE) {
                /* slip u(s) = u + (du/ds) s; it stops when |u| reaches 0 */
                uint32_t p = w->ev_plane[i];
                v3 n = v3_load(&w->normal[3 * p]), om = v3_load(&w->avel[3 * i]);
                v3 al = v3_load(&w->ev_alpha[3 * i]);
                v3 u = v3_sub(v, v3_scale(v3_cross(om, n), r));
                v3 du = v3_sub(a, v3_scale(v3_cross(al, n), r));
                double uu = v3_dot(u, u), ud = v3_dot(u, du), s;
                v3 cr = v3_cross(u, du);
                if (ud < 0.0) {
                    if (v3_dot(cr, cr) <= 1e-24 * uu * v3_dot(du, du)) {
                        s = -uu / ud; /* straight slip: exact stop time */
                    } else {
                        /* curving slip: re-evaluate after a short segment */
                        s = dt / 16.0;
                        if (-uu / ud < s)
                            s = -uu / ud;
                    }
                    if (s < best)
                        best = s;
                } else if (v3_dot(cr, cr) > 1e-24 * uu * v3_dot(du, du) && dt / 16.0 < best) {
                    best = dt / 16.0;
                }
            }
        }
        for (j = k + 1; j < w->sphere_count; ++j) {
            uint32_t b = w->spheres[j];
            v3 d, dv, da;
            double R = r + w->radius[b], c[5], s;
            if (!moves && w->fixed[b])
                continue;
            d = v3_sub(x, v3_load(&w->pos[3 * b]));
            dv = v3_sub(v, v3_load(&w->vel[3 * b]));
            da = v3_scale(v3_sub(moves ? a : v3_make(0, 0, 0),
                                 w->fixed[b] ? v3_make(0, 0, 0) : v3_load(&w->acc[3 * b])), 0.5);
            /* |d + dv s + da s^2|^2 - R^2 */
            c[0] = v3_dot(d, d) - R * R;
            c[1] = 2.0 * v3_dot(d, dv);
            c[2] = v3_dot(dv, dv) + 2.0 * v3_dot(d, da);
            c[3] = 2.0 * v3_dot(dv, da);
            c[4] = v3_dot(da, da);
            if (c[0] > 0.0) {
                /* quick reject: cannot close the distance within best */
                double hz = best < smax ? best : smax;
                double reach = sqrt(v3_dot(dv, dv)) * hz + sqrt(v3_dot(da, da)) * hz * hz;
                double dist = sqrt(c[0] + R * R) - R;
                if (reach < dist)
                    continue;
            }
            s = first_closing(c, 4, best < smax ? best : smax);
            if (s < best)
                best = s;
        }
    }
    return best;
}

/* Resolve the contacts touching now: impacts with restitution, and plastic
 * impulses for approaches slower than the resting threshold. */
static rbs_status resolve_contacts(rbs_world *w, double dt, rbs_step_info *info)
{
    uint32_t k;
    rbs_status st = rbs__detect(w, dt, 0);
    if (st != RBS_OK)
        return st;
    for (k = 0; k < w->contact_count; ++k) {
        rbs__contact *c = &w->contact[k];
        double vn = rbs__normal_velocity(w, c);
        if (vn < 0.0 && -vn <= c->thr)
            c->flags |= RBS__INELASTIC; /* resting: the Zeno cascade ends here */
        c->thr = 0.0;
    }
    rbs__solve_collisions(w, info);
    return RBS_OK;
}

rbs_status rbs__step_event(rbs_world *w, rbs_step_info *info)
{
    const double dt = w->def.dt;
    double left = dt;
    uint64_t events = 0;
    uint32_t stalled = 0;
    rbs_status st = check_scope(w);
    if (st != RBS_OK)
        return st;
    for (;;) {
        double s;
        st = resolve_contacts(w, dt, info);
        if (st != RBS_OK)
            return st;
        st = classify(w, dt);
        if (st != RBS_OK)
            return st;
        if (left <= 0.0)
            break;
        s = next_event(w, left, dt);
        if (s >= left) {
            advance(w, left, dt);
            left = 0.0;
            continue; /* resolve what touches at the frame's end */
        }
        advance(w, s, dt);
        /* an event that does not move time on (s below what time can
         * resolve here) repeated many times is a stuck configuration, not
         * a collapse: say so early instead of grinding to the cap */
        if (!(left - s < left)) {
            if (++stalled >= EV_MAX_STALLED) {
                char tb[40];
                return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                    "method \"event\": %u events in a row at t = %s did not advance time "
                    "(bodies jammed at a grazing contact?); use \"euler\"",
                    EV_MAX_STALLED, rbs__shortest(tb, rbs_world_time(w) + (dt - left)));
            }
        } else {
            stalled = 0;
        }
        left -= s;
        info->events++;
        if (++events >= (uint64_t)w->def.max_substeps * EV_EVENTS_PER_SUBSTEP)
            return (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED,
                "method \"event\": more than %llu events in one step (max_substeps %u x %u; "
                "inelastic collapse?); use \"euler\"",
                (unsigned long long)w->def.max_substeps * EV_EVENTS_PER_SUBSTEP,
                (unsigned)w->def.max_substeps, EV_EVENTS_PER_SUBSTEP);
    }
    info->substeps = 1;
    info->contacts = w->contact_count;
    info->max_overlap = rbs__max_overlap(w);
    return RBS_OK;
}
