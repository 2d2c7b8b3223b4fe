/*
 * broadphase.c - candidate sphere pairs from a uniform grid, in the world's
 * fixed memory, so that finding neighbours costs O(N) at fixed density.
 *
 * Each sphere is an item with a centre and a reach (its radius plus any
 * motion or margin the caller adds).  Two items are candidates when their
 * centres are closer than the sum of their reaches.  Items go into a grid
 * whose cell is twice the typical reach (indexed densely when the items' box
 * of cells fits the table, else hashed), and each looks at the 27 cells
 * around its own.  Items much larger than typical (radius ratios up to 1e6,
 * or a sphere crossing many cells in one step) would blow up the cell size:
 * they are kept on a short "big" list and tested against every item instead.
 * The result is exact: the grid only skips pairs that cannot touch.
 *
 * With a query mask only pairs with at least one queried item are visited
 * (the grid is still built from every item).  Callers do not walk the grid
 * themselves: rbs__broadphase_pairs (at the end) keeps a candidate list
 * built from it and visits pairs in order of (i, j).  The broad phase is
 * used for every world (for a handful of spheres it costs a few hundred
 * nanoseconds), so it is never a stage that pruning changes.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/team.h"

/* Cell coordinate of x: floor(x / cell), clamped so that huge positions
 * never overflow the integer conversion (far-away items share edge cells:
 * slower, never wrong, since the distance test decides). */
static int32_t cell_of(double x, double inv_cell)
{
    double c = floor(x * inv_cell);
    if (!(c < 1.0e9))
        c = 1.0e9;
    if (!(c > -1.0e9))
        c = -1.0e9;
    return (int32_t)c;
}

static uint32_t cell_hash(int32_t x, int32_t y, int32_t z, uint32_t mask)
{
    uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)y * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= (uint64_t)z * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return (uint32_t)(h ^ (h >> 32)) & mask;
}

/* The table slot of cell (x, y, z): its index in the box from lo (nx by ny
 * cells in x and y) when dense, else its hash. */
static inline uint32_t cell_key(int32_t x, int32_t y, int32_t z, uint32_t mask, int dense,
                                const int32_t *lo, uint64_t nx, uint64_t ny)
{
    if (dense)
        return (uint32_t)((uint64_t)(x - lo[0]) + nx * ((uint64_t)(y - lo[1]) + ny * (uint64_t)(z - lo[2])));
    return cell_hash(x, y, z, mask);
}

/* Items i and o are candidates when their centres are closer than the sum
 * of their reaches: then fn visits them, the lower item first. */
static inline void visit_if_close(const double *C, const double *R, uint32_t i,
                                  uint32_t o, rbs__pair_fn fn, void *ctx)
{
    double ex = C[3 * i] - C[3 * o], ey = C[3 * i + 1] - C[3 * o + 1], ez = C[3 * i + 2] - C[3 * o + 2];
    double sr = R[i] + R[o];
    if (ex * ex + ey * ey + ez * ez <= sr * sr)
        fn(ctx, i < o ? i : o, i < o ? o : i);
}

/* The half stencil's runs of cells for a list (grid_list): with the table
 * dense and x fastest, the cells (x, y + ey, z + ez) and (x + 1, y + ey,
 * z + ez) are neighbours in it, so their items are one run of g->item.
 * The half stencil's 14 cells are 9 runs: 5 of two cells (ex 0 and 1:
 * (ey, ez) = (0, 0), (0, 1), (1, -1), (1, 0), (1, 1)) and 4 of one (ex 1:
 * (0, -1), (-1, -1), (-1, 0), (-1, 1)). */
static const int32_t list_runs[9][3] = {{0, 0, 0},  {0, 0, 1},  {0, 1, -1}, {0, 1, 0},  {0, 1, 1},
                                        {1, 0, -1}, {1, -1, -1}, {1, -1, 0}, {1, -1, 1}};

/* The grid's cells for the items and its table (the counting sort of the
 * grid items by cell), for grid_pairs and grid_list. */
typedef struct grid_box {
    int32_t lo[3], hi[3];
    uint64_t nx, ny;
    uint32_t mask, big;
    int dense;
} grid_box;

/* The grid's cells and table for items with centres C and reaches R: the
 * big items listed, each grid item's cell and key, and the items sorted by
 * key (counting sort: the items of a cell in item order). */
static void grid_fill(const rbs_world *w, const rbs__grid_mem *g, const double *C, const double *R, uint32_t n,
                      grid_box *b)
{
    uint32_t i, big = 0, mask = w->bp_table_size - 1;
    double mean = 0.0, cell, inv;
    int32_t *lo = b->lo, *hi = b->hi;
    uint64_t nx = 0, ny = 0;
    int any = 0, dense, d;

    for (d = 0; d < 3; ++d) {
        lo[d] = INT32_MAX;
        hi[d] = INT32_MIN;
    }
    /* typical reach: the mean; items beyond 4x the mean are "big" */
    for (i = 0; i < n; ++i)
        mean += R[i];
    mean /= n;
    cell = 0.0;
    for (i = 0; i < n; ++i) {
        if (R[i] > 4.0 * mean)
            g->big[big++] = i;
        else if (R[i] > cell)
            cell = R[i];
    }
    cell = 2.0 * cell; /* every pair the test can take is within one cell */
    if (!(cell > 0.0) || !isfinite(cell))
        cell = 1.0;
    inv = 1.0 / cell;

    /* cells of the grid items, and the box of cells they fill */
    for (i = 0; i < n; ++i) {
        if (R[i] > 4.0 * mean) {
            g->key[i] = UINT32_MAX;
            continue;
        }
        g->key[i] = 0;
        for (d = 0; d < 3; ++d) {
            int32_t c = g->cell[3 * i + d] = cell_of(C[3 * i + d], inv);
            lo[d] = c < lo[d] ? c : lo[d];
            hi[d] = c > hi[d] ? c : hi[d];
        }
        any = 1;
    }
    /* A box of at most as many cells as the table has slots is indexed
     * densely, x fastest: neighbouring cells then sit next to each other in
     * memory, and items made in spatial order (a lattice, a pile) walk the
     * table in order instead of hopping through it (at a million bodies the
     * hash's random access was most of the cost).  Otherwise cells are
     * hashed. */
    dense = any && (int64_t)hi[0] - lo[0] <= (int64_t)mask && (int64_t)hi[1] - lo[1] <= (int64_t)mask &&
            (int64_t)hi[2] - lo[2] <= (int64_t)mask;
    if (dense) {
        nx = (uint64_t)((int64_t)hi[0] - lo[0]) + 1;
        ny = (uint64_t)((int64_t)hi[1] - lo[1]) + 1;
        dense = nx * ny <= (uint64_t)mask + 1 &&
                nx * ny * ((uint64_t)((int64_t)hi[2] - lo[2]) + 1) <= (uint64_t)mask + 1;
    }

    /* counting sort of the grid items by cell key */
    memset(g->start, 0, (size_t)(mask + 2) * sizeof(uint32_t));
    memset(g->fill, 0, (size_t)(mask + 1) * sizeof(uint32_t));
    for (i = 0; i < n; ++i) {
        if (g->key[i] == UINT32_MAX)
            continue;
        g->key[i] = cell_key(g->cell[3 * i], g->cell[3 * i + 1], g->cell[3 * i + 2], mask, dense, lo, nx, ny);
        g->start[g->key[i] + 1]++;
    }
    for (i = 0; i <= mask; ++i)
        g->start[i + 1] += g->start[i];
    for (i = 0; i < n; ++i)
        if (g->key[i] != UINT32_MAX)
            g->item[g->fill[g->key[i]]++ + g->start[g->key[i]]] = i;

    b->nx = nx;
    b->ny = ny;
    b->mask = mask;
    b->big = big;
    b->dense = dense;
}

/* Big items against everything (grid_fill listed them). */
static void grid_big(const rbs__grid_mem *g, uint32_t big, const double *C, const double *R, uint32_t n,
                     const uint8_t *query, rbs__pair_fn fn, void *ctx)
{
    uint32_t i, j;
    for (j = 0; j < big; ++j) {
        uint32_t b = g->big[j];
        for (i = 0; i < n; ++i) {
            if (i == b || (g->key[i] == UINT32_MAX && i < b))
                continue; /* big-big pairs once */
            if (query && !query[i] && !query[b])
                continue;
            visit_if_close(C, R, i, b, fn, ctx);
        }
    }
}

/* The grid's visits once grid_fill has made box: fn for every pair of
 * items whose centres C are closer than the sum of their reaches R. */
static void grid_visit(const rbs_world *w, const rbs__grid_mem *g, const grid_box *box, const double *C,
                       const double *R, uint32_t n, const uint8_t *query, rbs__pair_fn fn, void *ctx)
{
    const int32_t *lo = box->lo, *hi = box->hi;
    uint32_t i, big, mask;
    uint64_t nx, ny;
    int dense;

    (void)w;
    big = box->big;
    mask = box->mask;
    nx = box->nx;
    ny = box->ny;
    dense = box->dense;

    /* The common case -- every pair, a dense table -- walks the 14 cells of
     * the half stencil (those at or after (0, 0, 0), in the order the
     * general loop below takes them) from the item's own slot by fixed
     * offsets; the same visits in the same order, without the 13 skipped
     * cells and the slot arithmetic of each. */
    if (!query && dense) {
        int64_t off[14];
        int32_t ofs[14][3];
        int m = 0, ex, ey, ez;
        for (ex = 0; ex <= 1; ++ex)
            for (ey = -1; ey <= 1; ++ey) {
                if (ex == 0 && ey < 0)
                    continue;
                for (ez = -1; ez <= 1; ++ez) {
                    if (ex == 0 && ey == 0 && ez < 0)
                        continue;
                    ofs[m][0] = ex;
                    ofs[m][1] = ey;
                    ofs[m][2] = ez;
                    off[m] = (int64_t)ex + (int64_t)nx * ((int64_t)ey + (int64_t)ny * ez);
                    m++;
                }
            }
        for (i = 0; i < n; ++i) {
            int32_t cx, cy, cz;
            uint32_t key = g->key[i];
            if (key == UINT32_MAX)
                continue;
            cx = g->cell[3 * i];
            cy = g->cell[3 * i + 1];
            cz = g->cell[3 * i + 2];
            for (m = 0; m < 14; ++m) {
                uint32_t h, k;
                if (cx + ofs[m][0] > hi[0] || cy + ofs[m][1] < lo[1] || cy + ofs[m][1] > hi[1] ||
                    cz + ofs[m][2] < lo[2] || cz + ofs[m][2] > hi[2])
                    continue; /* outside the box: no items there (dx >= 0) */
                h = (uint32_t)((int64_t)key + off[m]);
                for (k = g->start[h]; k < g->start[h + 1]; ++k) {
                    uint32_t o = g->item[k];
                    if (o == i || (o < i && m == 0))
                        continue;
                    visit_if_close(C, R, i, o, fn, ctx);
                }
            }
        }
    } else {
        /* grid items against the 27 cells around them; a hashed bucket may
         * hold items of other cells (collisions), which the stored cell
         * filters out, so every partner is seen exactly once */
        for (i = 0; i < n; ++i) {
            int32_t cx, cy, cz;
            int dx, dy, dz;
            if (g->key[i] == UINT32_MAX || (query && !query[i]))
                continue;
            cx = g->cell[3 * i];
            cy = g->cell[3 * i + 1];
            cz = g->cell[3 * i + 2];
            for (dx = -1; dx <= 1; ++dx)
                for (dy = -1; dy <= 1; ++dy)
                    for (dz = -1; dz <= 1; ++dz) {
                        uint32_t h, k;
                        /* without a query, each pair once from the half of
                         * the stencil at or after (0, 0, 0): of two items in
                         * different cells exactly one sees the other there */
                        if (!query && (dx < 0 || (dx == 0 && (dy < 0 || (dy == 0 && dz < 0)))))
                            continue;
                        if (dense && (cx + dx < lo[0] || cx + dx > hi[0] || cy + dy < lo[1] ||
                                      cy + dy > hi[1] || cz + dz < lo[2] || cz + dz > hi[2]))
                            continue; /* outside the box: no items there */
                        h = cell_key(cx + dx, cy + dy, cz + dz, mask, dense, lo, nx, ny);
                        for (k = g->start[h]; k < g->start[h + 1]; ++k) {
                            uint32_t o = g->item[k];
                            /* each pair once: with a query, from the lower item
                             * when both are queried, else from the queried one;
                             * without, in a shared cell from the lower item */
                            if (o == i || (o < i && (query ? query[o] : (dx == 0 && dy == 0 && dz == 0))))
                                continue;
                            /* (a dense slot holds one cell only: no check) */
                            if (!dense && (g->cell[3 * o] != cx + dx || g->cell[3 * o + 1] != cy + dy ||
                                           g->cell[3 * o + 2] != cz + dz))
                                continue;
                            visit_if_close(C, R, i, o, fn, ctx);
                        }
                    }
        }
    }
    grid_big(g, big, C, R, n, query, fn, ctx);
}

/* The grid pass: fn for every pair of items whose centres C are closer
 * than the sum of their reaches R. */
static void grid_pairs(const rbs_world *w, const rbs__grid_mem *g, const double *C, const double *R, uint32_t n,
                       const uint8_t *query, rbs__pair_fn fn, void *ctx)
{
    grid_box box;
    if (n < 2)
        return;
    grid_fill(w, g, C, R, n, &box);
    grid_visit(w, g, &box, C, R, n, query, fn, ctx);
}

static void list_collect(void *vctx, uint32_t i, uint32_t j)
{
    rbs_world *w = (rbs_world *)vctx;
    if (w->vl_count < w->vl_cap) {
        w->vl_pair[2 * w->vl_count] = i;
        w->vl_pair[2 * w->vl_count + 1] = j;
    }
    w->vl_count++;
}

/* The list pass's grid (list_items): the table dense, its box and the
 * offsets of list_runs in it. */
typedef struct list_grid {
    const rbs__grid_mem *g;
    const double *C, *R;
    grid_box box;
    int64_t off[9];
} list_grid;

/* The pairs of items [begin, end) with the items of the half stencil's
 * cells (the 9 runs of list_runs, each run's items tested without a
 * branch), as (lower, higher) into out[0 .. cap - 1]; returns how many
 * there are (beyond cap: counted, not written). */
static uint32_t list_items(const list_grid *lg, uint32_t begin, uint32_t end, uint32_t *out, uint32_t cap)
{
    const rbs__grid_mem *g = lg->g;
    const double *C = lg->C, *R = lg->R;
    const int32_t *lo = lg->box.lo, *hi = lg->box.hi;
    const uint32_t *start = g->start, *item = g->item;
    uint32_t count = 0, i, sink[2];
    int m;
    for (i = begin; i < end; ++i) {
        const uint32_t key = g->key[i];
        const double xi = C[3 * i], yi = C[3 * i + 1], zi = C[3 * i + 2], ri = R[i];
        int32_t cx, cy, cz;
        int right;
        if (key == UINT32_MAX)
            continue;
        cx = g->cell[3 * i];
        cy = g->cell[3 * i + 1];
        cz = g->cell[3 * i + 2];
        right = cx < hi[0]; /* cell x + 1 is in the box */
        for (m = 0; m < 9; ++m) {
            const int32_t ex = list_runs[m][0], ey = list_runs[m][1], ez = list_runs[m][2];
            uint32_t h, k, own_end, run_end;
            if (cy + ey < lo[1] || cy + ey > hi[1] || cz + ez < lo[2] || cz + ez > hi[2] || (ex == 1 && !right))
                continue; /* outside the box: no items there */
            h = (uint32_t)((int64_t)key + lg->off[m]);
            /* m 0: the item's own cell (partners after it), then x + 1's */
            own_end = m == 0 ? start[h + 1] : start[h];
            run_end = start[h + 1 + (ex == 0 && right)];
            for (k = start[h]; k < run_end; ++k) {
                const uint32_t o = item[k];
                const double dx = xi - C[3 * o], dy = yi - C[3 * o + 1], dz = zi - C[3 * o + 2], sr = ri + R[o];
                const uint32_t hit =
                    (uint32_t)(dx * dx + dy * dy + dz * dz <= sr * sr) & (uint32_t)(k >= own_end || o > i);
                uint32_t *to = count < cap ? &out[2 * count] : sink;
                to[0] = i < o ? i : o;
                to[1] = i < o ? o : i;
                count += hit;
            }
        }
    }
    return count;
}

/* The grid for a list pass (grid_fill) and, when its table is dense, the
 * offsets of list_runs in it: 1 when the list can take list_items, 0 when
 * it takes grid_visit's walk. */
static int list_grid_make(const rbs_world *w, const rbs__grid_mem *g, const double *C, const double *R, uint32_t n,
                          list_grid *lg)
{
    int m;
    lg->g = g;
    lg->C = C;
    lg->R = R;
    grid_fill(w, g, C, R, n, &lg->box);
    for (m = 0; m < 9; ++m)
        lg->off[m] = (int64_t)list_runs[m][0] +
                     (int64_t)lg->box.nx * ((int64_t)list_runs[m][1] + (int64_t)lg->box.ny * list_runs[m][2]);
    return lg->box.dense;
}

/* The pairs of a list (list_build, which sorts them after) from the grid
 * lg made: every pair of items whose centres are closer than the sum of
 * their reaches, as (lower, higher) into w->vl_pair, counted in
 * w->vl_count (beyond vl_cap: counted, not written) -- the pairs grid_pairs
 * visits, in another order: list_items on a dense table, else grid_visit's
 * walk. */
static void grid_list(rbs_world *w, const list_grid *lg, uint32_t n)
{
    if (!lg->box.dense) {
        grid_visit(w, lg->g, &lg->box, lg->C, lg->R, n, NULL, list_collect, w);
        return;
    }
    w->vl_count += list_items(lg, 0, n, w->vl_pair + 2 * (size_t)w->vl_count,
                              w->vl_count < w->vl_cap ? w->vl_cap - w->vl_count : 0);
    grid_big(lg->g, lg->box.big, lg->C, lg->R, n, NULL, list_collect, w);
}

/* Items [begin, end) of a list whose pairs are in place by first item
 * (w->vl_start): each item's few partners in order (insertion). */
static void list_sort_items(rbs_world *w, uint32_t begin, uint32_t end)
{
    uint32_t *P = w->vl_pair, i, k;
    for (i = begin; i < end; ++i)
        for (k = w->vl_start[i] + 1; k < w->vl_start[i + 1]; ++k) {
            const uint32_t b = P[2 * k + 1];
            uint32_t at = k;
            while (at > w->vl_start[i] && P[2 * (at - 1) + 1] > b) {
                P[2 * at + 1] = P[2 * (at - 1) + 1];
                at--;
            }
            P[2 * at + 1] = b;
        }
}

/* The list's stages on the world's threads (list_shared): each share's
 * pairs into its own run of the buffer and counted by first item, then
 * moved to their places, then each item's partners sorted. */
typedef struct list_team {
    rbs_world *w;
    const list_grid *lg;
    uint32_t n, shares;
    uint32_t *buf;                     /* shares runs of room pairs */
    uint32_t room;
    uint32_t found[RBS__TEAM_SHARES];  /* each share's pairs (beyond room:
                                          counted, not written) */
    uint32_t *next;                    /* per item, where its next pair goes */
} list_team;

static void list_stage_find(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    list_team *t = (list_team *)ctx;
    uint32_t *run = t->buf + 2 * (size_t)share * t->room, k, found;
    found = list_items(t->lg, begin, end, run, t->room);
    t->found[share] = found;
    for (k = 0; k < found && k < t->room; ++k)
        (void)rbs__team_add(&t->w->vl_start[run[2 * k] + 1], t->shares > 1);
}

static void list_stage_place(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    list_team *t = (list_team *)ctx;
    uint32_t *P = t->w->vl_pair, s;
    (void)share;
    for (s = begin; s < end; ++s) {
        const uint32_t *run = t->buf + 2 * (size_t)s * t->room;
        uint32_t k;
        for (k = 0; k < t->found[s]; ++k) {
            const uint32_t at = rbs__team_add(&t->next[run[2 * k]], t->shares > 1);
            P[2 * at] = run[2 * k];
            P[2 * at + 1] = run[2 * k + 1];
        }
    }
}

static void list_stage_sort(void *ctx, uint32_t share, uint32_t begin, uint32_t end)
{
    list_team *t = (list_team *)ctx;
    (void)share;
    list_sort_items(t->w, begin, end);
    memcpy(&t->w->vl_pos[3 * (size_t)begin], &t->lg->C[3 * (size_t)begin], 3 * (size_t)(end - begin) * sizeof(double));
}

/* The list's pairs, in order, on the world's threads (team.h), from the
 * grid lg made (dense, no big items), through the buffer m->pairs: 1 when
 * done (w->vl_count, beyond vl_cap when they did not fit); 0 when a
 * share's pairs went beyond its run of the buffer, and nothing is written
 * but w->vl_start. */
static int list_shared(rbs_world *w, const rbs__grid_mem *m, const list_grid *lg, uint32_t n)
{
    list_team t;
    uint32_t i, k, total = 0, threads = rbs__team_threads(w);
    t.w = w;
    t.lg = lg;
    t.n = n;
    t.shares = threads > 1 ? 2 * threads : 1;
    if (t.shares > RBS__TEAM_SHARES)
        t.shares = RBS__TEAM_SHARES;
    if (t.shares > n)
        t.shares = n;
    t.buf = m->pairs;
    t.room = (uint32_t)(m->pair_room / t.shares < UINT32_MAX ? m->pair_room / t.shares : UINT32_MAX);
    memset(t.found, 0, sizeof t.found);
    memset(w->vl_start, 0, ((size_t)n + 1) * sizeof *w->vl_start);
    rbs__team_run(w, list_stage_find, &t, n, t.shares);
    for (k = 0; k < t.shares; ++k) {
        if (t.found[k] > t.room)
            return 0;
        total += t.found[k];
    }
    w->vl_count = total;
    if (total > w->vl_cap)
        return 1;
    /* each item's first place; the grid's fill (T >= n entries) is free */
    t.next = m->fill;
    for (i = 0; i < n; ++i) {
        w->vl_start[i + 1] += w->vl_start[i];
        t.next[i] = w->vl_start[i];
    }
    rbs__team_run(w, list_stage_place, &t, t.shares, t.shares);
    rbs__team_run(w, list_stage_sort, &t, n, t.shares);
    w->vl_items = n;
    w->vl_valid = 1;
    return 1;
}

/* The candidate-pair list (a Verlet list: Verlet, Phys. Rev. 159, 98, 1967),
 * with a skin of its own for each item.  Built from the grid with each
 * item's reach R_Li grown by its skin s_i to a list reach L_i = R_Li + s_i,
 * it holds each pair (i < j) whose centres were closer than L_i + L_j,
 * sorted by (i, j), with the centres c_L it was built at.  A later pass with
 * centres c and reaches R can take its pairs from the list while every item
 * stays within its list reach:
 *   R_i + |c_i - c_Li| <= L_i   for every i
 * -- then a pair closer than R_i + R_j now was closer than
 * R_i + |c_i - c_Li| + R_j + |c_j - c_Lj| <= L_i + L_j at the build (the
 * triangle inequality), so it is on the list.  The list is tested with the
 * pass's own R_i + R_j, so a pass visits the same pairs in the same (sorted)
 * order whether the list was built for it or reused: results never depend
 * on when it was built, nor on the skins (nor on a checkpoint's resume,
 * which starts without a list).
 *
 * The skin is a base of LIST_SKIN / 2 of the mean radius plus LIST_AHEAD
 * times the item's own motion in its reach, R_i - r_i (1 + fixed) (the
 * caller's fixed part left out: the sweep margin |v| dt + |a| dt^2 for
 * detection, half the path for the selective method's search, so that a
 * sphere at rest gets the base alone), at most LIST_SKIN_MAX of the mean
 * radius.  With one skin for all, any sphere moving faster than the
 * skin a frame (a pile's fall, a sphere kicked from rest by an impact) forced
 * a rebuild every frame; with its own, it forces one per LIST_AHEAD frames
 * or so, and the slow majority keeps the small base.  A list so grown that
 * it holds more pairs than there is room for is built with the base skin
 * alone, and failing that with no skin (a list for this pass only).
 *
 * Given room for pairs beside the grid (the soft step's, in the chunks'
 * room), the list is built on the world's threads (list_shared): a dense
 * table's pairs found share by share, counted by first item, moved to
 * their places and each item's partners sorted -- the same sorted list,
 * whatever the threads, as the serial way's American flag sort. */
#define LIST_SKIN 0.1     /* the base margin of a pair, of the mean radius */
#define LIST_AHEAD 4.0    /* frames of an item's own motion its skin holds */
#define LIST_SKIN_MAX 0.5 /* the most skin of an item, of the mean radius */

/* Build the list from the centres C and the reaches in w->bp_reach, each
 * grown by base (m) and ahead times the item's motion (at most most, m);
 * 0 (and no list) if it does not fit.  *grown: the largest skin beyond the
 * base, m. */
static int list_build(rbs_world *w, const rbs__grid_mem *m, const double *C, uint32_t n, double fixed, double base,
                      double ahead, double most, double *grown)
{
    /* the grid's start and fill (2 n entries and more each) are free once
     * the grid pass is over */
    uint32_t *start = m->start, *next = m->fill, *P = w->vl_pair, i, k;
    w->vl_valid = 0;
    w->vl_count = 0;
    for (i = 0; i < n; ++i) {
        double motion = w->bp_reach[i] - w->radius[w->spheres[i]] * (1.0 + fixed), skin = ahead * motion;
        skin = motion > 0.0 ? (skin < most ? skin : most) : 0.0;
        w->vl_reach[i] = w->bp_reach[i] + (base + skin);
        *grown = skin > *grown ? skin : *grown;
    }
    if (n >= 2) {
        list_grid lg;
        const int dense = list_grid_make(w, m, C, w->vl_reach, n, &lg);
        if (m->pairs != NULL && dense && lg.box.big == 0 && list_shared(w, m, &lg, n))
            return w->vl_valid;
        w->vl_count = 0;
        grid_list(w, &lg, n);
    }
    if (w->vl_count > w->vl_cap)
        return 0;
    /* sorted in place by the first item (American flag sort: McIlroy,
     * Bostic & McIlroy, "Engineering radix sort", Computing Systems 6(1),
     * 1993), then each first item's few partners by insertion */
    memset(start, 0, ((size_t)n + 1) * sizeof *start);
    for (k = 0; k < w->vl_count; ++k)
        start[P[2 * k] + 1]++;
    for (i = 0; i < n; ++i) {
        start[i + 1] += start[i];
        next[i] = start[i];
    }
    for (i = 0; i < n; ++i)
        while (next[i] < start[i + 1]) {
            uint32_t at = next[i], a = P[2 * at];
            if (a == i) {
                next[i]++;
            } else {
                /* the pair belongs to bucket a: swap it into a's next slot */
                uint32_t to = next[a]++, t0 = P[2 * to], t1 = P[2 * to + 1];
                P[2 * to] = a;
                P[2 * to + 1] = P[2 * at + 1];
                P[2 * at] = t0;
                P[2 * at + 1] = t1;
            }
        }
    /* each first item's pairs: its bucket, start[i] .. start[i + 1] - 1 */
    memcpy(w->vl_start, start, ((size_t)n + 1) * sizeof *start);
    list_sort_items(w, 0, n);
    memcpy(w->vl_pos, C, 3 * (size_t)n * sizeof(double));
    w->vl_items = n;
    w->vl_valid = 1;
    return 1;
}

/* The rounding allowance of both tests (the list's, the pass's): the
 * distances' rounding at the largest coordinate and reach, with room to
 * spare. */
static double round_guard(double size, double rmax)
{
    return 64.0 * DBL_EPSILON * (size + rmax);
}

int rbs__broadphase_keep(const rbs_world *w, uint32_t n, double size, double rmax, double slack)
{
    const double guard = round_guard(size, rmax);
    return w->vl_valid && w->vl_items == n && isfinite(guard) && slack >= guard; /* (false for a NaN) */
}

/* The world's own grid arrays. */
static rbs__grid_mem grid_mem_of(const rbs_world *w)
{
    rbs__grid_mem m;
    m.key = w->bp_key;
    m.item = w->bp_item;
    m.big = w->bp_big;
    m.start = w->bp_start;
    m.fill = w->bp_fill;
    m.cell = w->bp_cell;
    m.pairs = NULL;
    m.pair_room = 0;
    return m;
}

int rbs__grid_mem_in(const rbs_world *w, void *p, size_t bytes, uint32_t n, rbs__grid_mem *out)
{
    const size_t T = w->bp_table_size, words = 6 * (size_t)n + 2 * T + 1;
    uint32_t *u = (uint32_t *)p;
    if (p == NULL || (uintptr_t)p % sizeof(uint32_t) != 0 || bytes / sizeof(uint32_t) < words)
        return 0;
    out->start = u;
    out->fill = u + T + 1;
    out->key = out->fill + T;
    out->item = out->key + n;
    out->big = out->item + n;
    out->cell = (int32_t *)(void *)(out->big + n);
    out->pairs = (uint32_t *)(void *)(out->cell + 3 * (size_t)n);
    out->pair_room = (bytes / sizeof(uint32_t) - words) / 2;
    return 1;
}

int rbs__broadphase_build(rbs_world *w, const rbs__grid_mem *mem, const double *centers, uint32_t n, double fixed,
                          double size, double rmax, double rsum)
{
    const rbs__grid_mem own = grid_mem_of(w), *m = mem != NULL ? mem : &own;
    const double *C = centers != NULL ? centers : w->bp_center;
    const double guard = round_guard(size, rmax), mean = rsum / n;
    const double base = 0.5 * LIST_SKIN * mean + guard;
    double grown = 0.0;
    /* grown by skins, so that it lasts; if that holds more pairs than the
     * list has room for, by the base skin alone; else just what this pass
     * needs; else none */
    return list_build(w, m, C, n, fixed, base, LIST_AHEAD, LIST_SKIN_MAX * mean, &grown) ||
           (grown > base && list_build(w, m, C, n, fixed, base, 0.0, 0.0, &grown)) ||
           list_build(w, m, C, n, fixed, guard, 0.0, 0.0, &grown);
}

/* The candidate list ready for a pass of n >= 2 items (kept, or built
 * again); 1 when it holds every candidate pair, 0 when there are too many
 * for it. */
static int list_ready(rbs_world *w, const double *C, uint32_t n, double fixed)
{
    const double *R = w->bp_reach;
    double size = 0.0, rsum = 0.0, rmax = 0.0, slack = INFINITY;
    uint32_t i, k;
    for (i = 0; i < n; ++i) {
        rsum += w->radius[w->spheres[i]];
        rmax = R[i] > rmax ? R[i] : rmax;
        for (k = 0; k < 3; ++k)
            size = fabs(C[3 * i + k]) > size ? fabs(C[3 * i + k]) : size;
    }
    for (i = 0; w->vl_valid && w->vl_items == n && i < n; ++i) {
        double x = rbs__broadphase_slack(w, C, i);
        if (!(x >= slack))
            slack = x; /* (a NaN stays) */
    }
    if (rbs__broadphase_keep(w, n, size, rmax, slack))
        return 1;
    return rbs__broadphase_build(w, NULL, C, n, fixed, size, rmax, rsum);
}

void rbs__broadphase_pairs(rbs_world *w, const double *centers, uint32_t n, const uint8_t *query, double fixed,
                           rbs__pair_fn fn, void *ctx)
{
    const double *C = centers != NULL ? centers : w->bp_center, *R = w->bp_reach;
    uint32_t k;
    if (n < 2)
        return;
    if (!list_ready(w, C, n, fixed)) {
        /* more candidate pairs than the list holds: the grid itself (its
         * own order; a function of this pass's centres only) */
        const rbs__grid_mem m = grid_mem_of(w);
        grid_pairs(w, &m, C, R, n, query, fn, ctx);
        return;
    }
    for (k = 0; k < w->vl_count; ++k) {
        uint32_t a = w->vl_pair[2 * k], b = w->vl_pair[2 * k + 1];
        double ex, ey, ez, sr;
        if (query && !query[a] && !query[b])
            continue;
        ex = C[3 * a] - C[3 * b];
        ey = C[3 * a + 1] - C[3 * b + 1];
        ez = C[3 * a + 2] - C[3 * b + 2];
        sr = R[a] + R[b];
        if (ex * ex + ey * ey + ez * ez <= sr * sr)
            fn(ctx, a, b);
    }
}
