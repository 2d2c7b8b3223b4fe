/*
 * solver.c - impulses at contacts.
 *
 * Two passes per sub-step (see docs/physics.md):
 *  1. Collisions, on the velocities before this sub-step's forces: every
 *     contact approaching faster than its resting threshold gets the impulse
 *     that makes it leave with e times its approach speed, with Coulomb
 *     friction (stick if the impulse that stops slip is at most mu_s * Jn --
 *     mu_k * Jn when the impact starts with more slip than that stops:
 *     rbs__friction_cap -- else slide with mu_k * Jn against the slip it
 *     leaves: rbs__slide_impulse).  Pair by pair, swept until no contact
 *     approaches, at most max_sweeps times.
 *  2. Resting contact, after the forces: projected Gauss-Seidel on
 *     accumulated impulses (Jn >= 0, |Jt| <= mu * Jn with mu as above for
 *     the slip the contact had before the forces, rolling and spinning
 *     resistance bounded by Jn), cancelling the approach the forces built.
 *     A contact with friction and resistance takes its tangential and
 *     angular impulses as one block when they stay within their bounds
 *     (resist_block), else row by row.
 * A speculative contact (gap > slop, contact.c) takes no collision impulse;
 * the collision pass marks it as an impact (bias -1: left out of the resting
 * pass too) when it approaches faster than its threshold, and the resting
 * pass lets it approach at (gap - slop) / h, so it closes to the slop
 * (0 when gap - slop is within the rounding of its coordinates, which no
 * move could close: rbs__solve_resting_warm).
 */
#include <string.h>

#include "core/rows.h"

/* One collision impulse at a contact approaching at vn < 0: the normal
 * impulse that makes it leave at -e vn, then Coulomb friction. */
void rbs__collide(rbs_world *w, const rbs__contact *c, double vn)
{
    const rbs__pair *p = rbs__contact_pair(w, c);
    const int friction = w->plan.friction && (p->mu_s > 0.0 || p->mu_k > 0.0);
    double jn = -(1.0 + rbs__contact_e(w, c)) * vn / c->kn, jslip = 0.0;
    if (friction && p->mu_s > p->mu_k)
        /* the slip the impact starts with (rbs__friction_cap) */
        jslip = v3_len(rbs__stick_impulse(w, c, rbs__slip(w, c)));
    rbs__apply_pair(w, c, v3_scale(c->n, jn));
    if (friction) {
        rbs__kt kt;
        v3 vt = rbs__slip(w, c);
        v3 jt = rbs__stick_impulse_kt(w, c, vt, &kt);
        double l = v3_len(jt);
        if (l > rbs__friction_cap(p, jslip, jn) * jn)
            jt = rbs__slide_impulse(w, c, jt, l, p->mu_k * jn, &kt);
        rbs__apply_pair(w, c, jt);
    }
}

/* Each contact's jslip for the resting pass: the impulse that stops the
 * slip the collision pass leaves it, before the sub-step's forces add to it
 * (the start of the interval the pass covers), where mu_s > mu_k; else 0. */
static void slip_marks(rbs_world *w)
{
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        c->jslip = 0.0;
        if (w->plan.friction && p->mu_s > p->mu_k && !(c->bias < 0.0))
            c->jslip = v3_len(rbs__stick_impulse(w, c, rbs__slip(w, c)));
    }
}

double rbs__normal_velocity(const rbs_world *w, const rbs__contact *c)
{
    return v3_dot(rbs__rel_velocity(w, c), c->n);
}

/* The collision pass's sweeps: up to RBS__COLLISION_SWEEPS times
 * max_sweeps.  An elastic impact through a chain of touching bodies takes
 * about pi sqrt(M / m) / 2 sweeps to pass on (M/m the mass ratio: the
 * sequence of the pi billiard, G. Galperin, Regular and Chaotic Dynamics 8,
 * 2003), and what a capped pass leaves approaching the resting pass then
 * stops as if plastic: with 20 sweeps a 1000 kg ball dropped on a 1 kg ball
 * resting on a floor (e = 1) stuck to it, 40 % of the energy gone (a probe
 * of session 41).  Passes that do not converge are rare (none in 1,000
 * frames of the 288-ball euler pile, one with selective), so the bound is
 * generous: mass ratios up to about 1.6e6 at the default 20. */
#define RBS__COLLISION_SWEEPS 100u

int rbs__rounding_approach(const rbs_world *w, const rbs__contact *c, double vn)
{
    const double dt = w->def.dt;
    double scale = 0.0;
    uint32_t k;
    if (!(-vn * dt <= 1e-6 * rbs__contact_slop(w, c)))
        return 0;
    for (k = 0; k < 2; ++k) {
        const uint32_t i = k ? c->b : c->a;
        v3 a, t;
        if (w->type[i] != RBS_BODY_SPHERE || w->fixed[i])
            continue;
        rbs__accelerations_all(w, i, &a, &t);
        scale += v3_len(v3_load(&w->vel[3 * i])) + w->radius[i] * v3_len(v3_load(&w->avel[3 * i])) +
                 v3_len(a) * dt;
    }
    return -vn <= 0x1p-40 * scale;
}

static void collision_sweeps(rbs_world *w, rbs_step_info *info)
{
    uint32_t sweep, i, max_sweeps = w->def.max_sweeps * RBS__COLLISION_SWEEPS;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        c->jn = 0.0; /* used as a "collided" mark here */
        /* a speculative contact approaching as an impact (the test a
         * touching one gets below, on the velocities before any impulse) */
        c->bias = (c->flags & RBS__APART) && v3_dot(rbs__rel_velocity(w, c), c->n) < -c->thr ? -1.0 : 0.0;
    }
    for (sweep = 0; sweep < max_sweeps; ++sweep) {
        int active = 0;
        for (i = 0; i < w->contact_count; ++i) {
            rbs__contact *c = &w->contact[i];
            double vn;
            if (c->flags & RBS__APART) {
                /* speculative: not touching.  But one that an impulse of
                 * this pass has set approaching faster than its threshold
                 * is an impact too, when it touches: left out of the
                 * resting pass (bias -1), so that the step's overlap finds
                 * it and its impact has restitution.  Marked only on the
                 * velocities before any impulse, a cradle on a floor with
                 * gaps under g dt^2 (9.8 um at dt = 1 ms) lost 80 % of its
                 * energy: each ball struck in a sub-step was stopped by the
                 * resting pass against the next (a probe of session 40). */
                if (c->bias == 0.0 && v3_dot(rbs__rel_velocity(w, c), c->n) < -c->thr)
                    c->bias = -1.0;
                continue;
            }
            vn = v3_dot(rbs__rel_velocity(w, c), c->n);
            if (!(vn < -c->thr) || vn >= 0.0 || rbs__rounding_approach(w, c, vn))
                continue;
            rbs__collide(w, c, vn);
            if (c->jn == 0.0 && info)
                info->colliding++;
            c->jn = 1.0;
            active = 1;
        }
        if (!active)
            return;
    }
    if (info)
        info->sweep_limit++;
}

void rbs__solve_collisions(rbs_world *w, rbs_step_info *info)
{
    collision_sweeps(w, info);
    slip_marks(w);
}

/* Warm-start cache: the resting impulse rates (impulse / h) of the last
 * warm pass, one entry a contact that held, sorted by the key of its body
 * pair.  The key puts contacts with a plane (b a plane) before pairs of
 * spheres, and each by (a, b): the order rbs__detect makes them in (spheres
 * in slot order, each sphere's planes and partners likewise; pairs through
 * rbs__broadphase_pairs), so a pass writes the table in order and reads it
 * in order -- sequentially, at any size -- with no hashing.  (Slots are
 * below 2^24.)  The soft step's gathered layout stores it in buckets
 * instead (soft_detect.c, rbs__soft_store_place; w->warm_ranked), which
 * rbs__warm_sort puts back in key order before a pass here searches it. */
uint64_t rbs__warm_key(const rbs_world *w, const rbs__contact *c)
{
    return rbs__warm_key_of(w->type[c->b] == RBS_BODY_PLANE, c->a, c->b);
}

/* The entry of key k, or NULL.  *at: where the previous search ended; the
 * pass asks in ascending order, so a search gallops forward from there
 * (doubling steps, then bisection: O(1) a contact in order, O(log n) out of
 * order, and from the start when k is behind). */
const rbs__warm *rbs__warm_find(const rbs_world *w, uint64_t k, uint32_t *at)
{
    const rbs__warm *t = w->warm;
    uint32_t n = w->warm_used, lo = *at < n ? *at : n, hi, step = 1;
    if (lo > 0 && t[lo - 1].key >= k)
        lo = 0;
    /* every entry before lo is below k */
    hi = lo;
    while (hi < n && t[hi].key < k) {
        lo = hi + 1;
        hi = n - hi > step ? hi + step : n;
        step *= 2;
    }
    /* the first entry at or above k is in [lo, hi] (hi: n, or at or above k) */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (t[mid].key < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    *at = lo;
    return lo < n && t[lo].key == k ? &t[lo] : NULL;
}

/* Key order, for rbs__heap_sort: a pass whose contacts were not in key
 * order (pairs from the grid's own walk, when the candidate list could not
 * hold them; the soft step's guards) is sorted in place. */
static int warm_greater(const void *x, const void *y)
{
    return ((const rbs__warm *)x)->key > ((const rbs__warm *)y)->key;
}

void rbs__warm_finish(rbs_world *w, uint32_t n, int sorted)
{
    if (!sorted)
        rbs__heap_sort(w->warm, n, sizeof *w->warm, warm_greater);
    w->warm_used = n;
    w->warm_ranked = 0;
    w->warm_indexed = 0;
}

void rbs__warm_sort(rbs_world *w)
{
    if (w->warm_ranked)
        rbs__warm_finish(w, w->warm_used, 0);
}

/* Store this pass's impulse rates: one entry per contact that held (at most
 * max_contacts = warm_size), written in contact order, which is key order
 * (else sorted). */
void rbs__warm_store(rbs_world *w, double h)
{
    uint32_t i, n = 0;
    int sorted = 1;
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        rbs__warm *e = &w->warm[n];
        if (c->jn == 0.0)
            continue;
        e->key = rbs__warm_key(w, c);
        if (n > 0 && !(w->warm[n - 1].key < e->key))
            sorted = 0;
        e->n = c->jn / h;
        e->t = v3_scale(c->jt, 1.0 / h);
        n++;
    }
    rbs__warm_finish(w, n, sorted);
}

/* Inverse effective mass of one body of a contact along n (the other held). */
static double k_one(const rbs_world *w, uint32_t i, v3 r, v3 n)
{
    v3 x = v3_cross(r, n), t;
    if (w->inv_mass[i] == 0.0)
        return 0.0;
    rbs__body_inv_inertia_world(w, i, x, &t);
    return w->inv_mass[i] + v3_dot(x, t);
}

/* The level shock propagation handles contact c at (that of its upper
 * body), or 0 when it has none: no load, both bodies on one level, or a
 * body no loaded contact joins to the ground. */
static uint32_t shock_level(const rbs__contact *c, const int32_t *level, uint32_t max_level)
{
    int32_t top = level[c->a] > level[c->b] ? level[c->a] : level[c->b];
    if (c->jn == 0.0 || level[c->a] == level[c->b] || top == INT32_MAX || (uint32_t)top > max_level)
        return 0;
    return (uint32_t)top;
}

/* Shock propagation (Guendelman, Bridson & Fedkiw 2003), for when the
 * Gauss-Seidel sweeps did not converge -- a stack whose masses differ by
 * orders of magnitude converges at a rate of the mass ratio.  Bodies get a
 * level: 0 for planes and fixed bodies, then one more than the lowest body
 * they rest on.  Level by level from the ground up, each contact stops its
 * upper body's approach with the lower body held still, so no contact is
 * left approaching and nothing sinks.  Normal direction only. */
static void shock_propagation(rbs_world *w)
{
    int32_t *level = w->ev_mode; /* scratch: the event method's per-body mode */
    uint32_t i, k, max_level = 0;
    int changed = 1;
    for (k = 0; k < w->slots; ++k)
        level[k] = (w->type[k] == RBS_BODY_SPHERE && !w->fixed[k]) ? INT32_MAX : 0;
    for (k = 0; changed && k < w->contact_count + 1; ++k) {
        changed = 0;
        for (i = 0; i < w->contact_count; ++i) {
            const rbs__contact *c = &w->contact[i];
            if (c->jn == 0.0)
                continue;
            if (level[c->b] != INT32_MAX && level[c->b] + 1 < level[c->a]) {
                level[c->a] = level[c->b] + 1;
                changed = 1;
            }
            if (level[c->a] != INT32_MAX && level[c->a] + 1 < level[c->b]) {
                level[c->b] = level[c->a] + 1;
                changed = 1;
            }
        }
    }
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        int32_t top = level[c->a] > level[c->b] ? level[c->a] : level[c->b];
        if (c->jn > 0.0 && top != INT32_MAX && (uint32_t)top > max_level)
            max_level = (uint32_t)top;
    }
    /* The contacts to propagate through, grouped by the level of their
     * upper body (a counting sort, stable: contact order within a level),
     * so that the levels, ground up, take one walk over their own contacts
     * instead of each level walking every contact -- O(contacts), where a
     * pile of L levels took L walks.  (A level is one more than the level
     * of a different body, so it is below the number of bodies: the counts
     * fit in shock_order's max_bodies + 2 entries after max_contacts.) */
    {
        uint32_t *order = w->shock_order, *start = w->shock_order + w->def.max_contacts, n = 0;
        memset(start, 0, ((size_t)max_level + 2) * sizeof *start);
        for (i = 0; i < w->contact_count; ++i) {
            uint32_t top = shock_level(&w->contact[i], level, max_level);
            if (top != 0)
                start[top + 1]++;
        }
        for (k = 1; k <= max_level + 1; ++k)
            start[k] += start[k - 1];
        for (i = 0; i < w->contact_count; ++i) {
            uint32_t top = shock_level(&w->contact[i], level, max_level);
            if (top != 0) {
                order[start[top]++] = i; /* start[top] ends at the next level's start */
                n++;
            }
        }
        /* start[k] is now the end of level k: level k is [start[k-1], start[k]) */
        for (k = 0; k < n; ++k) {
            rbs__contact *c = &w->contact[order[k]];
            double vn, kk;
            vn = v3_dot(rbs__rel_velocity(w, c), c->n) + c->bias; /* (jn > 0: bias >= 0) */
            if (!(vn < 0.0))
                continue;
            if (level[c->a] > level[c->b]) {
                v3 ra = rbs__contact_ra(w, c);
                kk = k_one(w, c->a, ra, c->n);
                if (kk > 0.0)
                    rbs__apply_impulse(w, c->a, ra, v3_scale(c->n, -vn / kk));
            } else {
                v3 rb = rbs__contact_rb(w, c);
                kk = k_one(w, c->b, rb, c->n);
                if (kk > 0.0)
                    rbs__apply_impulse(w, c->b, rb, v3_scale(c->n, vn / kk));
            }
        }
    }
}

/* The resting pass's impulse J on a sphere pair acts over the sub-step as
 * a force does: half of it before the drift (positions move by half of its
 * velocity change), half after.  Both halves along the normal of the
 * sub-step's start leave the second one off the line of centres once the
 * pair has turned about each other: a torque that the kick-drift-kick of
 * central forces never gives.  Two balls pressed together and sliding
 * round each other (frictionless, mutual gravity) lost 15 % of their
 * angular momentum and 27 % of their energy in 0.5 s at dt = 1 ms, where
 * euler, which applies all of J before the drift, kept both (a probe of
 * session 44).  So the second half turns with the pair (verlet and rk4,
 * after their drift): J (normal and
 * friction, with its levers) rotated by the turn from the start's normal
 * n to the end's n'.  A plane's normal does not turn: nothing changes. */
/* v turned about the unit axis k by the angle whose cosine and sine are
 * cs, sn (Rodrigues: v cos + (k x v) sin + k (k.v)(1 - cos)). */
static v3 turn(v3 v, v3 k, double cs, double sn)
{
    return v3_add(v3_add(v3_scale(v, cs), v3_scale(v3_cross(k, v), sn)), v3_scale(k, v3_dot(k, v) * (1.0 - cs)));
}

void rbs__turn_second_halves(rbs_world *w)
{
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        rbs__contact e;
        v3 j, d, n1, k;
        double len, cs, sn;
        if (c->bias < 0.0 || w->type[c->b] != RBS_BODY_SPHERE)
            continue;
        j = v3_mad(c->jt, c->n, c->jn);
        if (j.x == 0.0 && j.y == 0.0 && j.z == 0.0)
            continue;
        d = v3_sub(v3_load(&w->pos[3 * c->a]), v3_load(&w->pos[3 * c->b]));
        len = v3_len(d);
        if (!(len > 0.0))
            continue;
        n1 = v3_scale(d, 1.0 / len);
        k = v3_cross(c->n, n1); /* sin(angle) along the axis */
        sn = v3_len(k);
        if (!(sn > 0.0))
            continue;
        cs = v3_dot(c->n, n1);
        k = v3_scale(k, 1.0 / sn);
        e = *c;
        e.n = n1;
        /* Each application puts equal and opposite impulses at one point
         * (the levers of an off-centre mass from its orientation now), so
         * the exchange keeps the pair's momentum and angular momentum. */
        rbs__apply_pair(w, c, v3_scale(j, -0.5));
        rbs__apply_pair(w, &e, v3_scale(turn(j, k, cs, sn), 0.5));
        {
            /* rolling and spinning resistance: the angular impulse turns too */
            const rbs__pair *p = rbs__contact_pair(w, c);
            if (p->rolling > 0.0 || p->spinning > 0.0) {
                const rbs__resist *r = &w->contact_resist[i];
                v3 l = v3_mad(r->jroll, c->n, r->jspin);
                if (l.x != 0.0 || l.y != 0.0 || l.z != 0.0) {
                    rbs__apply_angular_pair(w, c, v3_scale(l, -0.5));
                    rbs__apply_angular_pair(w, &e, v3_scale(turn(l, k, cs, sn), 0.5));
                }
            }
        }
    }
}

void rbs__solve_resting(rbs_world *w, rbs_step_info *info)
{
    rbs__solve_resting_warm(w, info, 0.0);
}

/* The two sweeps below share their arithmetic through these helpers (and
 * rows.h's), so they agree bit for bit.  normal_row: the accumulated normal
 * impulse that cancels the approach vn beyond the contact's bias, the
 * approach a speculative contact may keep (Jn >= 0; a touching contact's
 * bias is 0, which leaves vn the same number). */
static inline double normal_row(const rbs__contact *c, double vn)
{
    double jn_new = c->jn - (vn + c->bias) / c->kn;
    return jn_new < 0.0 ? 0.0 : jn_new;
}


/* Rolling and spinning resistance at contact i (its pair has some, and
 * Jn > 0): the resisting angular impulses, accumulated in
 * w->contact_resist[i] and kept within rolling * radius * Jn and
 * spinning * Jn.  Returns the square of the largest velocity change it made
 * (as the sweeps measure it), 0 if none. */
double rbs__resist_row(rbs_world *w, uint32_t i)
{
    const rbs__contact *c = &w->contact[i];
    const rbs__pair *p = rbs__contact_pair(w, c);
    rbs__resist *rs = &w->contact_resist[i];
    v3 wrel = v3_sub(v3_load(&w->avel[3 * c->a]), v3_load(&w->avel[3 * c->b]));
    double ws = v3_dot(wrel, c->n);
    v3 wr = v3_mad(wrel, c->n, -ws), ia, ib, dl = v3_make(0, 0, 0);
    double lr = v3_len_small(wr); /* (v3_len is 0 below 1e-162 rad/s: no resistance) */
    if (p->rolling > 0.0 && lr > 0.0) {
        v3 u = v3_unit_small(wr, lr), cand;
        double k = 0.0, lim = p->rolling * rs->radius * c->jn, l;
        rbs__body_inv_inertia_world(w, c->a, u, &ia);
        rbs__body_inv_inertia_world(w, c->b, u, &ib);
        k = v3_dot(u, ia) + v3_dot(u, ib);
        cand = v3_mad(rs->jroll, u, -lr / k);
        l = v3_len(cand);
        if (l > lim)
            cand = v3_scale(cand, lim / l);
        dl = v3_add(dl, v3_sub(cand, rs->jroll));
        rs->jroll = cand;
    }
    if (p->spinning > 0.0 && ws != 0.0) {
        double k, cand, lim = p->spinning * c->jn;
        rbs__body_inv_inertia_world(w, c->a, c->n, &ia);
        rbs__body_inv_inertia_world(w, c->b, c->n, &ib);
        k = v3_dot(c->n, ia) + v3_dot(c->n, ib);
        cand = rs->jspin - ws / k;
        if (cand > lim) cand = lim;
        if (cand < -lim) cand = -lim;
        dl = v3_mad(dl, c->n, cand - rs->jspin);
        rs->jspin = cand;
    }
    if (dl.x != 0.0 || dl.y != 0.0 || dl.z != 0.0) {
        double lever = rs->radius > 0.0 ? rs->radius : 1.0;
        double dl2 = v3_dot(dl, dl) * c->kn * c->kn / (lever * lever); /* squared, as change */
        rbs__apply_angular_pair(w, c, dl);
        return dl2;
    }
    return 0.0;
}

/* Solve the m equations of the augmented rows a -- row r's coefficients
 * a[r * stride + 0 .. m - 1], its right-hand side a[r * stride + m] -- by
 * Gaussian elimination with partial pivoting, into y[0 .. m - 1]; 0 (y
 * unset) when a pivot is not above tiny[k] in size (column k's; 0 with
 * tiny NULL): dependent rows.  The small blocks' one solver (resist_block,
 * solve_block). */
static int dense_solve(double *a, int m, int stride, const double *tiny, double *y)
{
    int k, r, q;
    for (k = 0; k < m; ++k) {
        int piv = k;
        for (r = k + 1; r < m; ++r)
            if (fabs(a[r * stride + k]) > fabs(a[piv * stride + k]))
                piv = r;
        if (!(fabs(a[piv * stride + k]) > (tiny != NULL ? tiny[k] : 0.0)))
            return 0;
        if (piv != k)
            for (q = k; q <= m; ++q) {
                const double t = a[k * stride + q];
                a[k * stride + q] = a[piv * stride + q];
                a[piv * stride + q] = t;
            }
        for (r = k + 1; r < m; ++r) {
            const double f = a[r * stride + k] / a[k * stride + k];
            for (q = k; q <= m; ++q)
                a[r * stride + q] -= f * a[k * stride + q];
        }
    }
    for (k = m - 1; k >= 0; --k) {
        double v = a[k * stride + m];
        for (q = k + 1; q < m; ++q)
            v -= a[k * stride + q] * y[q];
        y[k] = v / a[k * stride + k];
    }
    return 1;
}

/* Friction, rolling and spinning resistance of one contact (contact i: its
 * pair has friction and some resistance, Jn > 0) solved as one block: the
 * tangential impulse and the angular impulses that together stop the slip
 * and the relative turning (rolling: about the tangents, spinning: about n)
 * -- up to five unknowns, K x = -u with K the contact's Delassus block in
 * the basis (t1, t2 | t1, t2 | n) -- taken when each stays within its bound
 * (|Jt| <= cap Jn, rbs__cone's; |L_roll| <= rolling r Jn; |L_spin| <=
 * spinning Jn).  The rows one at a time fight: the friction row stops the
 * contact point by turning the ball, the rolling row stops the turning by
 * letting the contact point slip, and a ball held still by rolling
 * resistance converged by 5/7 a sweep (for a solid sphere on a floor), so
 * max_sweeps (20) left 1.2e-3 of a step's load each pass: a ball on a 3°
 * incline with mu_r = 0.1 crept at 6e-7 m/s for ever (a probe of session
 * 45).  The block is one contact's step of blocked Gauss-Seidel (K.
 * Erleben, Numerical methods for linear complementarity problems in
 * physics-based animation, SIGGRAPH 2013 course notes; Box2D v2's
 * b2ContactSolver solves a manifold's two normal rows as one 2x2 block the
 * same way, E. Catto and D. Gregorius): where the unbounded solution keeps
 * every bound it is the bounded one, so the step still only lowers the
 * pass's quadratic, as a row's does.  Returns 1 when taken (impulses
 * applied, *change raised to the square of its largest velocity change as
 * the sweeps measure it); 0 when some bound would be passed (nothing
 * changed: the rows one at a time then, which keep the bounds as before). */
static int resist_block(rbs_world *w, uint32_t i, const rbs__pair *p, double *change)
{
    rbs__contact *c = &w->contact[i];
    rbs__resist *rs = &w->contact_resist[i];
    const int moves_a = w->inv_mass[c->a] != 0.0, moves_b = w->inv_mass[c->b] != 0.0;
    const v3 ra = rbs__contact_ra(w, c), rb = rbs__contact_rb(w, c);
    v3 dir[5], dv[5], dw[5], rv, wrel, t1, t2, dj = {0, 0, 0}, dl = {0, 0, 0};
    int ang[5], m = 0, r, k;
    double kk[5][6], x[5], lim, lever, d2;
    /* a basis of the tangent plane: t1 normal to n and to n's smallest axis */
    {
        const v3 n = c->n;
        const double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z);
        v3 e = ax <= ay && ax <= az ? v3_make(1, 0, 0) : (ay <= az ? v3_make(0, 1, 0) : v3_make(0, 0, 1));
        t1 = v3_cross(n, e);
        t1 = v3_scale(t1, 1.0 / v3_len(t1));
        t2 = v3_cross(n, t1);
    }
    /* the unknowns: Jt along t1, t2; rolling about t1, t2; spinning about n */
    for (k = 0; k < 5; ++k) {
        if ((k == 2 || k == 3) && !(p->rolling > 0.0))
            continue;
        if (k == 4 && !(p->spinning > 0.0))
            continue;
        dir[m] = k == 4 ? c->n : (k % 2 == 0 ? t1 : t2);
        ang[m++] = k >= 2;
    }
    /* what a unit impulse of each unknown does to the relative velocity at
     * the contact (dv) and to the relative angular velocity (dw) */
    for (k = 0; k < m; ++k) {
        v3 ia = {0, 0, 0}, ib = {0, 0, 0};
        if (ang[k]) {
            /* +u on a, -u on b (rbs__apply_angular_pair) */
            if (moves_a)
                rbs__body_inv_inertia_world(w, c->a, dir[k], &ia);
            if (moves_b)
                rbs__body_inv_inertia_world(w, c->b, dir[k], &ib);
            dv[k] = v3_add(v3_cross(ia, ra), v3_cross(ib, rb));
        } else {
            /* j at ra on a, -j at rb on b (rbs__apply_pair) */
            if (moves_a)
                rbs__body_inv_inertia_world(w, c->a, v3_cross(ra, dir[k]), &ia);
            if (moves_b)
                rbs__body_inv_inertia_world(w, c->b, v3_cross(rb, dir[k]), &ib);
            dv[k] = rbs__k_apply(w, c, dir[k]);
        }
        dw[k] = v3_add(ia, ib);
    }
    /* K x = -u, by Gaussian elimination with partial pivoting (K is
     * symmetric positive definite for bodies with mass; a vanishing pivot
     * leaves it to the rows) */
    rv = rbs__rel_velocity(w, c);
    wrel = v3_sub(v3_load(&w->avel[3 * c->a]), v3_load(&w->avel[3 * c->b]));
    for (r = 0; r < m; ++r) {
        for (k = 0; k < m; ++k)
            kk[r][k] = v3_dot(dir[r], ang[r] ? dw[k] : dv[k]);
        kk[r][m] = -v3_dot(dir[r], ang[r] ? wrel : rv);
    }
    if (!dense_solve(&kk[0][0], m, 6, NULL, x))
        return 0;
    /* the block's impulses, taken only within every bound */
    dj = v3_add(v3_scale(t1, x[0]), v3_scale(t2, x[1]));
    {
        v3 jt = v3_add(c->jt, dj), jroll = rs->jroll;
        double jspin = rs->jspin;
        k = 2;
        lim = rbs__friction_cap(p, c->jslip, c->jn) * c->jn;
        if (!(v3_dot(jt, jt) <= lim * lim))
            return 0;
        if (p->rolling > 0.0) {
            v3 d = v3_add(v3_scale(t1, x[2]), v3_scale(t2, x[3]));
            jroll = v3_add(jroll, d);
            dl = d;
            lim = p->rolling * rs->radius * c->jn;
            if (!(v3_dot(jroll, jroll) <= lim * lim))
                return 0;
            k = 4;
        }
        if (p->spinning > 0.0) {
            jspin += x[k];
            dl = v3_mad(dl, c->n, x[k]);
            lim = p->spinning * c->jn;
            if (!(fabs(jspin) <= lim))
                return 0;
        }
        c->jt = jt;
        rs->jroll = jroll;
        rs->jspin = jspin;
    }
    rbs__apply_pair(w, c, dj);
    rbs__apply_angular_pair(w, c, dl);
    d2 = v3_dot(dj, dj) * c->kn * c->kn;
    if (d2 > *change)
        *change = d2;
    lever = rs->radius > 0.0 ? rs->radius : 1.0;
    d2 = v3_dot(dl, dl) * c->kn * c->kn / (lever * lever);
    if (d2 > *change)
        *change = d2;
    return 1;
}

/* One Gauss-Seidel sweep over every contact (any body, any resistance).
 * *change: the largest velocity change, m/s (the sweep keeps its square:
 * no square root a row); *total: the sum of normal
 * impulses; returns 1 if an impulse changed. */
/* A contact whose normal row left Jn = 0 bears no load, so its cones --
 * |Jt| <= mu Jn, |L_roll| <= rolling r Jn, |L_spin| <= spinning Jn -- hold
 * no impulse: what the warm start or an earlier sweep put in them is taken
 * back (the friction part added to *j, to go on with the normal impulse;
 * the angular ones applied here).  Returns push, set if *j now holds
 * something; raises *change (squared) as the rows do.  The friction row
 * used to skip an unloaded contact and keep it: a ball rolling down a 20°
 * incline onto a floor kept the incline's warm friction through the
 * sub-step of its landing, where the incline's contact parts -- 4.4e-5 N s
 * up the slope, 1.9e-6 m/s on the speed it rolls on at with verlet and
 * rk4 at dt = 1e-4 and 3e-4 s alike, not converging (a probe of session
 * 46). */
static int release_unloaded(rbs_world *w, uint32_t i, const rbs__pair *p, v3 *j, int push, double *change)
{
    rbs__contact *c = &w->contact[i];
    if (c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0) {
        v3 dj = v3_scale(c->jt, -1.0);
        *j = push ? v3_add(*j, dj) : dj;
        push = 1;
        c->jt = v3_make(0, 0, 0);
        if (v3_dot(dj, dj) * c->kn * c->kn > *change)
            *change = v3_dot(dj, dj) * c->kn * c->kn;
    }
    if (p->rolling > 0.0 || p->spinning > 0.0) {
        rbs__resist *rs = &w->contact_resist[i];
        v3 l = v3_mad(rs->jroll, c->n, rs->jspin);
        if (l.x != 0.0 || l.y != 0.0 || l.z != 0.0) {
            double lever = rs->radius > 0.0 ? rs->radius : 1.0;
            double dl2 = v3_dot(l, l) * c->kn * c->kn / (lever * lever);
            rbs__apply_angular_pair(w, c, v3_scale(l, -1.0));
            if (dl2 > *change)
                *change = dl2;
        }
        rs->jroll = v3_make(0, 0, 0);
        rs->jspin = 0.0;
    }
    return push;
}

static int sweep_generic(rbs_world *w, int friction, double *change_out, double *total_out)
{
    uint32_t i;
    int any = 0;
    double change = 0.0, total = 0.0;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        double jn_new, d, vn;
        v3 rv, j = {0, 0, 0};
        int push;
        if (c->bias < 0.0)
            continue; /* an impact on its way (speculative) */
        rv = rbs__rel_velocity(w, c);
        vn = v3_dot(rv, c->n);
        jn_new = normal_row(c, vn);
        d = jn_new - c->jn;
        push = 0;
        if (d != 0.0) {
            j = v3_scale(c->n, d);
            push = 1;
            c->jn = jn_new;
            if (d * d * c->kn * c->kn > change)
                change = d * d * c->kn * c->kn;
            any = 1;
        }
        total += c->jn;
        if (friction && c->jn == 0.0)
            push = release_unloaded(w, i, p, &j, push, &change);
        if (friction && c->jn != 0.0 && (p->mu_s > 0.0 || p->mu_k > 0.0) &&
            (p->rolling > 0.0 || p->spinning > 0.0)) {
            /* friction and resistance as one block (resist_block), else
             * row by row as below */
            if (push)
                rbs__apply_pair(w, c, j);
            push = 0;
            if (resist_block(w, i, p, &change))
                continue;
            rv = rbs__rel_velocity(w, c); /* (after the normal impulse) */
            vn = v3_dot(rv, c->n);
        }
        if (friction && c->jn != 0.0 && (p->mu_s > 0.0 || p->mu_k > 0.0)) {
            v3 vt;
            if (c->kt_inv > 0.0) {
                /* an isotropic tangent plane (centred spheres, r along n):
                 * the normal impulse changes the relative velocity along n
                 * only, so the slip is the one before it, and both
                 * impulses go on as one */
                vt = v3_mad(rv, c->n, -vn);
            } else {
                if (push)
                    rbs__apply_pair(w, c, j);
                push = 0;
                vt = rbs__slip(w, c);
            }
            if (vt.x != 0.0 || vt.y != 0.0 || vt.z != 0.0) {
                rbs__kt kt;
                v3 stick = rbs__stick_impulse_kt(w, c, vt, &kt);
                v3 cand = rbs__cone(w, c, p, stick, &kt), dj = v3_sub(cand, c->jt);
                j = push ? v3_add(j, dj) : dj;
                push = 1;
                c->jt = cand;
                if (v3_dot(dj, dj) * c->kn * c->kn > change)
                    change = v3_dot(dj, dj) * c->kn * c->kn;
            }
        }
        if (push)
            rbs__apply_pair(w, c, j);
        if (!friction || c->jn == 0.0)
            continue;
        if (p->rolling > 0.0 || p->spinning > 0.0) {
            double dl2 = rbs__resist_row(w, i);
            if (dl2 > change)
                change = dl2;
        }
    }
    *change_out = sqrt(change); /* change held its square */
    *total_out = total;
    return any;
}

/* The fast sweep.  Most worlds -- and every pile -- are centred isotropic
 * spheres without rolling or spinning resistance: then a contact needs of
 * each body only v, w, 1/m and the scalar 1/I, which the pass gathers into
 * one cache line per body (w->solver_body, RBS__SOLVER_STRIDE doubles per
 * slot: v, w, 1/m, 1/I) instead of reading five arrays per impulse.  The
 * arithmetic is sweep_generic's, operation for operation, so results are
 * bit-identical; fast_eligible says when it applies. */

static int fast_eligible(const rbs_world *w, int friction)
{
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        if (p->rolling > 0.0 || p->spinning > 0.0 || (c->flags & RBS__OFF))
            return 0; /* (an off-centre mass: levers not along n) */
        if ((w->inv_mass[c->a] != 0.0 && !w->isotropic[c->a]) ||
            (w->inv_mass[c->b] != 0.0 && !w->isotropic[c->b]))
            return 0;
        if (friction && (p->mu_s > 0.0 || p->mu_k > 0.0) && !(c->kt_inv > 0.0))
            return 0; /* anisotropic tangent plane: the 2x2 solve of stick_impulse */
    }
    return 1;
}

static void gather_body(rbs_world *w, uint32_t i)
{
    double *b = RBS__SB(w, i);
    memcpy(b, &w->vel[3 * i], 3 * sizeof(double));
    memcpy(b + 3, &w->avel[3 * i], 3 * sizeof(double));
    b[6] = w->inv_mass[i];
    b[7] = rbs__inv_inertia_xx(w, i); /* isotropic, or not moving (unused) */
}

static void scatter_body(rbs_world *w, uint32_t i)
{
    const double *b = RBS__SB(w, i);
    if (b[6] == 0.0)
        return; /* impulses never change a body that does not move */
    memcpy(&w->vel[3 * i], b, 3 * sizeof(double));
    memcpy(&w->avel[3 * i], b + 3, 3 * sizeof(double));
}

/* fn on every body of a contact: through the contacts' ends when they are
 * few, else through the body lists in slot order (a sequential walk; a
 * pile's contacts would visit each body several times, scattered). */
static void gather_scatter(rbs_world *w, void (*fn)(rbs_world *, uint32_t))
{
    uint32_t i;
    if (2 * (uint64_t)w->contact_count < w->sphere_count) {
        for (i = 0; i < w->contact_count; ++i) {
            fn(w, w->contact[i].a);
            fn(w, w->contact[i].b);
        }
        return;
    }
    for (i = 0; i < w->sphere_count; ++i)
        fn(w, w->spheres[i]);
    for (i = 0; i < w->plane_count; ++i)
        fn(w, w->planes[i]);
}

static int sweep_fast(rbs_world *w, int friction, double *change_out, double *total_out)
{
    uint32_t i;
    int any = 0;
    double change = 0.0, total = 0.0;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        double *ba = RBS__SB(w, c->a), *bb = RBS__SB(w, c->b), jn_new, d, vn, la;
        v3 rv, j = {0, 0, 0};
        int push;
        if (c->bias < 0.0)
            continue; /* an impact on its way (speculative) */
        /* levers along n (fast_eligible: no off-centre mass) */
        la = rbs__contact_la(w, c);
        rv = rbs__along_rel_velocity(c, la, v3_load(ba), v3_load(ba + 3), v3_load(bb), v3_load(bb + 3));
        vn = v3_dot(rv, c->n);
        jn_new = normal_row(c, vn);
        d = jn_new - c->jn;
        push = 0;
        if (d != 0.0) {
            j = v3_scale(c->n, d);
            push = 1;
            c->jn = jn_new;
            if (d * d * c->kn * c->kn > change)
                change = d * d * c->kn * c->kn;
            any = 1;
        }
        total += c->jn;
        if (friction && c->jn == 0.0) /* (its friction part: fast_eligible, no resistance) */
            push = release_unloaded(w, i, p, &j, push, &change);
        if (friction && c->jn != 0.0 && (p->mu_s > 0.0 || p->mu_k > 0.0)) {
            v3 vt = v3_mad(rv, c->n, -vn); /* the slip before the normal impulse (see sweep_generic) */
            if (vt.x != 0.0 || vt.y != 0.0 || vt.z != 0.0) {
                /* stick_impulse's isotropic case: -vt / kt (vt is not 0; its
                 * square is 0 below 1e-162 m/s, which left such a slip alone) */
                v3 stick = v3_scale(vt, -c->kt_inv);
                v3 cand = rbs__cone(w, c, p, stick, NULL), dj = v3_sub(cand, c->jt);
                j = push ? v3_add(j, dj) : dj;
                push = 1;
                c->jt = cand;
                if (v3_dot(dj, dj) * c->kn * c->kn > change)
                    change = v3_dot(dj, dj) * c->kn * c->kn;
            }
        }
        if (push)
            rbs__sb_apply_pair(ba, bb, c, la, j);
    }
    *change_out = sqrt(change); /* change held its square */
    *total_out = total;
    return any;
}

/* Kinetic energy of the moving bodies of the pass's contacts (each once:
 * ev_mode is the scratch mark, as for shock propagation), J -- to see
 * whether a warm-started pass that did not converge added energy.  (Over
 * the pass's bodies only: the whole world's cost 10 % of an euler pile's
 * time, and other bodies' energy only hid a gain.) */
static double pass_kinetic(rbs_world *w)
{
    int32_t *mark = w->ev_mode;
    double ke = 0.0;
    uint32_t k;
    int e;
    for (k = 0; k < w->contact_count; ++k) {
        mark[w->contact[k].a] = 0;
        mark[w->contact[k].b] = 0;
    }
    for (k = 0; k < w->contact_count; ++k) {
        for (e = 0; e < 2; ++e) {
            const uint32_t i = e ? w->contact[k].b : w->contact[k].a;
            v3 v, om;
            if (mark[i] || !rbs__body_moves(w, i))
                continue;
            mark[i] = 1;
            v = v3_load(&w->vel[3 * i]);
            om = v3_load(&w->avel[3 * i]);
            ke += 0.5 * w->mass[i] * v3_dot(v, v) +
                  0.5 * v3_dot(om, rbs__inertia_times(w, i, q_load(&w->orient[4 * i]), om));
        }
    }
    return ke;
}

/* Take back every impulse the pass holds (warm start and sweeps): the
 * velocities as they came, to rounding; the accumulators zero. */
static void pass_undo(rbs_world *w)
{
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        if (c->bias < 0.0)
            continue;
        if (c->jn != 0.0 || c->jt.x != 0.0 || c->jt.y != 0.0 || c->jt.z != 0.0)
            rbs__apply_pair(w, c, v3_scale(v3_add(v3_scale(c->n, c->jn), c->jt), -1.0));
        c->jn = 0.0;
        c->jt = v3_make(0, 0, 0);
        if (p->rolling > 0.0 || p->spinning > 0.0) {
            rbs__resist *r = &w->contact_resist[i];
            v3 l = v3_mad(r->jroll, c->n, r->jspin);
            if (l.x != 0.0 || l.y != 0.0 || l.z != 0.0)
                rbs__apply_angular_pair(w, c, v3_scale(l, -1.0));
            r->jroll = v3_make(0, 0, 0);
            r->jspin = 0.0;
        }
    }
}

/* Blocks.  A sphere held by static bodies (planes, fixed spheres) through
 * nearly parallel or opposite normals -- a V-groove whose walls are within
 * a few degrees of parallel, a big ball in the shallow cup of three small
 * fixed ones -- is a mode that the rows one at a time hardly move: the
 * Delassus block of its rows is (1/m) [s_i s_j n_i . n_j], whose small
 * eigenvalues (1 + n_1 . n_2 for a wedge, 3/2 sin^2 a for a cup of three
 * contacts a off the vertical) set how much of what it needs a sweep
 * gives.  max_sweeps (20) left a 10 m ball on three fixed 0.1 m balls 0.2
 * m from its axis (a = 1.1 deg) rattling at up to 4 mm/s for good, and a
 * ball in a V-groove with walls 0.1 deg off vertical sank 1 cm into it in
 * 2 s, 0.1 J lost, moving at up to 0.03 m/s (euler, verlet, rk4,
 * adaptive, selective; a probe of session 46).  Such a sphere's rows
 * against static bodies -- 2 to BLOCK_MAX of them (a cup of up to eight),
 * a pair of normals with |n_i . n_j| > BLOCK_COS, a centred mass so that
 * the levers are along n -- are solved as one linear complementarity
 * problem at the start of every
 * sweep: the one step of blocked Gauss-Seidel (as resist_block's, and the
 * soft step's wedge rows, docs/methods.md) that solves them exactly with
 * the rest of the world held, by trying the sets of active rows (K_SS x =
 * -q_S, x >= 0, the others not approaching; at most 3 active, the rank of
 * the block: Cottle, Pang & Stone, The
 * Linear Complementarity Problem, 1992, ch. 1).  The rows one at a time
 * then find them solved, and do friction.  A sphere on loose balls (a 10
 * m ball on three 0.1 m balls standing on a floor) has the same mode --
 * it rolls over them, its normals 1.1 deg apart -- and the balls' floors
 * hold it as the fixed cup's balls do: with only its rows in the block
 * (their partners' masses in K, well conditioned) the floor rows gave back
 * what the block took, and it wandered at up to 1.6 cm/s (mu = 1,
 * max_sweeps 20; a probe of session 46).  So a sphere's rows to smaller
 * moving spheres (the larger ball owns a row between two: see
 * block_owner) join its block, and with them each such partner's rows to
 * static bodies, while the block has at most BLOCK_MAX rows; K_ij is then
 * the sum over the bodies both rows move of s_i s_j n_i . n_j / m
 * (Delassus, levers along n), still the exact step of blocked
 * Gauss-Seidel over those rows with the rest held, of rank 3 a moving
 * body.  Now it stays to 2e-16 m/s.  Rows to moving partners count as ill
 * only when nearly parallel in the same sense (a cup): a ball pressed
 * between two is solved well one row at a time.  The blocks are found
 * once a pass: w->shock_order (scratch until shock propagation) holds a
 * list of each body's rows, next[] over the contacts and the first row
 * of each block after max_contacts; ev_mode marks the bodies taken. */
#define BLOCK_MAX 8
#define BLOCK_RANK 3 /* (the rows a centred moving body takes part in span 3-D normals) */
#define BLOCK_COS 0.9

/* The body whose list contact c goes in (else UINT32_MAX): the moving one
 * against a static body; between two moving ones the larger (the
 * heavier at equal radii, then a) -- the big ball over a cup of small
 * loose ones, whose normals to it are nearly parallel whatever the
 * masses.  Off-centre masses are left out (their levers are not
 * along n: the block's K below has no angular terms). */
static uint32_t block_owner(const rbs_world *w, const rbs__contact *c)
{
    const int ma = w->inv_mass[c->a] != 0.0, mb = w->inv_mass[c->b] != 0.0;
    if (c->bias < 0.0 || (c->flags & RBS__OFF) || (!ma && !mb))
        return UINT32_MAX;
    if (ma != mb)
        return ma ? c->a : c->b;
    if (w->radius[c->a] != w->radius[c->b])
        return w->radius[c->a] > w->radius[c->b] ? c->a : c->b;
    return w->inv_mass[c->b] < w->inv_mass[c->a] ? c->b : c->a;
}

/* The other body of contact c than x. */
static uint32_t block_other(const rbs__contact *c, uint32_t x) { return c->a == x ? c->b : c->a; }

/* Whether rows c and d of body x are nearly parallel or opposite
 * (against static bodies), or nearly parallel with the same sense (a
 * loose partner in either: a cup of balls under x, not x pressed between
 * two, which the rows one at a time solve well). */
static int block_ill(const rbs_world *w, uint32_t x, const rbs__contact *c, const rbs__contact *d)
{
    const double dot = v3_dot(c->n, d->n);
    if (w->inv_mass[block_other(c, x)] == 0.0 && w->inv_mass[block_other(d, x)] == 0.0)
        return fabs(dot) > BLOCK_COS;
    return ((c->a == x) == (d->a == x) ? dot : -dot) > BLOCK_COS;
}

/* Find the blocks; their count.  A block is a sphere's rows (static and
 * loose partners) with two nearly parallel or opposite normals, and the
 * rows of each loose partner to static bodies (its floor): with those
 * held, the loose partners' rows, however well conditioned alone, give
 * back what the sphere's rows took (the cup through the partners is as
 * ill-conditioned as a fixed one). */
static uint32_t find_blocks(rbs_world *w)
{
    uint32_t *next = w->shock_order, *head = w->shock_order + w->def.max_contacts;
    int32_t *used = w->ev_mode; /* scratch: a body whose rows went into a block */
    uint32_t i, k, n = 0;
    int any = 0;
    for (i = 0; i < w->contact_count && !any; ++i)
        any = block_owner(w, &w->contact[i]) != UINT32_MAX;
    if (!any)
        return 0;
    for (k = 0; k < w->slots; ++k) {
        head[k] = UINT32_MAX;
        used[k] = 0;
    }
    for (i = w->contact_count; i-- > 0;) {
        const uint32_t x = block_owner(w, &w->contact[i]);
        if (x != UINT32_MAX) {
            next[i] = head[x];
            head[x] = i;
        }
    }
    /* (used[]: 2 for a block's body, 1 for a partner whose static rows
     * went into one; the blocks' first rows are gathered after, as head[]
     * holds every partner's list until then) */
    for (k = 0; k < w->slots; ++k) {
        uint32_t a, b, rows = 0, ill = 0, tail = UINT32_MAX, first;
        if (used[k] || head[k] == UINT32_MAX)
            continue;
        for (a = head[k]; a != UINT32_MAX; a = next[a]) {
            rows++;
            tail = a;
            for (b = next[a]; b != UINT32_MAX; b = next[b])
                if (block_ill(w, k, &w->contact[a], &w->contact[b]))
                    ill = 1;
        }
        if (!ill || rows > BLOCK_MAX)
            continue;
        first = head[k];
        used[k] = 2;
        /* the loose partners' rows to static bodies, while they fit */
        for (a = first; a != UINT32_MAX; a = next[a]) {
            const uint32_t p = block_other(&w->contact[a], k);
            uint32_t extra = 0, e;
            if (w->inv_mass[p] == 0.0 || used[p] || w->type[p] != RBS_BODY_SPHERE)
                continue;
            for (e = head[p]; e != UINT32_MAX; e = next[e])
                if (w->inv_mass[block_other(&w->contact[e], p)] == 0.0)
                    extra++;
            if (extra == 0 || rows + extra > BLOCK_MAX)
                continue;
            used[p] = 1;
            rows += extra;
            for (e = head[p]; e != UINT32_MAX;) {
                const uint32_t after = next[e];
                if (w->inv_mass[block_other(&w->contact[e], p)] == 0.0) {
                    next[tail] = e;
                    next[e] = UINT32_MAX;
                    tail = e;
                }
                e = after;
            }
        }
    }
    for (k = 0; k < w->slots; ++k) /* (head[n] is written after head[k] is read, n <= k) */
        if (used[k] == 2)
            head[n++] = head[k];
    return n;
}

/* Solve the rows of the block that starts at contact first (see above):
 * the accumulated normal impulses of the LCP's solution, applied; the
 * square of the largest velocity change into *change, as the sweeps
 * measure it.  Nothing changes when no set of active rows passes (a
 * singular set, or rounding at a border): the rows one at a time then. */
static void solve_block(rbs_world *w, uint32_t first, double *change)
{
    const uint32_t *next = w->shock_order;
    rbs__contact *c[BLOCK_MAX] = {NULL};
    double k[BLOCK_MAX][BLOCK_MAX], q[BLOCK_MAX], x[BLOCK_MAX], qmax = 0.0;
    uint32_t i, j, n = 0, mask, at;
    int e2;
    uint32_t body[2 * BLOCK_MAX], bodies = 0, b;
    for (at = first; at != UINT32_MAX && n < BLOCK_MAX; at = next[at])
        c[n++] = &w->contact[at];
    /* K_ij = sum over the bodies both rows move of s_i s_j n_i . n_j / m
     * (s: +1 for the row's a, -1 for its b; levers along n; a row with one
     * moving body has its kn for 1/m), its diagonal the rows' kn */
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            double kk = 0.0;
            int e, f;
            if (i == j) {
                k[i][j] = c[i]->kn;
                continue;
            }
            for (e = 0; e < 2; ++e)
                for (f = 0; f < 2; ++f) {
                    const uint32_t xb = e ? c[i]->b : c[i]->a;
                    const double im = w->inv_mass[c[i]->a] != 0.0 && w->inv_mass[c[i]->b] != 0.0
                                          ? w->inv_mass[xb]
                                          : c[i]->kn;
                    if (xb == (f ? c[j]->b : c[j]->a) && w->inv_mass[xb] != 0.0)
                        kk += e == f ? im : -im;
                }
            k[i][j] = kk * v3_dot(c[i]->n, c[j]->n);
        }
        for (e2 = 0; e2 < 2; ++e2) {
            const uint32_t xb = e2 ? c[i]->b : c[i]->a;
            if (w->inv_mass[xb] == 0.0)
                continue;
            for (b = 0; b < bodies && body[b] != xb; ++b)
                ;
            if (b == bodies)
                body[bodies++] = xb;
        }
    }
    /* q: each row's approach beyond its bias with the block's impulses
     * taken out */
    for (i = 0; i < n; ++i) {
        q[i] = v3_dot(rbs__rel_velocity(w, c[i]), c[i]->n) + c[i]->bias;
        for (j = 0; j < n; ++j)
            q[i] -= k[i][j] * c[j]->jn;
        if (fabs(q[i]) > qmax)
            qmax = fabs(q[i]);
    }
    /* the sets of active rows, all of them first, then down in the mask's
     * order: the first that passes is taken */
    for (mask = (1u << n) - 1; mask > 0; --mask) {
        double a[BLOCK_MAX][BLOCK_MAX + 1], tiny[BLOCK_MAX], y[BLOCK_MAX];
        uint32_t idx[BLOCK_MAX], m = 0, r, col;
        int ok = 1;
        for (i = 0; i < n; ++i)
            if (mask & (1u << i))
                idx[m++] = i;
        if (m > BLOCK_RANK * bodies)
            continue; /* (K has rank 3 a moving body at most: singular) */
        for (r = 0; r < m; ++r) {
            for (col = 0; col < m; ++col)
                a[r][col] = k[idx[r]][idx[col]];
            a[r][m] = -q[idx[r]];
            tiny[r] = 1e-9 * c[idx[r]]->kn; /* (below it: a set of dependent rows) */
        }
        if (!dense_solve(&a[0][0], (int)m, BLOCK_MAX + 1, tiny, y))
            continue;
        for (i = 0; i < n; ++i)
            x[i] = 0.0;
        for (r = 0; r < m; ++r) {
            x[idx[r]] = y[r];
            if (!(y[r] >= 0.0))
                ok = 0;
        }
        /* the rows left out must not approach (to rounding of the pass) */
        for (i = 0; i < n && ok; ++i) {
            double v = q[i];
            if (mask & (1u << i))
                continue;
            for (j = 0; j < n; ++j)
                v += k[i][j] * x[j];
            if (v < -1e-12 * qmax)
                ok = 0;
        }
        if (!ok)
            continue;
        for (i = 0; i < n; ++i) {
            const double d = x[i] - c[i]->jn;
            if (d == 0.0)
                continue;
            rbs__apply_pair(w, c[i], v3_scale(c[i]->n, d));
            c[i]->jn = x[i];
            if (d * d * c[i]->kn * c[i]->kn > *change)
                *change = d * d * c[i]->kn * c[i]->kn;
        }
        return;
    }
}

/* Gauss-Seidel sweeps until converged (no contact's velocity changed by
 * more than tol of the pass's scale) or max_sweeps; the sweeps taken. */
static uint32_t pass_sweeps(rbs_world *w, int friction, int fast, uint32_t blocks, double scale,
                            int *any, uint32_t max_sweeps, double tol)
{
    const uint32_t *block = w->shock_order + w->def.max_contacts;
    uint32_t sweep, k;
    if (fast)
        gather_scatter(w, gather_body);
    for (sweep = 0; sweep < max_sweeps; ++sweep) {
        double change, total, moved = 0.0; /* largest velocity change, m/s; sum of Jn */
        for (k = 0; k < blocks; ++k) /* (never with fast: see the caller) */
            solve_block(w, block[k], &moved);
        if (fast ? sweep_fast(w, friction, &change, &total) : sweep_generic(w, friction, &change, &total))
            *any = 1;
        if (moved > 0.0) {
            *any = 1;
            if (sqrt(moved) > change)
                change = sqrt(moved); /* (moved held its square) */
        }
        /* converged when no contact's velocity changed by more than tol of
         * the scale of the pass: the first sweep's largest change or the
         * speed one step of gravity builds, whichever is larger */
        if (sweep == 0)
            scale = change > scale ? change : scale;
        if (change <= tol * scale || total == 0.0)
            break;
    }
    if (fast)
        gather_scatter(w, scatter_body);
    return sweep;
}

/* The approach speed along the start's normal n at a sub-step's end that
 * keeps the distance d of contact c's sphere centres under the trapezoid
 * drift while they move across n, m/s: h |u|^2 / d, u their predicted
 * mid-sub-step relative velocity across n (start velocity plus half a
 * sub-step of the smooth forces).  (x' = x + h m with m = (v + v')/2 keeps
 * |x'| = |x| = d when n . m = -h |m|^2 / (2 d); with n . v = 0 at the
 * start, n . v' = -h |m|^2 / d.)  0 against a plane, which does not
 * curve. */
static double path_bend(const rbs_world *w, const rbs__contact *c, double h)
{
    v3 u = v3_make(0, 0, 0), d, a, tau;
    int e;
    double len;
    if (w->type[c->b] != RBS_BODY_SPHERE || !(h > 0.0))
        return 0.0;
    for (e = 0; e < 2; ++e) {
        const uint32_t i = e ? c->b : c->a;
        v3 v = v3_load(&w->vel[3 * i]), arm = v3_sub(v3_load(&w->pos[3 * i]), rbs__body_com(w, i));
        v = v3_add(v, v3_cross(v3_load(&w->avel[3 * i]), arm)); /* the centre's */
        rbs__accelerations_all(w, i, &a, &tau);
        v = v3_mad(v, a, 0.5 * h);
        u = e ? v3_sub(u, v) : v;
    }
    d = v3_sub(v3_load(&w->pos[3 * c->a]), v3_load(&w->pos[3 * c->b]));
    len = v3_len(d);
    if (!(len > 0.0))
        return 0.0;
    u = v3_mad(u, c->n, -v3_dot(u, c->n));
    return h * v3_dot(u, u) / len;
}

/* The resting pass lets a speculative contact approach at (gap - slop) / h
 * at the sub-step's end, which closes it to the slop when the drift is by
 * the end velocity (euler).  verlet and rk4 drift by the mean of the start
 * and end velocities (the trapezoid): the gap left is about
 * gap + (vn0 + vn1) h / 2, vn0 the normal velocity the sub-step starts
 * with (as the collision pass leaves it; > 0 parting), vn1 the end's.  The
 * end approach allowed is B = 2 (gap - slop) / h + (3/4) vn0, kept here as
 * the gap (slop + B h, at least the slop: held like a touching contact).
 * With e = gap - slop and u = vn0 h a sub-step maps (e, u) to
 * (u/8, -2e - 3u/4), whose eigenvalues have modulus 1/2: what is
 * left of a gap or an approach halves each sub-step, and a contact parting
 * by the curvature of its path (c a sub-step) settles c above the slop
 * with vn0 = 0, as with euler.  Counting vn0 whole (B = 2e/h + vn0) closes
 * the gap in one sub-step but leaves vn0 flipping sign for ever, and the
 * normal impulse with it (+-2 % for a ball rolling over a fixed sphere at
 * dt = 1e-5 s, which then slipped 1 ms early); euler's B = e/h damps by
 * 0.71 a sub-step and leaves the contact 2c above the slop.  Without
 * speculative contacts (before session 45) the ball rolling over the
 * sphere drifted v^2 h^2 / (2 L) off it a sub-step, past the slop, and the
 * sub-steps until it fell back flew without friction: it slipped at 0.48
 * rad, where rolling needed a third of the static cone (a probe of
 * session 45).  Between two spheres the centres' path bends (path_bend):
 * a touching pair may approach at the bend's speed (its bias), and a
 * speculative pair's B takes it too.  Held to a zero approach along the
 * start's normal, a 1 kg ball sliding over a 1 g ball wedged in a box's
 * corner parted at v^2 h / d every sub-step, and the drift turned that
 * impulse's excess into lift: 2.8e-6 J gained in 80 steps at max_sweeps
 * 2000 (verlet; test_physics.c, converged_wedge_gains_no_energy; a probe
 * of session 49), 2.0e-8 J with the bend. */
void rbs__trapezoid_reach(rbs_world *w, double h)
{
    uint32_t i;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const double slop = rbs__contact_slop(w, c);
        double reach, bend;
        if (c->bias < 0.0)
            continue; /* an impact on its way */
        bend = path_bend(w, c, h);
        if (!(c->flags & RBS__APART)) {
            c->bias = bend; /* touching: it may close what the bend opens */
            continue;
        }
        reach = 2.0 * (c->gap - slop) + (0.75 * rbs__normal_velocity(w, c) + bend) * h;
        c->gap = slop + (reach > 0.0 ? reach : 0.0);
    }
}

/* Off-centre spheres' contact rows at the middle of the sub-step (verlet
 * and rk4; see world_internal.h): each such moving sphere is turned to its
 * middle orientation -- halfway (nlerp) from its start q0 to the end qe its
 * rotation sub-steps reached, or by w0 h/2 from q0 when it turns at constant
 * w0 -- and its contacts' kn, which depends on the lever, is taken again.
 * The caller's drift turns the body from q0 afterwards.  Why: an impulse J
 * along a row changes the energy by J times the mean of the row's velocity
 * before and after it, and the drift moves the centre by the trapezoid of
 * the velocities plus the turn of the arm from the centre of mass to the
 * centre; with the row at the arm's middle the two agree (the energy
 * changes by J / h times the contact's normal travel), at its start they
 * differ by J w^2 h c / 2 a sub-step.  A ball (r = 0.1 m, 1 kg, its mass
 * c = 0.03 m off its centre) rocking +-0.2 rad on a frictionless floor
 * gained 2.6e-3 J in 10 s at dt = 1 ms that way (45 % of its rocking
 * energy; 1.2e-3 J on a rough floor), and now loses 1.5e-5 J, the derived
 * -m c^2 h (A w)^4 / 8 per second of the separation's lifts against the
 * floor's varying load (tests/methods/test_rotation.c; session 52). */
void rbs__levers_at_middle(rbs_world *w, double h, uint32_t q0_at, uint32_t qe_at, uint32_t spun_at)
{
    uint32_t k;
    if (!w->plan.uneven)
        return;
    for (k = 0; k < w->sphere_count; ++k) {
        const uint32_t i = w->spheres[k];
        const double *S = &w->method_scratch[RBS__SCRATCH_STRIDE * i];
        quat q0, qm;
        if (w->fixed[i] ||
            (w->com_body[3 * i] == 0.0 && w->com_body[3 * i + 1] == 0.0 && w->com_body[3 * i + 2] == 0.0))
            continue;
        q0 = q_load(&S[q0_at]);
        if (S[spun_at] != 0.0) {
            quat qe = q_load(&S[qe_at]);
            const double s = q0.w * qe.w + q0.x * qe.x + q0.y * qe.y + q0.z * qe.z < 0.0 ? -1.0 : 1.0;
            qm.w = q0.w + s * qe.w;
            qm.x = q0.x + s * qe.x;
            qm.y = q0.y + s * qe.y;
            qm.z = q0.z + s * qe.z;
            qm = q_normalize(qm);
        } else {
            qm = q_normalize(q_mul(q_from_rotation(v3_load(&w->avel[3 * i]), 0.5 * h), q0));
        }
        q_store(&w->orient[4 * i], qm);
    }
    for (k = 0; k < w->contact_count; ++k) {
        rbs__contact *c = &w->contact[k];
        if (c->flags & RBS__OFF)
            c->kn = v3_dot(c->n, rbs__k_apply(w, c, c->n));
    }
}

/* A warm pass's sweeps: max_sweeps times the moving spheres' mass ratio
 * M/m (its whole part, 1 to RBS__COLLISION_SWEEPS).  Gauss-Seidel on a
 * light ball pressed between a heavy one and a floor takes back a share
 * 1/(1 + m/M) of its error a sweep (the 2 x 2 Delassus block
 * [[1/m + 1/M, -1/m], [-1/m, 1/m]], rate K12^2 / (K11 K22): Saad, Iterative
 * Methods for Sparse Linear Systems, 2003, sec. 4.2), so about
 * (M/m) ln(1/tol) sweeps converge it, and a warm start carries a pass's
 * unconverged rest into the next only while the contacts and h stay.  A
 * 10 kg ball (r = 0.1 m) dropped 1 cm onto a 4 x 4 bed of touching 0.1 kg
 * balls (r = 0.05 m) between walls (mu_s = 0.5, mu_k = 0.3) settled with
 * the bed's balls apart and kept rattling at up to 3.3e-3 m/s for good,
 * every pass at the limit and 5 rollbacks a step (a probe of session 49,
 * as reported at max_sweeps 20, at rest with 2000); with 100 x 20 sweeps
 * on the passes that need them it rests to 1e-14 m/s.  Equal masses (a
 * ratio under 2) keep max_sweeps, bit for bit.  verlet, rk4 and adaptive
 * take it too since the sphere pair's path bend (rbs__trapezoid_reach):
 * before it their passes, so converged, let a 1 kg ball wedged on a 1 g
 * ball in a box's corner (test_physics.c, wedged_balls_gain_no_energy)
 * gain 2.8e-6 J, over that test's bound of two slops' lift (2e-6 J); at
 * max_sweeps 20 without this it rattled for good (1.7 to 2.6 mm/s after
 * 2 s), and now rests to 5e-12 m/s (test wedge_comes_to_rest; a probe of
 * session 49). */
static uint32_t warm_sweeps_factor(const rbs_world *w)
{
    const double r = w->plan.mass_ratio;
    const rbs_method m = w->plan.method;
    /* (selective keeps max_sweeps: not measured there) */
    if (!(m == RBS_METHOD_EULER || m == RBS_METHOD_VERLET || m == RBS_METHOD_RK4 || m == RBS_METHOD_ADAPTIVE) ||
        !(r >= 2.0))
        return 1;
    return r < (double)RBS__COLLISION_SWEEPS ? (uint32_t)r : RBS__COLLISION_SWEEPS;
}

/* The warm start of contact c from its entry m for a sub-step of h: the
 * normal impulse m->n h and the tangential one, m->t h turned into today's
 * tangent plane and kept in the static cone (with friction; else 0). */
static void warm_impulse(const rbs__contact *c, const rbs__pair *p, const rbs__warm *m, int friction, double h,
                         double *jn, v3 *jt)
{
    *jn = m->n * h;
    *jt = v3_make(0, 0, 0);
    if (friction) {
        double l = m->t.x * m->t.x + m->t.y * m->t.y + m->t.z * m->t.z;
        v3 t = v3_mad(m->t, c->n, -v3_dot(m->t, c->n)); /* in today's plane */
        *jt = rbs__warm_tangent(l > 0.0 ? v3_scale(t, h) : v3_make(0, 0, 0),
                                rbs__friction_cap(p, c->jslip, *jn) * *jn);
    }
}

int rbs__warm_accelerations(rbs_world *w, double h, uint32_t at_slot)
{
    uint32_t i, k, at = 0;
    int any = 0;
    for (k = 0; k < w->sphere_count; ++k)
        memset(&w->method_scratch[RBS__SCRATCH_STRIDE * w->spheres[k] + at_slot], 0, 3 * sizeof(double));
    if (w->warm_used == 0)
        return 0;
    rbs__warm_sort(w);
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        const rbs__warm *m;
        double jn;
        v3 jt, j;
        int e;
        if (c->bias < 0.0)
            continue; /* an impact: no warm start */
        m = rbs__warm_find(w, rbs__warm_key(w, c), &at);
        if (m == NULL)
            continue;
        warm_impulse(c, rbs__contact_pair(w, c), m, w->plan.friction, h, &jn, &jt);
        j = v3_scale(v3_add(v3_scale(c->n, jn), jt), 1.0 / h); /* N */
        if (j.x == 0.0 && j.y == 0.0 && j.z == 0.0)
            continue;
        for (e = 0; e < 2; ++e) {
            const uint32_t b = e ? c->b : c->a;
            double *f = &w->method_scratch[RBS__SCRATCH_STRIDE * b + at_slot];
            if (!rbs__body_moves(w, b))
                continue;
            v3_store(f, v3_mad(v3_load(f), j, (e ? -1.0 : 1.0) * w->inv_mass[b]));
            any = 1;
        }
    }
    return any;
}

void rbs__solve_resting_warm(rbs_world *w, rbs_step_info *info, double h)
{
    uint32_t sweep, i, max_sweeps = w->def.max_sweeps, at = 0, blocks;
    int friction = w->plan.friction, any = 0, warmed = 0, fast;
    double scale = sqrt(w->def.gravity.x * w->def.gravity.x + w->def.gravity.y * w->def.gravity.y +
                        w->def.gravity.z * w->def.gravity.z) * w->def.dt;
    /* (the energy before the warm start: see below) */
    double ke0 = h > 0.0 && w->contact_count > 0 && w->warm_used > 0 ? pass_kinetic(w) : 0.0;
    rbs__warm_sort(w);
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        const rbs__pair *p = rbs__contact_pair(w, c);
        c->jn = 0.0;
        c->jt = v3_make(0, 0, 0);
        if ((c->flags & RBS__APART) && !(c->bias < 0.0)) {
            /* speculative, not an impact: it may close to the slop in h
             * (a cold pass, h <= 0, has no sub-step to close it in).  What
             * is left past the slop within half the spacing of the pair's
             * coordinates is held as touching: a move that small rounds
             * back (x + v h == x), and the approach it asked for stayed in
             * the velocity for good -- a ball dropped on a floor 1e9 m out
             * came to rest 4.3e-8 m past the slop still falling at 4.3e-5
             * m/s, every frame one of rbs_world_rounded_steps (euler,
             * selective; 2.1e-7 m/s at 1e7 m; a probe of session 52) */
            const double past = c->gap - rbs__contact_slop(w, c);
            const double far = fmax(rbs__max_abs(v3_load(&w->pos[3 * c->a])), rbs__max_abs(v3_load(&w->pos[3 * c->b])));
            c->bias = h > 0.0 ? (past > 0.5 * rbs__spacing(far) ? past / h : 0.0) : -1.0;
        }
        if (c->bias < 0.0)
            continue; /* left out of the pass: no warm start either */
        if (p->rolling > 0.0 || p->spinning > 0.0) {
            w->contact_resist[i].jroll = v3_make(0, 0, 0);
            w->contact_resist[i].jspin = 0.0;
        }
        if (h > 0.0) {
            /* warm start: what held this contact last sub-step, scaled to h
             * (a stack converges at once instead of creeping) */
            const rbs__warm *m = rbs__warm_find(w, rbs__warm_key(w, c), &at);
            if (m != NULL) {
                warm_impulse(c, p, m, friction, h, &c->jn, &c->jt);
                rbs__apply_pair(w, c, v3_add(v3_scale(c->n, c->jn), c->jt));
                any = warmed = 1;
            }
        }
    }
    /* (a pruning decision: with def.prune off every pass takes the generic
     * sweep, which test_prune compares bit for bit; so does a pass with
     * blocks, whose solve reads the bodies' own arrays) */
    blocks = find_blocks(w);
    fast = w->def.prune && w->contact_count > 0 && blocks == 0 && fast_eligible(w, friction);
    /* A pass with no contact warm (a world's first step among bodies at
     * rest in contact; not a group that comes to rest while others in the
     * world are warm -- the pass is the world's) may take
     * RBS__COLLISION_SWEEPS x max_sweeps sweeps: what
     * it leaves unconverged the warm passes after it cannot take back where
     * it went into a motion that costs no energy.  A ball on two balls
     * beside a wall (mu = 0.5) pushed the wall with 3.4e-5 N s in its first
     * 20 sweeps, and the three rolled away at 1e-5 m/s for good, bottom
     * balls forward and the top one backward (a probe of session 43); the
     * whole pass converges in under 100 sweeps and they stay put to 1e-11
     * m/s.  Passes after it have their warm start and max_sweeps.
     * For the same reason it converges to 1e-12 of its scale, not 1e-9:
     * a ball in the dimple of a resting 3 x 3 bed (mu = 0.5) pressed the
     * bed's unloaded balls with what 1e-9 left, 1e-8 g dt, and they rolled
     * off at 1e-10 m/s for good (6e-9 m in 60 s; a probe of session 49);
     * at 1e-12, 1e-13 m/s (test ball_in_a_dimple_stays_put). */
    if (!warmed && h > 0.0)
        max_sweeps *= RBS__COLLISION_SWEEPS;
    else
        max_sweeps *= warm_sweeps_factor(w);
    sweep = pass_sweeps(w, friction, fast, blocks, scale, &any, max_sweeps, !warmed && h > 0.0 ? 1e-12 : 1e-9);
    if (warmed && sweep == max_sweeps && pass_kinetic(w) > ke0 * (1.0 + 1e-9)) {
        /* A warm start that the sweeps could not bring to the solution may
         * leave energy it put in: the impulses that held last sub-step,
         * applied where the contacts no longer need them, and not taken
         * back in max_sweeps sweeps.  Sweeps from zero only ever take
         * energy out (each is a step down the pass's quadratic, whose
         * value is the energy change, from 0 at no impulse), so the pass
         * is done again cold.  A heavy ball wedged between two walls and a
         * light ball in a box's corner took 0.16 J in a frame, and was
         * flung 1400 m high in 3 s (a probe of session 40). */
        pass_undo(w);
        sweep = pass_sweeps(w, friction, fast, blocks, scale, &any, max_sweeps, 1e-9);
    }
    if (info && any) {
        for (i = 0; i < w->contact_count; ++i)
            if (w->contact[i].jn > 0.0)
                info->resting++;
        if (sweep == max_sweeps)
            info->sweep_limit++;
    }
    if (any && sweep == max_sweeps)
        shock_propagation(w);
    if (h > 0.0)
        rbs__warm_store(w, h);
}
