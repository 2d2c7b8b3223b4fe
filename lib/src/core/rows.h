/*
 * rows.h - the arithmetic of one contact row (internal): the relative
 * velocity at a contact, an impulse on its pair, the impulse that stops a
 * slip and Coulomb's cone.  Shared by the resting pass (solver.c) and the
 * soft step (step_soft.c), so both make the same operations.
 */
#ifndef RBS_CORE_ROWS_H
#define RBS_CORE_ROWS_H

#include "core/world_internal.h"

/* K u for the pair: (1/ma + 1/mb) u + (Ia^-1 (ra x u)) x ra + (Ib^-1 (rb x u)) x rb. */
static inline v3 rbs__k_apply(const rbs_world *w, const rbs__contact *c, v3 u)
{
    v3 r = v3_scale(u, w->inv_mass[c->a] + w->inv_mass[c->b]), t;
    if (w->inv_mass[c->a] != 0.0) {
        v3 ra = rbs__contact_ra(w, c);
        rbs__body_inv_inertia_world(w, c->a, v3_cross(ra, u), &t);
        r = v3_add(r, v3_cross(t, ra));
    }
    if (w->inv_mass[c->b] != 0.0) {
        v3 rb = rbs__contact_rb(w, c);
        rbs__body_inv_inertia_world(w, c->b, v3_cross(rb, u), &t);
        r = v3_add(r, v3_cross(t, rb));
    }
    return r;
}

/* The relative velocity at a contact, and an impulse on its pair (j on a,
 * -j on b).  With both levers along n (no off-centre mass: no RBS__OFF flag)
 *     v_rel = v_a - v_b + (la w_a - lb w_b) x n,
 *     dw_a = I_a^-1 (la (n x j)),  dw_b = I_b^-1 (-lb (n x j)):
 * one cross product each instead of two; the fast sweep below makes the
 * same operations, so the two sweeps agree bit for bit. */
static inline v3 rbs__along_rel_velocity(const rbs__contact *c, double la, v3 va, v3 wa, v3 vb, v3 wb)
{
    return v3_add(v3_sub(va, vb), v3_cross(v3_sub(v3_scale(wa, la), v3_scale(wb, c->lb)), c->n));
}

static inline v3 rbs__rel_velocity(const rbs_world *w, const rbs__contact *c)
{
    if (!(c->flags & RBS__OFF))
        return rbs__along_rel_velocity(c, rbs__contact_la(w, c), v3_load(&w->vel[3 * c->a]),
                                       v3_load(&w->avel[3 * c->a]), v3_load(&w->vel[3 * c->b]),
                                       v3_load(&w->avel[3 * c->b]));
    return v3_sub(rbs__point_velocity(w, c->a, rbs__contact_ra(w, c)),
                  rbs__point_velocity(w, c->b, rbs__contact_rb(w, c)));
}

static inline void rbs__apply_pair(rbs_world *w, const rbs__contact *c, v3 j)
{
    if (!(c->flags & RBS__OFF)) {
        v3 t = v3_cross(c->n, j);
        rbs__apply_impulse_torque(w, c->a, j, v3_scale(t, rbs__contact_la(w, c)));
        rbs__apply_impulse_torque(w, c->b, v3_scale(j, -1.0), v3_scale(t, -c->lb));
        return;
    }
    rbs__apply_impulse(w, c->a, rbs__contact_ra(w, c), j);
    rbs__apply_impulse(w, c->b, rbs__contact_rb(w, c), v3_scale(j, -1.0));
}

/* A contact's tangential mass K_tt in a basis of its tangent plane (set:
 * 0 until rbs__stick_impulse_kt has computed it), kept so that a sliding
 * contact's rbs__slide_impulse need not compute it again. */
typedef struct rbs__kt {
    v3 t1, t2;
    double k11, k12, k21, k22;
    int set;
} rbs__kt;

/* Tangential impulse that stops the slip vt (in the tangent plane): solves
 * the 2x2 system K_tt j = -vt in the basis (t1 = vt/|vt|, t2 = n x t1);
 * K_tt into *kt when kt is given and the plane is not isotropic. */
static inline v3 rbs__stick_impulse_kt(const rbs_world *w, const rbs__contact *c, v3 vt, rbs__kt *kt)
{
    double s = v3_len_small(vt), k11, k12, k21, k22, det, j1, j2; /* (v3_len is 0 below 1e-162 m/s) */
    v3 t1, t2, kt1, kt2;
    if (kt)
        kt->set = 0;
    if (!(s > 0.0))
        return v3_make(0, 0, 0);
    if (c->kt_inv > 0.0)
        return v3_scale(vt, -c->kt_inv); /* isotropic tangent plane */
    t1 = v3_unit_small(vt, s);
    t2 = v3_cross(c->n, t1);
    kt1 = rbs__k_apply(w, c, t1);
    kt2 = rbs__k_apply(w, c, t2);
    k11 = v3_dot(t1, kt1);
    k12 = v3_dot(t1, kt2);
    k21 = v3_dot(t2, kt1);
    k22 = v3_dot(t2, kt2);
    if (kt) {
        kt->t1 = t1;
        kt->t2 = t2;
        kt->k11 = k11;
        kt->k12 = k12;
        kt->k21 = k21;
        kt->k22 = k22;
        kt->set = 1;
    }
    det = k11 * k22 - k12 * k21;
    if (k12 == 0.0 && k21 == 0.0) {
        /* the common case (centred spheres): decoupled */
        j1 = -s / k11;
        j2 = 0.0;
    } else {
        j1 = -s * k22 / det;
        j2 = s * k21 / det;
    }
    return v3_add(v3_scale(t1, j1), v3_scale(t2, j2));
}

static inline v3 rbs__stick_impulse(const rbs_world *w, const rbs__contact *c, v3 vt)
{
    return rbs__stick_impulse_kt(w, c, vt, NULL);
}

/* Tangential part of the relative velocity at a contact. */
static inline v3 rbs__slip(const rbs_world *w, const rbs__contact *c)
{
    v3 v = rbs__rel_velocity(w, c);
    return v3_mad(v, c->n, -v3_dot(v, c->n));
}

/* A sliding contact's friction impulse: of the impulses |j| <= lim, the
 * one nearest to the sticking impulse stick (|stick| = len > lim) in the
 * metric of the contact's tangential mass K -- the one that leaves the
 * least kinetic energy, whose slip after it is against it (the principle
 * of maximal dissipation; Moreau 1988, Stewart & Trinkle 1996).  With K
 * isotropic in the tangent plane (c->kt_inv > 0: centred spheres of
 * isotropic inertia) that is stick scaled to lim.  Otherwise the slip
 * left by stick scaled down would not be against it: a sphere of
 * principal moments (2, 6, 5) g m^2 sliding diagonally on a floor went
 * 0.04 m/s (3 %) off Coulomb's law in 0.15 s (a probe of session 40).
 * In a basis (t1, t2) of the tangent plane -- kt's, when given and set,
 * else t1 = stick / len -- j = (K + s I)^-1 K stick with the s >= 0 that
 * makes |j| = lim: |j(s)| falls from len at s = 0 to at most |K stick| / s,
 * so s lies in (0, |K stick| / lim]; Newton's steps on 1/|j(s)| - 1/lim,
 * kept inside that bracket by bisection. */
static inline v3 rbs__slide_impulse(const rbs_world *w, const rbs__contact *c, v3 stick, double len,
                                    double lim, const rbs__kt *kt)
{
    v3 t1, t2;
    double k11, k12, k22, c1, c2, r1, r2, lo = 0.0, hi, s, j1, j2, l = len;
    int it;
    if (c->kt_inv > 0.0 || !(lim > 0.0))
        return v3_scale(stick, lim / len);
    if (kt && kt->set) {
        t1 = kt->t1;
        t2 = kt->t2;
        k11 = kt->k11;
        k22 = kt->k22;
        k12 = 0.5 * (kt->k12 + kt->k21); /* (K is symmetric) */
        c1 = v3_dot(stick, t1);
        c2 = v3_dot(stick, t2);
    } else {
        v3 kt1, kt2;
        t1 = v3_scale(stick, 1.0 / len);
        t2 = v3_cross(c->n, t1);
        kt1 = rbs__k_apply(w, c, t1);
        kt2 = rbs__k_apply(w, c, t2);
        k11 = v3_dot(t1, kt1);
        k22 = v3_dot(t2, kt2);
        k12 = 0.5 * (v3_dot(t1, kt2) + v3_dot(t2, kt1));
        c1 = len;
        c2 = 0.0;
    }
    j1 = c1;
    j2 = c2;
    r1 = k11 * c1 + k12 * c2;
    r2 = k12 * c1 + k22 * c2;
    hi = sqrt(r1 * r1 + r2 * r2) / lim;
    s = 0.0;
    for (it = 0; it < 200; ++it) {
        double a = k11 + s, b = k22 + s, det = a * b - k12 * k12, d1, d2, q, next;
        if (!(det > 0.0))
            break; /* (K not positive definite: cannot happen for bodies with mass) */
        j1 = (b * r1 - k12 * r2) / det;
        j2 = (a * r2 - k12 * r1) / det;
        l = sqrt(j1 * j1 + j2 * j2);
        if (l > lim)
            lo = s;
        else
            hi = s;
        /* d|j|/ds = -j.(K + s I)^-1 j / |j|, so d(1/|j|)/ds = q / |j|^3:
         * Newton on 1/|j| - 1/lim (nearly linear in s: a few steps) */
        d1 = (b * j1 - k12 * j2) / det;
        d2 = (a * j2 - k12 * j1) / det;
        q = j1 * d1 + j2 * d2;
        if (l == lim || !(hi - lo > 4e-16 * hi))
            break;
        next = q > 0.0 ? s - (1.0 / l - 1.0 / lim) * l * l * l / q : 0.5 * (lo + hi);
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        else if (fabs(next - s) <= 4e-16 * s)
            break; /* (Newton's step is rounding: s is the root) */
        s = next;
    }
    if (!(l > 0.0))
        return v3_scale(stick, lim / len);
    return v3_add(v3_scale(t1, j1 * lim / l), v3_scale(t2, j2 * lim / l));
}

/* The friction coefficient that decides whether a contact sticks, given
 * jslip, the impulse that would stop the slip it came in with, and its
 * normal impulse jn: mu_s, unless that slip is more than kinetic friction
 * mu_k jn can stop -- then the contact slides all the interval, only mu_k
 * acts, and it sticks only if mu_k jn suffices.  Static friction holds a
 * contact that does not slip; one that slips feels mu_k until its slip is
 * gone (Coulomb).  Sticking whenever mu_s jn could stop the slip rolled a
 * ball sliding on a floor up to (mu_s / mu_k - 1) steps early, and left an
 * impact's slip at zero where mu_k leaves some: an outcome that jumped at
 * mu_s jn (a probe of session 41).  With mu_s == mu_k, or no slip, mu_s. */
static inline double rbs__friction_cap(const rbs__pair *p, double jslip, double jn)
{
    return jslip > p->mu_k * jn ? p->mu_k : p->mu_s;
}

/* The accumulated friction impulse jt + stick kept within Coulomb's cone
 * (|Jt| <= cap Jn sticks, cap from rbs__friction_cap, else mu_k Jn:
 * rbs__slide_impulse). */
static inline v3 rbs__cone(const rbs_world *w, const rbs__contact *c, const rbs__pair *p, v3 stick,
                           const rbs__kt *kt)
{
    v3 cand = v3_add(c->jt, stick);
    double l2 = v3_dot(cand, cand), lim = rbs__friction_cap(p, c->jslip, c->jn) * c->jn;
    if (l2 > lim * lim) /* (a square root only to slide) */
        cand = rbs__slide_impulse(w, c, cand, sqrt(l2), p->mu_k * c->jn, kt);
    return cand;
}

/* rbs__apply_impulse_torque and rbs__apply_pair on gathered bodies. */
static inline void rbs__sb_apply(double *b, v3 j, v3 tau)
{
    if (b[6] == 0.0)
        return;
    v3_store(b, v3_mad(v3_load(b), j, b[6]));
    v3_store(b + 3, v3_add(v3_load(b + 3), v3_scale(tau, b[7])));
}

static inline void rbs__sb_apply_pair(double *ba, double *bb, const rbs__contact *c, double la, v3 j)
{
    v3 t = v3_cross(c->n, j);
    rbs__sb_apply(ba, j, v3_scale(t, la));
    rbs__sb_apply(bb, v3_scale(j, -1.0), v3_scale(t, -c->lb));
}

/* An angular impulse dl on a contact's pair: +dl on a, -dl on b (bodies
 * that do not move take nothing): rolling and spinning resistance. */
static inline void rbs__apply_angular_pair(rbs_world *w, const rbs__contact *c, v3 dl)
{
    v3 ia, ib;
    rbs__body_inv_inertia_world(w, c->a, dl, &ia);
    rbs__body_inv_inertia_world(w, c->b, dl, &ib);
    if (w->inv_mass[c->a] != 0.0)
        v3_store(&w->avel[3 * c->a], v3_add(v3_load(&w->avel[3 * c->a]), ia));
    if (w->inv_mass[c->b] != 0.0)
        v3_store(&w->avel[3 * c->b], v3_sub(v3_load(&w->avel[3 * c->b]), ib));
}

/* A body's compact record in w->solver_body (RBS__SOLVER_STRIDE doubles a
 * slot: v, w, 1/m, 1/I), read by the fast sweeps. */
#define RBS__SB(w, i) (&(w)->solver_body[RBS__SOLVER_STRIDE * (i)])

#endif
