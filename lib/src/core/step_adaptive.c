/*
 * step_adaptive.c - GSL odeiv2 with error control between contacts
 * (RBS_METHOD_ADAPTIVE).
 *
 * State: every moving sphere's centre of mass x, velocity v, orientation q
 * (4 components, renormalised after every accepted step) and angular
 * velocity w, packed 13 doubles a sphere into one vector of 13 * max_bodies
 * (unused tail entries stay zero and cost no error).  The right-hand side is
 *   x' = v,  v' = g + F/m + mutual gravity,  q' = 1/2 (0, w) q,
 *   w' = I^-1 (tau - w x I w)          (world frame)
 * integrated by GSL's Prince-Dormand 8(9) (gsl_odeiv2_step_rk8pd) under
 * gsl_odeiv2_evolve_apply with the standard control on y, absolute and
 * relative tolerance def.tolerance.  The step-size suggestion is carried
 * from frame to frame (in the world block, so checkpoints keep it); frames
 * still end exactly at k dt (GSL clips the last step).
 *
 * Contacts.  After every accepted step [t0, t1] the gap of every pair that
 * was apart at t0 is checked at t1, and inside the step: sphere-plane gaps
 * by their cubic Hermite interpolant from the end values and slopes (exact
 * for the parabolas of uniform gravity), sphere pairs along the straight
 * path between the two states (the swept test of the rollback methods).  A
 * pair that went through zero brackets an event; its time is found by
 * Brent's method (gsl_root_fsolver_brent) on the smallest gap, each trial
 * time s evaluated by re-integrating from the state at t0 with one rk8pd
 * step of s - t0 (no longer than the accepted step, so within tolerance).
 * The contact time is accepted when the gap is within 1e-3 of the pair's
 * slop.  There the core's impulses are applied (rbs__detect,
 * rbs__solve_collisions) and integration goes on; a contact whose applied
 * forces pull it apart (a ball under a ceiling) cannot rest, so even a slow
 * approach there bounces with restitution.  A contact that after the
 * collision pass does not separate faster than one frame of forces builds
 * (resting, rolling or sliding, a Zeno cascade) cannot be integrated by a
 * smooth ODE: the rest of that frame is stepped with the RK4 rollback
 * sub-steps (rbs__rk4_advance), which keep the resting pass.
 *
 * Limits (docs/methods.md): a sphere pair that touches and parts again
 * inside one accepted step along a curved path is not seen (the swept test
 * assumes straight relative motion over the step).  Work: a frame of more
 * than max_substeps contact events takes the rest of the frame as one RK4
 * sub-step, overlap pushed apart (work_limit); one of more than
 * max_substeps * 25 accepted ODE steps is RBS_E_NUMERIC (a tolerance too
 * tight for the forces).
 *
 * Memory: GSL's workspaces come from GSL's own allocator (malloc).  They are
 * allocated once, when a world is created with, or switched to, the
 * adaptive method (rbs__adaptive_reserve), and freed by rbs_world_destroy;
 * stepping allocates nothing.  This is the one exception to "a world takes
 * no memory but its block", documented in docs/methods.md.
 *
 * GSL errors: GSL's default error handler aborts, and replacing it is
 * process-global state, so this file never calls GSL in a way that can
 * raise one: the system's dimension always matches, the root finder is
 * only started on a checked bracket, and the functions it calls always
 * return finite values (a non-finite state is reported as RBS_E_NUMERIC).
 */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_roots.h>

#include "core/world_internal.h"

#define STRIDE 13            /* doubles per sphere in the ODE state */
#define STEPS_PER_SUBSTEP 25u /* accepted steps in one frame before giving up:
                                 max_substeps * 25 (102,400 at the default),
                                 the work bound the other methods share */
#define MIN_TOL 1e-15        /* below this, double precision cannot deliver */

struct rbs__adaptive {
    size_t dim;
    gsl_odeiv2_step *step;
    gsl_odeiv2_control *control;
    gsl_odeiv2_evolve *evolve;
    gsl_root_fsolver *root;
    gsl_odeiv2_system sys;
    double tol;        /* tolerance the control was set up with */
    rbs_world *w;
    uint32_t n;        /* packed moving spheres */
    uint32_t *map;     /* slot of each packed sphere (max_bodies) */
    int32_t *index;    /* packed index of each slot, -1 if not packed */
    double *y, *y0, *yt, *yerr;  /* dim each */
    uint32_t *flag;    /* flagged pairs: (a, b) slots, 2 * max_contacts */
    uint32_t flagged;
    uint32_t flag_cap;
    double t0;         /* start of the step being searched */
    int bad;           /* a non-finite state was met while root finding */
    uint32_t bad_body; /* slot whose derivative was not finite */
};

/* ------------------------------------------------------------------------- */
/* Workspaces                                                                */
/* ------------------------------------------------------------------------- */

static int rhs(double t, const double y[], double dydt[], void *params);

void rbs__adaptive_release(rbs_world *w)
{
    rbs__adaptive *a = w->adaptive;
    if (a == NULL)
        return;
    if (a->root)
        gsl_root_fsolver_free(a->root);
    if (a->evolve)
        gsl_odeiv2_evolve_free(a->evolve);
    if (a->control)
        gsl_odeiv2_control_free(a->control);
    if (a->step)
        gsl_odeiv2_step_free(a->step);
    free(a);
    w->adaptive = NULL;
}

rbs_status rbs__adaptive_reserve(rbs_world *w)
{
    rbs__adaptive *a;
    size_t B = w->def.max_bodies, C = w->def.max_contacts, dim = STRIDE * B, bytes;
    unsigned char *p;
    if (w->adaptive != NULL)
        return RBS_OK;
    /* the struct, then the arrays, in one allocation */
    bytes = sizeof *a + 4 * dim * sizeof(double) + B * sizeof(uint32_t) + B * sizeof(int32_t) +
            2 * C * sizeof(uint32_t);
    p = calloc(1, bytes);
    if (p == NULL)
        return RBS_E_MEMORY;
    a = (rbs__adaptive *)p;
    p += sizeof *a;
    a->y = (double *)p;
    a->y0 = a->y + dim;
    a->yt = a->y0 + dim;
    a->yerr = a->yt + dim;
    a->map = (uint32_t *)(a->yerr + dim);
    a->index = (int32_t *)(a->map + B);
    a->flag = (uint32_t *)(a->index + B);
    a->flag_cap = (uint32_t)C;
    a->dim = dim;
    a->w = w;
    a->tol = w->def.tolerance;
    a->sys.function = rhs;
    a->sys.jacobian = NULL;
    a->sys.dimension = dim;
    a->sys.params = a;
    w->adaptive = a;
    a->step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, dim);
    a->control = gsl_odeiv2_control_y_new(a->tol, a->tol);
    a->evolve = gsl_odeiv2_evolve_alloc(dim);
    a->root = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    if (!a->step || !a->control || !a->evolve || !a->root) {
        rbs__adaptive_release(w);
        return RBS_E_MEMORY;
    }
    return RBS_OK;
}

/* ------------------------------------------------------------------------- */
/* State vector                                                              */
/* ------------------------------------------------------------------------- */

/* Pack the moving spheres of the world into a->y (and build the map). */
static void pack(rbs__adaptive *a)
{
    rbs_world *w = a->w;
    uint32_t k, n = 0;
    for (k = 0; k < w->slots; ++k)
        a->index[k] = -1;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *y;
        if (w->fixed[i])
            continue;
        a->map[n] = i;
        a->index[i] = (int32_t)n;
        y = &a->y[STRIDE * n];
        v3_store(y, rbs__body_com(w, i));
        memcpy(y + 3, &w->vel[3 * i], 3 * sizeof(double));
        memcpy(y + 6, &w->orient[4 * i], 4 * sizeof(double));
        memcpy(y + 10, &w->avel[3 * i], 3 * sizeof(double));
        n++;
    }
    /* entries past the packed spheres stay zero */
    memset(&a->y[STRIDE * n], 0, (a->dim - STRIDE * n) * sizeof(double));
    a->n = n;
}

/* Geometric centre of packed sphere k in state y. */
static v3 centre_of(const rbs_world *w, uint32_t i, const double *y)
{
    v3 c = v3_load(&w->com_body[3 * i]);
    if (c.x == 0.0 && c.y == 0.0 && c.z == 0.0)
        return v3_load(y);
    return v3_sub(v3_load(y), q_rotate(q_normalize(q_load(y + 6)), c));
}

/* Write state y back into the world (orientations renormalised). */
static void unpack(rbs__adaptive *a, const double *y)
{
    rbs_world *w = a->w;
    uint32_t k;
    for (k = 0; k < a->n; ++k) {
        uint32_t i = a->map[k];
        const double *s = &y[STRIDE * k];
        quat q = q_normalize(q_load(s + 6));
        q_store(&w->orient[4 * i], q);
        v3_store(&w->pos[3 * i], centre_of(w, i, s));
        memcpy(&w->vel[3 * i], s + 3, 3 * sizeof(double));
        memcpy(&w->avel[3 * i], s + 10, 3 * sizeof(double));
    }
}

/* The right-hand side.  Every "zero" shortcut tests the values, so the
 * pruned and the full pipeline compute the same bits. */
static int rhs(double t, const double y[], double dydt[], void *params)
{
    rbs__adaptive *a = (rbs__adaptive *)params;
    const rbs_world *w = a->w;
    uint32_t k, j;
    (void)t;
    memset(dydt, 0, a->dim * sizeof(double));
    for (k = 0; k < a->n; ++k) {
        uint32_t i = a->map[k];
        const double *s = &y[STRIDE * k];
        double *d = &dydt[STRIDE * k];
        v3 acc, tau, om = v3_load(s + 10);
        rbs__accelerations(w, i, &acc, &tau);
        memcpy(d, s + 3, 3 * sizeof(double));
        v3_store(d + 3, acc);
        /* rotation by any angular velocity, as the other methods (contacts
         * can leave rounding-level spin on any body) */
        if (om.x != 0.0 || om.y != 0.0 || om.z != 0.0) {
            quat o = {0.0, om.x, om.y, om.z}, qd = q_mul(o, q_load(s + 6));
            d[6] = 0.5 * qd.w; d[7] = 0.5 * qd.x; d[8] = 0.5 * qd.y; d[9] = 0.5 * qd.z;
        }
        /* angular acceleration: zero unless there is a torque or the
         * gyroscopic term (the plan leaves it out only then) */
        if (w->plan.angular) {
            quat qn = q_normalize(q_load(s + 6));
            if (!w->isotropic[i])
                tau = v3_sub(tau, v3_cross(om, m3_mul_world(&w->inertia[9 * i], qn, om)));
            if (tau.x != 0.0 || tau.y != 0.0 || tau.z != 0.0) {
                v3 al;
                if (w->isotropic[i])
                    al = v3_scale(tau, w->iso_inv_inertia[i]);
                else
                    al = m3_mul_world(&w->inv_inertia[9 * i], qn, tau);
                v3_store(d + 10, al);
            }
        }
    }
    /* Mutual gravity: moving pairs from y, fixed spheres from the world. */
    if (w->plan.mutual) {
        double G = w->def.gravity_constant, eps2 = w->def.softening * w->def.softening;
        for (k = 0; k < w->sphere_count; ++k) {
            uint32_t ia = w->spheres[k];
            int32_t pa = a->index[ia];
            v3 xa = pa >= 0 ? v3_load(&y[STRIDE * pa]) : rbs__body_com(w, ia);
            for (j = k + 1; j < w->sphere_count; ++j) {
                uint32_t ib = w->spheres[j];
                int32_t pb = a->index[ib];
                v3 d = v3_sub(pb >= 0 ? v3_load(&y[STRIDE * pb]) : rbs__body_com(w, ib), xa);
                double r2 = v3_dot(d, d) + eps2, inv3;
                if (!(r2 > 0.0) || (pa < 0 && pb < 0))
                    continue;
                inv3 = G / (r2 * sqrt(r2));
                if (pa >= 0)
                    v3_store(&dydt[STRIDE * pa + 3], v3_mad(v3_load(&dydt[STRIDE * pa + 3]), d, inv3 * w->mass[ib]));
                if (pb >= 0)
                    v3_store(&dydt[STRIDE * pb + 3], v3_mad(v3_load(&dydt[STRIDE * pb + 3]), d, -inv3 * w->mass[ia]));
            }
        }
    }
    for (k = 0; k < STRIDE * a->n; ++k) {
        if (!isfinite(dydt[k])) {
            /* (not GSL_EBADFUNC, which ends the step: a trial stage of too
             * long a step can overflow where the motion does not -- the
             * gyroscopic term of a top at 2e5 rad/s, squared through
             * rk8pd's stages at dt = 1 ms, a probe of session 43 -- so
             * GSL halves the step and tries again; it fails only when the
             * step can shrink no more) */
            a->bad_body = a->map[k / STRIDE];
            return GSL_FAILURE;
        }
    }
    return GSL_SUCCESS;
}

/* ------------------------------------------------------------------------- */
/* Gaps and events                                                           */
/* ------------------------------------------------------------------------- */

/* Centre of slot i in state y (fixed spheres from the world). */
static v3 centre_in(const rbs__adaptive *a, uint32_t i, const double *y)
{
    int32_t p = a->index[i];
    return p >= 0 ? centre_of(a->w, i, &y[STRIDE * p]) : v3_load(&a->w->pos[3 * i]);
}

/* Gap of pair (i, b) in state y: b is a plane or a sphere. */
static double pair_gap(const rbs__adaptive *a, uint32_t i, uint32_t b, const double *y)
{
    const rbs_world *w = a->w;
    v3 pa = centre_in(a, i, y);
    if (w->type[b] == RBS_BODY_PLANE)
        return v3_dot(v3_sub(pa, v3_load(&w->pos[3 * b])), v3_load(&w->normal[3 * b])) - w->radius[i];
    return v3_len(v3_sub(pa, centre_in(a, b, y))) - w->radius[i] - w->radius[b];
}

/* Velocity of slot i's geometric centre in state y (zero for fixed). */
static v3 centre_vel(const rbs__adaptive *a, uint32_t i, const double *y)
{
    int32_t p = a->index[i];
    const double *s;
    v3 c, v;
    if (p < 0)
        return v3_make(0.0, 0.0, 0.0);
    s = &y[STRIDE * p];
    v = v3_load(s + 3);
    c = v3_load(&a->w->com_body[3 * i]);
    if (c.x != 0.0 || c.y != 0.0 || c.z != 0.0)
        v = v3_sub(v, v3_cross(v3_load(s + 10), q_rotate(q_normalize(q_load(s + 6)), c)));
    return v;
}

/* Lowest point in (0, 1) of the cubic Hermite interpolant of a gap with
 * values g0, g1 and end slopes m0, m1 (per unit s); exact for the parabolic
 * motion of uniform gravity.  Returns 1 and its s and value when the
 * interpolant dips below zero inside the step. */
static int hermite_dip(double g0, double g1, double m0, double m1, double *s_min, double *g_min)
{
    double A = 6.0 * (g0 - g1) + 3.0 * (m0 + m1), B = -6.0 * (g0 - g1) - 4.0 * m0 - 2.0 * m1, C = m0;
    double r[2], best = HUGE_VAL, sb = 0.0;
    int n = 0, k;
    if (A != 0.0) {
        double disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            double q = -0.5 * (B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
            r[n++] = q / A;
            if (q != 0.0)
                r[n++] = C / q;
        }
    } else if (B != 0.0) {
        r[n++] = -C / B;
    }
    for (k = 0; k < n; ++k) {
        double x = r[k], g;
        if (!(x > 0.0 && x < 1.0))
            continue;
        g = (2.0 * x * x * x - 3.0 * x * x + 1.0) * g0 + (x * x * x - 2.0 * x * x + x) * m0 +
            (-2.0 * x * x * x + 3.0 * x * x) * g1 + (x * x * x - x * x) * m1;
        if (g < best) {
            best = g;
            sb = x;
        }
    }
    if (!(best < 0.0))
        return 0;
    *s_min = sb;
    *g_min = best;
    return 1;
}

/* Smallest gap over the flagged pairs in state y. */
static double min_gap(const rbs__adaptive *a, const double *y)
{
    double g = HUGE_VAL;
    uint32_t k;
    for (k = 0; k < a->flagged; ++k) {
        double d = pair_gap(a, a->flag[2 * k], a->flag[2 * k + 1], y);
        if (d < g)
            g = d;
    }
    return g;
}

/* The state at time s of the step that started at a->t0 in a->y0, in a->yt:
 * one rk8pd step of s - t0.  Returns 0 on failure (non-finite). */
static int state_at(rbs__adaptive *a, double s)
{
    int st;
    memcpy(a->yt, a->y0, a->dim * sizeof(double));
    if (s == a->t0)
        return 1;
    gsl_odeiv2_step_reset(a->step);
    st = gsl_odeiv2_step_apply(a->step, a->t0, s - a->t0, a->yt, a->yerr, NULL, NULL, &a->sys);
    return st == GSL_SUCCESS;
}

/* The function Brent's method sees: the smallest flagged gap at time s.
 * Always finite (GSL aborts on a non-finite value); failure sets a->bad. */
static double gap_at(double s, void *params)
{
    rbs__adaptive *a = (rbs__adaptive *)params;
    double g;
    if (!state_at(a, s)) {
        a->bad = 1;
        return 1.0;
    }
    g = min_gap(a, a->yt);
    if (!isfinite(g)) {
        a->bad = 1;
        return 1.0;
    }
    return g;
}

static rbs_status flag_pair(rbs__adaptive *a, uint32_t i, uint32_t b)
{
    if (a->flagged >= a->flag_cap)
        return (rbs_status)rbs__world_set_error(a->w, RBS_E_CAPACITY,
            "adaptive: more than max_contacts = %u pairs meet in one step", (unsigned)a->flag_cap);
    a->flag[2 * a->flagged] = i;
    a->flag[2 * a->flagged + 1] = b;
    a->flagged++;
    return RBS_OK;
}

/* Flag the pairs that were apart at the step's start (a->y0) and touch at
 * its end (a->y) or, for sphere pairs, along the straight path between.
 * *t_end gets the earliest time at which a flagged pair is seen overlapping
 * (t1, or the time of the deepest point of a swept path). */
static rbs_status find_crossings(rbs__adaptive *a, double t1, double *t_end)
{
    const rbs_world *w = a->w;
    uint32_t k, j, p;
    rbs_status st;
    a->flagged = 0;
    *t_end = t1;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        int moves = !w->fixed[i];
        if (moves) {
            for (p = 0; p < w->plane_count; ++p) {
                uint32_t b = w->planes[p];
                double g0 = pair_gap(a, i, b, a->y0), g1, sm, gm, H = t1 - a->t0;
                v3 n;
                if (!(g0 > 0.0))
                    continue;
                g1 = pair_gap(a, i, b, a->y);
                if (g1 < 0.0) {
                    if ((st = flag_pair(a, i, b)) != RBS_OK)
                        return st;
                    continue;
                }
                /* touches and leaves inside the step: the gap's cubic
                 * Hermite interpolant (exact for parabolas) dips below 0 */
                n = v3_load(&w->normal[3 * b]);
                if (hermite_dip(g0, g1, H * v3_dot(centre_vel(a, i, a->y0), n),
                                H * v3_dot(centre_vel(a, i, a->y), n), &sm, &gm)) {
                    double ts = a->t0 + sm * H;
                    if ((st = flag_pair(a, i, b)) != RBS_OK)
                        return st;
                    if (ts < *t_end && ts > a->t0)
                        *t_end = ts;
                }
            }
        }
        for (j = k + 1; j < w->sphere_count; ++j) {
            uint32_t b = w->spheres[j];
            v3 a0, a1, b0, b1, d0, dd;
            double rs, l2, s = 1.0, dmin;
            if (!moves && w->fixed[b])
                continue;
            if (!(pair_gap(a, i, b, a->y0) > 0.0))
                continue;
            a0 = centre_in(a, i, a->y0); a1 = centre_in(a, i, a->y);
            b0 = centre_in(a, b, a->y0); b1 = centre_in(a, b, a->y);
            rs = w->radius[i] + w->radius[b];
            d0 = v3_sub(a0, b0);
            dd = v3_sub(v3_sub(a1, b1), d0);
            l2 = v3_dot(dd, dd);
            if (l2 > 0.0) {
                s = -v3_dot(d0, dd) / l2;
                s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
            }
            dmin = v3_len(v3_mad(d0, dd, s));
            if (dmin < rs) {
                /* meets inside the step: bracket at the deepest point, also
                 * when the end overlaps -- a pair that went through each
                 * other and out to a touch at the end (c at rest, d at
                 * -1000 m/s from 0.6 m + 1e-13 m away, dt = 1 ms) has an
                 * end gap of -1e-13 m, within the root's tolerance: from
                 * [t0, t1] Brent took that exit, where the pair parts, and
                 * d went on through c (a probe of session 44) */
                double ts = a->t0 + s * (t1 - a->t0);
                if ((st = flag_pair(a, i, b)) != RBS_OK)
                    return st;
                if (ts < *t_end && ts > a->t0)
                    *t_end = ts;
            }
        }
    }
    return RBS_OK;
}

/* Smallest slop over the flagged pairs, m. */
static double flagged_slop(const rbs__adaptive *a)
{
    const rbs_world *w = a->w;
    double s = HUGE_VAL;
    uint32_t k;
    for (k = 0; k < a->flagged; ++k) {
        uint32_t i = a->flag[2 * k], b = a->flag[2 * k + 1];
        double r = w->radius[i];
        if (w->type[b] == RBS_BODY_SPHERE && w->radius[b] < r)
            r = w->radius[b];
        if (w->def.slop * r < s)
            s = w->def.slop * r;
    }
    return s;
}

/* Locate the first contact in [t0, t_end] (gap(t0) > 0 > gap(t_end)) by
 * Brent's method; leaves the state at the contact time in a->yt and the
 * time in *te. */
static rbs_status locate(rbs__adaptive *a, double t_end, double *te)
{
    gsl_function F;
    double lo = a->t0, hi = t_end, r = t_end, tol_gap = 1e-3 * flagged_slop(a), g;
    int it, st;
    F.function = gap_at;
    F.params = a;
    a->bad = 0;
    st = gsl_root_fsolver_set(a->root, &F, lo, hi);
    for (it = 0; st == GSL_SUCCESS && it < 200; ++it) {
        st = gsl_root_fsolver_iterate(a->root);
        r = gsl_root_fsolver_root(a->root);
        lo = gsl_root_fsolver_x_lower(a->root);
        hi = gsl_root_fsolver_x_upper(a->root);
        if (a->bad)
            break;
        g = gap_at(r, a);
        if (fabs(g) <= tol_gap || hi - lo <= 4.0 * DBL_EPSILON * (fabs(hi) + a->w->def.dt))
            break;
    }
    if (a->bad || st != GSL_SUCCESS)
        return (rbs_status)rbs__world_set_error(a->w, RBS_E_NUMERIC,
            "adaptive: locating a contact in [%.17g, %.17g] s of the frame failed (%s)", a->t0, t_end,
            a->bad ? "the state became NaN or infinite" : gsl_strerror(st));
    /* take the root if its gap is within tolerance, else the last time
     * before the crossing */
    g = gap_at(r, a);
    if (!(fabs(g) <= tol_gap)) {
        r = lo;
        gap_at(r, a);
    }
    *te = r;
    return RBS_OK;
}

/* ------------------------------------------------------------------------- */
/* Stepping                                                                  */
/* ------------------------------------------------------------------------- */

/* Detect contacts for the segment starting now.  A contact whose applied
 * forces pull it apart (a ball under a ceiling) cannot rest, so a slow
 * approach there is an impact with restitution: its resting threshold is
 * set to 0 (the core's threshold |a_n| dt ignores the sign).  Speculative
 * contacts (within their creep reach) are looked for only when the last
 * resting pass held some contact (the warm table): resting_contact takes
 * only those that held.  (Looked for always, an orbit's bodies, whose
 * creep reach |a| dt^2 at a frame of a twentieth of a period is a tenth of
 * the orbit, were speculative contacts of each other.) */
static rbs_status detect_segment(rbs_world *w, double T)
{
    uint32_t k;
    rbs__coarse co;
    rbs_status st = rbs__detect(w, T, w->warm_used > 0);
    if (st != RBS_OK)
        return st;
    /* A contact where coordinates round by more than its slop can never
     * close to it: the event search put the ball back at its last rounded
     * place before the floor, again and again, while gravity went on adding
     * to its speed (at 1e12 m a ball hung 0.1 mm up falling at -18 m/s after
     * 1.9 s, each frame slower than the last; a probe of session 40).
     * Refused, as the other methods that decide by the slop refuse. */
    if (rbs__coarse_contact(w, &co))
        return rbs__coarse_error(w, &co);
    for (k = 0; k < w->contact_count; ++k) {
        rbs__contact *c = &w->contact[k];
        v3 aa, ab, ta;
        rbs__accelerations_all(w, c->a, &aa, &ta);
        rbs__accelerations_all(w, c->b, &ab, &ta);
        if (v3_dot(v3_sub(aa, ab), c->n) > 0.0)
            c->thr = 0.0;
    }
    return RBS_OK;
}

/* Does a contact (after the collision pass) stay closed: approach, or part
 * slower than the speed one frame of the forces builds (its resting
 * threshold: a body resting, or sliding over a curved one, which parts by
 * its curvature alone)?  But a contact the collision pass has just bounced
 * (its jn mark) flies on as an ODE whenever it parts beyond rounding (1e-9
 * of the threshold), its return an event: taken as rest, the rk4 sub-steps
 * that finish the frame met its return inside one sub-step and stopped it
 * in the air (a probe of session 39: e = 0.1, dt = 0.05 s, the ball held
 * still 8.5 mm up at 0.45 s).  (Any contact parting flew, first: a ball
 * sliding over a fixed sphere then made an event of every step of its
 * slide, and ran out of them.) */
static int resting_contact(rbs_world *w)
{
    uint32_t k, at = 0;
    rbs__warm_sort(w);
    for (k = 0; k < w->contact_count; ++k) {
        const rbs__contact *c = &w->contact[k];
        /* A contact a little apart (speculative) rests if it held a load in
         * the last resting pass and is not an impact: the rk4 sub-steps'
         * drift leaves a loaded contact over a curved body apart by about
         * v^2 h^2 / (2 R) (a ball rolling over a fixed sphere, R its radius
         * plus the ball's), more than the slop at dt = 1 ms, and the ODE
         * then flew the ball without friction to its next touch, a third of
         * the frame: it slipped where rolling needed a third of the static
         * cone (a probe of session 45). */
        if ((c->flags & RBS__APART) &&
            (c->bias < 0.0 || rbs__warm_find(w, rbs__warm_key(w, c), &at) == NULL))
            continue;
        if (rbs__normal_velocity(w, c) <= (c->jn > 0.0 ? 1e-9 : 1.0) * c->thr)
            return 1;
    }
    return 0;
}

/* The rest of the frame, [t, dt], with RK4 rollback sub-steps, at the
 * frame's resting thresholds (with the rest's own, shorter ones, an
 * approach this frame's collision pass left as resting was an impact
 * there: a ball dropped at dt = 0.5 s bounced where rk4 stops it). */
static rbs_status finish_with_rk4(rbs_world *w, rbs_step_info *info, double remaining)
{
    return rbs__step_rollback(w, info, rbs__rk4_advance, 0, remaining); /* mid-frame */
}

rbs_status rbs__step_adaptive(rbs_world *w, rbs_step_info *info)
{
    rbs__adaptive *a = w->adaptive;
    const double T = w->def.dt;
    double t = 0.0, *hmem = &w->method_state[0];
    uint32_t steps = 0, events = 0, substeps = 0;
    rbs_status st;

    if (a == NULL)
        return (rbs_status)rbs__world_set_error(w, RBS_E_MEMORY,
            "adaptive: GSL workspaces were not reserved (create the world with, or switch to, "
            "the adaptive method through rbs_world_set_method)");
    if (!(w->def.tolerance >= MIN_TOL))
        return (rbs_status)rbs__world_set_error(w, RBS_E_INVALID,
            "adaptive: tolerance %g is below what double precision can reach (use >= %g)",
            w->def.tolerance, MIN_TOL);
    if (a->tol != w->def.tolerance) {
        gsl_odeiv2_control_init(a->control, w->def.tolerance, w->def.tolerance, 1.0, 0.0);
        a->tol = w->def.tolerance;
    }
    if (!(*hmem > 0.0) || *hmem > T)
        *hmem = T;

    while (t < T) {
        double h, t_end = T, te = T;
        int gs;
        /* contacts at the start of the segment: impacts, then either free
         * flight or, with a closed contact, RK4 sub-steps to the frame end */
        st = detect_segment(w, T);
        if (st != RBS_OK)
            return st;
        rbs__solve_collisions(w, info);
        if (resting_contact(w)) {
            info->substeps += substeps;
            return finish_with_rk4(w, info, T - t);
        }
        pack(a);
        memcpy(a->y0, a->y, a->dim * sizeof(double));
        a->t0 = t;
        gsl_odeiv2_evolve_reset(a->evolve);
        gsl_odeiv2_step_reset(a->step);
        /* free flight until an event or the frame end */
        for (;;) {
            double h_in = *hmem;
            h = h_in;
            a->bad_body = UINT32_MAX;
            gs = gsl_odeiv2_evolve_apply(a->evolve, a->control, a->step, &a->sys, &t, T, &h, a->y);
            if (gs != GSL_SUCCESS && a->bad_body != UINT32_MAX)
                return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                    "adaptive: step %llu: the forces on body %u (\"%s\") became NaN or infinite "
                    "at %.17g s into the frame; the world is left at its last good state",
                    (unsigned long long)w->step_count + 1, (unsigned)a->bad_body, w->name[a->bad_body], t);
            if (gs != GSL_SUCCESS)
                return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                    "adaptive: step %llu: the integrator failed at %.17g s into the frame (%s)",
                    (unsigned long long)w->step_count + 1, t, gsl_strerror(gs));
            /* keep the step-size suggestion unless GSL clipped it to the frame end */
            *hmem = (t == T && h < h_in) ? h_in : h;
            if (++steps > (uint64_t)w->def.max_substeps * STEPS_PER_SUBSTEP)
                return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                    "adaptive: more than %llu steps in one frame (max_substeps %u x %u; tolerance %g "
                    "too tight?)",
                    (unsigned long long)w->def.max_substeps * STEPS_PER_SUBSTEP,
                    (unsigned)w->def.max_substeps, STEPS_PER_SUBSTEP, w->def.tolerance);
            substeps++;
            st = find_crossings(a, t, &t_end);
            if (st != RBS_OK)
                return st;
            if (a->flagged > 0) {
                if (t_end < t && !(gap_at(t_end, a) < 0.0)) {
                    /* a swept path looked close but the curved one stays
                     * apart: look only at the end of the step */
                    t_end = t;
                }
                if (gap_at(t_end, a) < 0.0 && !a->bad)
                    break;
                if (a->bad)
                    return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                        "adaptive: the state became NaN or infinite near %.17g s into the frame", t);
            }
            unpack(a, a->y);
            memcpy(a->y0, a->y, a->dim * sizeof(double));
            a->t0 = t;
            if (t >= T)
                break;
        }
        if (t >= T && a->flagged == 0)
            break;
        if (a->flagged > 0 && t > a->t0) {
            /* an event inside [t0, t_end]: move there and resolve it */
            st = locate(a, t_end, &te);
            if (st != RBS_OK)
                return st;
            unpack(a, a->yt);
            t = te;
            info->events++;
            if (++events > w->def.max_substeps && t < T) {
                /* The work cap: more than max_substeps contact events in
                 * one frame (each costs root finding).  The rest of the
                 * frame is one RK4 sub-step with its overlap pushed apart,
                 * as the rollback methods take theirs past the cap, and
                 * reported (work_limit).  (It was RBS_E_NUMERIC at a fixed
                 * 1000 events: the 1e6:1 pi billiard, 3141 impacts, stopped
                 * at dt = 1 ms as a "numerical failure".)  Far from the
                 * origin the events may be rounding alone: refused, as
                 * elsewhere. */
                rbs__coarse co;
                if (rbs__coarse_contact(w, &co))
                    return rbs__coarse_error(w, &co);
                info->work_limit = 1;
                info->substeps += substeps;
                return finish_with_rk4(w, info, T - t);
            }
            if (t >= T) {
                /* the contact is at the frame end: resolve it now */
                st = detect_segment(w, T);
                if (st != RBS_OK)
                    return st;
                rbs__solve_collisions(w, info);
            }
        }
    }
    info->substeps += substeps;
    info->contacts = rbs__touching(w);
    info->max_overlap = rbs__max_overlap(w);
    return RBS_OK;
}
