/*
 * step_euler.c - the seed's method: semi-implicit Euler with global rollback.
 *
 * rbs__step_rollback() is the loop every rollback method shares; a method
 * supplies the advance function that moves velocities and positions over one
 * sub-step (Euler's below; Verlet and RK4 plug in the same way).
 *
 * One frame (dt) is covered by sub-steps h = dt / 2^k.  Each sub-step:
 *   detect contacts; resolve collisions; v += a h, w += I^-1 (tau - w x Iw) h;
 *   resolve resting contacts; x += v h, q = exp(w h) q.
 * The contacts include speculative ones (contact.c): pairs a resting
 * approach can close within the step -- for every method of this loop
 * (verlet and rk4 took touching ones only before session 45, and a ball
 * rolling over a fixed sphere drifted off it past the slop and flew
 * sub-steps without friction; rbs__trapezoid_reach sets their reach).
 * If an overlap deeper than the slop appears (swept for sphere pairs), the
 * sub-step is undone and retried with h/2 (the seed's rollback) -- or with
 * the straight-line time of first touch when that is earlier -- down to the
 * floor dt / 2^max_halvings, where a contact first touched within the
 * sub-step splits it at the touch, and overlap still left is accepted,
 * pushed apart and reported.  After an accepted sub-step h doubles again.  Time is kept in
 * integer units of the floor, so a frame always ends exactly at dt.
 *
 * The work cap (max_substeps) bounds the sub-steps tried, accepted or
 * rolled back, strictly: a rollback is taken only while two more tries (the
 * retry and the rest of the frame) fit, and the last try allowed takes the
 * rest of the frame at once, its overlap pushed apart.  work_limit is set
 * only if the cap changed something: a rollback refused, or a sub-step
 * longer than the uncapped schedule's.
 */
#include <string.h>

#include "core/world_internal.h"

/* Mutual Newtonian gravity: accelerations into w->acc (exact pairwise sum). */
void rbs__mutual_gravity(rbs_world *w)
{
    uint32_t i, j;
    double G = w->def.gravity_constant, eps2 = w->def.softening * w->def.softening;
    w->acc_fresh = 0;
    memset(w->acc, 0, 3 * w->slots * sizeof(double));
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        v3 xa = rbs__body_com(w, a);
        for (j = i + 1; j < w->sphere_count; ++j) {
            uint32_t b = w->spheres[j];
            v3 d = v3_sub(rbs__body_com(w, b), xa);
            double r2 = v3_dot(d, d) + eps2, inv3;
            if (!(r2 > 0.0))
                continue;
            inv3 = G / (r2 * sqrt(r2));
            v3_store(&w->acc[3 * a], v3_mad(v3_load(&w->acc[3 * a]), d, inv3 * w->mass[b]));
            v3_store(&w->acc[3 * b], v3_mad(v3_load(&w->acc[3 * b]), d, -inv3 * w->mass[a]));
        }
    }
}

void rbs__mutual_gravity_start(rbs_world *w)
{
    if (!w->acc_fresh)
        rbs__mutual_gravity(w);
    w->acc_fresh = 0;
}

/* v += a h; w += I^-1 (tau - w x I w) h. */
void rbs__integrate_velocities(rbs_world *w, double h)
{
    uint32_t k;
    if (w->plan.mutual)
        rbs__mutual_gravity_start(w);
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
            /* torque only: the gyroscopic term w x Iw of an anisotropic body
             * is carried by conserving its angular momentum through the
             * rotation (rbs__integrate_positions) */
            v3 om = v3_load(&w->avel[3 * i]), dw;
            if (tau.x != 0.0 || tau.y != 0.0 || tau.z != 0.0) {
                rbs__body_inv_inertia_world(w, i, tau, &dw);
                v3_store(&w->avel[3 * i], v3_mad(om, dw, h));
            }
        }
    }
}

/* Past this bound on a sub-step's turn (rbs__spin_reach, rad), euler turns
 * an anisotropic body in parts.  The fixed point wm = F(wm) =
 * I(exp(wm h/2) q)^-1 L moves by |dF| <= (h/2) |L| (1/I_min - 1/I_max)
 * |dwm| (the commutator of a rotation's generator with I^-1, whose
 * eigenvalues span 1/I_max .. 1/I_min, and |dexp| <= 1), at most half the
 * reach |L| h / I_min times |dwm|: up to 1/2 rad a round contracts the
 * error at least 4-fold, and the 32 rounds reach 1e-14 (4^-24 = 3.6e-15). */
#define SPIN_ONE_TURN 0.5

/* x += v h (for the centre of mass); q = exp(w h) q, exactly.  An
 * anisotropic body (or one with an off-centre mass) keeps its angular
 * momentum L = I(q) w through the turn: w' = I(q')^-1 L.  That is Euler's
 * equation w x Iw without the explicit term, which blows up for fast spin
 * (w h ~ 1); |L| is conserved exactly (a Lie-Euler step).  A turn whose
 * reach exceeds SPIN_ONE_TURN is taken in verlet's parts of at most 1/4 rad
 * (rbs__spin_substeps, rbs__spin_stable), each the same midpoint turn. */
void rbs__integrate_positions(rbs_world *w, double h, rbs_step_info *info)
{
    uint32_t k;
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 v, om, c, L;
        quat q, qn;
        int spin, parted = 0;
        if (w->fixed[i])
            continue;
        v = v3_load(&w->vel[3 * i]);
        om = v3_load(&w->avel[3 * i]);
        c = v3_load(&w->com_body[3 * i]);
        spin = om.x != 0.0 || om.y != 0.0 || om.z != 0.0;
        q = q_load(&w->orient[4 * i]);
        L = om;
        qn = q;
        if (spin && !w->isotropic[i]) {
            /* The turn by the angular velocity of the sub-step's middle
             * (the fixed point wm = I(q_mid)^-1 L, q_mid = exp(wm h/2) q,
             * iterated to convergence), not of its start: the start's
             * (Lie-Euler) keeps |L| but not the energy, which grew
             * exponentially -- a free symmetric top spun at 5 rad/s gained
             * 22 % in 200 s at dt = 1 ms and ended turning about its axis
             * of least inertia (a probe of session 40).  The midpoint rule
             * is symmetric in time, so the energy only oscillates, by
             * O(h^2) -- once converged: two rounds (before session 47)
             * left it unsymmetric, and the energy fell steadily, a top at
             * 1e3 rad/s losing 56 % in 0.5 s at dt = 1 ms
             * (test_order.c, euler_spin_energy_does_not_drift).  Past
             * SPIN_ONE_TURN the fixed point need not converge (a symmetric
             * top at |w| h = 3 rad lost 30 % of its energy and 68 % of
             * |w_perp| in 10 s before session 49): parts, their count from
             * |L| (kept through the turn), so every step takes the same. */
            double reach = rbs__spin_reach(w, i, q, om, v3_make(0.0, 0.0, 0.0), h);
            if (reach > SPIN_ONE_TURN) {
                int stable, m = rbs__spin_substeps(w, info, reach, 0, &stable);
                rbs__spin_stable(w, i, v3_make(0.0, 0.0, 0.0), h, m, &qn, &om, NULL);
                parted = 1;
            } else {
                L = m3_mul_world(&w->inertia[9 * i], q, om);
                om = rbs__midpoint_spin(w, i, q, L, om, h);
            }
        }
        if (!parted && spin)
            qn = q_normalize(q_mul(q_from_rotation(om, h), q));
        if (c.x == 0.0 && c.y == 0.0 && c.z == 0.0) {
            v3_store(&w->pos[3 * i], v3_mad(v3_load(&w->pos[3 * i]), v, h));
        } else {
            v3 com = v3_mad(rbs__body_com(w, i), v, h);
            v3_store(&w->pos[3 * i], v3_sub(com, q_rotate(qn, c)));
        }
        if (!spin)
            continue;
        q_store(&w->orient[4 * i], qn);
        if (parted) {
            v3_store(&w->avel[3 * i], om); /* I(q')^-1 L, from rbs__spin_stable */
        } else if (!w->isotropic[i]) {
            v3 wn;
            rbs__body_inv_inertia_world(w, i, L, &wn);
            v3_store(&w->avel[3 * i], wn);
        }
    }
}

/* Euler's sub-step: forces, resting contact, then positions. */
static void euler_advance(rbs_world *w, double h, rbs_step_info *info)
{
    rbs__integrate_velocities(w, h);
    rbs__solve_resting_warm(w, info, h);
    rbs__integrate_positions(w, h, info);
}

rbs_status rbs__step_euler(rbs_world *w, rbs_step_info *info)
{
    return rbs__step_rollback(w, info, euler_advance, 1, w->def.dt);
}

/* Push a sub-step's overlap apart where the cap refused its rollback, and
 * take back the potential energy the pushes gave.  The sub-step ran past
 * the impact: a body that overtravelled into a floor by d under gravity g
 * arrives with u^2 = u_hit^2 + 2 g d, and the push restores the height but
 * not the speed, so the impact (resolved next step) returned m g d more
 * energy than it should (a ball at e = 0.9 under verlet at cap 3 kept
 * bouncing 0.11 mm high forever, +2.5e-4 J each time).  The pushes move
 * each body by d_i (all of them: out of planes and fixed bodies, and
 * between moving spheres), changing the potential energy of the forces by
 * dU = -sum m_i a_i.d_i.  Where that is a gain, it is taken back from the
 * bodies the pushes lifted against their forces (g_i = -m_i a_i.d_i > 0),
 * each its share g_i dU / sum g, from its speed along its push: u = v.n
 * (n = d_i / |d_i|) becomes sign(u) sqrt(u^2 - 2 e_i / m_i), down to zero.
 * For one body pushed out of a floor that is the constant-acceleration
 * motion back to contact, sqrt(u^2 + 2 a.d).  Pushes between free spheres
 * under uniform forces change nothing (dU = 0: momentum kept), but in a
 * stack the upper ball's push off the lower one lifts it while the lower
 * one's push out of the floor finds it at rest: counting only pushes
 * against fixed bodies, a ball on a ball on a floor (e = 0.9, verlet at
 * cap 1) kept hopping 62 um, gaining 0.061 J in 20 s (a review of session
 * 43).  The positions before the pushes, then each push and its gain,
 * are kept in w->method_scratch (4 per slot), free between sub-steps. */
static void separate_capped(rbs_world *w)
{
    double *sc = w->method_scratch, du = 0.0, gains = 0.0; /* per slot: x, then d and g */
    uint32_t k;
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t i = w->spheres[k];
        memcpy(&sc[4 * i], &w->pos[3 * i], 3 * sizeof(double));
    }
    if (!rbs__separate(w, NULL))
        return;
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t i = w->spheres[k];
        v3 d, a, tau;
        double g = 0.0;
        if (!w->fixed[i]) {
            d = v3_sub(v3_load(&w->pos[3 * i]), v3_load(&sc[4 * i]));
            if (d.x != 0.0 || d.y != 0.0 || d.z != 0.0) {
                rbs__accelerations_all(w, i, &a, &tau);
                g = -w->mass[i] * v3_dot(a, d);
            }
            v3_store(&sc[4 * i], d);
        }
        sc[4 * i + 3] = g;
        du += g;
        if (g > 0.0)
            gains += g;
    }
    if (!(du > 0.0) || !(gains > 0.0))
        return;
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t i = w->spheres[k];
        const double g = sc[4 * i + 3];
        v3 d, n, v;
        double u, u2, e;
        if (!(g > 0.0))
            continue; /* (fixed, not pushed, or pushed along its forces) */
        d = v3_load(&sc[4 * i]);
        e = du >= gains ? g : g * (du / gains); /* its share of the gain, J */
        n = v3_scale(d, 1.0 / v3_len(d));
        v = v3_load(&w->vel[3 * i]);
        u = v3_dot(v, n);
        if (u == 0.0)
            continue;
        u2 = u * u - 2.0 * e * w->inv_mass[i];
        u2 = u2 > 0.0 ? sqrt(u2) : 0.0;
        v3_store(&w->vel[3 * i], v3_mad(v, n, (u > 0.0 ? u2 : -u2) - u));
    }
}

rbs_status rbs__step_rollback(rbs_world *w, rbs_step_info *info, rbs__advance_fn advance,
                              int at_step_start, double span)
{
    const double dt = w->def.dt;
    const uint32_t K = w->def.max_halvings;
    const uint64_t total = (uint64_t)1 << K;
    const uint64_t cap = w->def.max_substeps;
    uint64_t done = 0, hu = total; /* progress and sub-step, in units of dt/2^K */
    uint64_t hu_free = total;      /* the sub-step the uncapped schedule would take */
    double pen = 0.0, first = 1.0;
    rbs__coarse coarse;
    rbs_status st;

    while (done < total) {
        double h, *save = w->sub_save;
        /* a sub-step undone takes its impulses back: the counts are of the
         * accepted sub-steps (an impact retried after a rollback counted
         * once per try: 329 for the 314 of a 100^2:1 pi billiard) */
        const uint32_t colliding = info->colliding, resting = info->resting;
        /* tries so far, this one excluded (adaptive's rest of a frame
         * counts the free flight's steps before it too) */
        const uint64_t tries = (uint64_t)info->substeps + info->rollbacks;
        if (hu > total - done)
            hu = total - done;
        if (hu_free > total - done)
            hu_free = total - done;
        if (tries + 1 >= cap)
            hu = total - done; /* the last try the cap allows: the rest at once */
        if (hu > hu_free)
            info->work_limit = 1; /* longer than the uncapped schedule's */
        h = span * ((double)hu / (double)total);
        /* until a sub-step is accepted the world is at the frame's start,
         * which rbs_world_step has just saved: no copy (and, for a frame of
         * one sub-step, sub_save is never touched) */
        if (at_step_start && done == 0)
            save = w->step_save;
        else
            rbs__save_state(w, save);
        st = rbs__detect(w, dt, 1);
        if (st != RBS_OK)
            return st;
        rbs__solve_collisions(w, info);
        advance(w, h, info);
        if (rbs__overlap_grew(w, save, &pen, &first, &coarse)) {
            /* (an overlap that rounding of the coordinates alone can make
             * grow -- far from the origin -- would be rolled back forever) */
            if (coarse.a != UINT32_MAX)
                return rbs__coarse_error(w, &coarse);
            if (hu > 1 && tries + 3 <= cap) {
                /* Retry with at most half the sub-step (the seed's rule);
                 * when the straight-line time of first touch is earlier,
                 * jump there at once instead of halving step by step.
                 * (The cap leaves room for this try, the retry and the
                 * rest of the frame.) */
                uint64_t toi = (uint64_t)((double)hu * first);
                rbs__restore_state(w, save);
                info->colliding = colliding;
                info->resting = resting;
                info->rollbacks++;
                hu = (toi >= 1 && toi < hu / 2) ? toi : hu / 2;
                hu_free = hu;
                continue;
            }
            if (hu == 1 && first > 0.0 && first < 1.0) {
                /* At the floor, a contact the sub-step's straight paths
                 * first touch within it: the sub-step again in two parts,
                 * met at that touch, so its impact is taken there.  A 1 mm
                 * ball at 1e8 m/s went 0.093 m in a floor sub-step of a
                 * 1 s frame (dt / 2^30) and through a ball 1 m away, the
                 * pass reported as a floor hit only (a probe of session
                 * 45).  Overlap still left is pushed apart, as below. */
                double f = first;
                rbs__restore_state(w, save);
                info->colliding = colliding;
                info->resting = resting;
                info->rollbacks++;
                advance(w, f * h, info);
                st = rbs__detect(w, dt, 1);
                if (st != RBS_OK)
                    return st;
                rbs__solve_collisions(w, info);
                advance(w, (1.0 - f) * h, info);
                if (!rbs__overlap_grew(w, save, &pen, &first, &coarse))
                    goto accepted;
            }
            info->floor_hits++;
            if (hu > 1) {
                info->work_limit = 1; /* a rollback the cap refused */
                separate_capped(w);
            } else {
                rbs__separate(w, NULL);
            }
        }
    accepted:
        done += hu;
        info->substeps++;
        if (hu < total)
            hu <<= 1; /* grow back after an accepted sub-step */
        hu_free = hu;
    }
    info->contacts = rbs__touching(w);
    info->max_overlap = pen;
    return RBS_OK;
}
