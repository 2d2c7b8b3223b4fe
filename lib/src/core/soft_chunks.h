/*
 * soft_chunks.h - packing one group's contacts into chunks of four lanes
 * (internal; soft_chunks.c).
 */
#ifndef RBS_CORE_SOFT_CHUNKS_H
#define RBS_CORE_SOFT_CHUNKS_H

#include "core/soft.h"

#define RBS__OPEN_CHUNKS 8 /* chunks of one kind open at a time (a byte of bits a body) */
/* The most chunks of a group of n contacts: full ones, and part-full the
 * open chunks of both kinds and a serial one. */
#define RBS__GROUP_CHUNKS(n) (((n) + 3u) / 4u + 2u * RBS__OPEN_CHUNKS + 1u)

typedef struct rbs__chunker {
    rbs__chunk *chunk;                    /* the group's chunks, in order */
    uint32_t used, cap;
    uint32_t open[2][RBS__OPEN_CHUNKS];   /* the open chunks of pairs [0] and
                                             planes [1] */
    unsigned open_mask[2];                /* bit k: open[kind][k] is open */
    uint32_t serial;                      /* the open serial chunk (UINT32_MAX: none) */
    uint16_t *member;                     /* per slot: bit k (pairs) or 8 + k
                                             (planes), open chunk k holds it
                                             (all zero between frames) */
} rbs__chunker;

/* Start packing into chunk[0 .. cap - 1]; member: 2 bytes a slot, zero,
 * used by no other chunker at the same time for the same bodies. */
void rbs__chunker_start(rbs__chunker *ch, rbs__chunk *chunk, uint32_t cap, uint16_t *member);
/* The chunk and lane (*lane) of a new contact of bodies a and b (plane: b
 * is a plane), with a and b written and every other field zero; NULL when
 * the chunks are full (never within RBS__GROUP_CHUNKS(contacts)). */
rbs__chunk *rbs__chunker_place(rbs__chunker *ch, uint32_t a, uint32_t b, int plane, uint32_t *lane);
/* Close every open chunk (the member bits are all zero again). */
void rbs__chunker_finish(rbs__chunker *ch);

#endif
