/*
 * step_soft.c - the soft step: sub-steps with soft contacts, for piles.
 *
 * Catto's "soft step" (Box2D v3's solver; E. Catto, "Solver2D", 2024, and
 * "Soft Constraints", GDC 2011), for spheres and planes.  One frame of dt:
 *
 *   detect once, with every pair the bodies' sweeps over the frame can
 *   close (rbs__detect_swept: margins |v| dt + |a| dt^2), and guards for
 *   the pairs a kick of a closing neighbour can close (guard_depth);
 *   for each of n sub-steps of h = dt / n (n = plan.soft_substeps: def's,
 *   or more under RBS_METHOD_AUTO (step.c), or with
 *   def.soft_tolerance fewer when no contact can go deep; tolerated_substeps):
 *     v += a h                      (forces)
 *     warm start                    (apply the accumulated impulses again;
 *                                    the gathered layout's later sub-steps
 *                                    take both per body: stage_velocities)
 *     solve, with bias              (one Gauss-Seidel pass: soft normal rows
 *                                    that also push out overlap, rigid
 *                                    Coulomb friction)
 *     x += v h                      (positions)
 *     relax, without bias           (one pass: rigid rows, which take back
 *                                    the velocity the push gave; over-
 *                                    relaxed for a contact that came in
 *                                    loaded: soft.h, RBS__SOFT_OVER)
 *   restitution                     (contacts that were approaching faster
 *                                    than their resting threshold at the
 *                                    frame's start leave at e times that,
 *                                    with friction in the cone of the
 *                                    normal impulse so grown)
 *   store the impulses for the next frame's warm start.
 * In the gathered layout a body that no contact of the frame touches flies
 * the frame exactly instead (stage_free); the general layout steps it on
 * the sub-steps with the others and then takes its centre back by the
 * sub-steps' lead, a dt h / 2 (fly_free), where its acceleration is constant.
 *
 * The separation of a contact during the frame is its gap at detection plus
 * the bodies' displacement along the normal since then (exact for a plane,
 * linearised for a pair of spheres, along the normal of their touch on the
 * straight paths when they are apart: rbs__detect_swept).  A contact apart
 * by s > 0 lets its pair close at s / h and no faster (speculative); a
 * touching one may overlap by the slop, and deeper overlap is pushed out
 * (at most SOFT_PUSH of the smaller radius a sub-step, as Box2D caps its
 * push speed) by a damped spring of frequency
 * omega = 2 pi RBS__SOFT_HERTZ / h and damping ratio SOFT_ZETA, as the soft
 * constraint's coefficients (Catto 2011) express it for an implicit step:
 *   bias rate = omega / (2 zeta + h omega),
 *   mass scale = h omega (2 zeta + h omega) / (1 + h omega (2 zeta + h omega)),
 *   impulse scale = 1 / (1 + h omega (2 zeta + h omega)).
 * A contact of effective mass m under a steady load L (N) sinks to exactly
 * L / (m omega^2) beyond the slop -- the soft row's fixed point after the
 * warm start -- (g / omega^2 = 0.25 um for a ball's own weight at dt = 1 ms
 * and the default 3 sub-steps, omega = 2 pi / dt): the compliance that buys
 * convergence in one pass.
 * Nothing is rolled back and no overlap is projected away (rbs_world_step
 * leaves it to the method): an impact lands within the sub-step, and the
 * bounce comes from the restitution pass, with the approach speed of the
 * frame's start.
 *
 * Two body layouts: centred isotropic spheres without rolling or spinning
 * resistance and without mutual gravity (every pile) are gathered into one
 * record per slot in w->method_scratch (v, w, 1/m, 1/I, the displacement
 * and the rotation of the frame, the slop and the push limit; after the
 * records each slot's velocity increments and its sweep margin) and
 * written back at its end, the rotation
 * as one turn by the sum of the sub-steps' w h (the order of the sub-steps'
 * turns is lost: an error of order (|w| dt)^2 in the orientation, which a
 * centred isotropic sphere's motion never reads).  Every other world steps
 * on its own arrays through the general rows and integrators.
 *
 * The gathered layout saves nothing at the frame's start (the world's
 * arrays are written only at its end, once every value is known finite),
 * takes all the sub-steps of a body that no contact touches at once, shares
 * one velocity increment among the bodies when none has its own force, and
 * measures the report in its last relax pass; each of these gives the same
 * bits as the sweeps it replaces (docs/methods.md, "soft").
 */
#include <string.h>

#include "core/rows.h"
#include "core/soft_detect.h"
#include "core/team.h"

/* Why the contact frequency (RBS__SOFT_HERTZ, soft.h) is a third of the
 * sub-step rate: with the default 3 sub-steps, 1 / dt (the spring of 4
 * sub-steps at a quarter of their rate, Box2D's cap, before session 37).
 * The soft coefficients
 * depend on h omega = 2 pi RBS__SOFT_HERTZ alone, and with SOFT_ZETA = 10 the
 * row is near rigid either way (mass scale 0.979 against 0.971); a frame of
 * 3 sub-steps pushes out 26 % of a deep overlap, as 4 did.  On the peers'
 * piles (7 of 1,000 spheres, 3 of 8,000) the overlaps during the run and
 * at its end were about those of 4 sub-steps, in 0.88x the time
 * (docs/methods.md, "Session 37").  RBS_METHOD_AUTO reads it too
 * (step.c: the sink it allows). */
#define SOFT_PUSH 0.01  /* the most overlap pushed out in one sub-step, of the smaller radius */
#define SOFT_ZETA 10.0  /* damping ratio of the contact spring */

/* The general layout's pass state (the gathered one's is rbs__soft_rows). */
typedef struct soft_pass {
    rbs_world *w;
    double inv_h;
    double bias_rate, mass_scale, impulse_scale;
    double hold;          /* rbs__soft_rows' */
    int friction;
    uint32_t restituted;  /* contacts the restitution pass changed */
    int last;             /* the frame's last sub-step */
} soft_pass;

enum { SOLVE = RBS__SOFT_SOLVE, RELAX = RBS__SOFT_RELAX, RESTITUTION = RBS__SOFT_RESTITUTION };

/* The displacement of slot i since the frame's start. */
static v3 displacement(const soft_pass *sp, uint32_t i)
{
    const rbs_world *w = sp->w;
    return v3_sub(v3_load(&w->pos[3 * i]), v3_load(&w->step_save[RBS__SAVE_STRIDE * i]));
}

/* Whether c is a centred sphere's contact with a fixed sphere that touched
 * at detection (its n the line of the centres): its rows take the normal
 * and separation of now (docs/methods.md, "soft"). */
static int turns(const soft_pass *sp, const rbs__contact *c)
{
    const rbs_world *w = sp->w;
    return w->type[c->b] == RBS_BODY_SPHERE && !(c->flags & RBS__OFF) &&
           (w->inv_mass[c->a] == 0.0 || w->inv_mass[c->b] == 0.0) && c->gap <= rbs__contact_slop(w, c);
}

/* A contact's separation now, m: its gap at detection plus the motion of
 * its bodies along n; against a fixed sphere (turns), the distance of the
 * centres less the radii. */
static double separation(const soft_pass *sp, const rbs__contact *c)
{
    if (turns(sp, c)) {
        const rbs_world *w = sp->w;
        return v3_len(v3_sub(v3_load(&w->pos[3 * c->a]), v3_load(&w->pos[3 * c->b]))) - w->radius[c->a] -
               w->radius[c->b];
    }
    return c->gap + v3_dot(c->n, v3_sub(displacement(sp, c->a), displacement(sp, c->b)));
}

/* Turn c's normal to the line of the centres now, when it turns. */
static void turn(const soft_pass *sp, rbs__contact *c)
{
    if (turns(sp, c)) {
        const rbs_world *w = sp->w;
        v3 d = v3_sub(v3_load(&w->pos[3 * c->a]), v3_load(&w->pos[3 * c->b]));
        double l = v3_len(d);
        if (l > 0.0)
            c->n = v3_scale(d, 1.0 / l);
    }
}

static inline v3 relative_velocity(const soft_pass *sp, const rbs__contact *c)
{
    return rbs__rel_velocity(sp->w, c);
}

/* The depth a guard contact (RBS__GUARD) may overlap before its rows act,
 * m: RBS__GUARD_DEPTH of the smaller radius (slop: the pair's slop, def.slop
 * of that radius).  A pair that only a kick within the frame can close is
 * the next impact of a chain, and met in the next frame it bounces with its
 * whole approach, as the impact law says, while rows acting in this frame
 * make the chain's impacts one inelastic impact (a guard acting at 1 % of
 * the radius gave a spaced Newton's cradle errors of up to 0.6 of its
 * speed, and one at a quarter lost a third of the energy of a ball shot at
 * 30 m/s into a grid of 64).  So a guard lets a kick take its pair half a
 * radius deep, as before (every test and pile is the same bits), and stops
 * it there: without guards such a pair was no contact at all, and a ball
 * kicked at 4 radii a frame went 1.4 radii into the next one and a line of
 * five gained 27 % of its energy; a ball shot at 100 m/s into the grid
 * went 0.97 radii deep and the grid gained 19 % (tests/methods/test_soft.c). */
static inline double guard_depth(const soft_pass *sp, double slop)
{
    return RBS__GUARD_DEPTH * slop / sp->w->def.slop;
}

/* The change of a contact's accumulated normal impulse in a SOLVE or RELAX
 * row: vn its normal approach, s its separation, slop and most its pair's
 * slop and push limit (most: m/s).  Apart (s > 0) it may close the gap
 * within the sub-step and no more; touching, the solve's soft row pushes
 * out the overlap beyond the slop and the relax's rigid row stops the
 * approach (RBS__SOFT_OVER times that for a contact that came in loaded,
 * RBS__WARM); a guard's s is taken guard_depth deeper.  In the frame's last
 * relax (last != 0) a pair still apart by
 * more than the slop that took no impulse in the frame -- an impact due
 * after the frame's end -- takes no new impulse (it may only give some
 * back): the next frame detects it again and meets the impact along the
 * normal of the touch, with the whole approach for restitution.  (Clipped
 * here to close its gap in one more sub-step, such an impact was split over
 * two frames along two normals and bounced from the clipped approach: up to
 * 11 % of the relative speed off in glancing impacts at dt = 10 ms.  A pair
 * within the slop has met, up to rounding, and one that took impulses is a
 * pile's contact: their rows stay as in every other relax, since leaving
 * every apart pair to the next frame made the 1,000 pile's deepest
 * overlap 18 % deeper, median of 8 piles.) */
static inline double normal_change(const soft_pass *sp, const rbs__contact *c, int stage, double vn, double s,
                                   double slop, double most, int last)
{
    double over, push;
    if (c->flags & RBS__GUARD)
        s += guard_depth(sp, slop);
    if (s > 0.0) {
        double dj = -(vn + s * sp->inv_h) * c->thr;
        return last && dj > 0.0 && s > slop && !(c->flags & RBS__TOUCHED) ? 0.0 : dj;
    }
    if (stage != SOLVE)
        return c->flags & RBS__WARM ? -vn * c->thr * RBS__SOFT_OVER : -vn * c->thr;
    over = s + slop < 0.0 ? s + slop : 0.0;
    push = sp->bias_rate * over;
    if (push < -most) {
        /* the limit is never below twice the push that holds the contact's
         * load (jn / m_eff over a): capped below it, a resting load sank
         * without end (soft_rows.h) */
        const double hold = sp->hold * c->jn * c->kn;
        if (hold > most)
            most = hold;
    }
    return -sp->mass_scale * (vn + (push < -most ? -most : push)) * c->thr - sp->impulse_scale * c->jn;
}

/* Whether the restitution pass takes c: it approached faster than its
 * resting threshold at the frame's start, with e > 0, and took an impulse. */
static inline int bounces(const rbs__contact *c)
{
    return (c->flags & (RBS__BOUNCE | RBS__TOUCHED)) == (RBS__BOUNCE | RBS__TOUCHED);
}

/* The restitution row's change of the normal impulse: the pair leaves at e
 * times its approach speed at the frame's start (c->bias). */
static inline double restitution_change(const rbs_world *w, const rbs__contact *c, double vn)
{
    return -(vn + rbs__contact_e(w, c) * c->bias) * c->thr;
}

/* Accumulate dj into c's normal impulse (kept >= 0); the impulse it adds,
 * along n. */
static inline v3 normal_accumulate(rbs__contact *c, double dj)
{
    double jn = c->jn + dj < 0.0 ? 0.0 : c->jn + dj;
    v3 j = v3_scale(c->n, jn - c->jn);
    c->jn = jn;
    if (jn > 0.0)
        c->flags |= RBS__TOUCHED;
    return j;
}

/* The rolling and spinning rows of contact i (rbs__resist_row), bounded by
 * the load its normal impulse carries, not by the impact in it: the other
 * methods resolve an impact in the collision pass, with friction only, and
 * the resistance acts on the resting load (docs/physics.md).  Bounded by
 * the whole Jn (before session 46), a spinning ball that landed lost
 * mu_sp Jn / I of its spin at once -- 1.21 rad/s of 10 dropped 0.3 m with
 * mu_sp = 0.002, at every dt, where the other methods converge to the
 * exact 10 - alpha (t - t1) -- and a ball rolling off an incline onto a
 * floor (mu_r = 0.02) rolled on 9.7e-3 m/s slow. */
static void resist_loaded(rbs_world *w, rbs__contact *c, uint32_t i)
{
    const double jn = c->jn, impact = w->contact_resist[i].impact;
    if (impact > 0.0)
        c->jn = jn > impact ? jn - impact : 0.0;
    (void)rbs__resist_row(w, i);
    c->jn = jn;
}

/* Rounds of a contact's friction and rolling rows (friction_and_rolling). */
#define ROLL_ROUNDS 64

/* The normal impulse j, then the friction and rolling-resistance rows of
 * contact i taken together: one row each, as the other contacts get, does
 * not hold a ball that mu_s and mu_r would hold on a slope -- the friction
 * row's stick impulse takes the ball as free to turn, the rolling row then
 * stops the turning, and the slip comes back smaller by 5/7 a round (a
 * solid ball) -- so that in a sub-step's one pass the friction stayed short
 * or, over the static cone on the way, slid at mu_k (a probe of session 39:
 * 20 degrees, mu_s 1.05 tan, mu_r 10 tan, the ball slid away at 3 m/s).
 * The two rows are repeated on this contact, the friction kept in the
 * static cone, until the stick impulse is rounding (at most ROLL_ROUNDS);
 * if the static cone still binds with the slip left, the contact slides,
 * at mu_k, and the rolling row takes the turning once more. */
static void friction_and_rolling(rbs_world *w, rbs__contact *c, const rbs__pair *p, uint32_t i, v3 j)
{
    const double lim = rbs__friction_cap(p, c->jslip, c->jn) * c->jn;
    int round, bound = 0, was_bound = 0;
    v3 stick = v3_make(0, 0, 0), unbound = v3_make(0, 0, 0);
    rbs__kt kt;
    rbs__apply_pair(w, c, j);
    kt.set = 0;
    for (round = 0; round < ROLL_ROUNDS; ++round) {
        v3 cand;
        double l2;
        stick = rbs__stick_impulse_kt(w, c, rbs__slip(w, c), &kt);
        cand = v3_add(c->jt, stick);
        l2 = v3_dot(cand, cand);
        bound = l2 > lim * lim;
        if (bound) {
            unbound = cand;
            cand = rbs__slide_impulse(w, c, cand, sqrt(l2), lim, &kt);
        }
        rbs__apply_pair(w, c, v3_sub(cand, c->jt));
        c->jt = cand;
        resist_loaded(w, c, i);
        if (v3_dot(stick, stick) <= 1e-24 * (lim * lim + v3_dot(c->jt, c->jt)) || (bound && was_bound))
            break; /* (held; or the cone binds twice: it slides) */
        was_bound = bound;
    }
    if (bound) {
        /* slides: kinetic friction along the last (static-limited) impulse;
         * without an isotropic tangent plane, the one nearest to the last
         * sticking impulse (see rbs__slide_impulse) */
        double l = v3_len(c->jt);
        if (l > 0.0) {
            v3 kin = c->kt_inv > 0.0 ? v3_scale(c->jt, p->mu_k * c->jn / l)
                                     : rbs__slide_impulse(w, c, unbound, v3_len(unbound), p->mu_k * c->jn, &kt);
            rbs__apply_pair(w, c, v3_sub(kin, c->jt));
            c->jt = kin;
            resist_loaded(w, c, i);
        }
    }
}

/* Whether contact c is a sphere's contact with a plane. */
static inline int with_plane(const rbs_world *w, const rbs__contact *c)
{
    return w->type[c->b] == RBS_BODY_PLANE;
}

/* Whether contact c is a moving sphere's contact with a fixed one. */
static inline int with_fixed(const rbs_world *w, const rbs__contact *c)
{
    return w->type[c->b] == RBS_BODY_SPHERE && (w->fixed[c->a] || w->fixed[c->b]);
}

/* One pass over the contacts, on the world's own arrays (the general
 * layout; row_fast is the gathered one): stage SOLVE (soft, with bias),
 * RELAX (rigid) or RESTITUTION (normal rows that make the pair leave at e
 * times its approach, and friction within Coulomb's cone of the grown
 * normal impulse, so that an oblique bounce follows the impact law), over
 * contacts [begin, end); apart < 0 every one, else only those apart now by
 * more than their slop (1) or not (0); fixed < 0 every one, else only those
 * with a fixed sphere (1) or without (0). */
static void pass_rows(soft_pass *sp, int stage, uint32_t begin, uint32_t end, int apart, int fixed)
{
    rbs_world *w = sp->w;
    uint32_t i;
    for (i = begin; i < end; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        v3 rv, j;
        if (fixed >= 0 && with_fixed(w, c) != fixed)
            continue;
        if (apart >= 0 && (separation(sp, c) > rbs__contact_slop(w, c)) != apart)
            continue;
        turn(sp, c);
        rv = relative_velocity(sp, c);
        double vn = v3_dot(rv, c->n), jn, dj;
        if (stage == RESTITUTION) {
            if (!bounces(c))
                continue;
            dj = restitution_change(w, c, vn);
        } else {
            double slop = rbs__contact_slop(w, c);
            /* (the push limit from the smaller radius, as the slop's) */
            dj = normal_change(sp, c, stage, vn, separation(sp, c), slop,
                               SOFT_PUSH * slop / w->def.slop * sp->inv_h, stage == RELAX && sp->last);
        }
        jn = c->jn;
        j = normal_accumulate(c, dj);
        if (stage == RESTITUTION && c->jn != jn) {
            sp->restituted++;
            if (p->rolling > 0.0 || p->spinning > 0.0)
                w->contact_resist[i].impact += c->jn - jn; /* (the bounce's: no load) */
        }
        jn = c->jn;
        if (sp->friction && p->rolling > 0.0 && jn > 0.0 && (p->mu_s > 0.0 || p->mu_k > 0.0)) {
            friction_and_rolling(w, c, p, i, j);
        } else {
            if (sp->friction && (p->mu_s > 0.0 || p->mu_k > 0.0) &&
                (jn > 0.0 || c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0)) {
                /* the slip after the normal impulse (levers need not lie along n) */
                v3 cand;
                rbs__apply_pair(w, c, j);
                rbs__kt kt;
                v3 stick = rbs__stick_impulse_kt(w, c, rbs__slip(w, c), &kt);
                cand = rbs__cone(w, c, p, stick, &kt);
                j = v3_sub(cand, c->jt);
                c->jt = cand;
            }
            rbs__apply_pair(w, c, j);
            if (sp->friction && jn > 0.0 && (p->rolling > 0.0 || p->spinning > 0.0))
                resist_loaded(w, c, i);
        }
        if (stage == RELAX && !sp->last && (p->rolling > 0.0 || p->spinning > 0.0)) {
            /* what of the impact this sub-step's normal impulse took, once
             * its rows are done (not after the last relax: the restitution
             * pass goes on with its accumulated impulse, the impact it held
             * included) */
            rbs__resist *rs = &w->contact_resist[i];
            rs->impact = rs->impact > jn ? rs->impact - jn : 0.0;
        }
    }
}

/* One pass of stage over the contacts, in order -- but in SOLVE and RELAX a
 * sphere's contacts with planes (detection makes them one run) take those
 * touching now (within their slop) before those apart, as a serial
 * chunk's lanes do in the gathered layout (soft_rows.h, row_lanes): a
 * touching row takes back what the warm start gave beyond its need (the
 * impulse that stopped an impact, given back at the next sub-step's start)
 * before the speculative row of an opposite wall reads that velocity as an
 * approach (docs/methods.md, "soft").  (Every touching contact before
 * every apart one made a general-layout pile of 400 balls 18 % deeper
 * during its run, median of 12; a probe of session 51.)  With a fixed
 * sphere in the world, the contacts with fixed spheres touching now go
 * before every other contact, and those apart after them all: a fixed
 * sphere never moves, like a plane, but a sphere's contacts with fixed
 * spheres are not one run (soft_rows.h, pass_stage, does the same). */
static void pass(soft_pass *sp, int stage)
{
    const rbs_world *w = sp->w;
    const int fixed = w->plan.fixed_spheres;
    uint32_t i = 0, j;
    if (stage == RESTITUTION) {
        pass_rows(sp, stage, 0, w->contact_count, -1, -1);
        return;
    }
    if (fixed)
        pass_rows(sp, stage, 0, w->contact_count, 0, 1);
    while (i < w->contact_count) {
        const rbs__contact *c = &w->contact[i];
        j = i + 1;
        if (!with_plane(w, c)) {
            /* (a run of other contacts, in order) */
            while (j < w->contact_count && !with_plane(w, &w->contact[j]))
                ++j;
            pass_rows(sp, stage, i, j, -1, fixed ? 0 : -1);
        } else {
            while (j < w->contact_count && w->contact[j].a == c->a && with_plane(w, &w->contact[j]))
                ++j;
            pass_rows(sp, stage, i, j, 0, -1);
            pass_rows(sp, stage, i, j, 1, -1);
        }
        i = j;
    }
    if (fixed)
        pass_rows(sp, stage, 0, w->contact_count, 1, 1);
}

/* Whether contact c is lone: each of its bodies is fixed (or a plane), or
 * in no other contact that came in loaded (count: each body's loaded
 * contacts, up to 2; soft.h, RBS__SOFT_OVER). */
static int lone(const rbs_world *w, const unsigned char *count, const rbs__contact *c)
{
    return (!rbs__body_moves(w, c->a) || count[c->a] == 1) && (!rbs__body_moves(w, c->b) || count[c->b] == 1);
}

/* Apply the accumulated impulses again (each sub-step starts from them). */
static void warm_start(soft_pass *sp)
{
    rbs_world *w = sp->w;
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        if (c->jn != 0.0 || c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0)
            rbs__apply_pair(w, c, v3_add(v3_scale(c->n, c->jn), c->jt));
        if (c->jn > 0.0) {
            const rbs__pair *p = rbs__contact_pair(w, c);
            if (p->rolling > 0.0 || p->spinning > 0.0) {
                const rbs__resist *rs = &w->contact_resist[i];
                rbs__apply_angular_pair(w, c, v3_mad(rs->jroll, c->n, rs->jspin));
            }
        }
    }
}

/* Each body's acceleration a and torque (the applied forces and gravity;
 * with mutual gravity its field now) into acc[6 slot ..], zero for planes
 * (unless acc is NULL), and how far each moving sphere may travel within
 * the frame, |v| dt + |a| dt^2, into margin[slot]. */
static void margins(rbs_world *w, double dt, double *acc, double *margin)
{
    uint32_t k;
    if (w->plan.mutual)
        rbs__mutual_gravity(w);
    for (k = 0; acc != NULL && k < w->plane_count; ++k)
        memset(&acc[6 * w->planes[k]], 0, 6 * sizeof(double));
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t i = w->spheres[k];
        v3 a, tau;
        rbs__accelerations(w, i, &a, &tau);
        if (w->plan.mutual && !w->fixed[i])
            a = v3_add(a, v3_load(&w->acc[3 * i]));
        if (acc != NULL) {
            v3_store(&acc[6 * i], a);
            v3_store(&acc[6 * i + 3], tau);
        }
        margin[i] = rbs__sweep_margin(w, i, a, dt);
    }
}

/* Whether every moving sphere has one and the same acceleration and no
 * angular one -- gravity as an acceleration and no applied force or torque,
 * as in every pile -- and then that acceleration into *a_out. */
static int uniform_acceleration(const rbs_world *w, v3 *a_out)
{
    uint32_t k;
    v3 a = v3_make(0, 0, 0), tau;
    /* (the plan knows whether any moving sphere has a force or torque) */
    if (w->def.gravity_mode != RBS_GRAVITY_ACCELERATION || w->plan.applied)
        return 0;
    for (k = 0; k < w->sphere_count; ++k)
        if (!w->fixed[w->spheres[k]]) {
            rbs__accelerations(w, w->spheres[k], &a, &tau);
            break;
        }
    *a_out = a;
    return 1;
}

/* The shared increment over a sub-step of h into inc[0..5]: a h, then 0 for
 * the angular part (what the table of increments would hold for each body,
 * bit for bit). */
static void shared_increment(v3 a, double h, double *inc)
{
    v3_store(inc, v3_scale(a, h));
    v3_store(inc + 3, v3_make(0, 0, 0));
}

/* The sub-steps of a frame under def.soft_tolerance: the fewest of
 * soft_substeps halved (down to 1) for which every contact's reachable
 * overlap -- its overlap now plus its approach over the frame,
 * -gap + max(0, -vn dt), as a fraction of its pair's smaller radius -- is
 * under soft_tolerance n / soft_substeps; q: the deepest of them over
 * soft_tolerance (a NaN keeps every sub-step).  It reads only the state at
 * the frame's start, so a checkpoint needs nothing more to resume it. */
static uint32_t tolerated_substeps(const rbs_world *w, double q)
{
    const uint32_t full = w->plan.soft_substeps;
    uint32_t n = full;
    while (n > 1 && q < (double)(n / 2) / (double)full)
        n /= 2;
    return n;
}

/* The velocity increments of slot i (without a shared increment) for
 * sub-steps of h, from the accelerations in inc -- those of a body of no
 * contact (touched 0), or a plane's (0), for the full sub-steps h_full; ii
 * its 1/I. */
static inline void increments_for_h(const rbs_world *w, double *inc, uint32_t i, double ii, int touched, double h,
                                    double h_full)
{
    const double hi = w->type[i] == RBS_BODY_SPHERE && touched ? h : h_full;
    v3_store(&inc[6 * i], v3_scale(v3_load(&inc[6 * i]), hi));
    v3_store(&inc[6 * i + 3], v3_scale(v3_load(&inc[6 * i + 3]), ii * hi));
}

/* A contact's warm start for sub-steps of h from the last frame's forces:
 * fn along n, ft its tangent force (in today's tangent plane; only with
 * friction), kept in the static cone (rbs__warm_tangent). */
static inline void warm_for_h(rbs__contact *c, const rbs__pair *p, int friction, double fn, v3 ft, double h)
{
    c->jn = fn * h;
    if (friction)
        c->jt = rbs__warm_tangent(v3_scale(ft, h), rbs__friction_cap(p, c->jslip, c->jn) * c->jn);
}

/* The row kernels of this processor: AVX where the build has them and the
 * processor runs them, else the plain ones (the same bits). */
const rbs__soft_kernels *rbs__soft_kernels_best(void)
{
#if defined(RBS_HAVE_AVX_KERNELS)
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl"))
        return &rbs__soft_kernels_avx512;
    if (__builtin_cpu_supports("avx"))
        return &rbs__soft_kernels_avx;
#endif
    return &rbs__soft_kernels_plain;
}

/* Slot i's record at the frame's start (soft.h): 1/I 0 for a body that does
 * not move, so that an impulse leaves it as it was. */
static void record_start(const rbs_world *w, double *r, uint32_t i)
{
    const int sphere = w->type[i] == RBS_BODY_SPHERE;
    memcpy(r + RBS__REC_V, &w->vel[3 * i], 3 * sizeof(double));
    memcpy(r + RBS__REC_W, &w->avel[3 * i], 3 * sizeof(double));
    memset(r + RBS__REC_D, 0, 3 * sizeof(double));
    r[RBS__REC_IM] = w->inv_mass[i];
    r[RBS__REC_II] = sphere && w->inv_mass[i] != 0.0 ? w->iso_inv_inertia[i] : 0.0;
    r[RBS__REC_R] = sphere ? w->radius[i] : 0.0;
    memset(r + RBS__REC_ROT, 0, 4 * sizeof(double));
}

/* The soft step's coefficients for sub-steps of h into the rows. */
static void rows_for_h(rbs__soft_rows *rows, double h)
{
    const double omega = rbs__soft_omega(h);
    const double a1 = 2.0 * SOFT_ZETA + h * omega, a2 = h * omega * a1;
    rows->inv_h = 1.0 / h;
    rows->bias_rate = omega / a1;
    rows->mass_scale = a2 / (1.0 + a2);
    rows->impulse_scale = 1.0 / (1.0 + a2);
    rows->push = SOFT_PUSH * rows->inv_h;
    rows->hold = 2.0 * rows->impulse_scale / rows->mass_scale;
}

/* A frame of the gathered layout: what its stages (team.h) read and write.
 * The per-body stages take the spheres of slabs [begin, end); the rows' the
 * groups [begin, end) of one level (soft_detect.h). */
typedef struct soft_frame {
    rbs_world *w;
    const rbs__soft_groups *g;
    double *rec, *inc;
    const uint8_t *touched;
    const double *ib_frame, *ib_free; /* the shared increments (shared), else NULL */
    int shared;
    double h, h_full, half_dt;        /* half_dt: dt / 2 (stage_free) */
    uint32_t full;
    uint32_t sub;                     /* the sub-step under way */
    rbs__soft_rows rows;
    int stage;                        /* the rows' stage of this pass */
    rbs__stage_fn before;             /* the per-body stage taken with the leaves (rows_pass) */
    uint32_t first;                   /* the level's first group */
    uint32_t bad[RBS_WORKERS_MAX];    /* write-back check: a non-finite slot, or UINT32_MAX */
    uint32_t runs;                    /* the write-back's runs of spheres (stage_write_back) */
    int writing;                      /* its stage: 0 check and count, 1 write and place */
    uint8_t item[RBS__TEAM_SHARES];   /* its items: run k (< runs), or the
                                         store's share k - runs */
    rbs__soft_store store;            /* the warm store (stage_write_back) */
    rbs__soft_report report[RBS_WORKERS_MAX];
} soft_frame;

/* The slot of the frame's record r (soft_detect.c: the records are the
 * spheres slab by slab). */
static inline uint32_t slot_of(const soft_frame *f, uint32_t r)
{
    return f->w->spheres[f->w->soft_order[r]];
}

/* The records of slabs [begin, end). */
#define SLAB_RECORDS(f, begin, end, r) r = (f)->g->slab_first[begin]; r < (f)->g->slab_first[end]; ++r

/* Records at the frame's start (and, without a shared increment, each
 * body's velocity increments for its sub-steps). */
static void stage_records(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    uint32_t r;
    (void)share;
    for (SLAB_RECORDS(f, begin, end, r)) {
        const uint32_t b = slot_of(f, r);
        record_start(f->w, &f->rec[RBS__REC * r], b);
        if (!f->shared)
            increments_for_h(f->w, f->inc, b, f->rec[RBS__REC * r + RBS__REC_II], f->touched[r], f->h, f->h_full);
    }
}

/* The velocities of the spheres in a contact at a sub-step's start, with
 * its warm start.  The first sub-step: v += a h, and the warm-start pass of
 * the rows then applies every contact's accumulated impulse.  A later one:
 * after sub-step s a body's velocity is v_s = v_(s-1) + a h + J_s (J_s the
 * sum of its contacts' accumulated impulses over its mass: the warm start
 * applied J_(s-1), solve and relax the changes to J_s), so the next
 * sub-step's v_s + a h + J_s is v_s + (v_s - v_(s-1)) -- the accumulated
 * impulses applied again without a pass over the contacts -- and likewise
 * for w.  (The same in exact arithmetic, rounded differently.)  Each body's
 * velocities before the sub-step are kept in the increments table, whose
 * increments are read only at the first sub-step (a free body's, in
 * stage_free, are not touched): 48 bytes a body in a contact that a pile
 * under gravity alone would not touch otherwise.  When the increment is
 * shared the table holds none, and the entry is the record's (rank r), so
 * that a slab's entries are together as its records are and a thread
 * writes its own cache lines; in slot order (a table of increments) the
 * slabs' bodies interleave, and the two threads wrote into the same lines
 * three times a frame. */
static void stage_velocities(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    uint32_t r;
    (void)share;
    for (SLAB_RECORDS(f, begin, end, r)) {
        double *q = &f->rec[RBS__REC * r], *p;
        v3 v, om, dv, dw;
        if (!f->touched[r] || q[RBS__REC_IM] == 0.0) /* (the flag first: a free body's record is not read) */
            continue;
        p = &f->inc[6 * (f->shared ? r : slot_of(f, r))];
        v = v3_load(q + RBS__REC_V);
        om = v3_load(q + RBS__REC_W);
        if (f->sub == 0) {
            const double *ib = f->shared ? f->ib_frame : p;
            dv = v3_load(ib);
            dw = v3_load(ib + 3);
        } else {
            dv = v3_sub(v, v3_load(p));
            dw = v3_sub(om, v3_load(p + 3));
        }
        v3_store(p, v);
        v3_store(p + 3, om);
        v3_store(q + RBS__REC_V, v3_add(v, dv));
        v3_store(q + RBS__REC_W, v3_add(om, dw));
    }
}

/* d += v h, rotation += w h for the spheres in a contact (each sub-step). */
static void stage_positions(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    uint32_t r;
    (void)share;
    for (SLAB_RECORDS(f, begin, end, r)) {
        double *q = &f->rec[RBS__REC * r];
        if (!f->touched[r] || q[RBS__REC_IM] == 0.0)
            continue;
        v3_store(q + RBS__REC_D, v3_mad(v3_load(q + RBS__REC_D), v3_load(q + RBS__REC_V), f->h));
        v3_store(q + RBS__REC_ROT, v3_mad(v3_load(q + RBS__REC_ROT), v3_load(q + RBS__REC_W), f->h));
    }
}

/* The spheres no contact touched fly the frame exactly: their velocities
 * take soft_substeps times the increment of h_full (a h_full, alpha h_full:
 * the frame's constant accelerations), at once, and their displacement and
 * rotation are the frame's mean velocities times dt -- (v0 + v1) dt / 2 =
 * v0 dt + a dt^2 / 2, exact for a constant acceleration, where Euler on the
 * sub-steps lagged by a dt h / 2 a frame (g T h / 2 over a fall of T). */
static void stage_free(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    const double n = (double)f->full;
    uint32_t r;
    (void)share;
    for (SLAB_RECORDS(f, begin, end, r)) {
        double *q = &f->rec[RBS__REC * r];
        const double *ib;
        v3 v, om, v0, om0, d, th, dv, dw;
        if (f->touched[r] || q[RBS__REC_IM] == 0.0)
            continue;
        ib = f->shared ? f->ib_free : &f->inc[6 * slot_of(f, r)];
        v = v3_load(q + RBS__REC_V);
        om = v3_load(q + RBS__REC_W);
        d = v3_load(q + RBS__REC_D);
        th = v3_load(q + RBS__REC_ROT);
        dv = v3_load(ib);
        dw = v3_load(ib + 3);
        v0 = v;
        om0 = om;
        v = v3_mad(v0, dv, n);
        om = v3_mad(om0, dw, n);
        d = v3_mad(d, v3_add(v0, v), f->half_dt);
        th = v3_mad(th, v3_add(om0, om), f->half_dt);
        v3_store(q + RBS__REC_V, v);
        v3_store(q + RBS__REC_W, om);
        v3_store(q + RBS__REC_D, d);
        v3_store(q + RBS__REC_ROT, th);
    }
}

/* q turned by the rotation vector th (rad; q_from_turn), not yet normalised
 * (normalised: by one division, check_run's second loop -- the result
 * differs from q_normalize's four divisions in the last bit or so -- an
 * orientation, which a centred isotropic sphere's motion never reads). */
static quat turned(v3 th, quat q)
{
    return q_mul(q_from_turn(th), q);
}

/* The write-back's first half: every new value made and checked finite (a
 * finite rotation too large to square gives a NaN turn), the new
 * orientation kept in the record (the rotation and the spare double after
 * it, free now; in the radius' place, free too, whether it turned); the
 * run's first sphere in slot order that is not, in bad[run].  The write-back takes
 * the spheres [begin, end) in slot order, not slab by slab: each thread
 * then writes its own run of the world's arrays (by slab, two threads
 * wrote into the same cache lines and the write-back took 9x as long).
 * The turned orientations are normalised in a second loop of their own:
 * its square roots and divisions, one chain a sphere, then overlap from
 * sphere to sphere (in the first loop's long body they held it up). */
static void check_run(soft_frame *f, uint32_t run, uint32_t begin, uint32_t end)
{
    const rbs_world *w = f->w;
    uint32_t i, bad = UINT32_MAX;
    for (i = begin; i < end; ++i) {
        const uint32_t b = w->spheres[i];
        double *q = &f->rec[RBS__REC * w->soft_rank[i]];
        v3 th = v3_load(q + RBS__REC_ROT);
        int ok = 1, turns = th.x != 0.0 || th.y != 0.0 || th.z != 0.0;
        uint32_t d;
        if (q[RBS__REC_IM] == 0.0)
            continue;
        for (d = 0; d < 3; ++d)
            ok &= isfinite(q[RBS__REC_V + d]) && isfinite(q[RBS__REC_W + d]) &&
                  isfinite(w->pos[3 * b + d] + q[RBS__REC_D + d]);
        if (turns)
            q_store(q + RBS__REC_ROT, turned(th, q_load(&w->orient[4 * b])));
        if (!ok && bad == UINT32_MAX)
            bad = b;
        q[RBS__REC_R] = turns;
    }
    for (i = begin; i < end; ++i) {
        double *q = &f->rec[RBS__REC * w->soft_rank[i]];
        quat r;
        double inv;
        if (q[RBS__REC_IM] == 0.0 || q[RBS__REC_R] == 0.0)
            continue;
        r = q_load(q + RBS__REC_ROT);
        inv = 1.0 / sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
        r.w *= inv;
        r.x *= inv;
        r.y *= inv;
        r.z *= inv;
        q_store(q + RBS__REC_ROT, r);
        if (!(isfinite(r.w) && isfinite(r.x) && isfinite(r.y) && isfinite(r.z)) && w->spheres[i] < bad) {
            bad = w->spheres[i];
            break; /* (a later one is later in slot order) */
        }
    }
    f->bad[run] = bad;
}

/* The write-back's second half, once every value is known good: x +=
 * displacement, the velocities, the turned orientations (spheres [begin,
 * end) in slot order, as check_run). */
static void write_run(soft_frame *f, uint32_t begin, uint32_t end)
{
    rbs_world *w = f->w;
    uint32_t i;
    for (i = begin; i < end; ++i) {
        const uint32_t b = w->spheres[i];
        const double *q = &f->rec[RBS__REC * w->soft_rank[i]];
        if (q[RBS__REC_IM] == 0.0)
            continue;
        memcpy(&w->vel[3 * b], q + RBS__REC_V, 3 * sizeof(double));
        memcpy(&w->avel[3 * b], q + RBS__REC_W, 3 * sizeof(double));
        v3_store(&w->pos[3 * b], v3_add(v3_load(&w->pos[3 * b]), v3_load(q + RBS__REC_D)));
        if (q[RBS__REC_R] != 0.0)
            memcpy(&w->orient[4 * b], q + RBS__REC_ROT, 4 * sizeof(double));
    }
}

/* The first sphere (in slot order) of the write-back's run k. */
static uint32_t run_begin(const soft_frame *f, uint32_t k)
{
    return (uint32_t)((uint64_t)k * f->w->sphere_count / f->runs);
}

/* The write-back's two stages (f->writing 0, then 1) over RBS__TEAM_SHARES
 * items, a share each: the warm store's shares (f->store.shares of them,
 * share q the item q RBS__TEAM_SHARES / shares -- the first share of the
 * thread whose leaves are the store share's slabs, team.h) take its count,
 * then its place (rbs__soft_store_count, rbs__soft_store_place), and the
 * other items, the f->runs runs of the spheres in slot order, the check,
 * then the write.  The store's scratch is the increments table, which
 * nothing reads after the rows; it touches the chunks and the warm-start
 * table, not the records and the world's arrays, and its first half
 * counts without changing the world, so it may go beside the check.  (On
 * one thread before: the other threads' contacts came from their caches,
 * and the next frame's detection read them from that thread's.) */
static void stage_write_back(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    uint32_t k;
    (void)share;
    for (k = begin; k < end; ++k) {
        const uint32_t x = f->item[k];
        if (x >= f->runs && !f->writing)
            rbs__soft_store_count(&f->store, x - f->runs);
        else if (x >= f->runs)
            rbs__soft_store_place(&f->store, x - f->runs);
        else if (!f->writing)
            check_run(f, x, run_begin(f, x), run_begin(f, x + 1u));
        else
            write_run(f, run_begin(f, x), run_begin(f, x + 1u));
    }
}

/* Groups [first + begin, first + end) in the frame's current rows stage.
 * On the leaves' level, group k is slab k, and its contacts touch no body
 * of another slab: the slab's bodies take the per-body stage that comes
 * before the pass (f->before, if any) just before the slab's rows, in the
 * same share -- the same operations on each body in the same order as a
 * stage of their own, without one more handover between the threads. */
static void stage_rows(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    soft_frame *f = (soft_frame *)ctx;
    uint32_t k;
    for (k = f->first + begin; k < f->first + end; ++k) {
        if (f->before != NULL)
            f->before(ctx, share, k - f->g->level_first[0], k - f->g->level_first[0] + 1); /* (slab k) */
        f->w->soft_kernels->pass(&f->rows, f->stage, f->g->first[k], f->g->first[k] + f->g->used[k],
                                 &f->report[share]);
    }
}

/* One pass of the rows (stage; < 0 the warm start) over every chunk: the
 * groups level by level from the leaves up, a level's groups side by side,
 * then the guards' group; before (NULL: none): the per-body stage over
 * slabs that must come first, taken slab by slab with the leaves. */
static void rows_pass(soft_frame *f, int stage, rbs__stage_fn before)
{
    const rbs__soft_groups *g = f->g;
    uint32_t l;
    f->stage = stage;
    for (l = 0; l <= g->levels; ++l) {
        uint32_t n = g->level_first[l + 1] - g->level_first[l];
        f->first = g->level_first[l];
        f->before = l == 0 ? before : NULL;
        rbs__team_run(f->w, stage_rows, f, n, n);
    }
}

/* The records, then the first sub-step's velocities (before its warm
 * start). */
static void stage_start(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    stage_records(ctx, share, begin, end);
    stage_velocities(ctx, share, begin, end);
}

/* The general layout's bodies that no contact of the frame touches (mark:
 * B bytes of scratch) flew its n sub-steps of h on semi-implicit Euler,
 * which leaves them a dt h / 2 ahead along their acceleration a (constant in
 * the frame without mutual gravity: the sum over the sub-steps of a h^2 k,
 * k = 1..n, is a dt^2 / 2 + a dt h / 2); taken back, their centres fly the
 * frame exactly, x0 + v0 dt + a dt^2 / 2, as the gathered layout's do
 * (stage_free) -- a ball falling 1 s in a world with rolling resistance
 * was g T h / 2 = 1.6e-3 m low at dt = 1 ms (a probe of session 47: a
 * resistance row for a body no sphere reaches took the world there).
 * Their orientations keep the sub-steps' turns (exact without a torque). */
static void fly_free(rbs_world *w, const double *acc, unsigned char *mark, double dt, double h)
{
    uint32_t k, i;
    memset(mark, 0, w->def.max_bodies);
    for (i = 0; i < w->contact_count; ++i) {
        mark[w->contact[i].a] = 1;
        mark[w->contact[i].b] = 1;
    }
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t j = w->spheres[k];
        const v3 a = v3_load(&acc[6 * j]);
        if (mark[j] || !rbs__body_moves(w, j) || (a.x == 0.0 && a.y == 0.0 && a.z == 0.0))
            continue;
        v3_store(&w->pos[3 * j], v3_mad(v3_load(&w->pos[3 * j]), a, -0.5 * dt * h));
    }
}

/* A frame in the gathered layout (the plan's gather): records, chunks and
 * the row kernels (soft.h), its stages on the world's threads (team.h). */
static rbs_status step_gathered(rbs_world *w, rbs_step_info *info)
{
    const uint32_t full = w->plan.soft_substeps, B = w->def.max_bodies;
    const double dt = w->def.dt, h_full = dt / full;
    /* adapt: def.soft_tolerance may take fewer sub-steps; the frame's n and
     * h are known once detection has measured every contact's reachable
     * overlap (g.q), and the warm starts wait for them */
    const int adapt = w->def.soft_tolerance > 0.0 && full > 1;
    /* per slot: the records (64-byte aligned), the velocity increments
     * a h, alpha h, the margins, and touched (a byte a slot) */
    double *rec = (double *)(void *)((unsigned char *)w->method_scratch +
                                     (64u - (uintptr_t)w->method_scratch % 64u) % 64u);
    double *inc = rec + (size_t)RBS__REC * B, *margin = inc + (size_t)6 * B;
    uint8_t *touched = (uint8_t *)(void *)(margin + B);
    double shared_inc[6], free_inc[6], h = h_full;
    uint32_t n = full, k, s;
    rbs__soft_groups g;
    rbs__soft_in in;
    soft_frame f;
    rbs_status st;
    /* one increment for every body (shared_inc for the frame's sub-steps,
     * free_inc for the full ones of bodies in no contact), or a table */
    const int shared = uniform_acceleration(w, &in.shared_a);

    /* The lent threads start now: detection splits among them too -- but
     * not for spheres too few for two slabs (soft_detect.c): in one slab
     * the rows, most of a frame, are one group on one thread, and the
     * handovers of the rest cost more than they share (the 125-sphere pile
     * took 1.5x its one-thread time on two).  The same bits either way. */
    if (rbs__slabs_for(w->def.max_bodies, w->sphere_count) > 1u)
        rbs__team_start(w);
    /* inc: accelerations and torques, which detection fills, then their
     * velocity increments a h, alpha h -- untouched when the increment is
     * shared; detection's scratch in the records' room (filled only after
     * it) */
    memset(touched, 0, w->sphere_count);
    in.margin = margin;
    in.acc = shared ? NULL : inc;
    in.dt = dt;
    in.h = adapt ? 0.0 : h_full;
    in.friction = w->plan.friction;
    in.touched = touched;
    in.scratch = rec;
    st = rbs__soft_detect(w, &in, &g);
    if (st != RBS_OK) {
        rbs__team_stop(w);
        return st;
    }
    if (adapt) {
        n = tolerated_substeps(w, g.q / w->def.soft_tolerance);
        h = dt / n;
        rbs__soft_warm_h(w, &g, in.friction, h);
    }
    if (shared) {
        shared_increment(in.shared_a, h, shared_inc);
        shared_increment(in.shared_a, h_full, free_inc);
    }
    f.w = w;
    f.g = &g;
    f.rec = rec;
    f.inc = inc;
    f.touched = touched;
    f.shared = shared;
    f.ib_frame = shared ? shared_inc : NULL;
    f.ib_free = shared ? free_inc : NULL;
    f.h = h;
    f.h_full = h_full;
    f.half_dt = 0.5 * dt;
    f.full = full;
    f.rows.rec = rec;
    f.rows.chunk = w->chunk;
    f.rows.pair = w->pair;
    f.rows.friction = in.friction;
    f.rows.slop = w->def.slop;
    f.rows.guard = RBS__GUARD_DEPTH;
    f.rows.touched = touched;
    f.rows.fixed = w->plan.fixed_spheres;
    rows_for_h(&f.rows, h);
    memset(f.report, 0, sizeof f.report);

    /* A body that no contact of the frame touches moves alone, after the
     * loop, body by body (stage_free: its exact flight over the frame),
     * instead of in one sweep over every record per sub-step -- at a
     * million bodies those sweeps were most of a falling lattice's cost --
     * its velocity by soft_substeps times the increment of h_full at once
     * (def.soft_tolerance concerns contacts). */
    for (s = 0; s < n; ++s) {
        f.sub = s;
        if (s == 0) {
            rows_pass(&f, -1, stage_start);
            rows_pass(&f, RBS__SOFT_SOLVE, NULL);
        } else {
            /* (the warm start in stage_velocities) */
            rows_pass(&f, RBS__SOFT_SOLVE, stage_velocities);
        }
        /* (the last relax also measures the report: positions are final) */
        rows_pass(&f, s == n - 1 ? RBS__SOFT_RELAX_REPORT : RBS__SOFT_RELAX, stage_positions);
    }
    rows_pass(&f, RBS__SOFT_RESTITUTION, stage_free);
    /* Write the bodies back.  Nothing was saved, so a failed step must
     * leave the world as it was: every new value is checked first (the
     * first bad sphere in slot order is named, whatever the threads). */
    for (k = 0; k < RBS_WORKERS_MAX; ++k)
        f.bad[k] = UINT32_MAX;
    /* (the runs beside the store: a thread done with its own takes another's) */
    rbs__soft_store_start(&f.store, w, &g, h, (uint32_t *)(void *)inc, rbs__team_threads(w));
    f.runs = RBS__TEAM_SHARES - f.store.shares;
    memset(f.item, 0xFF, sizeof f.item);
    for (k = 0; k < f.store.shares; ++k)
        f.item[k * RBS__TEAM_SHARES / f.store.shares] = (uint8_t)(f.runs + k);
    for (k = 0, s = 0; k < RBS__TEAM_SHARES; ++k)
        if (f.item[k] == 0xFFu)
            f.item[k] = (uint8_t)s++;
    f.writing = 0;
    rbs__team_run(w, stage_write_back, &f, RBS__TEAM_SHARES, RBS__TEAM_SHARES);
    for (k = 0; k < RBS_WORKERS_MAX; ++k)
        if (f.bad[k] != UINT32_MAX) {
            rbs__team_stop(w);
            return rbs__numeric_error(w, f.bad[k]);
        }
    f.writing = 1;
    rbs__team_run(w, stage_write_back, &f, RBS__TEAM_SHARES, RBS__TEAM_SHARES);
    info->resting = rbs__soft_store_finish(&f.store);
    w->step_checked = 1;

    /* Report: contacts touching at the end and the deepest overlap (the
     * last relax measured them), those holding, and the impacts.  (The lent
     * threads stop last: a pool whose threads spin between steps then keeps
     * them awake from one step to the next.) */
    info->substeps = n;
    for (k = 0; k < RBS_WORKERS_MAX; ++k) {
        info->colliding += f.report[k].restituted;
        info->contacts += f.report[k].touching;
        if (f.report[k].deepest > info->max_overlap)
            info->max_overlap = f.report[k].deepest;
    }
    rbs__team_stop(w);
    return RBS_OK;
}

rbs_status rbs__step_soft(rbs_world *w, rbs_step_info *info)
{
    const uint32_t n = w->plan.soft_substeps;
    const double dt = w->def.dt, h = dt / n;
    const uint32_t B = w->def.max_bodies;
    double *inc = w->method_scratch; /* per slot: the accelerations (6), then the margins */
    uint32_t i, at = 0, s;
    unsigned char *count;
    rbs__soft_rows k;
    soft_pass sp;
    rbs_status st;

    if (w->plan.gather)
        return step_gathered(w, info);

    /* The general layout steps the world's arrays (their state at the
     * frame's start saved, to measure displacements and to go back to),
     * through the general rows and integrators. */
    margins(w, dt, inc, inc + (size_t)6 * B);
    st = rbs__detect_swept(w, dt, inc + (size_t)6 * B, inc, inc + (size_t)7 * B, NULL, NULL);
    if (st != RBS_OK)
        return st;
    rbs__save_state(w, w->step_save);
    w->step_saved = 1;
    sp.w = w;
    sp.friction = w->plan.friction;
    sp.restituted = 0;

    /* Prepare: the approach speed at the frame's start (for restitution, in
     * c->bias), and the impulses of the last frame for the warm start --
     * with RBS__WARM, the over-relaxation, for a contact that came in loaded,
     * and then not for a lone one (soft.h, RBS__SOFT_OVER; each body's
     * loaded contacts counted, up to 2, in fly_free's bytes). */
    rbs__warm_sort(w);
    count = (unsigned char *)(void *)(inc + (size_t)8 * B);
    memset(count, 0, B);
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        const rbs__warm *m = rbs__warm_find(w, rbs__warm_key(w, c), &at);
        c->bias = v3_dot(relative_velocity(&sp, c), c->n);
        c->flags &= ~(RBS__TOUCHED | RBS__BOUNCE | RBS__WARM);
        if (rbs__contact_e(w, c) > 0.0 && c->bias < -c->thr)
            c->flags |= RBS__BOUNCE;
        if (p->rolling > 0.0 || p->spinning > 0.0)
            /* an impact's share of the normal impulse (resist_loaded) */
            w->contact_resist[i].impact = c->bias < -c->thr ? -c->bias / c->kn : 0.0;
        c->thr = 1.0 / c->kn; /* (its test is taken: from here the effective mass) */
        c->jslip = 0.0;
        if (sp.friction && p->mu_s > p->mu_k &&
            v3_len(rbs__stick_impulse(w, c, rbs__slip(w, c))) > p->mu_k * (m != NULL ? m->n : 0.0) * dt)
            /* it comes in slipping more than kinetic friction stops in the
             * frame at the last frame's load (none: a new contact): only
             * mu_k acts this frame (rbs__friction_cap with any jn > 0) */
            c->jslip = HUGE_VAL;
        if (p->rolling > 0.0 || p->spinning > 0.0) {
            w->contact_resist[i].jroll = v3_make(0, 0, 0);
            w->contact_resist[i].jspin = 0.0;
        }
        if (m != NULL && m->n > 0.0) {
            c->flags |= RBS__WARM;
            count[c->a] += count[c->a] < 2u;
            count[c->b] += count[c->b] < 2u;
        }
        if (m != NULL)
            warm_for_h(c, p, sp.friction, m->n, v3_mad(m->t, c->n, -v3_dot(m->t, c->n)), h);
    }
    for (i = 0; i < w->contact_count; ++i)
        if (lone(w, count, &w->contact[i]))
            w->contact[i].flags &= ~RBS__WARM;
    rows_for_h(&k, h);
    sp.inv_h = k.inv_h;
    sp.bias_rate = k.bias_rate;
    sp.mass_scale = k.mass_scale;
    sp.impulse_scale = k.impulse_scale;
    sp.hold = k.hold;

    for (s = 0; s < n; ++s) {
        rbs__integrate_velocities(w, h);
        warm_start(&sp);
        pass(&sp, SOLVE);
        rbs__integrate_positions(w, h, info);
        sp.last = s == n - 1;
        pass(&sp, RELAX);
    }
    if (!w->plan.mutual)
        fly_free(w, inc, (unsigned char *)(void *)(inc + (size_t)8 * B), dt, h);
    pass(&sp, RESTITUTION);
    info->substeps = n;
    info->colliding = sp.restituted;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        double sep = separation(&sp, c);
        if (sep <= rbs__contact_slop(w, c))
            info->contacts++;
        if (-sep > info->max_overlap)
            info->max_overlap = -sep;
        if (c->jn > 0.0)
            info->resting++;
    }
    rbs__warm_store(w, h);
    return RBS_OK;
}
