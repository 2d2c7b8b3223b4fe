/*
 * soft_rows.h - the soft step's contact rows, four lanes at a time
 * (internal; the body of soft_rows.c and soft_rows_avx.c, which include it
 * once each with their backend of core/wide.h and name the table it ends
 * with through RBS__SOFT_KERNELS).
 *
 * A row is step_soft.c's row of one contact (docs/methods.md, "soft"):
 *   relative velocity at the contact  rv = v_a - v_b + (la w_a - lb w_b) x n
 *   (la = -r_a: both levers along n, the bodies centred and isotropic)
 *   normal impulse change dj:
 *     apart (s > 0)       -(vn + s / h) mn          close the gap, no more
 *                         (the frame's last relax: 0 for a pair still apart
 *                         by more than the slop that took no impulse yet)
 *     touching, solve     -mass_scale (vn + max(push, -most)) mn
 *                         - impulse_scale jn        soft: pushes the overlap
 *                                                   beyond the slop out
 *     touching, relax     -vn mn                    rigid (times RBS__SOFT_OVER
 *                                                   for a lane that came in
 *                                                   loaded)
 *     restitution         -(vn + e v0) mn           leave at e times v0
 *   (s the separation now, gap + n . (d_a - d_b); a guard's s is taken
 *   RBS__GUARD_DEPTH of the smaller radius deeper), accumulated as jn >= 0;
 *   friction within Coulomb's cone of the new jn: the stick impulse
 *   -vt mt added to the accumulated jt, scaled to mu_k jn when it leaves
 *   the static cone mu_s jn; both impulses applied to the pair.
 * Each branch is computed for every lane and the lane's own is selected, as
 * C's ?: would pick it, so a lane gives the bits the row gives alone.
 */
#include <string.h>

#include "core/soft.h"
#include "core/wide.h"

/* Inlined into each stage's pass, so that a row is compiled for its stage
 * and kind of contact (GCC and Clang). */
#if defined(__GNUC__)
#define ROW_INLINE inline __attribute__((always_inline))
#else
#define ROW_INLINE inline
#endif

/* The number of bits set among four. */
static inline unsigned bits4(unsigned b) { return (b & 1u) + (b >> 1 & 1u) + (b >> 2 & 1u) + (b >> 3 & 1u); }

/* The bodies of a chunk as lanes: x[0..11] = v (3), w (3), d (3), 1/m,
 * 1/I, r (the records' first three blocks). */
enum { BV = 0, BW = 3, BD = 6, BIM = 9, BII = 10, BR = 11 };

static ROW_INLINE void gather(const rbs__soft_rows *k, const rbs__chunk *c, const uint32_t *slot, double *zero,
                              rbs__wd *x, double **rec)
{
    /* (one by one: GCC would make vector arithmetic of a loop here) */
    rec[0] = k->rec + (size_t)RBS__REC * slot[0];
    rec[1] = k->rec + (size_t)RBS__REC * slot[1];
    rec[2] = k->rec + (size_t)RBS__REC * slot[2];
    rec[3] = k->rec + (size_t)RBS__REC * slot[3];
    if (c->count < RBS__LANES) {
        /* unused lanes: a record of zeros of this row's own */
        uint32_t l;
        memset(zero, 0, RBS__REC * sizeof(double));
        for (l = c->count; l < RBS__LANES; ++l)
            rec[l] = zero;
    }
    wd_gather((const double *const *)rec, 3, x);
}

/* An impulse j on the lanes' bodies x, with the angular impulse t (per unit
 * of lever) times lever l: v += j / m, w += (t l) / I. */
static ROW_INLINE void take(rbs__wd *x, rbs__wd jx, rbs__wd jy, rbs__wd jz, const rbs__wd *t, rbs__wd l)
{
    x[BV] = wd_add(x[BV], wd_mul(jx, x[BIM]));
    x[BV + 1] = wd_add(x[BV + 1], wd_mul(jy, x[BIM]));
    x[BV + 2] = wd_add(x[BV + 2], wd_mul(jz, x[BIM]));
    x[BW] = wd_add(x[BW], wd_mul(wd_mul(t[0], l), x[BII]));
    x[BW + 1] = wd_add(x[BW + 1], wd_mul(wd_mul(t[1], l), x[BII]));
    x[BW + 2] = wd_add(x[BW + 2], wd_mul(wd_mul(t[2], l), x[BII]));
}

/* Apply the impulse j (on a; -j on b) to the lanes' bodies and write their
 * velocities back (b not at all when it is a plane). */
static ROW_INLINE void apply(rbs__wd *xa, rbs__wd *xb, double **ra, double **rb, rbs__wd nx, rbs__wd ny, rbs__wd nz,
                         rbs__wd jx, rbs__wd jy, rbs__wd jz, rbs__wd lb, int plane)
{
    /* t = n x j; a takes t la (la = -r_a), b takes -t lb */
    rbs__wd t[3];
    t[0] = wd_sub(wd_mul(ny, jz), wd_mul(nz, jy));
    t[1] = wd_sub(wd_mul(nz, jx), wd_mul(nx, jz));
    t[2] = wd_sub(wd_mul(nx, jy), wd_mul(ny, jx));
    take(xa, jx, jy, jz, t, wd_neg(xa[BR]));
    wd_scatter(ra, 2, xa);
    if (plane)
        return;
    take(xb, wd_neg(jx), wd_neg(jy), wd_neg(jz), t, wd_neg(lb));
    wd_scatter(rb, 2, xb);
}

/* 1 / x where x > 0, else 0 (an unused lane's records are zeros). */
static ROW_INLINE rbs__wd inverse_or_zero(rbs__wd x)
{
    return wd_sel(wm_gt(x, wd_zero()), wd_div(wd_set(1.0), x), wd_zero());
}

/* Apply every lane's accumulated impulses again (the warm start of a
 * sub-step): j = n jn + jt. */
static ROW_INLINE void warm_chunk(const rbs__soft_rows *k, rbs__chunk *c, int plane)
{
    rbs__wd xa[12], xb[12], nx, ny, nz, jn, jx, jy, jz;
    double *ra[RBS__LANES], *rb[RBS__LANES], za[RBS__REC], zb[RBS__REC];
    jn = wd_load(c->jn);
    jx = wd_load(c->jx);
    jy = wd_load(c->jy);
    jz = wd_load(c->jz);
    if (wm_bits(wm_or(wm_or(wm_ne(jn, wd_zero()), wm_ne(jx, wd_zero())), wm_or(wm_ne(jy, wd_zero()),
                                                                            wm_ne(jz, wd_zero())))) == 0)
        return; /* (nothing to apply: a pile's falling contacts) */
    nx = wd_load(c->nx);
    ny = wd_load(c->ny);
    nz = wd_load(c->nz);
    jx = wd_add(wd_mul(nx, jn), jx);
    jy = wd_add(wd_mul(ny, jn), jy);
    jz = wd_add(wd_mul(nz, jn), jz);
    gather(k, c, c->a, za, xa, ra);
    if (!plane)
        gather(k, c, c->b, zb, xb, rb);
    apply(xa, xb, ra, rb, nx, ny, nz, jx, jy, jz, wd_load(c->lb), plane);
}

/* Clear RBS__CH_WARM on c's lone lanes -- each body of the lane fixed (1/m
 * 0), a plane, or in no other contact that came in loaded (touched without
 * RBS__LOADED_MORE): their relax rows stay rigid (soft.h, RBS__SOFT_OVER).
 * In the warm start, once the frame's records are made. */
static ROW_INLINE void lone_lanes(const rbs__soft_rows *k, rbs__chunk *c)
{
    const unsigned f = c->flags, warm = f >> RBS__CH_WARM & 15u;
    unsigned linked = 0; /* bit l: lane l is not lone */
    uint32_t l;
    if (warm == 0)
        return;
    for (l = 0; l < c->count; ++l) {
        /* (a plane's lane reads a's byte twice: b is no record) */
        const uint32_t b = f >> (RBS__CH_PLANE + l) & 1u ? c->a[l] : c->b[l];
        linked |= ((k->touched[c->a[l]] | k->touched[b]) & RBS__LOADED_MORE) != 0 ? 1u << l : 0u;
    }
    if (f >> RBS__CH_FIXED & 1u) {
        /* (a fixed sphere's own contacts do not link it: it does not move) */
        linked = 0;
        for (l = 0; l < c->count; ++l) {
            const uint32_t a = c->a[l], b = c->b[l];
            const int plane = f >> (RBS__CH_PLANE + l) & 1u;
            linked |= (((k->touched[a] & RBS__LOADED_MORE) && k->rec[(size_t)RBS__REC * a + RBS__REC_IM] != 0.0) ||
                       (!plane && (k->touched[b] & RBS__LOADED_MORE) &&
                        k->rec[(size_t)RBS__REC * b + RBS__REC_IM] != 0.0))
                      << l;
        }
    }
    c->flags &= ~((warm & ~linked) << RBS__CH_WARM);
}

/* One row of each lane of c in stage; active: the lanes it may change (bit
 * l: lane l; the others keep their impulses and give nothing). */
static ROW_INLINE void row_chunk(const rbs__soft_rows *k, rbs__chunk *c, int stage, int plane, unsigned active,
                                 rbs__soft_report *report)
{
    rbs__wd xa[12], xb[12], nx, ny, nz, la, lb, ux, uy, uz, rvx, rvy, rvz, vn, im, mn, jn0, jn1, dj, t, dn, jx, jy, jz;
    rbs__wd jtx, jty, jtz, curved = wd_zero();
    rbs__wm act, fixed = wm_from_bits(0u);
    double *ra[RBS__LANES], *rb[RBS__LANES], za[RBS__REC], zb[RBS__REC];
    const rbs__wd zero = wd_zero();
    unsigned flags = c->flags;
    int some;

    gather(k, c, c->a, za, xa, ra);
    if (!plane)
        gather(k, c, c->b, zb, xb, rb);
    nx = wd_load(c->nx);
    ny = wd_load(c->ny);
    nz = wd_load(c->nz);
    la = wd_neg(xa[BR]);
    lb = plane ? wd_zero() : wd_load(c->lb);
    if (!plane && (flags >> RBS__CH_FIXED & 1u)) {
        /* a lane against a fixed sphere: the normal and separation of now
         * (curved), from the centres' offset at detection (L + gap) n plus
         * the displacements (docs/methods.md, "soft") */
        fixed = wm_and(wm_or(wm_le(xa[BIM], zero), wm_le(xb[BIM], zero)), wm_from_bits(active));
        if (wm_bits(fixed)) {
            /* (touching at detection: n is the line of the centres) */
            rbs__wd rm = wd_sel(wm_lt(xa[BR], xb[BR]), xa[BR], xb[BR]);
            fixed = wm_and(fixed, wm_le(wd_load(c->gap), wd_mul(wd_set(k->slop), rm)));
        }
        if (wm_bits(fixed)) {
            rbs__wd len = wd_add(xa[BR], xb[BR]), reach = wd_add(len, wd_load(c->gap));
            rbs__wd px = wd_add(wd_mul(reach, nx), wd_sub(xa[BD], xb[BD]));
            rbs__wd py = wd_add(wd_mul(reach, ny), wd_sub(xa[BD + 1], xb[BD + 1]));
            rbs__wd pz = wd_add(wd_mul(reach, nz), wd_sub(xa[BD + 2], xb[BD + 2]));
            rbs__wd dist = wd_sqrt(wd_dot3(px, py, pz, px, py, pz));
            fixed = wm_and(fixed, wm_gt(dist, zero));
            nx = wd_sel(fixed, wd_div(px, dist), nx);
            ny = wd_sel(fixed, wd_div(py, dist), ny);
            nz = wd_sel(fixed, wd_div(pz, dist), nz);
            curved = wd_sub(dist, len);
        }
    }

    /* rv = v_a - v_b + (la w_a - lb w_b) x n, and its normal part */
    if (plane) {
        ux = wd_mul(la, xa[BW]);
        uy = wd_mul(la, xa[BW + 1]);
        uz = wd_mul(la, xa[BW + 2]);
        rvx = xa[BV];
        rvy = xa[BV + 1];
        rvz = xa[BV + 2];
    } else {
        ux = wd_sub(wd_mul(la, xa[BW]), wd_mul(lb, xb[BW]));
        uy = wd_sub(wd_mul(la, xa[BW + 1]), wd_mul(lb, xb[BW + 1]));
        uz = wd_sub(wd_mul(la, xa[BW + 2]), wd_mul(lb, xb[BW + 2]));
        rvx = wd_sub(xa[BV], xb[BV]);
        rvy = wd_sub(xa[BV + 1], xb[BV + 1]);
        rvz = wd_sub(xa[BV + 2], xb[BV + 2]);
    }
    rvx = wd_add(rvx, wd_sub(wd_mul(uy, nz), wd_mul(uz, ny)));
    rvy = wd_add(rvy, wd_sub(wd_mul(uz, nx), wd_mul(ux, nz)));
    rvz = wd_add(rvz, wd_sub(wd_mul(ux, ny), wd_mul(uy, nx)));
    vn = wd_dot3(rvx, rvy, rvz, nx, ny, nz);
    /* the normal effective mass 1 / (1/m_a + 1/m_b) (the levers lie along n),
     * from the records (1/m: 0 for a fixed sphere; a plane has none) */
    im = plane ? xa[BIM] : wd_add(xa[BIM], xb[BIM]);
    mn = inverse_or_zero(im);
    jn0 = wd_load(c->jn);

    if (stage == RBS__SOFT_RESTITUTION) {
        dj = wd_mul(wd_neg(wd_add(vn, wd_load(c->eb))), mn);
    } else {
        /* the pair's smaller radius, its slop and push limit */
        rbs__wd rmin = plane ? xa[BR] : wd_sel(wm_lt(xa[BR], xb[BR]), xa[BR], xb[BR]);
        rbs__wd slop = wd_mul(wd_set(k->slop), rmin), s, apart, touch;
        rbs__wm touched = wm_from_bits(flags >> RBS__CH_TOUCHED);
        if (plane) {
            s = wd_add(wd_load(c->gap), wd_dot3(nx, ny, nz, xa[BD], xa[BD + 1], xa[BD + 2]));
        } else {
            s = wd_add(wd_load(c->gap), wd_dot3(nx, ny, nz, wd_sub(xa[BD], xb[BD]), wd_sub(xa[BD + 1], xb[BD + 1]),
                                                wd_sub(xa[BD + 2], xb[BD + 2])));
            if (wm_bits(fixed))
                s = wd_sel(fixed, curved, s);
        }
        if (stage == RBS__SOFT_RELAX_REPORT) {
            /* (the frame's positions are final: the report of its end) */
            int l;
            double deep[RBS__LANES];
            report->touching += bits4(wm_bits(wm_le(s, slop)) & active);
            wd_store(deep, wd_neg(s));
            for (l = 0; l < RBS__LANES; ++l)
                if ((active >> l & 1u) && deep[l] > report->deepest)
                    report->deepest = deep[l];
        }
        if (flags >> RBS__CH_GUARD & 15u)
            s = wd_sel(wm_from_bits(flags >> RBS__CH_GUARD), wd_add(s, wd_mul(wd_set(k->guard), rmin)), s);
        /* apart: close the gap within the sub-step and no more */
        apart = wd_mul(wd_neg(wd_add(vn, wd_mul(s, wd_set(k->inv_h)))), mn);
        if (stage == RBS__SOFT_RELAX_REPORT) {
            /* an impact due after the frame's end waits for the next one */
            rbs__wm wait = wm_andnot(wm_and(wm_gt(apart, zero), wm_gt(s, slop)), touched);
            apart = wd_sel(wait, zero, apart);
        }
        if (stage == RBS__SOFT_SOLVE) {
            rbs__wd over = wd_add(s, slop), most = wd_neg(wd_mul(wd_set(k->push), rmin)), push, hold;
            /* the limit, never below twice the push that holds the lane's
             * load (a steady row gives dj = 0 at vn = 0 when push = -jn
             * (1/m_eff) / a, a = mass_scale / impulse_scale): 1 % of the
             * radius a sub-step alone let a ball of r = 1 mm at dt = 0.03 s
             * (g dt^2 > 4.2 r at 3 sub-steps) sink through the floor */
            hold = wd_neg(wd_mul(wd_mul(jn0, im), wd_set(k->hold)));
            most = wd_sel(wm_lt(hold, most), hold, most);
            over = wd_sel(wm_lt(over, zero), over, zero);
            push = wd_mul(wd_set(k->bias_rate), over);
            push = wd_sel(wm_lt(push, most), most, push);
            touch = wd_sub(wd_mul(wd_mul(wd_neg(wd_set(k->mass_scale)), wd_add(vn, push)), mn),
                           wd_mul(wd_set(k->impulse_scale), jn0));
        } else {
            touch = wd_mul(wd_neg(vn), mn);
            if (flags >> RBS__CH_WARM & 15u)
                /* (a lane that came in loaded over-relaxes: RBS__SOFT_OVER) */
                touch = wd_sel(wm_from_bits(flags >> RBS__CH_WARM), wd_mul(touch, wd_set(RBS__SOFT_OVER)), touch);
        }
        dj = wd_sel(wm_gt(s, zero), apart, touch);
    }

    /* accumulate: jn >= 0, the impulse along n */
    t = wd_add(jn0, dj);
    jn1 = wd_sel(wm_lt(t, zero), zero, t);
    act = wm_from_bits(active);
    /* (the lanes not active keep their impulses: restitution's that do not
     * bounce, and pass_stage's lanes with and without a fixed sphere) */
    some = stage == RBS__SOFT_RESTITUTION || active != (1u << c->count) - 1u;
    if (some)
        jn1 = wd_sel(act, jn1, jn0);
    dn = wd_sub(jn1, jn0);
    jx = wd_mul(nx, dn);
    jy = wd_mul(ny, dn);
    jz = wd_mul(nz, dn);
    if (stage == RBS__SOFT_RESTITUTION)
        report->restituted += bits4(wm_bits(wm_ne(jn1, jn0)) & active);
    flags |= (wm_bits(wm_gt(jn1, zero)) & active) << RBS__CH_TOUCHED;
    wd_store(c->jn, jn1);

    jtx = wd_load(c->jx);
    jty = wd_load(c->jy);
    jtz = wd_load(c->jz);
    if (k->friction) {
        /* the stick impulse, kept in the cone of the new jn */
        rbs__wd mus, muk, vtx, vty, vtz, cx, cy, cz, l2, lim, kt, mt;
        rbs__wm on;
        if (c->row[0] == c->row[1] && c->row[0] == c->row[2] && c->row[0] == c->row[3]) {
            /* (one pair: a scene of one material, most chunks of a few) */
            mus = wd_set(k->pair[c->row[0]].mu_s);
            muk = wd_set(k->pair[c->row[0]].mu_k);
        } else {
            const rbs__pair *p0 = &k->pair[c->row[0]], *p1 = &k->pair[c->row[1]], *p2 = &k->pair[c->row[2]],
                            *p3 = &k->pair[c->row[3]];
            mus = wd_make(p0->mu_s, p1->mu_s, p2->mu_s, p3->mu_s);
            muk = wd_make(p0->mu_k, p1->mu_k, p2->mu_k, p3->mu_k);
        }
        if (flags >> RBS__CH_SLIP & 0xFu)
            /* lanes that came in slipping: kinetic friction only */
            mus = wd_sel(wm_from_bits(flags >> RBS__CH_SLIP & 0xFu), muk, mus);
        on = wm_and(wm_or(wm_gt(jn1, zero), wm_or(wm_or(wm_ne(jtx, zero), wm_ne(jty, zero)), wm_ne(jtz, zero))),
                    wm_or(wm_gt(mus, zero), wm_gt(muk, zero)));
        /* the tangent effective mass 1 / (1/m_a + 1/m_b + r_a^2/I_a +
         * l_b^2/I_b), summed in this order (1/I: 0 for a fixed sphere) */
        kt = wd_add(im, wd_mul(wd_mul(la, la), xa[BII]));
        if (!plane)
            kt = wd_add(kt, wd_mul(wd_mul(lb, lb), xb[BII]));
        mt = wd_neg(inverse_or_zero(kt));
        rbs__wm stick;
        if (some)
            on = wm_and(on, act);
        vtx = wd_sub(rvx, wd_mul(nx, vn));
        vty = wd_sub(rvy, wd_mul(ny, vn));
        vtz = wd_sub(rvz, wd_mul(nz, vn));
        /* a slip to stop: vt not 0 (|vt|^2 > 0 missed slips under 1e-162 m/s,
         * whose square is 0) */
        stick = wm_or(wm_or(wm_ne(vtx, zero), wm_ne(vty, zero)), wm_ne(vtz, zero));
        cx = wd_add(jtx, wd_sel(stick, wd_mul(vtx, mt), zero));
        cy = wd_add(jty, wd_sel(stick, wd_mul(vty, mt), zero));
        cz = wd_add(jtz, wd_sel(stick, wd_mul(vtz, mt), zero));
        l2 = wd_dot3(cx, cy, cz, cx, cy, cz);
        lim = wd_mul(mus, jn1);
        if (wm_bits(wm_and(wm_gt(l2, wd_mul(lim, lim)), on))) {
            /* (a square root only when a lane slides) */
            rbs__wm slide = wm_gt(l2, wd_mul(lim, lim));
            rbs__wd scale = wd_div(wd_mul(muk, jn1), wd_sqrt(l2));
            cx = wd_sel(slide, wd_mul(cx, scale), cx);
            cy = wd_sel(slide, wd_mul(cy, scale), cy);
            cz = wd_sel(slide, wd_mul(cz, scale), cz);
        }
        jx = wd_sel(on, wd_add(jx, wd_sub(cx, jtx)), jx);
        jy = wd_sel(on, wd_add(jy, wd_sub(cy, jty)), jy);
        jz = wd_sel(on, wd_add(jz, wd_sub(cz, jtz)), jz);
        wd_store(c->jx, wd_sel(on, cx, jtx));
        wd_store(c->jy, wd_sel(on, cy, jty));
        wd_store(c->jz, wd_sel(on, cz, jtz));
    }
    c->flags = flags;
    apply(xa, xb, ra, rb, nx, ny, nz, jx, jy, jz, lb, plane);
}

/* Lane l's separation now, m, for row_lanes' order: the gap at detection
 * plus the displacements along n (a fixed sphere's lane too: the order
 * needs no turned normal). */
static inline double lane_separation(const rbs__soft_rows *k, const rbs__chunk *c, uint32_t l)
{
    const double *ra = k->rec + (size_t)RBS__REC * c->a[l];
    double dx = ra[RBS__REC_D], dy = ra[RBS__REC_D + 1], dz = ra[RBS__REC_D + 2];
    if (!(c->flags >> (RBS__CH_PLANE + l) & 1u)) {
        const double *rb = k->rec + (size_t)RBS__REC * c->b[l];
        dx -= rb[RBS__REC_D];
        dy -= rb[RBS__REC_D + 1];
        dz -= rb[RBS__REC_D + 2];
    }
    return c->gap[l] + (c->nx[l] * dx + c->ny[l] * dy + c->nz[l] * dz);
}

/* Whether lane l of c is touching now: its separation (lane_separation)
 * within the slop of its smaller radius. */
static inline int lane_touching(const rbs__soft_rows *k, const rbs__chunk *c, uint32_t l)
{
    double r = k->rec[(size_t)RBS__REC * c->a[l] + RBS__REC_R];
    if (!(c->flags >> (RBS__CH_PLANE + l) & 1u)) {
        const double rb = k->rec[(size_t)RBS__REC * c->b[l] + RBS__REC_R];
        r = rb < r ? rb : r;
    }
    return !(lane_separation(k, c, l) > k->slop * r);
}

/* The lanes of c (a chunk with RBS__CH_FIXED) whose pair has a fixed sphere
 * (1/m 0 in its record), as bits. */
static inline unsigned fixed_lanes(const rbs__soft_rows *k, const rbs__chunk *c)
{
    unsigned bits = 0;
    uint32_t l;
    for (l = 0; l < c->count; ++l)
        if (!(c->flags >> (RBS__CH_PLANE + l) & 1u) && (k->rec[(size_t)RBS__REC * c->a[l] + RBS__REC_IM] == 0.0 ||
                                                         k->rec[(size_t)RBS__REC * c->b[l] + RBS__REC_IM] == 0.0))
            bits |= 1u << l;
    return bits;
}

/* The lanes of c in bits (bit l: lane l) one after the other, each alone
 * in a chunk of its own (lane 0; the others unused).  In a SOLVE or RELAX
 * pass the lanes touching now (within their slop) go first, then those
 * apart, each set in lane order: the lanes of a serial chunk may share a
 * body, and a touching lane's row takes back what the warm start gave
 * beyond its need (the impulse that stopped an impact, given back at the
 * next sub-step's start) before a speculative row of the same body reads
 * that velocity as an approach -- solved first, the row of a wall 1.8 m
 * away took it as an impulse of its own, and a ball between two walls
 * (v h > 1.8 m) worked its way out of the box (docs/methods.md, "soft"). */
static void row_lanes(const rbs__soft_rows *k, rbs__chunk *c, unsigned bits, int stage, rbs__soft_report *report)
{
    uint32_t l, order[RBS__LANES], m = 0, x;
    if (stage == RBS__SOFT_SOLVE || stage == RBS__SOFT_RELAX || stage == RBS__SOFT_RELAX_REPORT) {
        unsigned apart = 0;
        for (l = 0; l < c->count; ++l) {
            if (!(bits >> l & 1u))
                continue;
            if (lane_touching(k, c, l))
                order[m++] = l;
            else
                apart |= 1u << l;
        }
        for (l = 0; l < c->count; ++l)
            if (apart >> l & 1u)
                order[m++] = l;
    } else {
        for (l = 0; l < c->count; ++l)
            if (bits >> l & 1u)
                order[m++] = l;
    }
    for (x = 0; x < m; ++x) {
        rbs__chunk one;
        unsigned bit, f = c->flags;
        int plane;
        l = order[x];
        bit = 1u << l;
        plane = (f >> RBS__CH_PLANE & bit) != 0;
        memset(&one, 0, sizeof one);
        one.a[0] = c->a[l];
        one.b[0] = c->b[l];
        one.nx[0] = c->nx[l];
        one.ny[0] = c->ny[l];
        one.nz[0] = c->nz[l];
        one.lb[0] = c->lb[l];
        one.gap[0] = c->gap[l];
        one.jn[0] = c->jn[l];
        one.jx[0] = c->jx[l];
        one.jy[0] = c->jy[l];
        one.jz[0] = c->jz[l];
        one.row[0] = c->row[l];
        one.eb[0] = c->eb[l];
        one.count = 1;
        one.flags = ((f >> RBS__CH_TOUCHED >> l & 1u) << RBS__CH_TOUCHED) |
                    ((f >> RBS__CH_BOUNCE >> l & 1u) << RBS__CH_BOUNCE) |
                    ((f >> RBS__CH_GUARD >> l & 1u) << RBS__CH_GUARD) |
                    ((f >> RBS__CH_PLANE >> l & 1u) << RBS__CH_PLANE) |
                    ((f >> RBS__CH_SLIP >> l & 1u) << RBS__CH_SLIP) |
                    ((f >> RBS__CH_WARM >> l & 1u) << RBS__CH_WARM) | (f & 1u << RBS__CH_FIXED);
        if (stage < 0) {
            /* (each kind compiled on its own, its branches known) */
            if (plane)
                warm_chunk(k, &one, 1);
            else
                warm_chunk(k, &one, 0);
            continue;
        }
        if (stage == RBS__SOFT_RESTITUTION &&
            !((one.flags >> RBS__CH_TOUCHED) & (one.flags >> RBS__CH_BOUNCE) & 1u))
            continue;
        if (plane)
            row_chunk(k, &one, stage, 1, 1u, report);
        else
            row_chunk(k, &one, stage, 0, 1u, report);
        c->jn[l] = one.jn[0];
        c->jx[l] = one.jx[0];
        c->jy[l] = one.jy[0];
        c->jz[l] = one.jz[0];
        c->flags |= (one.flags >> RBS__CH_TOUCHED & 1u) << (RBS__CH_TOUCHED + l);
    }
}

/* A wedge's lane o let go (its change dj_o; soft_rows.h, row_wedge), and
 * the other lane's row after it, within its bounds, into dj. */
static inline void wedge_let_go(double im, double d, const double *rhs, const double *jn, const int *wait, uint32_t o,
                                double dj_o, double *dj)
{
    const uint32_t e = 1u - o;
    dj[o] = dj_o;
    dj[e] = (rhs[e] - d * im * dj[o]) / im;
    if (jn[e] + dj[e] < 0.0)
        dj[e] = -jn[e];
    else if (wait[e] && dj[e] > 0.0)
        dj[e] = 0.0;
}

/* Whether lane o, let go in dj, stays content: its row, with the other's
 * change, asks for no more impulse (or it waits: it may take none). */
static inline int wedge_holds(double im, double d, const double *rhs, const int *wait, uint32_t o, const double *dj)
{
    return wait[o] || rhs[o] - im * (dj[o] + d * dj[1u - o]) <= 0.0;
}

/* The wedges of chunk c (RBS__CH_WEDGE: lanes l, l + 1 are the contacts of
 * one sphere with two planes whose normals n1, n2 are nearly opposed) in a
 * SOLVE, RELAX or RESTITUTION pass (the warm start takes the lanes one
 * after the other, as any serial chunk's).  One after the other, the two
 * rows cannot hold the sphere: the mode in which it sinks into both (the
 * impulses j1 = j2) has an effective mass 1 / (1 + n1.n2) times either
 * row's -- 286 times at walls 0.1 degrees off vertical -- so each pass
 * moves it by about that fraction of what it needs, the load is carried
 * by the warm-started impulses alone, and the soft rows' impulse scale
 * lets those follow the depth only some sub-steps late: a spring with a
 * lag, which gains energy once h omega is large (a linearisation of the
 * frame: its largest eigenvalue 1.00014 at 0.1 degrees, 1.0006 at 1,
 * unstable above RBS__SOFT_HERTZ 0.31 and 0.33; stable at 1/4, the rate before
 * session 37).  So the two rows are solved as one 2 x 2 block, on the
 * pair's matrix K = (1/m) [1 d; d 1], d = n1.n2 (the levers lie along the
 * normals: no turning): each lane's row is an equation on (K dj)_i --
 * apart, -(vn + s / h); touching, rigid (relax) -vn, or soft (solve)
 * -mass_scale (vn + push) - impulse_scale (K j)_i; restitution, when both
 * lanes bounce, -(vn + e v0) -- which for one row alone is row_chunk's
 * (one after the other, the restitution rows met an impact into the wedge
 * plastically); a lane whose impulse would go below 0 (or, in the
 * frame's last relax, an impact due after the frame that would take one)
 * lets go, and the other takes its own row after it.  With friction, or a
 * fixed sphere, the rows one after the other, as before.  At rest the
 * soft block's push is impulse_scale / mass_scale (K j)_i, the velocity
 * the impulses give along n_i: a load L on the wedge (along the bisector)
 * sinks it by L / (m omega^2), as a ball on a floor (each wall's overlap
 * that times sqrt((1 + d) / 2)), where the rows sank each wall by its own
 * load, L / sqrt(2 (1 + d)), over m omega^2. */
static void row_wedge(const rbs__soft_rows *k, rbs__chunk *c, int stage, rbs__soft_report *report)
{
    uint32_t l;
    for (l = 0; l + 1u < c->count; l += 2u) {
        double *rec = k->rec + (size_t)RBS__REC * c->a[l];
        const double im = rec[RBS__REC_IM], r = rec[RBS__REC_R];
        const double slop = k->slop * r;
        double n[2][3], vn[2], s[2], rhs[2], dj[2], jn[2], d, den;
        int wait[2], bad[2];
        uint32_t i;
        const rbs__pair *p0 = &k->pair[c->row[l]], *p1 = &k->pair[c->row[l + 1u]];
        const int block = im > 0.0 && !(k->friction && (p0->mu_s > 0.0 || p0->mu_k > 0.0 || p1->mu_s > 0.0 ||
                                                        p1->mu_k > 0.0));
        for (i = 0; i < 2u; ++i) {
            const uint32_t x = l + i;
            n[i][0] = c->nx[x];
            n[i][1] = c->ny[x];
            n[i][2] = c->nz[x];
            vn[i] = rec[RBS__REC_V] * n[i][0] + rec[RBS__REC_V + 1] * n[i][1] + rec[RBS__REC_V + 2] * n[i][2];
            s[i] = c->gap[x] +
                   (n[i][0] * rec[RBS__REC_D] + n[i][1] * rec[RBS__REC_D + 1] + n[i][2] * rec[RBS__REC_D + 2]);
            jn[i] = c->jn[x];
            /* the frame's last relax: an impact due after the frame takes
             * no new impulse (row_chunk) */
            wait[i] = stage == RBS__SOFT_RELAX_REPORT && s[i] > slop && !(c->flags >> (RBS__CH_TOUCHED + x) & 1u);
        }
        d = n[0][0] * n[1][0] + n[0][1] * n[1][1] + n[0][2] * n[1][2];
        den = im * (1.0 - d * d);
        if (!block || !(den > 0.0)) {
            /* (with friction, or a fixed sphere: the rows one after the other) */
            row_lanes(k, c, 3u << l, stage, report);
            continue;
        }
        if (stage == RBS__SOFT_RESTITUTION &&
            !(c->flags >> (RBS__CH_TOUCHED + l) & c->flags >> (RBS__CH_BOUNCE + l) &
              c->flags >> (RBS__CH_TOUCHED + l + 1u) & c->flags >> (RBS__CH_BOUNCE + l + 1u) & 1u)) {
            /* (a lane that does not bounce keeps its impulse: the other's
             * row alone) */
            row_lanes(k, c, 3u << l, stage, report);
            continue;
        }
        /* each lane's row as an equation on K dj: apart, close the gap
         * within the sub-step, -(vn + s / h); touching, rigid (relax) -vn,
         * or soft (solve) -mass_scale (vn + push) - impulse_scale (K j)_i,
         * the push and its limit as row_chunk makes them; restitution,
         * leave at e times the frame-start approach, -(vn + e v0) */
        for (i = 0; i < 2u; ++i) {
            if (stage == RBS__SOFT_RESTITUTION) {
                rhs[i] = -(vn[i] + c->eb[l + i]);
            } else if (s[i] > 0.0) {
                rhs[i] = -(vn[i] + s[i] * k->inv_h);
            } else if (stage == RBS__SOFT_SOLVE) {
                const double over = s[i] + slop < 0.0 ? s[i] + slop : 0.0;
                double most = -(k->push * r), hold = -(jn[i] * im * k->hold), push = k->bias_rate * over;
                most = hold < most ? hold : most;
                rhs[i] = -k->mass_scale * (vn[i] + (push < most ? most : push)) -
                         k->impulse_scale * im * (jn[i] + d * jn[1u - i]);
            } else {
                rhs[i] = -vn[i];
            }
        }
        /* dj = K^-1 rhs, K^-1 = [1 -d; -d 1] / (im (1 - d^2)) */
        for (i = 0; i < 2u; ++i)
            dj[i] = (rhs[i] - d * rhs[1u - i]) / den;
        for (i = 0; i < 2u; ++i)
            bad[i] = jn[i] + dj[i] < 0.0 || (wait[i] && dj[i] > 0.0);
        if (bad[0] || bad[1]) {
            /* a lane that would pull lets go (its impulse to 0; a waiting
             * one keeps it), and the other takes its own row after that,
             * within the same bounds -- unless the lane let go would then
             * push (its row, with the other's change, still asks for
             * more) and the other way round holds: then that lane lets go
             * instead.  (The lane that would pull in the block's answer
             * need not be the one to let go: a ball flying across a groove
             * 0.001 degrees from parallel towards one wall, the other
             * behind it, both within the frame's reach, made both lanes
             * pull in the nearly singular block; the first let go was the
             * wall ahead, nothing stopped the ball, and from 1e3 m/s it
             * went 0.2 m into the wall -- a probe of session 51.) */
            double alt[2];
            uint32_t o = bad[0] ? 0u : 1u;
            wedge_let_go(im, d, rhs, jn, wait, o, jn[o] + dj[o] < 0.0 ? -jn[o] : 0.0, dj);
            if (!wedge_holds(im, d, rhs, wait, o, dj)) {
                o = 1u - o;
                wedge_let_go(im, d, rhs, jn, wait, o, -jn[o], alt);
                if (wedge_holds(im, d, rhs, wait, o, alt)) {
                    dj[0] = alt[0];
                    dj[1] = alt[1];
                }
            }
        }
        for (i = 0; i < 2u; ++i) {
            const uint32_t x = l + i;
            const double j = jn[i] + dj[i] < 0.0 ? 0.0 : jn[i] + dj[i], dn = j - jn[i];
            rec[RBS__REC_V] += n[i][0] * dn * im;
            rec[RBS__REC_V + 1] += n[i][1] * dn * im;
            rec[RBS__REC_V + 2] += n[i][2] * dn * im;
            if (stage == RBS__SOFT_RESTITUTION)
                report->restituted += j != jn[i];
            c->jn[x] = j;
            if (j > 0.0)
                c->flags |= 1u << (RBS__CH_TOUCHED + x);
            if (stage == RBS__SOFT_RELAX_REPORT) {
                report->touching += s[i] <= slop;
                if (-s[i] > report->deepest)
                    report->deepest = -s[i];
            }
        }
    }
}

/* Chunks a pass asks the memory for ahead of the one it takes: a chunk's
 * lines are read out of order (the warm start reads its impulses first,
 * a row its header, normal, gap, impulses), which the processor's own
 * stream detection follows poorly; at 10^5 spheres, where the chunks no
 * longer fit the caches, this took a settled stack 0.92x the time, at
 * 1,000 1.00x (paired whole-process timings, docs/methods.md). */
#define RBS__AHEAD 4

/* The lanes with a fixed sphere of the chunks [begin, end) that are
 * touching now (apart = 0) or apart (1), in a SOLVE or RELAX pass
 * (pass_stage). */
static void fixed_sweep(const rbs__soft_rows *k, int stage, uint32_t begin, uint32_t end, int apart,
                        rbs__soft_report *report)
{
    uint32_t i, l;
    for (i = begin; i < end; ++i) {
        rbs__chunk *c = &k->chunk[i];
        unsigned bits, pick = 0;
        if (!(c->flags >> RBS__CH_FIXED & 1u))
            continue;
        bits = fixed_lanes(k, c);
        for (l = 0; l < c->count; ++l)
            if ((bits >> l & 1u) && lane_touching(k, c, l) != apart)
                pick |= 1u << l;
        if (pick == 0)
            continue;
        if (c->flags >> RBS__CH_SERIAL & 1u)
            row_lanes(k, c, pick, stage, report);
        else
            row_chunk(k, c, stage, 0, pick, report);
    }
}

/* One pass over the chunks [begin, end) in stage (stage < 0: the warm
 * start).  With a fixed sphere in the world (k->fixed), a SOLVE or RELAX
 * pass takes the lanes with a fixed sphere apart from the others: those
 * touching now before every other lane of the chunks, those apart after
 * them (fixed_sweep), as a serial chunk takes its touching lanes first
 * (row_lanes) -- a fixed sphere never moves, like a plane, and a moving
 * sphere's contacts with two of them lie in different chunks: the impulse
 * that stopped a ball at one, given back by the next sub-step's warm
 * start, was taken by the other's speculative row when that came first,
 * and a ball between two fixed spheres passed through one from 3e4 m/s
 * (docs/methods.md, "soft").  The lanes of a chunk that is not serial
 * share no body, so its two sets are each taken side by side (row_chunk
 * with the set active): they give the bits they would together. */
static ROW_INLINE void pass_stage(const rbs__soft_rows *k, int stage, uint32_t begin, uint32_t end,
                                  rbs__soft_report *report)
{
    const int fixed = k->fixed && (stage == RBS__SOFT_SOLVE || stage == RBS__SOFT_RELAX ||
                                   stage == RBS__SOFT_RELAX_REPORT);
    uint32_t i;
    if (fixed)
        fixed_sweep(k, stage, begin, end, 0, report);
    for (i = begin; i < end; ++i) {
        rbs__chunk *c = &k->chunk[i];
        unsigned f = c->flags, used = (1u << c->count) - 1u, active = used;
        int plane = (f >> RBS__CH_PLANE & 1u) != 0;
#if defined(__GNUC__)
        if (i + RBS__AHEAD < end) {
            /* (restitution reads the header of most chunks and nothing
             * more: the header's line alone) */
            const char *p = (const char *)(const void *)&k->chunk[i + RBS__AHEAD];
            const size_t bytes = stage == RBS__SOFT_RESTITUTION ? 64u : sizeof(rbs__chunk);
            size_t at;
            for (at = 0; at < bytes; at += 64)
                __builtin_prefetch(p + at, 1, 3); /* (for writing, kept in every cache) */
        }
#endif
        if (stage < 0)
            lone_lanes(k, c);
        if (fixed && (f >> RBS__CH_FIXED & 1u)) {
            /* (its lanes with a fixed sphere: fixed_sweep's) */
            const unsigned rest = used & ~fixed_lanes(k, c);
            if (rest && (f >> RBS__CH_SERIAL & 1u))
                row_lanes(k, c, rest, stage, report);
            else if (rest)
                row_chunk(k, c, stage, 0, rest, report);
            continue;
        }
        if (f >> RBS__CH_SERIAL & 1u) {
            if (f >> RBS__CH_WEDGE & 1u && stage >= 0)
                row_wedge(k, c, stage, report);
            else
                row_lanes(k, c, used, stage, report);
            continue;
        }
        if (stage < 0) {
            if (plane)
                warm_chunk(k, c, 1);
            else
                warm_chunk(k, c, 0);
            continue;
        }
        if (stage == RBS__SOFT_RESTITUTION) {
            /* only the lanes that bounce, and not a chunk without one */
            active = (f >> RBS__CH_TOUCHED) & (f >> RBS__CH_BOUNCE) & used;
            if (active == 0)
                continue;
        }
        if (plane)
            row_chunk(k, c, stage, 1, active, report);
        else
            row_chunk(k, c, stage, 0, active, report);
    }
    if (fixed)
        fixed_sweep(k, stage, begin, end, 1, report);
}

static void kernel_pass(const rbs__soft_rows *k, int stage, uint32_t begin, uint32_t end, rbs__soft_report *report)
{
    /* (each stage compiled on its own, its branches known) */
    if (stage < 0)
        pass_stage(k, -1, begin, end, report);
    else if (stage == RBS__SOFT_SOLVE)
        pass_stage(k, RBS__SOFT_SOLVE, begin, end, report);
    else if (stage == RBS__SOFT_RELAX)
        pass_stage(k, RBS__SOFT_RELAX, begin, end, report);
    else if (stage == RBS__SOFT_RELAX_REPORT)
        pass_stage(k, RBS__SOFT_RELAX_REPORT, begin, end, report);
    else
        pass_stage(k, RBS__SOFT_RESTITUTION, begin, end, report);
}

const rbs__soft_kernels RBS__SOFT_KERNELS = {kernel_pass};
