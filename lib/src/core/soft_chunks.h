/*
 * soft_chunks.h - packing contacts into chunks of four lanes by colour
 * (internal; soft_chunks.c).
 */
#ifndef RBS_CORE_SOFT_CHUNKS_H
#define RBS_CORE_SOFT_CHUNKS_H

#include "core/soft.h"

/* Chunks a frame of n contacts needs at most: full ones, and in each of the
 * four runs of one kind (planes, pairs, the guards' pairs and planes) one
 * part-full chunk of each colour and a serial one. */
#define RBS__CHUNKS(n) (((n) + 3u) / 4u + 4u * (RBS__COLORS + 1u))

typedef struct rbs__chunker {
    rbs__chunk *chunk;               /* the chunks, as they are opened */
    uint32_t used, cap;
    uint32_t open[RBS__COLORS + 1];  /* each colour's open chunk of this kind,
                                        and the serial one (UINT32_MAX: none) */
    uint64_t *color;                 /* per slot: the colours of its contacts
                                        (all zero between frames) */
    int plane;                       /* the kind of the open chunks */
} rbs__chunker;

/* Start packing into chunk[0 .. cap - 1]; color: 8 bytes a slot, zero. */
void rbs__chunker_start(rbs__chunker *ch, rbs__chunk *chunk, uint32_t cap, uint64_t *color);
/* The chunk and lane (*lane) of a new contact of bodies a and b (plane: b
 * is a plane), with a and b written and every other field zero; NULL when
 * the chunks are full (never within RBS__CHUNKS(contacts)). */
rbs__chunk *rbs__chunker_place(rbs__chunker *ch, uint32_t a, uint32_t b, int plane, uint32_t *lane);
/* The chunks in the order the passes take them -- by colour, then as they
 * were opened; the serial ones last -- into order[0 .. used - 1], where
 * colour k's start at start[k] (start[RBS__COLORS]: the serial ones,
 * start[RBS__COLORS + 1] = used); the colours are all zero again. */
void rbs__chunker_finish(rbs__chunker *ch, uint32_t *order, uint32_t *start);

#endif
