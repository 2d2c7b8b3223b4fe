/*
 * step_verlet.c - velocity Verlet between contacts (RBS_METHOD_VERLET).
 *
 * The sub-step loop (detect, collision impulses, advance, overlap check,
 * rollback with h/2) is Euler's rbs__step_rollback(); only the advance
 * differs.  For the smooth forces (uniform gravity, applied force and torque,
 * mutual gravity) one sub-step of h is the kick-drift-kick form of Verlet
 * (Hairer, Lubich & Wanner, Geometric Numerical Integration, 2006, I.1.4):
 *
 *   v+ = v + a(x) h/2,  w+ = w + alpha(q, w) h/2     half kick
 *   resting pass on (v+, w+)
 *   x' = x + v+ h,      q' = exp(w+ h) q             drift (exact rotation)
 *   v' = v+ + a(x') h/2, w' = w+ + alpha(q', w') h/2 half kick
 *   resting pass on (v', w')
 *
 * Linear motion is the symplectic, second-order Stormer-Verlet scheme.  The
 * gyroscopic torque -w x I w depends on w itself, so the second half kick is
 * implicit in w'; one fixed-point iteration from the predictor w+ +
 * alpha(q', w+) h/2 keeps the local error O(h^3), i.e. second order overall.
 * For isotropic, torque-free bodies w is constant and the rotation is exact.
 *
 * Contacts: the resting pass runs twice, once on the drift velocities (so a
 * body at rest does not sink during the drift) and once on the end
 * velocities (so a body at rest ends the sub-step at rest).  With constant
 * forces this reproduces the exact constant-acceleration motion of rolling
 * and sliding, like Euler.  Accelerations are evaluated twice per sub-step
 * (no reuse across sub-steps, since contacts, rollback and setters move
 * bodies in between).
 */
#include <string.h>

#include "core/world_internal.h"

/* Half kick of every moving sphere by h (= half the sub-step).  With
 * corrector set, the angular kick is the one-iteration trapezoid described
 * above; the caller has just run the drift. */
static void kick(rbs_world *w, double h, int corrector)
{
    uint32_t k;
    if (w->plan.mutual)
        rbs__mutual_gravity(w);
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 a, tau;
        if (w->fixed[i])
            continue;
        rbs__accelerations(w, i, &a, &tau);
        if (w->plan.mutual)
            a = v3_add(a, v3_load(&w->acc[3 * i]));
        v3_store(&w->vel[3 * i], v3_mad(v3_load(&w->vel[3 * i]), a, h));
        if (w->plan.angular) {
            v3 om = v3_load(&w->avel[3 * i]), t = tau, dw;
            quat q = q_load(&w->orient[4 * i]);
            if (!w->isotropic[i])
                t = v3_sub(t, v3_cross(om, m3_mul_world(&w->inertia[9 * i], q, om)));
            if (t.x == 0.0 && t.y == 0.0 && t.z == 0.0)
                continue;
            rbs__body_inv_inertia_world(w, i, t, &dw);
            if (corrector && !w->isotropic[i]) {
                /* w' = w+ + alpha(q', w_p) h with the predictor w_p */
                v3 wp = v3_mad(om, dw, h);
                t = v3_sub(tau, v3_cross(wp, m3_mul_world(&w->inertia[9 * i], q, wp)));
                rbs__body_inv_inertia_world(w, i, t, &dw);
            }
            v3_store(&w->avel[3 * i], v3_mad(om, dw, h));
        }
    }
}

static void verlet_advance(rbs_world *w, double h, rbs_step_info *info)
{
    rbs_step_info first;
    memset(&first, 0, sizeof first);
    kick(w, 0.5 * h, 0);
    rbs__solve_resting(w, &first);
    rbs__integrate_positions(w, h);
    kick(w, 0.5 * h, 1);
    rbs__solve_resting(w, info);
    info->sweep_limit += first.sweep_limit;
}

rbs_status rbs__step_verlet(rbs_world *w, rbs_step_info *info)
{
    return rbs__step_rollback(w, info, verlet_advance);
}
