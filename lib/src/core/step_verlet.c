/*
 * step_verlet.c - velocity Verlet between contacts (RBS_METHOD_VERLET).
 *
 * The sub-step loop (detect, collision impulses, advance, overlap check,
 * rollback with h/2) is Euler's rbs__step_rollback(); only the advance
 * differs.  For the smooth forces (uniform gravity, applied force and torque,
 * mutual gravity) one sub-step of h is velocity Verlet (Hairer, Lubich &
 * Wanner, Geometric Numerical Integration, 2006, I.1.4), written with the
 * end velocity predicted first so that contacts see it:
 *
 *   v_e = v + a(x) h;   resting pass on v_e (and w): changes dv, dw
 *   x' = x + (v + a(x) h/2 + dv/2) h
 *   v' = v_e + dv + (a(x') - a(x)) h/2
 *
 * Without contacts this is exactly velocity Verlet (symplectic, second
 * order).  Rotation: isotropic, torque-free bodies keep their spin and turn
 * by the exact rotation.  Bodies with torque or anisotropic inertia have
 * (q, w) advanced first, on their own (rotation and translation do not
 * couple between contacts), in m parts of at most 1/4 rad each as euler
 * turns (rbs__spin_stable): L = I(q) w kicked by half the torque's impulse,
 * q turned by the part's middle angular velocity wm = I(exp(wm hs/2) q)^-1 L
 * (a fixed point, converged), the other half kick.  The turn is symmetric
 * (time-reversible) and keeps L exactly without torque, so the energy
 * L.I(q)^-1 L / 2 oscillates at O((|w| hs)^2) and does not drift, and the
 * count m comes from |L| / I_min (rbs__spin_reach), which a torque-free body
 * keeps: a count that followed w broke the symmetry from part to part
 * (reversible methods and their loss under state-dependent step sizes:
 * Hairer, Lubich & Wanner, ch. V and VIII).
 * (Until session 49 the parts were kick-drift-kick on w with m from |w|
 * at each sub-step's start: a top of I = diag(1, 2, 3) kg m^2 tumbling at
 * |w| dt = 1 lost 16 % of its energy and 8 % of L in 10 s at dt = 1 ms,
 * at 3 rad 56 % and 34 %; tests/methods/test_free_top.c.)  A contact's dw
 * turns the body by exp(dw h/2).
 *
 * Contacts: one resting pass per sub-step, on the end velocities, as in
 * Euler, speculative contacts included with the reach the trapezoid drift
 * needs (rbs__trapezoid_reach); its velocity change moves positions by half of it over the
 * sub-step (the trapezoid of the start and end velocities), and the other
 * half of a sphere pair's impulse acts along the pair's end normal
 * (rbs__turn_second_halves).  With constant
 * forces this is the exact constant-acceleration motion of free, resting,
 * rolling and sliding bodies.  Accelerations are evaluated twice per
 * sub-step (no reuse across sub-steps: contacts, rollback and setters move
 * bodies in between).
 */
#include <string.h>

#include "core/world_internal.h"

/* Per-slot scratch (w->method_scratch). */
enum {
    S_X0 = 0,    /* COM at the start, 3 */
    S_V0 = 3,    /* velocity at the start, 3 */
    S_Q0 = 6,    /* orientation at the start, 4 */
    S_W0 = 10,   /* angular velocity at the start, 3 */
    S_A0 = 13,   /* a(x) at the start, 3 */
    S_QE = 16,   /* orientation at the end (spinning bodies), 4 */
    S_WE = 20,   /* angular velocity at the end (spinning bodies), 3 */
    S_SPIN = 23, /* 1: (q, w) advanced by spin_verlet */
    S_USED = 24
};



/* (q, w) of body i over h in parts of at most 1/4 rad, each turned as
 * euler turns (see the top); the end state into S. */
static void spin_verlet(rbs_world *w, rbs_step_info *info, uint32_t i, v3 tau, double h, double *S)
{
    quat q = q_load(&S[S_Q0]);
    v3 om = v3_load(&S[S_W0]);
    double reach = rbs__spin_reach(w, i, q, om, tau, h);
    int m, stable;
    /* (a torque-free isotropic body does not come here: its w is constant
     * and verlet_advance's one rotation is exact; past the step's budget,
     * the parts are the budget's rest, the same update) */
    m = rbs__spin_substeps(w, info, reach, 0, &stable);
    rbs__spin_stable(w, i, tau, h, m, &q, &om, NULL);
    q_store(&S[S_QE], q);
    v3_store(&S[S_WE], om);
}

/* Linear acceleration of body i (mutual gravity from w->acc when on). */
static v3 lin_acc(const rbs_world *w, uint32_t i, v3 *tau)
{
    v3 a;
    rbs__accelerations(w, i, &a, tau);
    if (w->plan.mutual)
        a = v3_add(a, v3_load(&w->acc[3 * i]));
    return a;
}

static void verlet_advance(rbs_world *w, double h, rbs_step_info *info)
{
    uint32_t k;

    /* Forces at the start; predicted end velocities; spinning bodies'
     * rotation over the whole sub-step. */
    rbs__trapezoid_reach(w, h);
    if (w->plan.mutual)
        rbs__mutual_gravity_start(w);
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        v3 a, tau, om = v3_load(&w->avel[3 * i]);
        if (w->fixed[i])
            continue;
        a = lin_acc(w, i, &tau);
        v3_store(&S[S_X0], rbs__body_com(w, i));
        memcpy(&S[S_V0], &w->vel[3 * i], 3 * sizeof(double));
        memcpy(&S[S_Q0], &w->orient[4 * i], 4 * sizeof(double));
        v3_store(&S[S_W0], om);
        v3_store(&S[S_A0], a);
        v3_store(&w->vel[3 * i], v3_mad(v3_load(&S[S_V0]), a, h));
        S[S_SPIN] = 0.0;
        if (w->plan.angular && ((tau.x != 0.0 || tau.y != 0.0 || tau.z != 0.0) ||
                                (!w->isotropic[i] && (om.x != 0.0 || om.y != 0.0 || om.z != 0.0)))) {
            S[S_SPIN] = 1.0;
            spin_verlet(w, info, i, tau, h, S);
            memcpy(&w->avel[3 * i], &S[S_WE], 3 * sizeof(double));
        }
    }

    /* Resting contact on the end velocities, off-centre spheres' rows at
     * the sub-step's middle orientation. */
    rbs__levers_at_middle(w, h, S_Q0, S_QE, S_SPIN);
    rbs__solve_resting_warm(w, info, h);

    /* Drift by the mean of the start and end velocities. */
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        v3 a0 = v3_load(&S[S_A0]), v0 = v3_load(&S[S_V0]), om = v3_load(&w->avel[3 * i]);
        v3 dv, vd, c;
        quat q;
        if (w->fixed[i])
            continue;
        dv = v3_sub(v3_load(&w->vel[3 * i]), v3_mad(v0, a0, h));
        vd = v3_add(v3_mad(v0, a0, 0.5 * h), v3_scale(dv, 0.5));
        q = rbs__end_orientation(S[S_SPIN] != 0.0, q_load(&S[S_Q0]), v3_load(&S[S_W0]), q_load(&S[S_QE]),
                                 v3_load(&S[S_WE]), om, h);
        q_store(&w->orient[4 * i], q);
        c = v3_load(&w->com_body[3 * i]);
        if (c.x == 0.0 && c.y == 0.0 && c.z == 0.0)
            v3_store(&w->pos[3 * i], v3_mad(v3_load(&S[S_X0]), vd, h));
        else
            v3_store(&w->pos[3 * i], v3_sub(v3_mad(v3_load(&S[S_X0]), vd, h), q_rotate(q, c)));
    }

    /* Contacts between spheres: the second half of each impulse along the
     * line of centres at the end (rbs__turn_second_halves). */
    rbs__turn_second_halves(w);

    /* Forces at the end: the second half kick's correction. */
    if (w->plan.mutual)
        rbs__mutual_gravity(w);
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        v3 a1, tau, da;
        if (w->fixed[i])
            continue;
        a1 = lin_acc(w, i, &tau);
        da = v3_sub(a1, v3_load(&S[S_A0]));
        if (da.x != 0.0 || da.y != 0.0 || da.z != 0.0)
            v3_store(&w->vel[3 * i], v3_mad(v3_load(&w->vel[3 * i]), da, 0.5 * h));
    }
}

rbs_status rbs__step_verlet(rbs_world *w, rbs_step_info *info)
{
    return rbs__step_rollback(w, info, verlet_advance, 1, w->def.dt);
}
