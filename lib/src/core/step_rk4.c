/*
 * step_rk4.c - classical Runge-Kutta between contacts (RBS_METHOD_RK4).
 *
 * The sub-step loop is Euler's rbs__step_rollback(); this file supplies the
 * advance.  For the smooth forces the state (x, v) of every moving sphere's
 * centre of mass is advanced by one classical RK4 step of h with a(x)
 * (uniform gravity, applied force, mutual gravity at the stage positions):
 *
 *   x' = x + h (v1 + 2 v2 + 2 v3 + v4) / 6,  v' = v + h (a1 + 2 a2 + 2 a3 + a4) / 6
 *
 * Rotation: a body whose angular velocity cannot change (isotropic inertia,
 * no applied torque) turns by the exact rotation exp(w h), as in Euler.  A
 * body with torque or anisotropic inertia (off-centre mass included) has
 * (q, L) advanced by the same RK4 on  q' = 1/2 (0, I(q)^-1 L) q,  L' = tau
 * (world frame, L = I(q) w), q renormalised after each part, w' = I(q')^-1 L'
 * at the end: fourth order for the torque-free and the torqued rigid body
 * (the same ODE as w' = I^-1 (tau - w x I w), written in L), and L' = tau is
 * integrated exactly (a torque-free body keeps L to rounding).  Rotation and
 * translation do not couple between contacts (forces act at the centre of
 * mass, torques do not depend on position), so (q, L) is integrated on its
 * own, in m equal RK4 parts with |w| h / m <= 1/4 rad: m from |L| / I_min
 * (rbs__spin_reach), as verlet's and euler's parts, which a torque-free
 * body keeps.  (Until session 50 the parts were RK4 on (q, w) counted from
 * (|w| + |alpha| h) h: |alpha| of a free anisotropic body grows as |w|^2,
 * so the count grew as (|w| h)^2 -- a sphere of I = (4, 6, 9) g m^2 at
 * 1e6 rad/s took 25.7 s for 200 steps of 1 ms (the other methods 0.7-1.1 s)
 * and ran out of the step's rotation budget in 39 of them -- and RK4's
 * damping of w's turn in the world frame lost L: a symmetric top at
 * |w| dt = 1 lost 1.3e-2 of L in 10 s; tests/methods/test_free_top.c.)
 * RK4 is not symmetric: the energy L.I(q)^-1 L / 2 still drifts, by
 * O((|w| h / m)^6) a part.
 *
 * Contacts, as in Verlet: one resting pass per sub-step, on the RK4 end
 * velocities, speculative contacts included (rbs__trapezoid_reach); what
 * it changes moves positions by half of it over the
 * sub-step (the trapezoid), and orientations by exp(dw h / 2); the other
 * half of a sphere pair's impulse acts along the pair's end normal
 * (rbs__turn_second_halves).  With
 * constant forces this is the exact constant-acceleration motion
 * (x' = x + v h + a h^2/2) of free, resting, rolling and sliding bodies.
 * Four acceleration evaluations per sub-step.
 *
 * With mutual gravity the stages also take the contacts' forces as the
 * pass's warm start predicts them (rbs__warm_accelerations: last
 * sub-step's impulse rates), so that they go along the path the contacts
 * allow; those forces' share is then taken back out of the velocities the
 * pass sees and of the drift, where the pass's own change stands for them.
 * The RK4 position less the trapezoid of its end velocity is
 * h^2 (a1 - a4) / 12 (the jerk's term); for a pair held together by its
 * attraction, stages along the free path fall into each other, where the
 * attraction is stronger (a4 - a1 about h^2 a a' / 2), and the drift moved
 * the pair apart by h^4 a a' / 24 a sub-step, which no pass took back: two
 * 1 kg balls of r = 0.1 m touching, G = 1, crept apart 1.04e-9 m a step at
 * dt = 1 ms until past the slop, then kept the speculative contact's
 * approach, +-5.2e-7 m/s, for good (session 52; now only the first step,
 * which has no warm start, moves them: test_gravity.c,
 * pair_held_by_its_attraction_rests).  Without mutual gravity the
 * accelerations do not depend on the stages' path, the prediction would
 * change nothing but rounding, and it is not made.
 */
#include <string.h>

#include "core/world_internal.h"

/* Per-slot scratch (w->method_scratch, RBS__SCRATCH_STRIDE doubles). */
enum {
    S_X0 = 0,    /* COM at the start, 3 */
    S_V0 = 3,    /* velocity at the start, 3 */
    S_Q0 = 6,    /* orientation at the start, 4 */
    S_W0 = 10,   /* angular velocity at the start, 3 */
    S_SX = 13,   /* sum of b_k v_k, 3 */
    S_SV = 16,   /* sum of b_k a_k, 3 */
    S_WE = 19,   /* RK4 angular velocity at the end, 3 */
    S_QE = 22,   /* RK4 orientation at the end, 4 */
    S_SPIN = 26, /* 1: (q, w) integrated by RK4 */
    S_CF = 27,   /* the contacts' acceleration the warm start predicts, 3 */
    S_USED = 30
};


static quat q_axpy(quat a, quat b, double s)
{
    quat r = {a.w + b.w * s, a.x + b.x * s, a.y + b.y * s, a.z + b.z * s};
    return r;
}

/* dq/dt = 1/2 (0, w) q for a world-frame w. */
static quat q_dot(v3 om, quat q)
{
    quat o = {0.0, om.x, om.y, om.z}, r = q_mul(o, q);
    r.w *= 0.5; r.x *= 0.5; r.y *= 0.5; r.z *= 0.5;
    return r;
}


/* I(q)^-1 L of body i in world axes (q of unit length). */
static v3 spin_of(const rbs_world *w, uint32_t i, quat q, v3 L)
{
    if (w->isotropic[i])
        return v3_scale(L, w->iso_inv_inertia[i]);
    return m3_mul_world(&w->inv_inertia[9 * i], q, L);
}

/* RK4 on q' = 1/2 (0, I(q)^-1 L) q, L' = tau over h for body i, in m equal
 * parts of at most 1/4 rad (rbs__spin_reach, rbs__spin_substeps).  Writes
 * the end orientation and angular velocity I(q')^-1 L' into S. */
static void spin_rk4(rbs_world *w, rbs_step_info *info, uint32_t i, v3 tau, double h, double *S)
{
    quat q = q_load(&S[S_Q0]);
    v3 om = v3_load(&S[S_W0]), L;
    double hs;
    int m, k, stable;
    if (w->isotropic[i] && tau.x == 0.0 && tau.y == 0.0 && tau.z == 0.0) {
        /* torque-free and isotropic: w is constant; the rotation is exact */
        if (om.x != 0.0 || om.y != 0.0 || om.z != 0.0)
            q = q_normalize(q_mul(q_from_rotation(om, h), q));
        q_store(&S[S_QE], q);
        v3_store(&S[S_WE], om);
        return;
    }
    m = rbs__spin_substeps(w, info, rbs__spin_reach(w, i, q, om, tau, h), 0, &stable);
    if (stable) {
        /* the step's rotation budget is spent */
        rbs__spin_stable(w, i, tau, h, m, &q, &om, NULL);
        q_store(&S[S_QE], q);
        v3_store(&S[S_WE], om);
        return;
    }
    hs = h / m;
    L = rbs__inertia_times(w, i, q, om);
    for (k = 0; k < m; ++k) {
        const v3 Lm = v3_mad(L, tau, 0.5 * hs), Le = v3_mad(L, tau, hs);
        v3 w1 = spin_of(w, i, q, L), w2, w3, w4;
        quat d1 = q_dot(w1, q), q2, q3, q4, d2, d3, d4;
        q2 = q_axpy(q, d1, 0.5 * hs);
        w2 = spin_of(w, i, q_normalize(q2), Lm);
        d2 = q_dot(w2, q2);
        q3 = q_axpy(q, d2, 0.5 * hs);
        w3 = spin_of(w, i, q_normalize(q3), Lm);
        d3 = q_dot(w3, q3);
        q4 = q_axpy(q, d3, hs);
        w4 = spin_of(w, i, q_normalize(q4), Le);
        d4 = q_dot(w4, q4);
        q = q_normalize(q_axpy(q, q_axpy(q_axpy(d1, d4, 1.0), q_axpy(d2, d3, 1.0), 2.0), hs / 6.0));
        L = Le;
    }
    om = spin_of(w, i, q, L);
    q_store(&S[S_QE], q);
    v3_store(&S[S_WE], om);
}

/* Place body i's geometric centre so that its COM is at com for orientation q. */
static void place(rbs_world *w, uint32_t i, v3 com, quat q)
{
    v3 c = v3_load(&w->com_body[3 * i]);
    if (c.x == 0.0 && c.y == 0.0 && c.z == 0.0)
        v3_store(&w->pos[3 * i], com);
    else
        v3_store(&w->pos[3 * i], v3_sub(com, q_rotate(q, c)));
}

void rbs__rk4_advance(rbs_world *w, double h, rbs_step_info *info)
{
    static const double b[4] = {1.0, 2.0, 2.0, 1.0};
    const double c[3] = {0.5 * h, 0.5 * h, h};
    uint32_t k;
    int s, held;

    /* Start of the sub-step. */
    rbs__trapezoid_reach(w, h);
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        v3 a, tau;
        if (w->fixed[i])
            continue;
        v3_store(&S[S_X0], rbs__body_com(w, i));
        memcpy(&S[S_V0], &w->vel[3 * i], 3 * sizeof(double));
        memcpy(&S[S_Q0], &w->orient[4 * i], 4 * sizeof(double));
        memcpy(&S[S_W0], &w->avel[3 * i], 3 * sizeof(double));
        memset(&S[S_SX], 0, 6 * sizeof(double));
        S[S_SPIN] = 0.0;
        if (w->plan.angular) {
            v3 om = v3_load(&w->avel[3 * i]);
            rbs__accelerations(w, i, &a, &tau);
            if ((tau.x != 0.0 || tau.y != 0.0 || tau.z != 0.0) ||
                (!w->isotropic[i] && (om.x != 0.0 || om.y != 0.0 || om.z != 0.0))) {
                S[S_SPIN] = 1.0;
                spin_rk4(w, info, i, tau, h, S);
            }
        }
    }

    /* The contacts' forces along the stages (see the top): with mutual
     * gravity only, where the stages' path changes their accelerations. */
    held = w->plan.mutual && rbs__warm_accelerations(w, h, S_CF);

    /* Four stages: evaluate at the current stage state, accumulate (the
     * smooth forces' accelerations; the velocities with the contacts'
     * share), move to the next stage state. */
    for (s = 0; s < 4; ++s) {
        if (w->plan.mutual) {
            if (s == 0)
                rbs__mutual_gravity_start(w);
            else
                rbs__mutual_gravity(w);
        }
        for (k = 0; k < w->sphere_count; ++k) {
            uint32_t i = w->spheres[k];
            double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
            v3 a, tau, vs = v3_load(&w->vel[3 * i]);
            if (w->fixed[i])
                continue;
            rbs__accelerations(w, i, &a, &tau);
            if (w->plan.mutual)
                a = v3_add(a, v3_load(&w->acc[3 * i]));
            v3_store(&S[S_SX], v3_mad(v3_load(&S[S_SX]), vs, b[s]));
            v3_store(&S[S_SV], v3_mad(v3_load(&S[S_SV]), a, b[s]));
            if (s < 3) {
                v3 as = held ? v3_add(a, v3_load(&S[S_CF])) : a;
                place(w, i, v3_mad(v3_load(&S[S_X0]), vs, c[s]), q_load(&S[S_Q0]));
                v3_store(&w->vel[3 * i], v3_mad(v3_load(&S[S_V0]), as, c[s]));
            }
        }
    }

    /* Resting contact on the end velocities. */
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        if (w->fixed[i])
            continue;
        v3_store(&w->vel[3 * i], v3_mad(v3_load(&S[S_V0]), v3_load(&S[S_SV]), h / 6.0));
        memcpy(&w->avel[3 * i], S[S_SPIN] != 0.0 ? &S[S_WE] : &S[S_W0], 3 * sizeof(double));
        memcpy(&w->orient[4 * i], &S[S_Q0], 4 * sizeof(double));
        place(w, i, v3_load(&S[S_X0]), q_load(&S[S_Q0]));
    }
    rbs__levers_at_middle(w, h, S_Q0, S_QE, S_SPIN); /* (off-centre rows: verlet's) */
    rbs__solve_resting_warm(w, info, h);

    /* Drift: the RK4 mean velocity plus half of what the resting pass
     * changed (the trapezoid over the sub-step); less the contacts' share
     * the stages' velocities took, (2 h/2 + 2 h/2 + h) / 6 = h/2 of it,
     * which the pass's change holds. */
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        v3 dv, vd, om = v3_load(&w->avel[3 * i]);
        quat q;
        if (w->fixed[i])
            continue;
        dv = v3_sub(v3_load(&w->vel[3 * i]), v3_mad(v3_load(&S[S_V0]), v3_load(&S[S_SV]), h / 6.0));
        vd = v3_add(v3_scale(v3_load(&S[S_SX]), 1.0 / 6.0), v3_scale(dv, 0.5));
        if (held)
            vd = v3_mad(vd, v3_load(&S[S_CF]), -0.5 * h);
        q = rbs__end_orientation(S[S_SPIN] != 0.0, q_load(&S[S_Q0]), v3_load(&S[S_W0]), q_load(&S[S_QE]),
                                 v3_load(&S[S_WE]), om, h);
        q_store(&w->orient[4 * i], q);
        place(w, i, v3_mad(v3_load(&S[S_X0]), vd, h), q);
    }
    /* the second half of each sphere pair's impulse along its end normal */
    rbs__turn_second_halves(w);
}

rbs_status rbs__step_rk4(rbs_world *w, rbs_step_info *info)
{
    return rbs__step_rollback(w, info, rbs__rk4_advance, 1, w->def.dt);
}
