/*
 * soft_detect.c - the soft step's detection in the gathered layout: the
 * frame's contacts, found and packed into chunks by groups of bodies that
 * the world's threads take side by side (soft.h, team.h).
 *
 * Slabs.  The spheres are cut into S slabs along a long side of the box
 * of their centres (slab_axis), of nearly equal counts (by a histogram of 256 bins),
 * S a power of two: one slab for every RBS__SLAB_SPHERES spheres, at most
 * rbs__slabs_max(max_bodies) -- fixed by the world, never by the threads,
 * so that results do not depend on them.
 *
 * Groups (nested dissection: George, "Nested dissection of a regular finite
 * element mesh", SIAM J. Numer. Anal. 10, 1973).  The slabs are the leaves
 * of a binary tree; a contact belongs to the lowest node whose slabs hold
 * both its bodies -- the leaf of its slab, for a plane or a pair within one
 * slab, else the node where the two slabs' paths meet.  The nodes of one
 * level share no body, so their contacts can be taken side by side, a node
 * on one thread in its own order, and the levels one after the other, from
 * the leaves up: the same Gauss-Seidel order whatever the threads.  A pile
 * of N spheres cut across its long side has only the spheres near each cut
 * in the nodes above the leaves (about 4 % of the 1,000 pile's contacts),
 * and a thread that takes the same leaves every pass keeps their bodies in
 * its cache (with contacts dealt out by colour instead, every record moved
 * between the cores at every colour, and the rows ran 1.3 to 3 times slower).
 * The top node, which one thread took alone while the others waited, is two
 * groups: its contacts whose two items are both below the middle of the
 * centres' box along its longer side across the cut, and those both above
 * it; the few with one item on each side go to a level of their own, the
 * tie, above the top (about one contact a frame in the 1,000 pile).
 *
 * Detection in two passes over the slabs, side by side.  The first counts
 * each group's contacts (the candidate pairs within the sweeps' reach, the
 * planes within the slop and margin), and puts the pairs that span slabs
 * aside, slab by slab (from the end of the slab's run, backwards), for
 * their group; the counts give each group its own run of chunks.  The second
 * makes each group's contacts into its chunks: a leaf's from its slab's
 * spheres and pairs, a node's from the pairs put aside in its slabs, in the
 * order of the slabs and the candidate list -- the groups in the tree's
 * order (leaf, node, leaf, ...), so that each thread's even share of them
 * is a run of slabs with the nodes among them.  A
 * chunk lane is prepared as the contact is found (soft.h; step_soft.c's
 * rows read nothing else), and the kicks of closing pairs are summed per
 * level (a level's groups share no body), then per sphere, for the guards,
 * which a serial pass adds to the guards' group (contact.c,
 * rbs__detect_guards).  A frame whose contacts overflow max_contacts, or
 * whose candidate pairs overflow the list, is detected by the general
 * pass, serially, into one group (the capacity rules of rbs__detect_swept).
 */
#include <string.h>

#include "core/soft_detect.h"
#include "core/team.h"

#define HIST_BINS 256
#define CUT_SHARES 4 /* the most shares of the cut's passes */

/* The level of group k. */
static inline uint32_t level_of(const rbs__soft_groups *g, uint32_t k)
{
    uint32_t l = 0;
    while (l + 1 < g->levels + 1 && g->level_first[l + 1] <= k)
        l++;
    return l;
}

void rbs__soft_group_slabs(const rbs__soft_groups *g, uint32_t k, uint32_t *lo, uint32_t *hi)
{
    const uint32_t tree = g->levels - (g->slabs > 1u), l = level_of(g, k), node = k - g->level_first[l];
    *lo = l + 1 < tree ? node << l : 0u;
    *hi = l + 1 < tree ? (node + 1u) << l : g->slabs;
}

/* One group's emitter: the chunker of its run and what it finds. */
typedef struct emitter {
    rbs__chunker ch;
    uint32_t count;      /* contacts */
    double q;            /* h 0: the deepest reachable overlap, of the slop */
    double *kick;        /* per slot, its level's kick sums (NULL: none) */
    double kick_max;     /* the largest of them this group made (a NaN: unknown) */
    rbs_status status;
    unsigned char pad[64];
} emitter;

/* What a share of the prepare pass finds. */
typedef struct prepared {
    double lo[3], hi[3];  /* the box of its centres */
    double size;          /* its largest coordinate, in magnitude */
    double rmax, rsum;    /* its largest reach, the sum of its radii */
    double slack;         /* its least slack in the candidate list */
    uint32_t jumps[3];    /* its spheres (but the first of all) whose centre is
                             more than their radius along each axis from the
                             last sphere's, in slot order */
    unsigned char pad[64];
} prepared;

/* The detection of one frame: what the passes share. */
typedef struct detect {
    rbs_world *w;
    const rbs__soft_in *in;
    rbs__soft_groups *g;
    const double *centres;  /* the spheres' centres, 3 doubles an item */
    int pairs;              /* pairs of spheres are detected (the plan's) */
    double thr_shared;      /* in->acc NULL: two moving spheres' resting threshold */
    int threads;            /* more than one thread detects: the marks are atomic */
    uint32_t slab_pairs[RBS__SLABS_MAX + 1]; /* slab s's candidate pairs start
                                                (its run of soft_aside) */
    uint32_t listed[RBS__SLABS_MAX];         /* contact pairs within slab s it listed
                                                (from its run's start) */
    uint32_t crossed[RBS__SLABS_MAX];        /* and those to other slabs (from
                                                its run's end, backwards) */
    uint32_t count[RBS__SLABS_MAX][RBS__GROUPS_MAX]; /* contacts slab s found of group k */
    prepared prep[RBS_WORKERS_MAX];          /* the prepare pass's shares */
    double lo[3], hi[3];                     /* the centres' box */
    uint32_t tree;                           /* the slab tree's levels (g->levels
                                                is one more with a tie level) */
    uint32_t side_axis;                      /* the top node's split: along it, */
    double side_mid;                         /* below this or not */
    uint32_t emit_group[RBS__GROUPS_MAX];    /* the emission's items: groups */
    /* the cut's two passes (cut_slabs): */
    uint32_t cut_axis;
    double cut_lo, cut_scale;                /* bin of x: (x - cut_lo) * cut_scale */
    uint32_t hist[CUT_SHARES][HIST_BINS];    /* each share's items by bin */
    uint32_t bin_slab[HIST_BINS];
    uint32_t next[CUT_SHARES][RBS__SLABS_MAX]; /* each share's first rank in each slab */
    uint32_t jumps[3];                       /* the shares' jumps, summed */
    emitter em[RBS__GROUPS_MAX];
} detect;

/* The level where slabs *sa and sb meet in the slab tree (0: the same
 * slab), and in *sa the node there. */
static inline uint32_t tree_meet(uint32_t *sa, uint32_t sb)
{
    uint32_t l = 0;
    while (*sa != sb) {
        *sa >>= 1;
        sb >>= 1;
        l++;
    }
    return l;
}

/* The group of a contact between items i and j of slabs sa and sb (a plane:
 * j = i, sb = sa): the lowest node of the slab tree holding both slabs --
 * but the top node's contacts (more than one slab) go to one of two groups,
 * by the side of the top's split (side_axis, side_mid) both items are on,
 * or, on both sides, to the tie level's group: the two share no body, so
 * the top's contacts too are taken side by side, all but the few across
 * both cuts. */
static inline uint32_t group_of(const detect *d, uint32_t sa, uint32_t sb, uint32_t i, uint32_t j)
{
    const rbs__soft_groups *g = d->g;
    const uint32_t l = tree_meet(&sa, sb);
    int si, sj;
    if (l + 1 < d->tree || g->slabs == 1)
        return g->level_first[l] + sa;
    si = d->centres[3 * i + d->side_axis] >= d->side_mid;
    sj = d->centres[3 * j + d->side_axis] >= d->side_mid;
    return si == sj ? g->level_first[l] + (uint32_t)si : g->level_first[l + 1];
}

/* ------------------------------------------------------------------------- */
/* Lanes                                                                     */
/* ------------------------------------------------------------------------- */

/* A contact's resting threshold (rbs__resting_threshold of its bodies'
 * accelerations). */
static double threshold(const detect *d, uint32_t a, uint32_t b, v3 n)
{
    const rbs_world *w = d->w;
    const rbs__soft_in *in = d->in;
    int ma, mb;
    v3 z = v3_make(0, 0, 0);
    if (in->acc != NULL)
        return rbs__resting_threshold(v3_load(&in->acc[6 * a]), v3_load(&in->acc[6 * b]), n, in->dt);
    ma = rbs__body_moves(w, a);
    mb = rbs__body_moves(w, b);
    if (ma && mb)
        return d->thr_shared;
    return rbs__resting_threshold(ma ? in->shared_a : z, mb ? in->shared_a : z, n, in->dt);
}

/* A lane's warm start from the last frame's forces fn (normal) and ft
 * (tangent, in this frame's tangent plane) for sub-steps of h, the tangent
 * kept in the static cone (rbs__warm_tangent). */
static void lane_warm(rbs__chunk *k, uint32_t l, int friction, double mu, double fn, v3 ft, double h)
{
    k->jn[l] = fn * h;
    if (friction) {
        const v3 jt = rbs__warm_tangent(v3_scale(ft, h), mu * k->jn[l]);
        k->jx[l] = jt.x;
        k->jy[l] = jt.y;
        k->jz[l] = jt.z;
    }
}

/* Mark record i's byte in touched (soft_detect.h) for a contact: bit 0,
 * and for one that came in loaded RBS__LOADED_ONE, or RBS__LOADED_MORE
 * when that was set already (the warm start's lone lanes: soft.h,
 * RBS__SOFT_OVER).  Groups on other threads mark the same bodies: then
 * atomically (the one of two loaded marks that finds RBS__LOADED_ONE set
 * sets RBS__LOADED_MORE; read-modify-writes, which one thread, on the
 * 1,000 pile, would pay 1.3 % of its time for). */
static void mark(const detect *d, uint32_t i, int loaded)
{
    uint8_t *t = &d->in->touched[i];
    const uint8_t bits = loaded ? (uint8_t)(1u | RBS__LOADED_ONE) : (uint8_t)1;
#if defined(__GNUC__)
    if (d->threads) {
        if ((__atomic_fetch_or(t, bits, __ATOMIC_RELAXED) & RBS__LOADED_ONE) && loaded)
            __atomic_fetch_or(t, (uint8_t)RBS__LOADED_MORE, __ATOMIC_RELAXED);
        return;
    }
#endif
    *t |= bits | (*t & bits & RBS__LOADED_ONE) << 1; /* (RBS__LOADED_MORE = 2 RBS__LOADED_ONE) */
}

/* The warm-start entry of key k (plane: of a plane contact) of sphere a,
 * or NULL: a scan of a's bucket of its kind (a handful of entries), which
 * w->warm_at finds -- in whatever order the last store left the table
 * (rbs__soft_store_place's buckets, or key order), since the table holds
 * one entry a key and each bucket's entries are together.  (Before, the
 * table was in key order and searched from where the last search ended,
 * galloping over the other slabs' keys; the buckets let each thread store
 * its own slabs' contacts and read them in its own cache.) */
static const rbs__warm *warm_of(const rbs_world *w, uint64_t k, int plane, uint32_t a)
{
    const rbs__warm *t = w->warm;
    const uint64_t bucket = k >> 32;
    uint32_t j;
    for (j = w->warm_at[2u * a + (plane == 0)]; j < w->warm_used && t[j].key >> 32 == bucket; ++j)
        if (t[j].key == k)
            return &t[j];
    return NULL;
}

/* w->warm_at for a table the soft step did not store (key order: another
 * method's, or a checkpoint's): each bucket's first entry.  A slot without
 * one keeps what it held, which is not an entry of its bucket (warm_of
 * stops at once). */
static void warm_index(rbs_world *w)
{
    const rbs__warm *t = w->warm;
    uint32_t j;
    for (j = 0; j < w->warm_used; ++j)
        if (j == 0 || t[j].key >> 32 != t[j - 1].key >> 32) {
            const int plane = (t[j].key >> 63) == 0;
            const uint32_t a = (uint32_t)(t[j].key >> 32) & 0x7FFFFFFFu;
            w->warm_at[2u * a + (plane == 0)] = j;
        }
    w->warm_indexed = 1;
}

/* A contact into a lane of the emitter's group: sphere a and body b (plane:
 * a plane) -- slots, and the records ra, rb of the frame (soft_rank; a
 * plane has none) -- of material-pair row `row`, the unit normal n from b to a, the
 * gap along it and b's lever, whether it is a guard, and whether it is one
 * of a wedge's two plane contacts (placed as a pair: rbs__chunker_wedge) --
 * with what its
 * rows read: its pair's row (the rows make the effective masses from the
 * records), its approach speed at the frame's start (restitution's target
 * e v0, and whether it bounces: faster than its resting threshold) and the
 * last frame's impulses for the warm start. */
static void lane_fill(const detect *d, emitter *em, uint32_t ra, uint32_t rb, uint32_t a, uint32_t b, int plane,
                      uint32_t row, v3 n, double gap, double lb, int guard, int wedge)
{
    rbs_world *w = d->w;
    const rbs__soft_in *in = d->in;
    const rbs__pair *p = &w->pair[row];
    const double la = -w->radius[a];
    const double rest = p->e >= 0.0 ? p->e : w->def.restitution;
    const rbs__warm *m;
    double bias;
    v3 u, rv;
    uint32_t l;
    rbs__chunk *k = wedge ? rbs__chunker_wedge(&em->ch, ra, b, &l)
                          : rbs__chunker_place(&em->ch, ra, plane ? b : rb, plane, &l);
    if (k == NULL) {
        /* (the message is set by the step's thread, after the pass) */
        em->status = RBS_E_CAPACITY;
        return;
    }
    em->count++;
    k->nx[l] = n.x;
    k->ny[l] = n.y;
    k->nz[l] = n.z;
    k->lb[l] = lb;
    k->gap[l] = gap;
    k->row[l] = row;
    /* the approach at the frame's start (levers along n) */
    u = v3_sub(v3_scale(v3_load(&w->avel[3 * a]), la), v3_scale(v3_load(&w->avel[3 * b]), lb));
    rv = v3_add(v3_sub(v3_load(&w->vel[3 * a]), v3_load(&w->vel[3 * b])), v3_cross(u, n));
    bias = v3_dot(rv, n);
    k->eb[l] = rest * bias;
    if (rest > 0.0 && bias < 0.0 && bias < -threshold(d, a, b, n))
        k->flags |= 1u << (RBS__CH_BOUNCE + l);
    if (guard)
        k->flags |= 1u << (RBS__CH_GUARD + l);
    if (!plane && (w->fixed[a] || w->fixed[b]))
        k->flags |= 1u << RBS__CH_FIXED;
    if (in->h == 0.0) {
        /* def.soft_tolerance: how deep it can go within the frame, of its slop */
        double close = -bias * in->dt, rb = plane ? -la : w->radius[b];
        double q = ((close > 0.0 ? close : 0.0) - gap) / ((-la < rb ? -la : rb));
        if (!(q <= em->q))
            em->q = q; /* (a NaN stays, and keeps every sub-step) */
    }
    m = warm_of(w, rbs__warm_key_of(plane, a, b), plane, a);
    if (in->friction && p->mu_s > p->mu_k) {
        /* the slip it comes in with: more than kinetic friction stops in
         * the frame at the last frame's load (none: a new contact), and
         * only mu_k acts (rbs__friction_cap) */
        const v3 vt = v3_mad(rv, n, -bias);
        double kt = w->inv_mass[a] + la * la * w->iso_inv_inertia[a];
        if (!plane)
            kt += w->inv_mass[b] + lb * lb * w->iso_inv_inertia[b];
        if (kt > 0.0 && v3_len(vt) / kt > p->mu_k * (m != NULL ? m->n : 0.0) * in->dt)
            k->flags |= 1u << (RBS__CH_SLIP + l);
    }
    if (m != NULL) {
        v3 ft = in->friction ? v3_mad(m->t, n, -v3_dot(m->t, n)) : v3_make(0, 0, 0);
        if (m->n > 0.0)
            k->flags |= 1u << (RBS__CH_WARM + l);
        if (in->h == 0.0) {
            /* (the forces, until h is known) */
            k->jn[l] = m->n;
            k->jx[l] = ft.x;
            k->jy[l] = ft.y;
            k->jz[l] = ft.z;
        } else {
            lane_warm(k, l, in->friction, k->flags >> (RBS__CH_SLIP + l) & 1u ? p->mu_k : p->mu_s, m->n, ft,
                      in->h);
        }
    }
    /* (after the warm start's lookup: whether it came in loaded) */
    mark(d, ra, m != NULL && m->n > 0.0);
    if (!plane)
        mark(d, rb, m != NULL && m->n > 0.0);
}

/* A contact made by the general detection (the guards, the serial path)
 * into a lane of emitter em. */
static void lane_of_contact(const detect *d, emitter *em, const rbs__contact *c)
{
    const rbs_world *w = d->w;
    const int plane = w->type[c->b] == RBS_BODY_PLANE;
    lane_fill(d, em, w->soft_rank[w->item[c->a]], plane ? 0u : w->soft_rank[w->item[c->b]], c->a, c->b, plane, c->row,
              c->n, c->gap, c->lb, (c->flags & RBS__GUARD) != 0, 0);
}

/* ------------------------------------------------------------------------- */
/* Slabs                                                                     */
/* ------------------------------------------------------------------------- */

/* The axis to cut the slabs along: of the sides of the centres' box (lo,
 * hi) at least half as long as the longest (a cut across a short side
 * would cross many contacts), the one along which the spheres in slot order
 * jump least (jumps: prepared), the longest of those equal.  A slab is
 * then a few long runs of slots (a lattice made x fastest is cut along y:
 * each slab whole rows), so the frame's gather from the world's arrays in
 * slot order into the records in slab order streams instead of hopping --
 * cut along x, every slab took a run of a few spheres from each row of a
 * 300,000-sphere lattice, and the frame took 1.6x as long -- and each
 * thread's slabs are its own runs of the world's arrays.  jumps are counts,
 * the same whatever the threads, so the results do not depend on them. */
static uint32_t slab_axis(const double *lo, const double *hi, const uint32_t *jumps)
{
    uint32_t k, axis = 0, best = 3;
    for (k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    for (k = 0; k < 3; ++k)
        if (hi[k] - lo[k] >= 0.5 * (hi[axis] - lo[axis]) &&
            (best == 3 || jumps[k] < jumps[best] ||
             (jumps[k] == jumps[best] && hi[k] - lo[k] > hi[best] - lo[best])))
            best = k;
    return best < 3 ? best : axis; /* (a NaN side: the longest rule's) */
}

/* The cut's first pass, items [begin, end): each item's bin (in soft_slab
 * until the slabs are known) and the share's count of each bin (counted a
 * run at a time: consecutive items are mostly in one bin, and a count kept
 * in a register does not wait on its own last store). */
static void pass_bins(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    detect *d = (detect *)ctx;
    const double *C = d->centres, lo = d->cut_lo, scale = d->cut_scale;
    uint8_t *slab = d->w->soft_slab;
    uint32_t *hist = d->hist[share], i, cur = 0, run = 0;
    memset(hist, 0, sizeof d->hist[share]);
    for (i = begin; i < end; ++i) {
        double t = (C[3 * i + d->cut_axis] - lo) * scale;
        uint32_t b = t >= 1.0 ? (t < HIST_BINS ? (uint32_t)t : HIST_BINS - 1u) : 0u; /* (a NaN: bin 0) */
        slab[i] = (uint8_t)b;
        if (b != cur) {
            hist[cur] += run;
            cur = b;
            run = 0;
        }
        run++;
    }
    hist[cur] += run;
}

/* The second: items [begin, end) into their slabs, and their ranks -- the
 * slabs in order, each in item order: the share's first rank in each slab
 * follows the earlier shares' items there, so the ranks do not depend on
 * the split. */
static void pass_ranks(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    detect *d = (detect *)ctx;
    rbs_world *w = d->w;
    uint8_t *slab = w->soft_slab;
    uint32_t *next = d->next[share], i, cur, at;
    if (begin >= end)
        return;
    cur = d->bin_slab[slab[begin]];
    at = next[cur];
    for (i = begin; i < end; ++i) {
        const uint32_t sl = d->bin_slab[slab[i]];
        slab[i] = (uint8_t)sl;
        if (sl != cur) {
            next[cur] = at;
            cur = sl;
            at = next[sl];
        }
        w->soft_rank[i] = at;
        w->soft_order[at++] = i;
    }
}

/* Cut the items into g->slabs slabs of nearly equal counts along an axis
 * of their centres' box (lo, hi; slab_axis), on the world's threads: soft_slab
 * per item, soft_order the items slab by slab (in their order within each)
 * -- the order of the frame's records, so that a slab's are together in
 * memory -- and soft_rank each item's place in it; the axis.  One slab when
 * the box has no length (or is not finite).  (On the stepping thread
 * alone, the cut took 2 % of the 1,000 pile's frame on two threads: it
 * read the centres the other thread had written.) */
static uint32_t cut_slabs(detect *d)
{
    rbs_world *w = d->w;
    rbs__soft_groups *g = d->g;
    const uint32_t n = w->sphere_count, S = g->slabs;
    const uint32_t threads = rbs__team_threads(w), shares = threads < CUT_SHARES ? threads : CUT_SHARES;
    uint32_t start[RBS__SLABS_MAX + 1];
    uint32_t i, k, b, axis = slab_axis(d->lo, d->hi, d->jumps), below = 0;
    const double scale = HIST_BINS / (d->hi[axis] - d->lo[axis]);
    if (S == 1 || !(scale > 0.0) || !isfinite(scale)) {
        g->slabs = 1;
        for (i = 0; i < n; ++i) {
            w->soft_slab[i] = 0;
            w->soft_order[i] = w->soft_rank[i] = i;
        }
        g->slab_first[0] = 0;
        g->slab_first[1] = n;
        return axis;
    }
    d->cut_axis = axis;
    d->cut_lo = d->lo[axis];
    d->cut_scale = scale;
    /* (shares of at least one item: n >= 512 here) */
    rbs__team_run(w, pass_bins, d, n, shares);
    /* each bin to the slab of its middle item: slabs of nearly equal counts */
    memset(start, 0, sizeof start);
    for (b = 0; b < HIST_BINS; ++b) {
        uint32_t h = 0;
        uint64_t mid;
        for (k = 0; k < shares; ++k)
            h += d->hist[k][b];
        mid = 2u * (uint64_t)below + h;
        d->bin_slab[b] = (uint32_t)(mid * S / (2u * (uint64_t)n));
        below += h;
        start[d->bin_slab[b] + 1] += h;
    }
    for (k = 0; k < S; ++k)
        start[k + 1] += start[k];
    memcpy(g->slab_first, start, (S + 1) * sizeof *start);
    /* each share's first rank in each slab */
    for (k = 0; k < shares; ++k) {
        memcpy(d->next[k], start, S * sizeof *start);
        for (b = 0; b < HIST_BINS; ++b)
            start[d->bin_slab[b]] += d->hist[k][b];
    }
    rbs__team_run(w, pass_ranks, d, n, shares);
    return axis;
}

/* ------------------------------------------------------------------------- */
/* Before the passes                                                         */
/* ------------------------------------------------------------------------- */

/* Items [begin, end): each sphere's accelerations (into the table, when
 * there is one) and margin -- how far it may move within the frame,
 * |v| dt + |a| dt^2 (0 for a fixed sphere or one not finite) -- its reach
 * for the broad phase, and the share's box, sizes and slack. */
static void pass_prepare(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    detect *d = (detect *)ctx;
    rbs_world *w = d->w;
    const rbs__soft_in *in = d->in;
    const int keep = w->vl_valid && w->vl_items == w->sphere_count;
    /* (the share's running values in locals, stored once at the end: kept
     * in d->prep, each step of each waited on the store of the last) */
    prepared p;
    uint32_t k, c;
    for (c = 0; c < 3; ++c) {
        p.lo[c] = INFINITY;
        p.hi[c] = -INFINITY;
    }
    p.size = p.rmax = p.rsum = 0.0;
    p.slack = INFINITY;
    p.jumps[0] = p.jumps[1] = p.jumps[2] = 0;
    for (k = begin; k < end; ++k) {
        const uint32_t a = w->spheres[k];
        double margin, reach;
        v3 acc, tau;
        rbs__accelerations(w, a, &acc, &tau);
        if (in->acc != NULL) {
            v3_store(&in->acc[6 * a], acc);
            v3_store(&in->acc[6 * a + 3], tau);
        }
        margin = rbs__sweep_margin(w, a, acc, in->dt);
        in->margin[a] = margin;
        if (d->centres == w->bp_center)
            memcpy(&w->bp_center[3 * k], &w->pos[3 * a], 3 * sizeof(double));
        reach = rbs__sphere_reach(w, a, margin);
        w->bp_reach[k] = reach;
        p.rsum += w->radius[a];
        p.rmax = reach > p.rmax ? reach : p.rmax;
        for (c = 0; c < 3; ++c) {
            const double x = d->centres[3 * k + c];
            p.lo[c] = x < p.lo[c] ? x : p.lo[c];
            p.hi[c] = x > p.hi[c] ? x : p.hi[c];
            p.size = fabs(x) > p.size ? fabs(x) : p.size;
            /* (from the world's positions: another share may be copying
             * the last sphere's centre right now) */
            if (k > 0)
                p.jumps[c] += fabs(w->pos[3 * a + c] - w->pos[3 * w->spheres[k - 1] + c]) > w->radius[a];
        }
        if (keep) {
            const double x = rbs__broadphase_slack(w, d->centres, k);
            if (!(x >= p.slack))
                p.slack = x; /* (a NaN stays) */
        }
    }
    memcpy(d->prep[share].lo, p.lo, sizeof p.lo);
    memcpy(d->prep[share].hi, p.hi, sizeof p.hi);
    memcpy(d->prep[share].jumps, p.jumps, sizeof p.jumps);
    d->prep[share].size = p.size;
    d->prep[share].rmax = p.rmax;
    d->prep[share].rsum = p.rsum;
    d->prep[share].slack = p.slack;
}

/* ------------------------------------------------------------------------- */
/* The two passes                                                            */
/* ------------------------------------------------------------------------- */

/* Whether a candidate pair of items i, j is a contact of the frame (the
 * broad phase's test with the sweeps' reaches; a pair of fixed spheres is
 * none): fixed_i, whether i's sphere is fixed (j's is read only then). */
static inline int pair_is_contact(const detect *d, const double *C, const double *R, uint32_t i, uint32_t j,
                                  int fixed_i)
{
    const double ex = C[3 * i] - C[3 * j], ey = C[3 * i + 1] - C[3 * j + 1], ez = C[3 * i + 2] - C[3 * j + 2];
    const double sr = R[i] + R[j];
    return (ex * ex + ey * ey + ez * ez <= sr * sr) & !(fixed_i && d->w->fixed[d->w->spheres[j]]);
}

/* The gap of sphere a to plane p, and whether it is a contact (within the
 * slop and the sphere's margin). */
static inline int plane_is_contact(const detect *d, uint32_t a, uint32_t p, double *gap)
{
    const rbs_world *w = d->w;
    double ra = w->radius[a];
    *gap = v3_dot(v3_sub(v3_load(&w->pos[3 * a]), v3_load(&w->pos[3 * p])), v3_load(&w->normal[3 * p])) - ra;
    return *gap <= w->def.slop * ra + d->in->margin[a];
}

/* Sphere a (record x) in contact with two planes or more (bits: the first
 * pass's, as in the leaf): the first two, in the planes' order, whose
 * normals make a wedge (n1.n2 < RBS__WEDGE_COS), emitted as one into a
 * wedges' chunk, and their indices into *wq, *wr (else both UINT32_MAX).
 * A pile's spheres against a box's floor and walls meet none (their
 * normals are square). */
static void wedge_planes(const detect *d, emitter *em, uint32_t x, uint32_t a, unsigned bits, uint32_t *wq,
                         uint32_t *wr)
{
    const rbs_world *w = d->w;
    uint32_t q, r;
    double gq, gr;
    for (q = 0; q < w->plane_count; ++q) {
        const uint32_t pq = w->planes[q];
        if ((q < 8 && !(bits >> q & 1u)) || !plane_is_contact(d, a, pq, &gq))
            continue;
        for (r = q + 1; r < w->plane_count; ++r) {
            const uint32_t pr = w->planes[r];
            if ((r < 8 && !(bits >> r & 1u)) ||
                !(v3_dot(v3_load(&w->normal[3 * pq]), v3_load(&w->normal[3 * pr])) < RBS__WEDGE_COS) ||
                !plane_is_contact(d, a, pr, &gr))
                continue;
            lane_fill(d, em, x, 0u, a, pq, 1, rbs__pair_row(w, a, pq), v3_load(&w->normal[3 * pq]), gq, 0.0, 0, 1);
            lane_fill(d, em, x, 0u, a, pr, 1, rbs__pair_row(w, a, pr), v3_load(&w->normal[3 * pr]), gr, 0.0, 0, 1);
            *wq = q;
            *wr = r;
            return;
        }
    }
}

/* The first pass over slab s's records: each group's count; each sphere's
 * planes in contact, as bits in soft_planes (0xFF for all: more than 8
 * planes are tested again); and the candidate pairs that are contacts in
 * the slab's run of soft_aside: those within the slab in order from its
 * start (listed), those to other slabs from its end backwards (crossed) --
 * a node's emission then reads only the few that can be its own; and its
 * records' kick sums zeroed for the emission. */
static void pass_count(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    detect *d = (detect *)ctx;
    rbs_world *w = d->w;
    const rbs__soft_groups *g = d->g;
    const uint8_t *slab = w->soft_slab;
    uint32_t s, x, k, q;
    (void)share;
    for (s = begin; s < end; ++s) {
        uint32_t *count = d->count[s], *list = &w->soft_aside[d->slab_pairs[s]], put = 0, cross = 0;
        uint32_t *back = &w->soft_aside[d->slab_pairs[s + 1]];
        /* (the slab's records' kick sums, for the emission, each level's) */
        for (k = 0; k < g->levels; ++k)
            memset(d->in->scratch + (size_t)k * w->def.max_bodies + g->slab_first[s], 0,
                   (size_t)(g->slab_first[s + 1] - g->slab_first[s]) * sizeof(double));
        const uint32_t leaf = g->level_first[0] + s;
        /* (the candidate list's arrays, and the leaf's count, in locals:
         * stored through a uint32_t pointer, vl_start's end and the count
         * were read again for every pair) */
        const uint32_t *vl_start = w->vl_start, *vl_pair = w->vl_pair;
        const double *C = d->centres, *R = w->bp_reach;
        uint32_t own = 0;
        memset(count, 0, sizeof d->count[s]);
        for (x = g->slab_first[s]; x < g->slab_first[s + 1]; ++x) {
            const uint32_t i = w->soft_order[x], a = w->spheres[i];
            const uint32_t k_end = d->pairs ? vl_start[i + 1] : 0;
            const int fixed_a = w->fixed[a] != 0;
            unsigned bits = 0;
            double gap;
            if (!fixed_a)
                for (q = 0; q < w->plane_count; ++q)
                    if (plane_is_contact(d, a, w->planes[q], &gap)) {
                        bits |= q < 8 ? 1u << q : 0xFFu;
                        own++;
                    }
            w->soft_planes[x] = (uint8_t)bits;
            for (k = d->pairs ? vl_start[i] : 0; k < k_end; ++k) {
                const uint32_t j = vl_pair[2 * k + 1];
                const uint32_t hit = (uint32_t)pair_is_contact(d, C, R, i, j, fixed_a);
                const uint32_t here = hit & (uint32_t)(slab[j] == s);
                /* a contact within the slab: listed without a branch (the
                 * slot after the listed ones is free whether or not it is
                 * one: the crossed ones, from the end, are fewer than the
                 * pairs not yet listed); one to another slab (a few in a
                 * hundred) aside */
                list[put] = k;
                put += here;
                if (hit != here) {
                    count[group_of(d, s, slab[j], i, j)]++;
                    *--back = k;
                    cross++;
                }
            }
        }
        count[leaf] += own + put;
        d->listed[s] = put;
        d->crossed[s] = cross;
    }
}

/* The contact of candidate pair k (items i < j) into emitter em, its kicks
 * into its level's sums (as contact.c's detect_pair and rbs__pair_contact
 * make it). */
static void emit_pair(const detect *d, emitter *em, uint32_t k)
{
    const rbs_world *w = d->w;
    const uint32_t i = w->vl_pair[2 * k], j = w->vl_pair[2 * k + 1], a = w->spheres[i], b = w->spheres[j];
    const uint32_t ra = w->soft_rank[i], rb = w->soft_rank[j];
    const v3 dv = v3_sub(v3_load(&w->pos[3 * a]), v3_load(&w->pos[3 * b]));
    const double dist = v3_len(dv);
    double gap, lb;
    v3 n;
    if (dist > 0.0) {
        double u = rbs__kick_speed(w, a, b, dv, dist);
        if (u != 0.0) {
            const double ka = em->kick[ra] += 2.0 * w->inv_mass[a] * u;
            const double kb = em->kick[rb] += 2.0 * w->inv_mass[b] * u;
            if (!(ka <= em->kick_max))
                em->kick_max = ka;
            if (!(kb <= em->kick_max))
                em->kick_max = kb;
        }
    }
    /* (apart: the normal of the touch on the straight paths) */
    rbs__pair_touch(w, a, b, dv, dist, d->in->dt, 1, &n, &gap, &lb);
    lane_fill(d, em, ra, rb, a, b, 0, rbs__pair_row(w, a, b), n, gap, lb, 0, 0);
}

/* The second pass: items [begin, end) of emit_group, each a group's
 * contacts into its run of chunks. */
static void pass_emit(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    detect *d = (detect *)ctx;
    rbs_world *w = d->w;
    rbs__soft_groups *g = d->g;
    const uint8_t *slab = w->soft_slab;
    uint32_t item;
    (void)share;
    for (item = begin; item < end; ++item) {
        const uint32_t gk = d->emit_group[item];
        emitter *em = &d->em[gk];
        const uint32_t l = level_of(g, gk), node = gk - g->level_first[l];
        uint32_t s, x, k, q, s_lo, s_hi;
        rbs__soft_group_slabs(g, gk, &s_lo, &s_hi);
        rbs__chunker_start(&em->ch, &w->chunk[g->first[gk]], RBS__GROUP_CHUNKS(g->used[gk]),
                           &w->chunk_member[(size_t)l * w->def.max_bodies]);
        em->count = 0;
        em->q = 0.0;
        em->kick = d->in->scratch + (size_t)l * w->def.max_bodies;
        em->kick_max = 0.0;
        em->status = RBS_OK;
        if (l == 0) {
            /* a leaf: its slab's planes and pairs, sphere by sphere */
            const uint32_t *list = &w->soft_aside[d->slab_pairs[node]];
            uint32_t at = 0;
            s = node;
            for (x = g->slab_first[s]; x < g->slab_first[s + 1] && em->status == RBS_OK; ++x) {
                const uint32_t i = w->soft_order[x], a = w->spheres[i];
                const unsigned bits = w->soft_planes[x];
                uint32_t wq = UINT32_MAX, wr = UINT32_MAX;
                double gap;
                if (bits & (bits - 1u))
                    /* two planes or more: a wedge's pair first (wedge_planes) */
                    wedge_planes(d, em, x, a, bits, &wq, &wr);
                for (q = 0; bits != 0 && q < w->plane_count; ++q) {
                    const uint32_t pl = w->planes[q];
                    /* (the first pass's bit says; the test gives the gap) */
                    if (q == wq || q == wr || (q < 8 && !(bits >> q & 1u)) || !plane_is_contact(d, a, pl, &gap))
                        continue;
                    lane_fill(d, em, x, 0u, a, pl, 1, rbs__pair_row(w, a, pl), v3_load(&w->normal[3 * pl]), gap,
                              0.0, 0, 0);
                }
                for (; at < d->listed[s] && w->vl_pair[2 * list[at]] == i; ++at)
                    emit_pair(d, em, list[at]);
            }
        } else {
            /* a node: the pairs its slabs listed that are its own */
            for (s = s_lo; s < s_hi && s < g->slabs; ++s) {
                const uint32_t *back = &w->soft_aside[d->slab_pairs[s + 1]];
                for (x = 1; x <= d->crossed[s]; ++x) {
                    const uint32_t j = w->vl_pair[2 * (k = back[-(ptrdiff_t)x]) + 1];
                    if (group_of(d, s, slab[j], w->vl_pair[2 * k], j) == gk)
                        emit_pair(d, em, k);
                }
            }
        }
        rbs__chunker_finish(&em->ch);
        g->used[gk] = em->ch.used;
    }
}

/* The guards' sink (rbs__detect_guards): into the guards' group. */
static rbs_status emit_guard(void *ctx, const rbs__contact *c)
{
    detect *d = (detect *)ctx;
    emitter *em = &d->em[d->g->level_first[d->g->levels]];
    lane_of_contact(d, em, c);
    if (em->status != RBS_OK)
        return (rbs_status)rbs__world_set_error(d->w, em->status, "the soft step's contact chunks are full");
    return RBS_OK;
}

/* The serial detection's sink: into the one group. */
static rbs_status emit_serial(void *ctx, const rbs__contact *c)
{
    detect *d = (detect *)ctx;
    lane_of_contact(d, &d->em[0], c);
    if (d->em[0].status != RBS_OK)
        return (rbs_status)rbs__world_set_error(d->w, d->em[0].status, "the soft step's contact chunks are full");
    return RBS_OK;
}

/* A frame whose contacts do not fit the groups' way (more than max_contacts,
 * or candidate pairs beyond the list): the general detection, serially, into
 * one group (its kicks and guards included). */
static rbs_status detect_serially(detect *d)
{
    rbs_world *w = d->w;
    rbs__soft_groups *g = d->g;
    emitter *em = &d->em[0];
    rbs_status st;
    g->slabs = 1;
    g->levels = 1;
    g->level_first[0] = 0;
    g->level_first[1] = 1; /* (the guards' group: empty) */
    g->level_first[2] = 2;
    g->first[0] = 0;
    g->used[0] = 0;
    g->first[1] = 0;
    g->used[1] = 0;
    g->slab_first[0] = 0;
    g->slab_first[1] = w->sphere_count;
    (void)cut_slabs(d);
    rbs__chunker_start(&em->ch, w->chunk, w->chunk_cap, w->chunk_member);
    em->count = 0;
    em->q = 0.0;
    em->status = RBS_OK;
    st = rbs__detect_swept(w, d->in->dt, d->in->margin, d->in->acc, d->in->scratch, emit_serial, d);
    rbs__chunker_finish(&em->ch);
    g->used[0] = em->ch.used;
    g->first[1] = em->ch.used;
    g->contacts = em->count;
    g->q = em->q;
    return st;
}

/* ------------------------------------------------------------------------- */
/* The frame                                                                 */
/* ------------------------------------------------------------------------- */

rbs_status rbs__soft_detect(rbs_world *w, const rbs__soft_in *in, rbs__soft_groups *g)
{
    const uint32_t n = w->sphere_count, B = w->def.max_bodies, threads = rbs__team_threads(w);
    uint32_t S = rbs__slabs_for(B, n), i, k, s, total, groups, guard;
    detect d;
    double *kick_sum;
    int kicked = 0;
    rbs_status st = RBS_OK;

    if (!w->warm_indexed)
        warm_index(w);
    d.w = w;
    d.in = in;
    d.g = g;
    d.thr_shared = rbs__resting_threshold(in->shared_a, in->shared_a, v3_make(0, 0, 1), in->dt);
    d.threads = threads > 1u;
    w->contact_count = 0;
    /* the spheres' centres (in place when they hold consecutive slots),
     * margins and reaches, their box, and the candidate list */
    d.centres = w->plan.consecutive && n > 0 ? &w->pos[3 * w->spheres[0]] : w->bp_center;
    if (in->acc != NULL)
        for (i = 0; i < w->plane_count; ++i)
            memset(&in->acc[6 * w->planes[i]], 0, 6 * sizeof(double));
    rbs__team_run(w, pass_prepare, &d, n, threads);
    {
        double size = 0.0, rmax = 0.0, rsum = 0.0, slack = INFINITY;
        uint32_t c;
        for (c = 0; c < 3; ++c) {
            d.lo[c] = INFINITY;
            d.hi[c] = -INFINITY;
        }
        d.jumps[0] = d.jumps[1] = d.jumps[2] = 0;
        for (k = 0; k < (n < threads ? n : threads); ++k) {
            const prepared *p = &d.prep[k];
            for (c = 0; c < 3; ++c)
                d.jumps[c] += p->jumps[c];
            for (c = 0; c < 3; ++c) {
                d.lo[c] = p->lo[c] < d.lo[c] ? p->lo[c] : d.lo[c];
                d.hi[c] = p->hi[c] > d.hi[c] ? p->hi[c] : d.hi[c];
            }
            size = p->size > size ? p->size : size;
            rmax = p->rmax > rmax ? p->rmax : rmax;
            rsum += p->rsum;
            if (!(p->slack >= slack))
                slack = p->slack;
        }
        g->slabs = S;
        d.pairs = w->plan.sphere_pairs;
        if (d.pairs && n >= 2 && !rbs__broadphase_keep(w, n, size, rmax, slack)) {
            /* the grid's working arrays in the chunks' room: the last
             * frame's chunks are stored (the warm start) and this frame's
             * come after the list (pages the chunks touch anyway, not the
             * world's own grid arrays: 40 bytes a sphere less resident) */
            rbs__grid_mem m;
            const int room = rbs__grid_mem_in(w, w->chunk, (size_t)w->chunk_cap * sizeof(rbs__chunk), n, &m);
            if (!rbs__broadphase_build(w, room ? &m : NULL, d.centres, n, w->def.slop, size, rmax, rsum))
                return detect_serially(&d);
        }
    }

    /* slabs, the tree's levels and its groups, the guards' group last */
    {
        const uint32_t axis = cut_slabs(&d);
        const uint32_t u = (axis + 1u) % 3u, v = (axis + 2u) % 3u;
        d.side_axis = d.hi[v] - d.lo[v] > d.hi[u] - d.lo[u] ? v : u;
        d.side_mid = 0.5 * (d.lo[d.side_axis] + d.hi[d.side_axis]);
    }
    S = g->slabs;
    d.tree = rbs__slab_levels(S);
    /* the tree's levels, the top's as two groups and a tie level above it
     * (with more than one slab) */
    g->levels = d.tree + (S > 1);
    for (k = 0, groups = 0; k < d.tree; ++k) {
        g->level_first[k] = groups;
        groups += S > 1 && k + 1 == d.tree ? 2u : S >> k;
    }
    if (S > 1)
        g->level_first[k++] = groups++;
    g->level_first[g->levels] = groups;
    guard = groups++;
    g->level_first[g->levels + 1] = groups;
    /* the emission's order: the tree in order (leaf 0, the node between
     * leaves 0 and 1, leaf 1, ...; the top as its first group, the tie's,
     * its second), so that the threads' even shares of it are each about
     * a run of slabs with the nodes among them */
    for (s = 0, k = 0; s < S; ++s) {
        uint32_t a = s, l;
        d.emit_group[k++] = g->level_first[0] + s;
        if (s + 1 == S)
            break;
        l = tree_meet(&a, s + 1);
        if (l + 1 < d.tree) {
            d.emit_group[k++] = g->level_first[l] + a;
        } else {
            d.emit_group[k++] = g->level_first[l];
            d.emit_group[k++] = g->level_first[l + 1];
            d.emit_group[k++] = g->level_first[l] + 1u;
        }
    }
    for (s = 0; s < S; ++s) {
        uint32_t pairs = 0, x;
        for (x = g->slab_first[s]; d.pairs && x < g->slab_first[s + 1]; ++x)
            pairs += w->vl_start[w->soft_order[x] + 1] - w->vl_start[w->soft_order[x]];
        d.slab_pairs[s + 1] = pairs;
    }
    d.slab_pairs[0] = 0;
    for (s = 0; s < S; ++s)
        d.slab_pairs[s + 1] += d.slab_pairs[s];

    /* first pass: the counts, and each group its run of chunks */
    rbs__team_run(w, pass_count, &d, S, threads);
    total = 0;
    for (k = 0; k < guard; ++k) {
        uint32_t c = 0;
        for (s = 0; s < S; ++s)
            c += d.count[s][k];
        g->first[k] = k == 0 ? 0 : g->first[k - 1] + RBS__GROUP_CHUNKS(g->used[k - 1]);
        g->used[k] = c; /* (its contacts, until the second pass) */
        total += c;
    }
    g->first[guard] = g->first[guard - 1] + RBS__GROUP_CHUNKS(g->used[guard - 1]);
    if (total > w->def.max_contacts || g->first[guard] > w->chunk_cap)
        return detect_serially(&d);

    /* second pass: the contacts into their groups' chunks */
    rbs__team_run(w, pass_emit, &d, guard, threads);
    g->q = 0.0;
    g->contacts = 0;
    for (k = 0; k < guard; ++k) {
        if (d.em[k].status != RBS_OK && st == RBS_OK)
            st = d.em[k].status;
        if (!(d.em[k].q <= g->q))
            g->q = d.em[k].q;
        g->contacts += d.em[k].count;
    }
    w->contact_count = g->contacts;
    if (w->contact_count > w->contacts_high)
        w->contacts_high = w->contact_count;
    g->used[guard] = 0;
    if (st != RBS_OK)
        return (rbs_status)rbs__world_set_error(w, st, "the soft step's contact chunks are full (%u contacts)",
                                                (unsigned)g->contacts);

    /* the guards: each sphere's kicks, the levels summed in order, and the
     * second pass of the swept detection for those kicked far enough */
    /* (skipped when no sphere can be kicked far enough: a sphere's sum,
     * over the levels in order, is at most the sum of each level's largest,
     * non-negative terms added in the same order -- rounding is monotonic) */
    kick_sum = in->scratch + (size_t)g->levels * B;
    {
        double bound = 0.0;
        int may = 0;
        uint32_t l;
        for (l = 0; l < g->levels; ++l) {
            double most = 0.0;
            for (k = g->level_first[l]; k < g->level_first[l + 1]; ++k)
                if (!(d.em[k].kick_max <= most))
                    most = d.em[k].kick_max;
            bound += most;
        }
        may = !(bound * in->dt <= RBS__GUARD_DEPTH * w->plan.min_radius); /* (a NaN: may) */
        for (k = 0; may && k < n; ++k) {
            uint32_t a = w->spheres[k], r = w->soft_rank[k];
            double sum = 0.0;
            for (l = 0; l < g->levels; ++l)
                sum += in->scratch[(size_t)l * B + r];
            kick_sum[a] = sum;
            kicked |= !w->fixed[a] && sum * in->dt > RBS__GUARD_DEPTH * w->plan.min_radius;
        }
    }
    if (kicked) {
        emitter *em = &d.em[guard];
        rbs__chunker_start(&em->ch, &w->chunk[g->first[guard]], w->chunk_cap - g->first[guard],
                           &w->chunk_member[(size_t)g->levels * B]);
        em->count = 0;
        em->q = 0.0;
        em->status = RBS_OK;
        st = rbs__detect_guards(w, in->dt, in->margin, in->acc, kick_sum, emit_guard, &d);
        rbs__chunker_finish(&em->ch);
        g->used[guard] = em->ch.used;
        g->contacts += em->count;
        if (!(em->q <= g->q))
            g->q = em->q;
    }
    return st;
}

/* ------------------------------------------------------------------------- */
/* After detection                                                           */
/* ------------------------------------------------------------------------- */

void rbs__soft_warm_h(rbs_world *w, const rbs__soft_groups *g, int friction, double h)
{
    uint32_t k, i, l;
    for (k = 0; k < g->level_first[g->levels + 1]; ++k)
        for (i = g->first[k]; i < g->first[k] + g->used[k]; ++i) {
            rbs__chunk *c = &w->chunk[i];
            for (l = 0; l < c->count; ++l)
                lane_warm(c, l, friction,
                          c->flags >> (RBS__CH_SLIP + l) & 1u ? w->pair[c->row[l]].mu_k : w->pair[c->row[l]].mu_s,
                          c->jn[l], v3_make(c->jx[l], c->jy[l], c->jz[l]), h);
        }
}

/* Lane l of chunk c: whether b is a plane. */
static inline int lane_plane(const rbs__chunk *c, uint32_t l)
{
    return (c->flags >> (RBS__CH_PLANE + l) & 1u) != 0;
}

/* Share q of the store: its records [*r0, *r1) (their spheres' buckets
 * are its own), and how each group takes part (take[k]: 0 not at all -- no
 * slab of the share's; 1 whole -- only the share's slabs; 2 lane by lane,
 * those whose sphere a is one of its records); the groups. */
enum { STORE_NONE, STORE_WHOLE, STORE_LANES };
static uint32_t store_share(const rbs__soft_store *st, uint32_t q, uint32_t *r0, uint32_t *r1, uint8_t *take)
{
    const rbs__soft_groups *g = st->g;
    const uint32_t S = g->slabs, groups = g->level_first[g->levels + 1];
    const uint32_t s0 = (uint32_t)((uint64_t)q * S / st->shares), s1 = (uint32_t)((uint64_t)(q + 1u) * S / st->shares);
    uint32_t k, lo, hi;
    *r0 = g->slab_first[s0];
    *r1 = g->slab_first[s1];
    for (k = 0; k < groups; ++k) {
        rbs__soft_group_slabs(g, k, &lo, &hi);
        take[k] = s0 == s1 || hi <= s0 || lo >= s1 ? STORE_NONE : lo >= s0 && hi <= s1 ? STORE_WHOLE : STORE_LANES;
    }
    return groups;
}

/* Whether lane l of chunk c, of a group that takes part as take, is the
 * share's (records [r0, r1)). */
static inline int store_lane(const rbs__chunk *c, uint32_t l, uint8_t take, uint32_t r0, uint32_t r1)
{
    return take == STORE_WHOLE || (c->a[l] >= r0 && c->a[l] < r1);
}

void rbs__soft_store_start(rbs__soft_store *st, rbs_world *w, const rbs__soft_groups *g, double h,
                           uint32_t *scratch, uint32_t shares)
{
    st->w = w;
    st->g = g;
    st->cursor = scratch;
    st->h = h;
    st->shares = shares < 1u ? 1u : shares > RBS__STORE_SHARES ? RBS__STORE_SHARES : shares;
}

/* The first half, share q: each of its buckets' entries counted (bucket
 * 2 r + 1 of record r: its pairs; 2 r: its planes), and its lanes holding
 * a normal impulse. */
void rbs__soft_store_count(rbs__soft_store *st, uint32_t q)
{
    uint8_t take[RBS__GROUPS_MAX];
    uint32_t r0, r1, k, l, entries = 0, resting = 0;
    const uint32_t groups = store_share(st, q, &r0, &r1, take);
    memset(&st->cursor[2u * r0], 0, 2u * (size_t)(r1 - r0) * sizeof *st->cursor);
    for (k = 0; k < groups; ++k) {
        const rbs__chunk *c = &st->w->chunk[st->g->first[k]], *end = c + st->g->used[k];
        for (; take[k] != STORE_NONE && c < end; ++c)
            for (l = 0; l < c->count; ++l)
                if (store_lane(c, l, take[k], r0, r1)) {
                    resting += c->jn[l] > 0.0;
                    if (c->jn[l] != 0.0) {
                        st->cursor[2u * c->a[l] + !lane_plane(c, l)]++;
                        entries++;
                    }
                }
    }
    st->entries[q] = entries;
    st->resting[q] = resting;
}

/* The second half, share q (every share's count done): its buckets from
 * the end of the shares' before it, their entries, and warm_at of its
 * spheres.  Rates: the impulses over h. */
void rbs__soft_store_place(rbs__soft_store *st, uint32_t q)
{
    rbs_world *w = st->w;
    rbs__warm *t = w->warm;
    uint8_t take[RBS__GROUPS_MAX];
    uint32_t r0, r1, r, k, l, at = 0;
    const uint32_t groups = store_share(st, q, &r0, &r1, take);
    for (k = 0; k < q; ++k)
        at += st->entries[k];
    for (r = r0; r < r1; ++r) {
        const uint32_t a = w->spheres[w->soft_order[r]];
        for (k = 0; k < 2u; ++k) {
            const uint32_t n = st->cursor[2u * r + k];
            w->warm_at[2u * a + k] = n > 0 ? at : UINT32_MAX;
            st->cursor[2u * r + k] = at;
            at += n;
        }
    }
    for (k = 0; k < groups; ++k) {
        const rbs__chunk *c = &w->chunk[st->g->first[k]], *end = c + st->g->used[k];
        for (; take[k] != STORE_NONE && c < end; ++c)
            for (l = 0; l < c->count; ++l)
                if (c->jn[l] != 0.0 && store_lane(c, l, take[k], r0, r1)) {
                    const int plane = lane_plane(c, l);
                    rbs__warm *e = &t[st->cursor[2u * c->a[l] + !plane]++];
                    e->key = rbs__warm_key_of(plane, w->spheres[w->soft_order[c->a[l]]],
                                              plane ? c->b[l] : w->spheres[w->soft_order[c->b[l]]]);
                    e->n = c->jn[l] / st->h;
                    e->t = v3_scale(v3_make(c->jx[l], c->jy[l], c->jz[l]), 1.0 / st->h);
                }
    }
}

uint32_t rbs__soft_store_finish(rbs__soft_store *st)
{
    uint32_t q, entries = 0, resting = 0;
    for (q = 0; q < st->shares; ++q) {
        entries += st->entries[q];
        resting += st->resting[q];
    }
    st->w->warm_used = entries;
    st->w->warm_ranked = 1;
    st->w->warm_indexed = 1;
    return resting;
}
