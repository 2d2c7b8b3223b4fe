/*
 * step.c - the stepping entry point: plans the stages a world needs,
 * dispatches to the chosen method, and guards the world against numerical
 * failure (a step that produces NaN or infinity is undone).
 */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "core/soft.h"
#include "core/world_internal.h"

static int nonzero3(const double *p) { return p[0] != 0.0 || p[1] != 0.0 || p[2] != 0.0; }

static int row_has(const rbs__pair *r, int resist)
{
    return r->rolling > 0.0 || r->spinning > 0.0 || (!resist && (r->mu_s > 0.0 || r->mu_k > 0.0));
}

/* rbs__row_in_use's search (its cache aside). */
static int32_t row_in_use_find(const rbs_world *w, int resist)
{
    /* the materials of moving spheres and of all bodies, one bit each (at
     * most 4096 materials and "none": 1 KiB on the stack) */
    unsigned char moving[(4097 + 7) / 8], any[(4097 + 7) / 8];
    const uint32_t n = w->def.max_materials + 1;
    uint32_t i, a, b;
    for (i = 0; i < w->pairs; ++i)
        if (row_has(&w->pair[i], resist))
            break;
    if (i == w->pairs)
        return -1; /* (the common case: no row has it) */
    memset(moving, 0, (n + 7) / 8);
    memset(any, 0, (n + 7) / 8);
    for (i = 0; i < w->sphere_count; ++i) {
        const uint32_t s = w->spheres[i], m = w->material[s];
        any[m >> 3] |= (unsigned char)(1u << (m & 7));
        if (!w->fixed[s])
            moving[m >> 3] |= (unsigned char)(1u << (m & 7));
    }
    for (i = 0; i < w->plane_count; ++i) {
        const uint32_t m = w->material[w->planes[i]];
        any[m >> 3] |= (unsigned char)(1u << (m & 7));
    }
    for (a = 0; a < n; ++a) {
        if (!(moving[a >> 3] & (1u << (a & 7))))
            continue;
        for (b = 0; b < n; ++b) {
            int32_t row;
            if (!(any[b >> 3] & (1u << (b & 7))))
                continue;
            row = w->pair_table[a * n + b];
            if (row >= 0 && row_has(&w->pair[row], resist))
                return row;
        }
    }
    return -1;
}

int32_t rbs__row_in_use(const rbs_world *w, int resist)
{
    /* (cached by rbs__world_plan: a setter makes the plan again, and the
     * search is O(materials^2) at worst -- 22 ms a step with 4000) */
    if (!w->rows_dirty)
        return resist ? w->row_resist : w->row_friction;
    return row_in_use_find(w, resist);
}

/* Decide which stages can change the result.  A stage left out is one whose
 * every contribution would be exactly zero, so results are bit-identical. */
void rbs__plan_compute(const rbs_world *w, rbs__plan *out)
{
    rbs__plan p;
    uint32_t i, moving = 0;
    double im_lo = 0.0, im_hi = 0.0; /* the moving spheres' 1/m, least and most */
    double load = 0.0; /* the moving spheres' largest load |m a|, N */
    double r_lo = 0.0;  /* ... and their smallest radius, m */
    double omega;
    memset(&p, 0, sizeof p);
    /* (rows no contact can take -- a material on no body -- count for
     * nothing: an unused row with rolling resistance took the soft step
     * off its gathered layout, first order in free fall, and refused the
     * scene to event; a probe of session 40) */
    p.gather = rbs__row_in_use(w, 1) < 0;
    p.friction = rbs__row_in_use(w, 0) >= 0;
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t s = w->spheres[i];
        if (!w->isotropic[s] || nonzero3(&w->com_body[3 * s]))
            p.gather = 0; /* (fixed spheres too: their records are read) */
        if (w->fixed[s])
            continue;
        moving++;
        if (moving == 1 || w->inv_mass[s] < im_lo)
            im_lo = w->inv_mass[s];
        if (moving == 1 || w->inv_mass[s] > im_hi)
            im_hi = w->inv_mass[s];
        if (nonzero3(&w->force[3 * s]) || nonzero3(&w->torque[3 * s]))
            p.applied = 1;
        {
            v3 a, torque;
            double f;
            rbs__accelerations(w, s, &a, &torque);
            f = v3_len(a) / w->inv_mass[s];
            if (!(f <= load)) /* (a NaN is kept: it keeps euler) */
                load = f;
            if (moving == 1 || w->radius[s] < r_lo)
                r_lo = w->radius[s];
        }
        if (nonzero3(&w->avel[3 * s]) || nonzero3(&w->torque[3 * s]) || nonzero3(&w->com_body[3 * s]))
            p.angular = 1;
        /* anisotropic: contact impulses leave rounding-level spin (the lever
         * arm is computed, never exactly along the normal) that the
         * gyroscopic term then sees, so angular motion must run too */
        if (!w->isotropic[s] || nonzero3(&w->com_body[3 * s]))
            p.gyroscopic = p.angular = p.uneven = 1;
    }
    if (p.friction)
        p.angular = 1;
    p.sphere_pairs = moving >= 1 && w->sphere_count >= 2;
    p.fixed_spheres = moving < w->sphere_count;
    p.min_radius = 0.0;
    for (i = 0; i < w->sphere_count; ++i) {
        double r = w->radius[w->spheres[i]];
        if (p.min_radius == 0.0 || r < p.min_radius)
            p.min_radius = r;
    }
    p.consecutive = w->sphere_count > 0;
    for (i = 0; i < w->sphere_count && p.consecutive; ++i)
        p.consecutive = w->spheres[i] == w->spheres[0] + i;
    p.mutual = p.mutual_acts = w->def.mutual_gravity != 0 && moving >= 1 && w->sphere_count >= 2;
    /* (mutual gravity that cannot act -- one sphere, or none moving --
     * does not take the soft step off its gathered layout: it changed a
     * lone bouncing ball's bits, and event refused the scene; a probe of
     * session 46) */
    if (p.mutual_acts)
        p.gather = 0;
    p.mass_ratio = moving > 0 ? im_hi / im_lo : 1.0;
    omega = rbs__soft_omega(w->def.dt / (double)w->def.soft_substeps);
    p.soft_sink = moving > 0 ? load * im_hi / (omega * omega * r_lo) : 0.0;
    p.method = w->def.method;
    /* (a mass ratio beyond what soft holds -- a heavy ball sinks into a
     * light one by its load over m_eff omega^2, and from about 1e5 the
     * pair no longer settles -- keeps euler, whose resting pass holds
     * stacks of 1e9:1 still; a probe of session 46 saw a 1e9 kg ball
     * crush a 1 kg one in a heap that auto stepped with soft; a ratio
     * that overflows keeps euler too; so does a sink beyond
     * RBS_METHOD_AUTO_SOFT_SINK of the smallest radius under the largest
     * load on the lightest sphere -- the sink is a length, g / omega^2 =
     * 0.25 um for a sphere's own weight at dt = 1 ms, so soft sank a pile
     * of 1 um grains by a quarter of a radius and 1 nm ones through the
     * floor, and a 1000 kg ball pressed a 0.1 kg one of 0.05 m 4.6 % of its
     * radius into the floor; a probe of session 52 -- unless more
     * sub-steps, at most RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS times as many,
     * bring it within: then soft on those) */
    p.soft_substeps = w->def.soft_substeps;
    if (p.method == RBS_METHOD_AUTO) {
        int soft = moving >= RBS_METHOD_AUTO_SOFT_BODIES && !w->def.mutual_gravity &&
                   p.mass_ratio <= RBS_METHOD_AUTO_SOFT_MASS_RATIO;
        if (soft && !(p.soft_sink <= RBS_METHOD_AUTO_SOFT_SINK)) {
            /* the sink falls with h^2: the fewest sub-steps that bring it
             * within the bound, up to RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS
             * times soft_substeps (a NaN: none) */
            const double n = ceil(w->def.soft_substeps * sqrt(p.soft_sink / RBS_METHOD_AUTO_SOFT_SINK));
            soft = n <= (double)RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS * w->def.soft_substeps &&
                   n <= (double)RBS__SOFT_SUBSTEPS_MAX;
            if (soft)
                p.soft_substeps = (uint32_t)n;
        }
        p.method = soft ? RBS_METHOD_SOFT : RBS_METHOD_EULER;
    }
    if (!w->def.prune) {
        p.angular = p.gyroscopic = p.friction = p.sphere_pairs = 1;
        p.mutual = w->def.mutual_gravity != 0;
    }
    *out = p;
}

void rbs__world_plan(rbs_world *w)
{
    if (w->rows_dirty) {
        w->row_friction = row_in_use_find(w, 0);
        w->row_resist = row_in_use_find(w, 1);
        w->rows_dirty = 0;
    }
    rbs__plan_compute(w, &w->plan);
    w->plan_dirty = 0;
}

/* Copy the dynamic state of every slot to/from a save area. */
void rbs__save_state(const rbs_world *w, double *save)
{
    uint32_t i;
    for (i = 0; i < w->slots; ++i) {
        double *s = &save[RBS__SAVE_STRIDE * i];
        memcpy(s, &w->pos[3 * i], 3 * sizeof(double));
        memcpy(s + 3, &w->vel[3 * i], 3 * sizeof(double));
        memcpy(s + 6, &w->avel[3 * i], 3 * sizeof(double));
        memcpy(s + 9, &w->orient[4 * i], 4 * sizeof(double));
    }
}

void rbs__restore_state(rbs_world *w, const double *save)
{
    uint32_t i;
    for (i = 0; i < w->slots; ++i) {
        const double *s = &save[RBS__SAVE_STRIDE * i];
        memcpy(&w->pos[3 * i], s, 3 * sizeof(double));
        memcpy(&w->vel[3 * i], s + 3, 3 * sizeof(double));
        memcpy(&w->avel[3 * i], s + 6, 3 * sizeof(double));
        memcpy(&w->orient[4 * i], s + 9, 4 * sizeof(double));
    }
}

#define SPIN_MAX_ANGLE 0.25 /* rad per rotation sub-step */

double rbs__spin_reach(const rbs_world *w, uint32_t i, quat q, v3 om, v3 tau, double h)
{
    double n;
    if (w->isotropic[i])
        n = w->iso_inv_inertia[i];
    else {
        const double *m = &w->inv_inertia[9 * i];
        double r0 = fabs(m[0]) + fabs(m[1]) + fabs(m[2]), r1 = fabs(m[3]) + fabs(m[4]) + fabs(m[5]),
               r2 = fabs(m[6]) + fabs(m[7]) + fabs(m[8]);
        n = r0 > r1 ? r0 : r1;
        n = n > r2 ? n : r2;
    }
    return (v3_len(rbs__inertia_times(w, i, q, om)) + v3_len(tau) * h) * n * h;
}

int rbs__spin_substeps(rbs_world *w, rbs_step_info *info, double reach, int exact, int *stable)
{
    double m;
    *stable = 0;
    if (exact || !(reach > SPIN_MAX_ANGLE))
        return 1;
    m = ceil(reach / SPIN_MAX_ANGLE);
    if (!(m <= (double)w->spin_left) || !(m <= (double)INT_MAX)) {
        /* The step's budget is spent: the rotation in what is left of it
         * (at least one part) by the stable update, reported.  (It was one
         * sub-step of the method over the whole turn, which verlet and rk4
         * cannot take: a top spun at 3e5 rad/s, dt = 1 s, went from 9e7 J
         * to 5e306 J in two steps with verlet.) */
        uint64_t n = w->spin_left > 0 ? w->spin_left : 1;
        info->work_limit = 1;
        w->spin_left = 0;
        *stable = 1;
        return n < (uint64_t)INT_MAX ? (int)n : INT_MAX;
    }
    w->spin_left -= (uint64_t)m;
    return (int)m;
}

/* I(q)^-1 L in world axes. */
static v3 inv_inertia_at(const rbs_world *w, uint32_t i, quat q, v3 L)
{
    if (w->isotropic[i])
        return v3_scale(L, w->iso_inv_inertia[i]);
    return m3_mul_world(&w->inv_inertia[9 * i], q, L);
}

#define SPIN_ROUNDS 32  /* fixed-point rounds of a turn's middle, at most */
#define SPIN_TOL2 1e-28 /* converged: a round changes wm by 1e-14 of itself */

v3 rbs__midpoint_spin(const rbs_world *w, uint32_t i, quat q, v3 L, v3 wm, double h)
{
    int it;
    for (it = 0; it < SPIN_ROUNDS; ++it) {
        quat qm = q_normalize(q_mul(q_from_rotation(wm, 0.5 * h), q));
        v3 wn = inv_inertia_at(w, i, qm, L), d = v3_sub(wn, wm);
        wm = wn;
        if (v3_dot(d, d) <= SPIN_TOL2 * v3_dot(wn, wn))
            break; /* converged */
    }
    return wm;
}

void rbs__spin_stable(const rbs_world *w, uint32_t i, v3 tau, double h, int n, quat *q, v3 *om, v3 *mean)
{
    const double hs = h / n;
    v3 L = rbs__inertia_times(w, i, *q, *om), sum = v3_make(0.0, 0.0, 0.0), wm = *om;
    quat qq = *q;
    int k;
    for (k = 0; k < n; ++k) {
        /* half the torque's impulse, the turn by the middle's angular
         * velocity, the other half.  The fixed point is iterated to
         * convergence (1e-14), as euler's is since session 47: at 0.3 rad
         * a part two rounds left the turn unsymmetric, and the top of
         * tests/methods/test_work_cap.c lost half its energy over 1e6
         * parts, ending about its axis of most inertia.  (A part too long
         * to converge still keeps |L|.) */
        L = v3_mad(L, tau, 0.5 * hs);
        wm = rbs__midpoint_spin(w, i, qq, L, wm, hs);
        if (wm.x != 0.0 || wm.y != 0.0 || wm.z != 0.0)
            qq = q_normalize(q_mul(q_from_rotation(wm, hs), qq));
        sum = v3_add(sum, wm);
        L = v3_mad(L, tau, 0.5 * hs);
    }
    *q = qq;
    *om = inv_inertia_at(w, i, qq, L);
    if (mean != NULL)
        *mean = v3_scale(sum, 1.0 / n);
}

/* First non-finite body, or UINT32_MAX. */
static uint32_t first_bad(const rbs_world *w)
{
    uint32_t i;
    int k;
    for (i = 0; i < w->slots; ++i) {
        if (!rbs__body_moves(w, i))
            continue;
        for (k = 0; k < 3; ++k)
            if (!isfinite(w->pos[3 * i + k]) || !isfinite(w->vel[3 * i + k]) ||
                !isfinite(w->avel[3 * i + k]))
                return i;
        for (k = 0; k < 4; ++k)
            if (!isfinite(w->orient[4 * i + k]))
                return i;
    }
    return UINT32_MAX;
}

rbs_status rbs__numeric_error(rbs_world *w, uint32_t bad)
{
    return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
        "step %llu: body %u (\"%s\") became NaN or infinite; the world is left at its last good state",
        (unsigned long long)w->step_count + 1, (unsigned)bad, w->name[bad]);
}

rbs_status rbs__coarse_error(rbs_world *w, const rbs__coarse *c)
{
    return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
        "step %llu: %s: body %u (\"%s\") touches %u (\"%s\") %.3g m from the origin, where coordinates "
        "round in steps of %.3g m, over twice its slop (%.3g m); move the scene nearer the origin, take a "
        "larger slop, or use soft or selective",
        (unsigned long long)w->step_count + 1, rbs_method_name(w->plan.method), (unsigned)c->a, w->name[c->a],
        (unsigned)c->b, w->name[c->b], c->at, rbs__spacing(c->at), c->slop);
}

/* A moving sphere whose move over a frame would be largely rounding: along
 * some axis it moves more than a thousandth of its radius (|v| dt), yet
 * coordinates there round by more than 1 % of that move.  Far from the origin x + v h rounds
 * back to x: at 1e15 m (steps of 0.125 m) a ball launched at 1 m/s stayed
 * where it was with every method, two balls closing at 1 m/s never met,
 * and a dropped one hung at its start height for 6 s while its speed grew
 * to 62 m/s; at 1e12 m a slide came out 2.4 % long (a probe of session 40).
 * Contacts have their own rule (rbs__coarse_touch); this one is about
 * free motion, so it holds for every method.  Slower moves are left alone:
 * a bounce passes through them at its top, where the error a frame is
 * still the same half spacing, small beside the bounce (at 1e10 m, a 0.1 m
 * ball: 1e-6 m); a ball slower than a thousandth of its radius a frame far
 * out is not refused but reported: *slow is set when such a move (one not
 * resting at rounding level: the rounding is also beyond 1e-9 of the
 * radius, so nothing near the origin counts) loses more than 1 % of
 * itself (rbs_world_rounded_steps: 0.05 m/s at 1e12 m froze, 0.8 % short at
 * 1e10 m, unreported; a probe of session 45).
 * Returns the slot and the axis (into *axis), or UINT32_MAX. */
static uint32_t lost_motion(const rbs_world *w, int *axis, int *slow)
{
    const double dt = w->def.dt;
    uint32_t k;
    int c;
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t i = w->spheres[k];
        const double least = 1e-3 * w->radius[i];
        if (w->fixed[i])
            continue;
        for (c = 0; c < 3; ++c) {
            const double d = fabs(w->vel[3 * i + c]) * dt, x = fabs(w->pos[3 * i + c]);
            /* (0.5 spacing(x) <= x 2^-53: most bodies stop at the first test) */
            if (!(x * 0x1p-53 > 0.01 * d))
                continue;
            if (!(d > least)) {
                if (!*slow && d > 0.0 && x * 0x1p-53 > 1e-9 * w->radius[i]) {
                    const double half = 0.5 * rbs__spacing(x);
                    *slow = half > 0.01 * d && half > 1e-9 * w->radius[i];
                }
                continue;
            }
            if (0.5 * rbs__spacing(x) > 0.01 * d) {
                *axis = c;
                return i;
            }
        }
    }
    return UINT32_MAX;
}

rbs_status rbs_world_step(rbs_world *w, rbs_step_info *info)
{
    rbs_step_info local;
    rbs_status st;
    uint32_t bad, warm_used = 0;
    int slow = 0, warm_saved;
    double method_state[8] = {0.0};
    if (w == NULL || w->magic != 0x72627377u)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (info == NULL)
        info = &local;
    memset(info, 0, sizeof *info);
    if (w->plan_dirty)
        rbs__world_plan(w);
    {
        int axis = 0;
        uint32_t lost;
        /* (the time after the step must be a number: dt = 1e308 made the
         * second step's time inf, with status OK; a probe of session 40) */
        const double t1 = w->time_base + (double)(w->step_count + 1 - w->step_base) * w->def.dt;
        if (!isfinite(t1)) {
            char nb[32], nb2[32];
            return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                "step %llu: the time after it would be beyond the largest double (t = %s s, dt = %s s)",
                (unsigned long long)w->step_count + 1, rbs__shortest(nb, rbs_world_time(w)),
                rbs__shortest(nb2, w->def.dt));
        }
        lost = lost_motion(w, &axis, &slow);
        if (lost != UINT32_MAX) {
            const double x = w->pos[3 * lost + axis], d = fabs(w->vel[3 * lost + axis]) * w->def.dt;
            return (rbs_status)rbs__world_set_error(w, RBS_E_NUMERIC,
                "step %llu: body %u (\"%s\") is %.3g m from the origin along %c, where coordinates "
                "round in steps of %.3g m, over 1 %% of the %.3g m it moves a frame: its motion would be "
                "lost to rounding; move the scene nearer the origin",
                (unsigned long long)w->step_count + 1, (unsigned)lost, w->name[lost], x, "xyz"[axis],
                rbs__spacing(fabs(x)), d);
        }
    }
    /* the state to go back to if the step fails (the soft step saves it
     * itself, and only for the layout that needs it: see step_soft.c).
     * With the bodies go the warm-start table, which the rollback methods
     * store after every sub-step's resting pass, and adaptive's step-size
     * suggestion: a step that failed mid-frame left its sub-steps' impulses
     * and step size behind, so a world stepped on after the error (a body
     * removed, dt changed) took other bits than the same world restored
     * from a checkpoint written before the failed step (a probe of session
     * 50: 27 balls dropped into a box with max_contacts 27, every method but
     * soft; adaptive's next step even succeeded where the restored world's
     * failed).  The soft step's gathered layout writes its table only once
     * the frame is known good; its general layout stores it before this
     * function's last check, so it is saved too. */
    w->step_saved = w->plan.method != RBS_METHOD_SOFT;
    if (w->step_saved)
        rbs__save_state(w, w->step_save);
    warm_saved = w->plan.method != RBS_METHOD_SOFT || !w->plan.gather;
    if (warm_saved) {
        warm_used = w->warm_used;
        memcpy(w->warm_save, w->warm, (size_t)warm_used * sizeof *w->warm);
        memcpy(method_state, w->method_state, sizeof method_state);
    }
    w->spin_left = (uint64_t)w->def.max_substeps * 256u;
    w->overlap_unmeasured = 0;
    w->step_checked = 0;
    switch (w->plan.method) {
    case RBS_METHOD_EULER:
        st = rbs__step_euler(w, info);
        break;
    case RBS_METHOD_VERLET:
        st = rbs__step_verlet(w, info);
        break;
    case RBS_METHOD_RK4:
        st = rbs__step_rk4(w, info);
        break;
    case RBS_METHOD_ADAPTIVE:
        st = rbs__step_adaptive(w, info);
        break;
    case RBS_METHOD_SELECTIVE:
        st = rbs__step_selective(w, info);
        break;
    case RBS_METHOD_EVENT:
        st = rbs__step_event(w, info);
        break;
    case RBS_METHOD_SOFT:
        st = rbs__step_soft(w, info);
        break;
    default:
        st = (rbs_status)rbs__world_set_error(w, RBS_E_UNSUPPORTED, "method \"%s\" is not available",
                                               rbs_method_name(w->plan.method));
        break;
    }
    /* Overlap the step did not make (bodies placed overlapping, or left by
     * the rollback floor) is pushed apart now, so the next step starts
     * clean; the report then describes the separated state. */
    if (st == RBS_OK && w->plan.method != RBS_METHOD_SOFT &&
        (w->overlap_unmeasured || info->max_overlap > w->def.slop * w->plan.min_radius)) {
        /* (separation moves nothing when no overlap exceeds the slop, so a
         * method that did not measure can always take this path; it
         * reports the deepest overlap of the state it leaves).  The soft step
     * pushes overlap out with its contacts' springs and is left alone. */
        double pen;
        rbs__separate(w, &pen);
        info->max_overlap = pen;
    }
    w->overlap_unmeasured = 0;
    if (st == RBS_OK && !w->step_checked && (bad = first_bad(w)) != UINT32_MAX)
        st = rbs__numeric_error(w, bad);
    if (st != RBS_OK) {
        /* (a step that saved nothing wrote nothing either) */
        if (w->step_saved)
            rbs__restore_state(w, w->step_save);
        if (warm_saved) {
            /* (in whatever order it was: the soft step's buckets, whose
             * index by slot the failed step may have remade, are put in key
             * order and indexed again when next needed, as after loading a
             * checkpoint) */
            memcpy(w->warm, w->warm_save, (size_t)warm_used * sizeof *w->warm);
            w->warm_used = warm_used;
            w->warm_ranked = 1;
            w->warm_indexed = 0;
            memcpy(w->method_state, method_state, sizeof method_state);
        }
        /* The candidate-pair list the failed step built (from the reaches
         * of the state that failed: an overflowing velocity's) is dropped;
         * the next step builds one from the restored state, which gives
         * the bits of any list still valid (a probe of session 50: euler and
         * selective kept such a list after an overflow and diverged) */
        w->vl_valid = 0;
        return st;
    }
    w->rounded_steps += (uint64_t)slow;
    w->step_count++;
    return RBS_OK;
}
