/*
 * soft_chunks.c - packing a frame's contacts into chunks of four lanes
 * whose bodies differ (the soft step's gathered layout; soft.h).
 *
 * Each contact takes a colour, the lowest that no other contact of either
 * of its bodies has taken this frame (a greedy colouring of the contact
 * graph, one 64-bit mask of colours a body; a plane does not move and takes
 * none), and goes into its colour's open chunk: contacts of one colour
 * share no moving body, so any four of them can be a chunk, and all the
 * chunks of one colour can be taken in any order -- one after the other or
 * side by side -- with the same result.  Contacts come in detection's order
 * (each sphere's planes, then the pairs in the order of the candidate list,
 * neighbours in space close together), and a colour's chunks keep it.  A
 * contact whose bodies have taken all RBS__COLORS colours between them (a
 * body touching more than 64 others, or a pair of them) goes into a serial
 * chunk, whose lanes the passes take one after the other, after the
 * colours.  Planes and pairs are not mixed in a chunk (a plane's rows read
 * one body only): the open chunks are left when the kind changes, which it
 * does at most three times a frame, so a frame needs at most
 * RBS__CHUNKS(contacts) chunks.  The order is a function of the contacts
 * alone: results are deterministic.
 */
#include <string.h>

#include "core/soft_chunks.h"

/* The lowest bit set in bits (> 0). */
static int lowest_bit(uint64_t bits)
{
#if defined(__GNUC__)
    return __builtin_ctzll(bits);
#else
    int k = 0;
    while (!(bits >> k & 1u))
        k++;
    return k;
#endif
}

static rbs__chunk *chunk_new(rbs__chunker *ch, unsigned flags, uint32_t color)
{
    rbs__chunk *c;
    if (ch->used >= ch->cap)
        return NULL;
    c = &ch->chunk[ch->used];
    memset(c, 0, sizeof *c);
    c->flags = flags;
    c->color = color;
    ch->open[color] = ch->used++;
    return c;
}

static void leave_open(rbs__chunker *ch)
{
    int k;
    for (k = 0; k <= RBS__COLORS; ++k)
        ch->open[k] = UINT32_MAX;
}

void rbs__chunker_start(rbs__chunker *ch, rbs__chunk *chunk, uint32_t cap, uint64_t *color)
{
    ch->chunk = chunk;
    ch->cap = cap;
    ch->used = 0;
    ch->color = color;
    ch->plane = 1;
    leave_open(ch);
}

rbs__chunk *rbs__chunker_place(rbs__chunker *ch, uint32_t a, uint32_t b, int plane, uint32_t *lane)
{
    uint64_t taken;
    uint32_t k;
    rbs__chunk *c;
    if (plane != ch->plane) {
        leave_open(ch);
        ch->plane = plane;
    }
    taken = ch->color[a] | (plane ? 0u : ch->color[b]);
    k = taken == ~(uint64_t)0 ? RBS__COLORS : (uint32_t)lowest_bit(~taken);
    if (ch->open[k] != UINT32_MAX && ch->chunk[ch->open[k]].count < RBS__LANES) {
        c = &ch->chunk[ch->open[k]];
    } else {
        unsigned flags = k == RBS__COLORS ? 1u << RBS__CH_SERIAL : plane ? 15u << RBS__CH_PLANE : 0u;
        c = chunk_new(ch, flags, k);
        if (c == NULL)
            return NULL;
    }
    *lane = c->count++;
    c->a[*lane] = a;
    c->b[*lane] = b;
    if (k == RBS__COLORS) {
        if (plane)
            c->flags |= 1u << (RBS__CH_PLANE + *lane);
        return c;
    }
    ch->color[a] |= (uint64_t)1 << k;
    if (!plane)
        ch->color[b] |= (uint64_t)1 << k;
    return c;
}

void rbs__chunker_finish(rbs__chunker *ch, uint32_t *order, uint32_t *start)
{
    uint32_t i, k;
    for (k = 0; k <= RBS__COLORS + 1; ++k)
        start[k] = 0;
    for (i = 0; i < ch->used; ++i) {
        const rbs__chunk *c = &ch->chunk[i];
        uint32_t l;
        start[c->color + 1]++;
        for (l = 0; l < c->count; ++l) {
            ch->color[c->a[l]] = 0;
            ch->color[c->b[l]] = 0;
        }
    }
    for (k = 0; k <= RBS__COLORS; ++k)
        start[k + 1] += start[k];
    /* (start[k] now the next place of colour k; moved back below) */
    for (i = 0; i < ch->used; ++i)
        order[start[ch->chunk[i].color]++] = i;
    for (k = RBS__COLORS + 1; k > 0; --k)
        start[k] = start[k - 1];
    start[0] = 0;
    leave_open(ch);
}
