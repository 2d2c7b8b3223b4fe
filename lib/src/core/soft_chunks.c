/*
 * soft_chunks.c - packing one group's contacts into chunks of four lanes
 * whose bodies differ (the soft step's gathered layout; soft.h).
 *
 * A group's contacts come in detection's order (neighbours in space close
 * together) and its chunks are taken in the order they were opened, by one
 * thread.  Up to RBS__OPEN_CHUNKS chunks of each kind (pairs of spheres;
 * spheres against planes, whose rows read one body) are open at a time; a
 * contact goes into the first open chunk of its kind that holds neither of
 * its bodies, or opens a new one, and a chunk is closed when its four lanes
 * are full.  Which open chunks hold a body is a pair of bytes of bits per
 * body (member), so a placement costs a few instructions, and the chunks
 * keep detection's order nearly as it was: a pass sweeps the records nearly
 * in order, and Gauss-Seidel carries an impulse along as it would contact
 * by contact.  A contact that fits no open chunk and finds none free (a
 * body in contact with more than RBS__OPEN_CHUNKS others in a row: a large
 * sphere under many small ones) goes into a serial chunk, whose lanes are
 * taken one after the other; so do a wedge's two contacts, a pair of lanes
 * in a chunk of wedges (rbs__chunker_wedge), solved together.  The order is a function of the contacts
 * alone: results are deterministic.
 */
#include <string.h>

#include "core/soft_chunks.h"

/* A new chunk, its lanes unused.  Only the impulses and the pair rows are
 * cleared of the last frame's values (an unused lane's other fields are
 * left: its rows read a record of zeros, and its results go nowhere; the
 * warm start skips a chunk whose impulses are all zero). */
static rbs__chunk *chunk_new(rbs__chunker *ch, unsigned flags)
{
    rbs__chunk *c;
    if (ch->used >= ch->cap)
        return NULL;
    c = &ch->chunk[ch->used++];
    memset(c->jn, 0, sizeof c->jn);
    memset(c->jx, 0, sizeof c->jx);
    memset(c->jy, 0, sizeof c->jy);
    memset(c->jz, 0, sizeof c->jz);
    memset(c->row, 0, sizeof c->row); /* (the bytes may be another method's) */
    c->count = 0;
    c->flags = flags;
    return c;
}

void rbs__chunker_close(rbs__chunker *ch, int kind, int k)
{
    const rbs__chunk *c = &ch->chunk[ch->open[kind][k]];
    const uint16_t keep = (uint16_t)~(1u << (8 * kind + k));
    uint32_t l;
    for (l = 0; l < c->count; ++l) {
        ch->member[c->a[l]] &= keep;
        if (!kind)
            ch->member[c->b[l]] &= keep;
    }
    ch->open_mask[kind] &= ~(1u << k);
}

void rbs__chunker_start(rbs__chunker *ch, rbs__chunk *chunk, uint32_t cap, uint16_t *member)
{
    ch->chunk = chunk;
    ch->cap = cap;
    ch->used = 0;
    ch->member = member;
    ch->serial = UINT32_MAX;
    ch->wedges = UINT32_MAX;
    ch->open_mask[0] = ch->open_mask[1] = 0;
}

void rbs__chunker_finish(rbs__chunker *ch)
{
    int kind, k;
    for (kind = 0; kind < 2; ++kind)
        for (k = 0; k < RBS__OPEN_CHUNKS; ++k)
            if (ch->open_mask[kind] >> k & 1u)
                rbs__chunker_close(ch, kind, k);
    ch->serial = UINT32_MAX;
    ch->wedges = UINT32_MAX;
}

rbs__chunk *rbs__chunker_open(rbs__chunker *ch, uint32_t a, uint32_t b, int kind, uint32_t *lane)
{
    const unsigned all = (1u << RBS__OPEN_CHUNKS) - 1u;
    rbs__chunk *c;
    int k;
    if (ch->open_mask[kind] != all) {
        /* a free slot: a new chunk there */
        k = rbs__lowest_bit(~ch->open_mask[kind] & all);
        c = chunk_new(ch, kind ? 15u << RBS__CH_PLANE : 0u);
        if (c == NULL)
            return NULL;
        ch->open[kind][k] = (uint32_t)(c - ch->chunk);
        ch->open_mask[kind] |= 1u << k;
        rbs__chunker_put(ch, c, kind, k, a, b, lane);
        return c;
    }
    /* no open chunk can take it and none is free: the serial chunk */
    if (ch->serial == UINT32_MAX || ch->chunk[ch->serial].count == RBS__LANES) {
        c = chunk_new(ch, 1u << RBS__CH_SERIAL);
        if (c == NULL)
            return NULL;
        ch->serial = (uint32_t)(c - ch->chunk);
    }
    c = &ch->chunk[ch->serial];
    *lane = c->count++;
    c->a[*lane] = a;
    c->b[*lane] = b;
    if (kind)
        c->flags |= 1u << (RBS__CH_PLANE + *lane);
    return c;
}

rbs__chunk *rbs__chunker_wedge(rbs__chunker *ch, uint32_t a, uint32_t b, uint32_t *lane)
{
    rbs__chunk *c;
    /* (a wedge's first contact finds the open chunk's count even: a new
     * chunk when it is full) */
    if (ch->wedges == UINT32_MAX || ch->chunk[ch->wedges].count == RBS__LANES) {
        c = chunk_new(ch, 1u << RBS__CH_SERIAL | 1u << RBS__CH_WEDGE);
        if (c == NULL)
            return NULL;
        ch->wedges = (uint32_t)(c - ch->chunk);
    }
    c = &ch->chunk[ch->wedges];
    *lane = c->count++;
    c->a[*lane] = a;
    c->b[*lane] = b;
    c->flags |= 1u << (RBS__CH_PLANE + *lane);
    return c;
}
