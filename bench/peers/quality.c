/*
 * quality.c - judges a driver's final state against its scene, the same way
 * for every engine:
 *
 *   peers_quality SCENE STATE    prints one JSON line
 *
 *  - escaped: spheres whose centre is behind a plane (outside the box, or
 *    through the floor) or not finite;
 *  - worst sphere-sphere overlap (r_i + r_j - |x_i - x_j|) / min(r_i, r_j)
 *    and worst sphere-plane overlap (r - distance) / r, and how many pairs
 *    or sphere-plane contacts overlap by more than 1 % of the radius;
 *  - energy: sum of m v^2/2 + I w^2/2 (I = 2/5 m r^2, solid) + m |g| z, J.
 * Sphere pairs are found with a uniform grid of cell 2 r_max (sorted cells,
 * binary search), so a million spheres take about a second.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "peers_io.h"

typedef struct cell_item {
    int64_t cx, cy, cz;
    uint32_t i;
} cell_item;

static int cmp_cell(const int64_t *a, const int64_t *b)
{
    int k;
    for (k = 0; k < 3; ++k)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int cmp_item(const void *pa, const void *pb)
{
    const cell_item *a = pa, *b = pb;
    int c = cmp_cell(&a->cx, &b->cx);
    if (c)
        return c;
    return a->i < b->i ? -1 : (a->i > b->i);
}

/* First item whose cell is >= key. */
static size_t lower_bound(const cell_item *items, size_t n, const int64_t *key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cmp_cell(&items[mid].cx, key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static int read_state(const char *path, size_t n, double *state)
{
    char magic[8];
    double dn;
    FILE *f = fopen(path, "rb");
    int bad;
    if (f == NULL) {
        fprintf(stderr, "peers_quality: state %s: cannot open\n", path);
        return 1;
    }
    bad = fread(magic, 1, 8, f) != 8 || memcmp(magic, "RBSSTAT1", 8) != 0 ||
          fread(&dn, sizeof dn, 1, f) != 1 || dn != (double)n ||
          fread(state, sizeof(double), 9 * n, f) != 9 * n;
    fclose(f);
    if (bad)
        fprintf(stderr, "peers_quality: state %s: not a state of %zu spheres\n", path, n);
    return bad;
}

int main(int argc, char **argv)
{
    peers_scene sc;
    double *st, rmax = 0.0, cell, g;
    double worst_ss = 0.0, worst_sp = 0.0, ke = 0.0, pe = 0.0;
    size_t i, j, p, m = 0, escaped = 0, nonfinite = 0, ss_over = 0, sp_over = 0;
    cell_item *items;

    if (argc != 3) {
        fprintf(stderr, "usage: peers_quality SCENE STATE\n");
        return 2;
    }
    if (peers_scene_read(argv[1], &sc))
        return 2;
    st = malloc((9 * sc.n + 1) * sizeof(double));
    items = malloc((sc.n + 1) * sizeof *items);
    if (st == NULL || items == NULL) {
        fprintf(stderr, "peers_quality: out of memory\n");
        return 2;
    }
    if (read_state(argv[2], sc.n, st))
        return 2;
    g = fabs(sc.gravity_z);

    /* Per sphere: finiteness, planes, energy. */
    for (i = 0; i < sc.n; ++i) {
        const double *s = &sc.spheres[8 * i], *x = &st[9 * i];
        double r = s[0], mass = s[1];
        int k, finite = 1, out = 0;
        for (k = 0; k < 9; ++k)
            finite &= isfinite(x[k]) != 0;
        if (!finite) {
            nonfinite++;
            escaped++;
            continue;
        }
        if (r > rmax)
            rmax = r;
        for (p = 0; p < sc.n_planes; ++p) {
            const double *q = &sc.planes[6 * p];
            double d = (x[0] - q[0]) * q[3] + (x[1] - q[1]) * q[4] + (x[2] - q[2]) * q[5];
            double ov = (r - d) / r;
            if (d < 0.0)
                out = 1;
            if (ov > worst_sp)
                worst_sp = ov;
            if (ov > 0.01)
                sp_over++;
        }
        escaped += (size_t)out;
        ke += 0.5 * mass * (x[3] * x[3] + x[4] * x[4] + x[5] * x[5]) +
              0.5 * 0.4 * mass * r * r * (x[6] * x[6] + x[7] * x[7] + x[8] * x[8]);
        pe += mass * g * x[2];
        items[m].i = (uint32_t)i;
        m++;
    }

    /* Sphere pairs through the grid: each pair once (j > i). */
    cell = 2.0 * rmax > 0.0 ? 2.0 * rmax : 1.0;
    for (i = 0; i < m; ++i) {
        const double *x = &st[9 * items[i].i];
        items[i].cx = (int64_t)floor(x[0] / cell);
        items[i].cy = (int64_t)floor(x[1] / cell);
        items[i].cz = (int64_t)floor(x[2] / cell);
    }
    qsort(items, m, sizeof *items, cmp_item);
    for (i = 0; i < m; ++i) {
        uint32_t a = items[i].i;
        const double *xa = &st[9 * a];
        double ra = sc.spheres[8 * a];
        int dx, dy, dz;
        for (dx = -1; dx <= 1; ++dx)
            for (dy = -1; dy <= 1; ++dy)
                for (dz = -1; dz <= 1; ++dz) {
                    int64_t key[3];
                    key[0] = items[i].cx + dx;
                    key[1] = items[i].cy + dy;
                    key[2] = items[i].cz + dz;
                    for (j = lower_bound(items, m, key);
                         j < m && cmp_cell(&items[j].cx, key) == 0; ++j) {
                        uint32_t b = items[j].i;
                        const double *xb = &st[9 * b];
                        double rb = sc.spheres[8 * b], d, ov;
                        if (b <= a)
                            continue;
                        d = sqrt((xa[0] - xb[0]) * (xa[0] - xb[0]) + (xa[1] - xb[1]) * (xa[1] - xb[1]) +
                                 (xa[2] - xb[2]) * (xa[2] - xb[2]));
                        ov = (ra + rb - d) / (ra < rb ? ra : rb);
                        if (ov > worst_ss)
                            worst_ss = ov;
                        if (ov > 0.01)
                            ss_over++;
                    }
                }
    }

    printf("{\"n\": %zu, \"nonfinite\": %zu, \"escaped\": %zu, \"max_ss_overlap_rel\": %.6g, "
           "\"max_sp_overlap_rel\": %.6g, \"ss_over_1pct\": %zu, \"sp_over_1pct\": %zu, "
           "\"kinetic\": %.9g, \"potential\": %.9g, \"energy\": %.9g}\n",
           sc.n, nonfinite, escaped, worst_ss, worst_sp, ss_over, sp_over, ke, pe, ke + pe);
    free(items);
    free(st);
    peers_scene_free(&sc);
    return 0;
}
