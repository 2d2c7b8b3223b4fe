/*
 * step_soft.c - the soft step: sub-steps with soft contacts, for piles.
 *
 * Catto's "soft step" (Box2D v3's solver; E. Catto, "Solver2D", 2024, and
 * "Soft Constraints", GDC 2011), for spheres and planes.  One frame of dt:
 *
 *   detect once, with every pair the bodies' sweeps over the frame can
 *   close (rbs__detect_swept: margins |v| dt + |a| dt^2), and guards for
 *   the pairs a kick of a closing neighbour can close (guard_depth);
 *   for each of n sub-steps of h = dt / n (n = def.soft_substeps, or with
 *   def.soft_tolerance fewer when no contact can go deep; tolerated_substeps):
 *     v += a h                      (forces)
 *     warm start                    (apply the accumulated impulses again)
 *     solve, with bias              (one Gauss-Seidel pass: soft normal rows
 *                                    that also push out overlap, rigid
 *                                    Coulomb friction)
 *     x += v h                      (positions)
 *     relax, without bias           (one pass: rigid rows, which take back
 *                                    the velocity the push gave)
 *   restitution                     (contacts that were approaching faster
 *                                    than their resting threshold at the
 *                                    frame's start leave at e times that,
 *                                    with friction in the cone of the
 *                                    normal impulse so grown)
 *   store the impulses for the next frame's warm start.
 *
 * The separation of a contact during the frame is its gap at detection plus
 * the bodies' displacement along the normal since then (exact for a plane,
 * linearised for a pair of spheres, along the normal of their touch on the
 * straight paths when they are apart: rbs__detect_swept).  A contact apart
 * by s > 0 lets its pair close at s / h and no faster (speculative); a
 * touching one may overlap by the slop, and deeper overlap is pushed out
 * (at most SOFT_PUSH of the smaller radius a sub-step, as Box2D caps its
 * push speed) by a damped spring of frequency
 * omega = 2 pi SOFT_HERTZ / h and damping ratio SOFT_ZETA, as the soft
 * constraint's coefficients (Catto 2011) express it for an implicit step:
 *   bias rate = omega / (2 zeta + h omega),
 *   mass scale = h omega (2 zeta + h omega) / (1 + h omega (2 zeta + h omega)),
 *   impulse scale = 1 / (1 + h omega (2 zeta + h omega)).
 * A contact of effective mass m under a steady load L (N) sinks to exactly
 * L / (m omega^2) beyond the slop -- the soft row's fixed point after the
 * warm start -- (g / omega^2 = 0.25 um for a ball's own weight at dt = 1 ms
 * and 4 sub-steps): the compliance that buys convergence in one pass.
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

#define SOFT_HERTZ 0.25 /* contact frequency, as a fraction of the sub-step rate */
#define SOFT_PUSH 0.01  /* the most overlap pushed out in one sub-step, of the smaller radius */
#define SOFT_ZETA 10.0  /* damping ratio of the contact spring */
#if defined(__GNUC__)
#define SOFT_INLINE inline __attribute__((always_inline)) /* one copy per stage */
#else
#define SOFT_INLINE inline
#endif
#define REC 16          /* doubles a slot in the gathered layout */
/* record: v 0-2, w 3-5, 1/m 6, 1/I 7, displacement 8-10, rotation 11-13,
 * slop length 14 (def.slop r), push speed limit 15 (SOFT_PUSH r / h); both
 * infinite for a plane */

typedef struct soft_pass {
    rbs_world *w;
    double *rec;          /* gathered records (fast), else NULL */
    double inv_h;
    double bias_rate, mass_scale, impulse_scale;
    int friction;
    uint32_t restituted;  /* contacts the restitution pass changed */
    uint32_t plane_contacts; /* the leading contacts whose b is a plane */
    uint32_t quarter;     /* ceil(pair contacts / 4) */
    int last;             /* the frame's last sub-step (pass() reads it; the
                             gathered rows have RELAX_REPORT) */
    uint32_t touching;    /* RELAX_REPORT: contacts within their slop */
    double deepest;       /* RELAX_REPORT: the deepest overlap, m (>= 0) */
} soft_pass;

/* RELAX_REPORT: the last sub-step's relax pass in the gathered layout, which
 * also counts the contacts touching at the frame's end and the deepest
 * overlap (the positions are final once it runs) */
enum { SOLVE, RELAX, RESTITUTION, RELAX_REPORT };

/* The displacement of slot i since the frame's start. */
static v3 displacement(const soft_pass *sp, uint32_t i)
{
    const rbs_world *w = sp->w;
    if (sp->rec != NULL)
        return v3_load(&sp->rec[REC * i + 8]);
    return v3_sub(v3_load(&w->pos[3 * i]), v3_load(&w->step_save[RBS__SAVE_STRIDE * i]));
}

/* A contact's separation now, m: its gap at detection plus the motion of
 * its bodies along n. */
static double separation(const soft_pass *sp, const rbs__contact *c)
{
    return c->gap + v3_dot(c->n, v3_sub(displacement(sp, c->a), displacement(sp, c->b)));
}

static inline v3 relative_velocity(const soft_pass *sp, const rbs__contact *c)
{
    if (sp->rec != NULL) {
        const double *ba = &sp->rec[REC * c->a], *bb = &sp->rec[REC * c->b];
        return rbs__along_rel_velocity(c, rbs__contact_la(sp->w, c), v3_load(ba), v3_load(ba + 3), v3_load(bb),
                                       v3_load(bb + 3));
    }
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
 * approach; a guard's s is taken guard_depth deeper.  In the frame's last
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
        return -vn * c->thr;
    over = s + slop < 0.0 ? s + slop : 0.0;
    push = sp->bias_rate * over;
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

/* One pass over the contacts, on the world's own arrays (the general
 * layout; row_fast is the gathered one): stage SOLVE (soft, with bias),
 * RELAX (rigid) or RESTITUTION (normal rows that make the pair leave at e
 * times its approach, and friction within Coulomb's cone of the grown
 * normal impulse, so that an oblique bounce follows the impact law). */
static void pass(soft_pass *sp, int stage)
{
    rbs_world *w = sp->w;
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        v3 rv = relative_velocity(sp, c), j;
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
        if (stage == RESTITUTION && c->jn != jn)
            sp->restituted++;
        jn = c->jn;
        if (sp->friction && (p->mu_s > 0.0 || p->mu_k > 0.0) && (jn > 0.0 || c->jt.x != 0.0 ||
                                                                 c->jt.y != 0.0 || c->jt.z != 0.0)) {
            /* the slip after the normal impulse (levers need not lie along n) */
            v3 cand;
            rbs__apply_pair(w, c, j);
            cand = rbs__cone(c, p, rbs__stick_impulse(w, c, rbs__slip(w, c)));
            j = v3_sub(cand, c->jt);
            c->jt = cand;
        }
        rbs__apply_pair(w, c, j);
        if (sp->friction && jn > 0.0 && (p->rolling > 0.0 || p->spinning > 0.0))
            (void)rbs__resist_row(w, i);
    }
}

/* One row of pass() for the gathered layout, with the records inline
 * (levers along n, isotropic bodies: the normal impulse leaves the slip as
 * it was, and the stick impulse is -vt / kt).  b_static: body b is a plane
 * (no velocity, no motion, never pushed), known at compile time in each of
 * pass_fast's two loops. */
static SOFT_INLINE void row_fast(soft_pass *sp, rbs__contact *c, int stage, int b_static)
{
    const rbs_world *w = sp->w;
    double *ba, *bb;
    v3 va, wa, rv, j;
    double vn, jn, dj, s, la;
    if (stage == RESTITUTION && !bounces(c))
        return; /* (before its bodies are read: most contacts do not bounce) */
    ba = &sp->rec[REC * c->a];
    bb = &sp->rec[REC * c->b];
    va = v3_load(ba);
    wa = v3_load(ba + 3);
    la = rbs__contact_la(w, c);
    if (b_static)
        rv = v3_add(va, v3_cross(v3_scale(wa, la), c->n));
    else
        rv = rbs__along_rel_velocity(c, la, va, wa, v3_load(bb), v3_load(bb + 3));
    vn = v3_dot(rv, c->n);
    if (stage == RESTITUTION) {
        dj = restitution_change(w, c, vn);
    } else {
        /* the pair's slop and push limit: the smaller of the records' (a
         * plane's are infinite), as rbs__contact_slop computes the slop */
        double slop = b_static || ba[14] < bb[14] ? ba[14] : bb[14];
        s = c->gap + v3_dot(c->n, b_static ? v3_load(ba + 8) : v3_sub(v3_load(ba + 8), v3_load(bb + 8)));
        if (stage == RELAX_REPORT) {
            sp->touching += s <= slop;
            sp->deepest = -s > sp->deepest ? -s : sp->deepest;
        }
        dj = normal_change(sp, c, stage, vn, s, slop, b_static || ba[15] < bb[15] ? ba[15] : bb[15],
                           stage == RELAX_REPORT);
    }
    jn = c->jn;
    j = normal_accumulate(c, dj);
    if (stage == RESTITUTION && c->jn != jn)
        sp->restituted++;
    jn = c->jn;
    if (sp->friction && (jn > 0.0 || c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0)) {
        const rbs__pair *p = rbs__contact_pair(w, c);
        if (p->mu_s > 0.0 || p->mu_k > 0.0) {
            v3 vt = v3_mad(rv, c->n, -vn), cand;
            cand = rbs__cone(c, p, v3_dot(vt, vt) > 0.0 ? v3_scale(vt, -c->kt_inv) : v3_make(0, 0, 0));
            j = v3_add(j, v3_sub(cand, c->jt));
            c->jt = cand;
        }
    }
    if (b_static)
        rbs__sb_apply(ba, j, v3_scale(v3_cross(c->n, j), la));
    else
        rbs__sb_apply_pair(ba, bb, c, la, j);
}

/* pass() for the gathered layout: the contacts with a plane first
 * (detection makes them first), then the pairs of spheres in four
 * interleaved runs (the k-th of each quarter in turn): rows next to each
 * other then seldom share a body, so one row need not wait for the last
 * one's stores (about 4 % faster on the 1,000 pile; the order is fixed, so
 * results stay deterministic).  Inlined for each stage, so that a row is
 * compiled for its stage and kind of pair. */
static SOFT_INLINE void pass_fast_stage(soft_pass *sp, int stage)
{
    rbs__contact *c = sp->w->contact;
    uint32_t i, n = sp->w->contact_count, planes = sp->plane_contacts, q = sp->quarter;
    for (i = 0; i < planes; ++i)
        row_fast(sp, &c[i], stage, 1);
    for (i = planes; i < planes + q; ++i) {
        row_fast(sp, &c[i], stage, 0);
        if (i + q < n)
            row_fast(sp, &c[i + q], stage, 0);
        if (i + 2 * q < n)
            row_fast(sp, &c[i + 2 * q], stage, 0);
        if (i + 3 * q < n)
            row_fast(sp, &c[i + 3 * q], stage, 0);
    }
}

static void pass_fast(soft_pass *sp, int stage)
{
    if (stage == SOLVE)
        pass_fast_stage(sp, SOLVE);
    else if (stage == RELAX)
        pass_fast_stage(sp, RELAX);
    else if (stage == RELAX_REPORT)
        pass_fast_stage(sp, RELAX_REPORT);
    else
        pass_fast_stage(sp, RESTITUTION);
}

/* A pass in the layout the frame took. */
static void run_pass(soft_pass *sp, int stage)
{
    if (sp->rec != NULL)
        pass_fast(sp, stage);
    else
        pass(sp, stage);
}

/* Apply the accumulated impulses again (each sub-step starts from them). */
static void warm_start(soft_pass *sp)
{
    rbs_world *w = sp->w;
    uint32_t i;
    if (sp->rec != NULL) {
        /* (the contacts with a plane first: only body a takes the impulse) */
        for (i = 0; i < sp->plane_contacts; ++i) {
            const rbs__contact *c = &w->contact[i];
            v3 j = v3_add(v3_scale(c->n, c->jn), c->jt);
            rbs__sb_apply(&sp->rec[REC * c->a], j, v3_scale(v3_cross(c->n, j), rbs__contact_la(w, c)));
        }
        for (; i < w->contact_count; ++i) {
            const rbs__contact *c = &w->contact[i];
            if (c->jn != 0.0 || c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0)
                rbs__sb_apply_pair(&sp->rec[REC * c->a], &sp->rec[REC * c->b], c, rbs__contact_la(w, c),
                                   v3_add(v3_scale(c->n, c->jn), c->jt));
        }
        return;
    }
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
        double m;
        rbs__accelerations(w, i, &a, &tau);
        if (w->plan.mutual && !w->fixed[i])
            a = v3_add(a, v3_load(&w->acc[3 * i]));
        if (acc != NULL) {
            v3_store(&acc[6 * i], a);
            v3_store(&acc[6 * i + 3], tau);
        }
        m = v3_len(v3_load(&w->vel[3 * i])) * dt + v3_len(a) * dt * dt;
        margin[i] = w->fixed[i] || !isfinite(m) ? 0.0 : m;
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
    const uint32_t full = w->def.soft_substeps;
    uint32_t n = full;
    while (n > 1 && q < (double)(n / 2) / (double)full)
        n /= 2;
    return n;
}

/* The parts of gathered slot i that depend on the sub-step h: its push
 * limit and (without a shared increment) its velocity increments, from the
 * accelerations in inc -- those of a body of no contact, or a plane's (0),
 * for the full sub-steps h_full. */
static inline void record_for_h(const rbs_world *w, double *b, double *inc, uint32_t i, int shared,
                                const double *touched, double h, double h_full)
{
    b[15] = w->type[i] == RBS_BODY_SPHERE ? SOFT_PUSH * w->radius[i] / h : INFINITY;
    if (!shared) {
        const double hi = w->type[i] == RBS_BODY_SPHERE && touched[i] != 0.0 ? h : h_full;
        v3_store(&inc[6 * i], v3_scale(v3_load(&inc[6 * i]), hi));
        v3_store(&inc[6 * i + 3], v3_scale(v3_load(&inc[6 * i + 3]), b[7] * hi));
    }
}

/* A contact's warm start for sub-steps of h from the last frame's forces:
 * fn along n, ft its tangent force (in today's tangent plane; only with
 * friction), dropped if outside the static cone. */
static inline void warm_for_h(rbs__contact *c, const rbs__pair *p, int friction, double fn, v3 ft, double h)
{
    c->jn = fn * h;
    if (friction) {
        c->jt = v3_scale(ft, h);
        if (v3_len(c->jt) > p->mu_s * c->jn)
            c->jt = v3_make(0, 0, 0);
    }
}

rbs_status rbs__step_soft(rbs_world *w, rbs_step_info *info)
{
    const uint32_t full = w->def.soft_substeps;
    const double dt = w->def.dt, h_full = dt / full;
    /* adapt: def.soft_tolerance may take fewer sub-steps (the gathered
     * layout only); the frame's n and h are known once the prepare pass
     * has measured every contact's reachable overlap (q, over the
     * tolerance), and what depends on h waits for them */
    const int adapt = w->def.soft_tolerance > 0.0 && full > 1 && w->plan.gather;
    uint32_t n = full;
    double h = h_full, omega, a1, a2, q = 0.0;
    const uint32_t B = w->def.max_bodies;
    double *rec = NULL, *inc = w->method_scratch + (size_t)REC * B; /* per slot: a h, alpha h */
    double *touched = NULL, shared_inc[6], free_inc[6];
    v3 shared_a = v3_make(0, 0, 0);
    uint32_t i, k, at = 0;
    uint32_t s;
    soft_pass sp;
    rbs_status st;
    const int gather = w->plan.gather; /* (rbs__plan_compute) */
    /* one increment for every body (shared_inc for the frame's sub-steps,
     * free_inc for the full ones of bodies in no contact), or a table */
    const int shared = gather && uniform_acceleration(w, &shared_a);

    /* inc: accelerations and torques for detection, then (gathered) their
     * velocity increments a h, alpha h -- untouched when the increment is
     * shared, and detection then computes the accelerations it needs, the
     * same values; the margins after inc; detection's kicks in the records'
     * room (filled only after detection) */
    margins(w, dt, shared ? NULL : inc, inc + (size_t)6 * B);
    st = rbs__detect_swept(w, dt, inc + (size_t)6 * B, shared ? NULL : inc, w->method_scratch);
    if (st != RBS_OK)
        return st;

    /* A gathered body that no contact of the frame touches moves alone: all
     * its sub-steps are taken after the loop, body by body (the same
     * operations in the same order, so the same bits), instead of in one
     * sweep over every record per sub-step -- at a million bodies those
     * sweeps were most of a falling lattice's cost -- and always all
     * soft_substeps of them, of h_full (def.soft_tolerance concerns
     * contacts).  touched[slot]: 1 for a body in a contact (the margins'
     * room, free after detection). */
    if (gather) {
        touched = inc + (size_t)6 * B;
        for (k = 0; k < w->sphere_count; ++k)
            touched[w->spheres[k]] = 0.0;
        for (i = 0; i < w->contact_count; ++i) {
            touched[w->contact[i].a] = 1.0;
            touched[w->contact[i].b] = 1.0;
        }
    }
    sp.w = w;
    sp.friction = w->plan.friction;
    sp.restituted = 0;
    if (gather) {
        rec = w->method_scratch;
        for (i = 0; i < w->slots; ++i) {
            double *b = &rec[REC * i];
            memcpy(b, &w->vel[3 * i], 3 * sizeof(double));
            memcpy(b + 3, &w->avel[3 * i], 3 * sizeof(double));
            b[6] = w->inv_mass[i];
            b[7] = w->type[i] == RBS_BODY_SPHERE ? w->iso_inv_inertia[i] : 0.0;
            memset(b + 8, 0, 6 * sizeof(double));
            b[14] = w->type[i] == RBS_BODY_SPHERE ? w->def.slop * w->radius[i] : INFINITY;
            if (!adapt)
                record_for_h(w, b, inc, i, shared, touched, h, h_full);
        }
    } else {
        /* the general layout steps the world's arrays: their state at the
         * frame's start, to measure displacements and to go back to */
        rbs__save_state(w, w->step_save);
        w->step_saved = 1;
    }
    sp.rec = rec;

    /* Prepare: the approach speed at the frame's start (for restitution, in
     * c->bias), and the impulses of the last frame for the warm start. */
    sp.plane_contacts = 0;
    while (sp.plane_contacts < w->contact_count && w->type[w->contact[sp.plane_contacts].b] == RBS_BODY_PLANE)
        sp.plane_contacts++;
    sp.quarter = (w->contact_count - sp.plane_contacts + 3) / 4;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        const rbs__warm *m = rbs__warm_find(w, rbs__warm_key(w, c), &at);
        c->bias = v3_dot(relative_velocity(&sp, c), c->n);
        if (adapt) {
            double close = -c->bias * dt;
            double d = ((close > 0.0 ? close : 0.0) - c->gap) * w->def.slop / rbs__contact_slop(w, c);
            if (!(d <= q))
                q = d; /* (a NaN stays, and keeps every sub-step) */
        }
        c->flags &= ~(RBS__TOUCHED | RBS__BOUNCE);
        if (rbs__contact_e(w, c) > 0.0 && c->bias < -c->thr)
            c->flags |= RBS__BOUNCE;
        c->thr = 1.0 / c->kn; /* (its test is taken: from here the effective mass) */
        if (p->rolling > 0.0 || p->spinning > 0.0) {
            w->contact_resist[i].jroll = v3_make(0, 0, 0);
            w->contact_resist[i].jspin = 0.0;
        }
        if (m == NULL)
            continue;
        /* (adapt: the forces, until h is known; detection made both 0) */
        if (adapt) {
            c->jn = m->n;
            if (sp.friction)
                c->jt = v3_mad(m->t, c->n, -v3_dot(m->t, c->n));
        } else {
            warm_for_h(c, p, sp.friction, m->n, v3_mad(m->t, c->n, -v3_dot(m->t, c->n)), h);
        }
    }
    if (adapt) {
        n = tolerated_substeps(w, q / w->def.soft_tolerance);
        h = dt / n;
        for (i = 0; i < w->slots; ++i)
            record_for_h(w, &rec[REC * i], inc, i, shared, touched, h, h_full);
        for (i = 0; i < w->contact_count; ++i) {
            rbs__contact *c = &w->contact[i];
            warm_for_h(c, rbs__contact_pair(w, c), sp.friction, c->jn, c->jt, h);
        }
    }
    omega = 2.0 * 3.14159265358979323846 * SOFT_HERTZ / h;
    a1 = 2.0 * SOFT_ZETA + h * omega;
    a2 = h * omega * a1;
    sp.inv_h = 1.0 / h;
    sp.bias_rate = omega / a1;
    sp.mass_scale = a2 / (1.0 + a2);
    sp.impulse_scale = 1.0 / (1.0 + a2);
    if (shared) {
        shared_increment(shared_a, h, shared_inc);
        shared_increment(shared_a, h_full, free_inc);
    }

    sp.touching = 0;
    sp.deepest = 0.0;
    for (s = 0; s < n; ++s) {
        if (rec != NULL) {
            for (k = 0; k < w->sphere_count; ++k) {
                uint32_t b = w->spheres[k];
                double *r = &rec[REC * b];
                const double *ib = shared ? shared_inc : &inc[6 * b];
                if (touched[b] == 0.0 || r[6] == 0.0) /* (the flag first: a free body's record is not read) */
                    continue;
                v3_store(r, v3_add(v3_load(r), v3_load(ib)));
                v3_store(r + 3, v3_add(v3_load(r + 3), v3_load(ib + 3)));
            }
        } else {
            rbs__integrate_velocities(w, h);
        }
        warm_start(&sp);
        run_pass(&sp, SOLVE);
        if (rec != NULL) {
            for (k = 0; k < w->sphere_count; ++k) {
                double *r = &rec[REC * w->spheres[k]];
                if (touched[w->spheres[k]] == 0.0 || r[6] == 0.0)
                    continue;
                v3_store(r + 8, v3_mad(v3_load(r + 8), v3_load(r), h));
                v3_store(r + 11, v3_mad(v3_load(r + 11), v3_load(r + 3), h));
            }
        } else {
            rbs__integrate_positions(w, h);
        }
        sp.last = s == n - 1;
        run_pass(&sp, rec != NULL && sp.last ? RELAX_REPORT : RELAX);
    }
    if (rec != NULL) {
        for (k = 0; k < w->sphere_count; ++k) {
            uint32_t b = w->spheres[k];
            double *r = &rec[REC * b];
            const double *ib = shared ? free_inc : &inc[6 * b];
            v3 v, om, d, th, dv, dw;
            if (touched[b] != 0.0 || r[6] == 0.0)
                continue;
            v = v3_load(r);
            om = v3_load(r + 3);
            d = v3_load(r + 8);
            th = v3_load(r + 11);
            dv = v3_load(ib);
            dw = v3_load(ib + 3);
            for (s = 0; s < full; ++s) {
                v = v3_add(v, dv);
                om = v3_add(om, dw);
                d = v3_mad(d, v, h_full);
                th = v3_mad(th, om, h_full);
            }
            v3_store(r, v);
            v3_store(r + 3, om);
            v3_store(r + 8, d);
            v3_store(r + 11, th);
        }
    }
    run_pass(&sp, RESTITUTION);

    /* Write the gathered bodies back: x += displacement, one turn by the
     * frame's rotation.  Nothing was saved, so a failed step must leave the
     * world as it was: first every new value is made and checked finite (a
     * finite rotation too large to square gives a NaN turn), the new
     * orientation kept in the record (rotation 11-13 and slop 14, free now;
     * 15: whether it turned), then all of it is written. */
    if (rec != NULL) {
        for (k = 0; k < w->sphere_count; ++k) {
            uint32_t b = w->spheres[k], d;
            double *r = &rec[REC * b];
            v3 th = v3_load(r + 11);
            int ok = 1, turns = th.x != 0.0 || th.y != 0.0 || th.z != 0.0;
            quat q;
            if (r[6] == 0.0)
                continue;
            for (d = 0; d < 3; ++d)
                ok &= isfinite(r[d]) && isfinite(r[3 + d]) && isfinite(w->pos[3 * b + d] + r[8 + d]);
            if (turns) {
                q = q_normalize(q_mul(q_from_rotation(th, 1.0), q_load(&w->orient[4 * b])));
                ok &= isfinite(q.w) && isfinite(q.x) && isfinite(q.y) && isfinite(q.z);
                q_store(r + 11, q);
            }
            if (!ok)
                return rbs__numeric_error(w, b);
            r[15] = turns;
        }
        for (k = 0; k < w->sphere_count; ++k) {
            uint32_t b = w->spheres[k];
            const double *r = &rec[REC * b];
            if (r[6] == 0.0)
                continue;
            memcpy(&w->vel[3 * b], r, 3 * sizeof(double));
            memcpy(&w->avel[3 * b], r + 3, 3 * sizeof(double));
            v3_store(&w->pos[3 * b], v3_add(v3_load(&w->pos[3 * b]), v3_load(r + 8)));
            if (r[15] != 0.0)
                memcpy(&w->orient[4 * b], r + 11, 4 * sizeof(double));
        }
    }

    /* Report: contacts touching at the end and the deepest overlap. */
    info->substeps = n;
    info->colliding = sp.restituted;
    if (rec != NULL) {
        /* (the last relax pass measured the separations) */
        info->contacts = sp.touching;
        info->max_overlap = sp.deepest;
        for (i = 0; i < w->contact_count; ++i)
            info->resting += w->contact[i].jn > 0.0;
        rbs__warm_store(w, h);
        return RBS_OK;
    }
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
