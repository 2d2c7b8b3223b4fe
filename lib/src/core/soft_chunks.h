/*
 * soft_chunks.h - packing one group's contacts into chunks of four lanes
 * (internal; soft_chunks.c).
 */
#ifndef RBS_CORE_SOFT_CHUNKS_H
#define RBS_CORE_SOFT_CHUNKS_H

#include "core/soft.h"

#define RBS__OPEN_CHUNKS 8 /* chunks of one kind open at a time (a byte of bits a body) */
/* The most chunks of a group of n contacts: full ones, and part-full the
 * open chunks of both kinds, a serial one and a wedges' one. */
#define RBS__GROUP_CHUNKS(n) (((n) + 3u) / 4u + 2u * RBS__OPEN_CHUNKS + 2u)

typedef struct rbs__chunker {
    rbs__chunk *chunk;                    /* the group's chunks, in order */
    uint32_t used, cap;
    uint32_t open[2][RBS__OPEN_CHUNKS];   /* the open chunks of pairs [0] and
                                             planes [1] */
    unsigned open_mask[2];                /* bit k: open[kind][k] is open */
    uint32_t serial;                      /* the open serial chunk (UINT32_MAX: none) */
    uint32_t wedges;                      /* the open wedges' chunk (UINT32_MAX: none) */
    uint16_t *member;                     /* per slot: bit k (pairs) or 8 + k
                                             (planes), open chunk k holds it
                                             (all zero between frames) */
} rbs__chunker;

/* Start packing into chunk[0 .. cap - 1]; member: 2 bytes a slot, zero,
 * used by no other chunker at the same time for the same bodies. */
void rbs__chunker_start(rbs__chunker *ch, rbs__chunk *chunk, uint32_t cap, uint16_t *member);
/* rbs__chunker_place when no open chunk of the kind can take the contact:
 * a new chunk, or the serial one (soft_chunks.c). */
rbs__chunk *rbs__chunker_open(rbs__chunker *ch, uint32_t a, uint32_t b, int kind, uint32_t *lane);
/* The chunk and lane (*lane) of one of the two plane contacts of sphere a
 * that make a wedge (RBS__CH_WEDGE), b the plane: the two, placed one after
 * the other, take lanes 0-1 or 2-3 of a wedges' chunk; NULL when the chunks
 * are full (soft_chunks.c). */
rbs__chunk *rbs__chunker_wedge(rbs__chunker *ch, uint32_t a, uint32_t b, uint32_t *lane);
/* Close open chunk k of kind (its bodies are free of it; soft_chunks.c). */
void rbs__chunker_close(rbs__chunker *ch, int kind, int k);

/* The lowest bit set in bits (> 0). */
static inline int rbs__lowest_bit(unsigned bits)
{
#if defined(__GNUC__)
    return __builtin_ctz(bits);
#else
    int k = 0;
    while (!(bits >> k & 1u))
        k++;
    return k;
#endif
}

/* Bodies a and b (kind 1: b is a plane) into the next lane of open chunk k
 * of their kind, c (*lane: which), and the chunk marked on them. */
static inline void rbs__chunker_put(rbs__chunker *ch, rbs__chunk *c, int kind, int k, uint32_t a, uint32_t b,
                                    uint32_t *lane)
{
    *lane = c->count++;
    c->a[*lane] = a;
    c->b[*lane] = b;
    ch->member[a] |= (uint16_t)(1u << (8 * kind + k));
    if (!kind)
        ch->member[b] |= (uint16_t)(1u << k);
}

/* The chunk and lane (*lane) of a new contact of bodies a and b (plane: b
 * is a plane), with a and b written; NULL when the chunks are full (never
 * within RBS__GROUP_CHUNKS(contacts)).  Inline: the first open chunk that
 * can take it, the common case (the rest out of line). */
static inline rbs__chunk *rbs__chunker_place(rbs__chunker *ch, uint32_t a, uint32_t b, int plane, uint32_t *lane)
{
    const int kind = plane != 0;
    const unsigned busy = (unsigned)(ch->member[a] >> (8 * kind)) | (kind ? 0u : ch->member[b]);
    const unsigned fits = ch->open_mask[kind] & ~busy & ((1u << RBS__OPEN_CHUNKS) - 1u);
    rbs__chunk *c;
    int k;
    if (fits == 0)
        return rbs__chunker_open(ch, a, b, kind, lane);
    k = rbs__lowest_bit(fits);
    c = &ch->chunk[ch->open[kind][k]];
    rbs__chunker_put(ch, c, kind, k, a, b, lane);
    if (c->count == RBS__LANES)
        rbs__chunker_close(ch, kind, k);
    return c;
}
/* Close every open chunk (the member bits are all zero again). */
void rbs__chunker_finish(rbs__chunker *ch);

#endif
