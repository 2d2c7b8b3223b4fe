/*
 * soft_detect.h - the soft step's detection in the gathered layout: slabs,
 * groups and their chunks (internal; soft_detect.c).
 */
#ifndef RBS_CORE_SOFT_DETECT_H
#define RBS_CORE_SOFT_DETECT_H

#include "core/soft_chunks.h"

#define RBS__SLAB_SPHERES 256 /* spheres a slab at the least */
#define RBS__SLABS_MAX 16
#define RBS__LEVELS_MAX 6     /* levels of a tree of RBS__SLABS_MAX slabs, and
                                 the tie level (soft_detect.c) */
#define RBS__GROUPS_MAX (2 * RBS__SLABS_MAX + 2) /* 2 S - 1 groups, the top's
                                                    second, the tie's and the
                                                    guards' */

/* The most slabs of a world of max_bodies B: a power of two, one for every
 * RBS__SLAB_SPHERES bodies, at most RBS__SLABS_MAX (capacity: the chunks
 * a world reserves depend on it). */
static inline uint32_t rbs__slabs_max(uint32_t B)
{
    uint32_t s = 1;
    while (2u * s <= RBS__SLABS_MAX && 2u * s * RBS__SLAB_SPHERES <= B)
        s *= 2u;
    return s;
}
/* The slabs of a frame of n spheres in a world of max_bodies B: the most,
 * halved while a slab would hold fewer than RBS__SLAB_SPHERES. */
static inline uint32_t rbs__slabs_for(uint32_t B, uint32_t n)
{
    uint32_t s = rbs__slabs_max(B);
    while (s > 1u && s * RBS__SLAB_SPHERES > n)
        s /= 2u;
    return s;
}
/* Levels of the slab tree of s slabs (log2 s + 1). */
static inline uint32_t rbs__slab_levels(uint32_t s)
{
    uint32_t l = 1;
    while (s > 1u) {
        s /= 2u;
        l++;
    }
    return l;
}
/* Chunks a frame of at most C contacts takes in a world of max_bodies B:
 * each of its 2 S + 2 groups a part-full chunk for every lane short of four
 * and its chunkers' part-full ones (RBS__GROUP_CHUNKS). */
#define RBS__SOFT_CHUNKS(C, B) (((C) + 3u) / 4u + (2u * rbs__slabs_max(B) + 2u) * (RBS__GROUP_CHUNKS(0) + 1u))

/* What detection reads and fills besides the world. */
typedef struct rbs__soft_in {
    double *margin;       /* per slot, out: how far the body may move in the
                             frame, m */
    double *acc;          /* per slot, 6 doubles, out: acceleration and torque
                             (zero for a plane); or NULL: shared_a for every
                             moving sphere */
    v3 shared_a;
    double dt;
    double h;             /* the sub-step, s; 0 while it is not known
                             (def.soft_tolerance): the warm starts are then
                             the last frame's forces, for rbs__soft_warm_h */
    int friction;
    uint8_t *touched;     /* per slot, zero on entry: bit 0 for a body in a
                             contact, RBS__LOADED_ONE in one that came in
                             loaded, with RBS__LOADED_MORE in more (soft.h) */
    double *scratch;      /* per slot, RBS__LEVELS_MAX + 1 doubles (the records'
                             room, free during detection) */
} rbs__soft_in;

/* The frame's slabs and groups (soft_detect.c).  Group g's chunks are
 * w->chunk[first[g] .. first[g] + used[g] - 1], taken in that order; the
 * groups of one level share no body, and are taken after the levels below
 * them; the guards' group last.  Slab s's items (indexes into w->spheres)
 * are w->soft_order[slab_first[s] .. slab_first[s + 1] - 1]. */
typedef struct rbs__soft_groups {
    uint32_t slabs, levels;
    uint32_t level_first[RBS__LEVELS_MAX + 2]; /* level l's groups start at
                                                  level_first[l]; then the
                                                  guards' group, then the end */
    uint32_t first[RBS__GROUPS_MAX], used[RBS__GROUPS_MAX];
    uint32_t slab_first[RBS__SLABS_MAX + 1];
    uint32_t contacts;    /* contacts of the frame */
    double q;             /* h 0: the deepest reachable overlap, of its pair's
                             slop (a NaN keeps every sub-step) */
} rbs__soft_groups;

/* The frame's contacts into chunks, on the world's threads (team.h; started
 * by the caller). */
rbs_status rbs__soft_detect(rbs_world *w, const rbs__soft_in *in, rbs__soft_groups *g);
/* The warm starts (stored as forces: in->h was 0) for sub-steps of h. */
void rbs__soft_warm_h(rbs_world *w, const rbs__soft_groups *g, int friction, double h);
/* Group k's slabs: [*lo, *hi) (a node of the tree below the top: its
 * subtree's; the top's two groups, the tie's and the guards': all). */
void rbs__soft_group_slabs(const rbs__soft_groups *g, uint32_t k, uint32_t *lo, uint32_t *hi);

/* The warm store: the frame's impulses into the warm-start table, as rates
 * for the next frame (h: the sub-step), in buckets -- a bucket for each
 * sphere's contacts with planes and one for those with spheres, the
 * buckets in the order of the frame's records (slab by slab), each one's
 * entries in the order of the groups -- with w->warm_at their index by
 * slot, which the next frame's detection searches (soft_detect.c,
 * warm_of).  The table is the same whatever the threads.  In shares: share
 * q of `shares` (at most RBS__STORE_SHARES) stores the contacts of the
 * spheres of slabs [q S / shares, (q + 1) S / shares) -- those of a thread
 * whose leaves are these slabs, in its own cache.  rbs__soft_store_count
 * counts a share's buckets into the scratch (2 words a sphere, left alone
 * by the caller until the store is finished) and changes nothing of the
 * world: it may run before the step knows it will succeed; every share's
 * count, then every share's place, then rbs__soft_store_finish, which
 * returns the lanes holding a normal impulse. */
#define RBS__STORE_SHARES 8
typedef struct rbs__soft_store {
    rbs_world *w;
    const rbs__soft_groups *g;
    uint32_t *cursor;  /* the scratch: each bucket's count, then where its
                          next entry goes */
    double h;
    uint32_t shares;
    uint32_t entries[RBS__STORE_SHARES];  /* each share's */
    uint32_t resting[RBS__STORE_SHARES];  /* each share's lanes holding a normal impulse */
} rbs__soft_store;
void rbs__soft_store_start(rbs__soft_store *st, rbs_world *w, const rbs__soft_groups *g, double h,
                           uint32_t *scratch, uint32_t shares);
void rbs__soft_store_count(rbs__soft_store *st, uint32_t q);
void rbs__soft_store_place(rbs__soft_store *st, uint32_t q);
uint32_t rbs__soft_store_finish(rbs__soft_store *st);

#endif
