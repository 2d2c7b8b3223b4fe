/*
 * wide.h - four doubles side by side (internal): the lanes of the soft
 * step's contact rows (soft_rows.h).
 *
 * Two backends behind one set of inline functions, chosen when the file is
 * compiled: with RBS__WIDE_AVX, AVX intrinsics (one 256-bit register a
 * value; the translation unit is compiled with -mavx and entered only when
 * the processor has AVX); otherwise four plain doubles, lane by lane.  Every
 * function is, lane for lane, the C operation its comment names -- IEEE-754
 * addition, multiplication, division and square root are correctly rounded,
 * comparisons are C's (false when either side is NaN, except !=), and
 * nothing is fused -- so the two backends give the same bits (tests/core/
 * test_wide.c steps piles with both and compares).
 *
 * Masks are lanes of all ones (true) or all zeros (false); wd_sel picks
 * lane by lane as C's ?: does.
 */
#ifndef RBS_CORE_WIDE_H
#define RBS_CORE_WIDE_H

#include <stdint.h>

#include "core/ieee.h"

#define RBS__LANES 4

#if defined(RBS__WIDE_AVX)
#include <immintrin.h>

typedef __m256d rbs__wd; /* four doubles */
typedef __m256d rbs__wm; /* four lane masks */

static inline rbs__wd wd_load(const double *p) { return _mm256_loadu_pd(p); }
static inline void wd_store(double *p, rbs__wd a) { _mm256_storeu_pd(p, a); }
static inline rbs__wd wd_set(double x) { return _mm256_set1_pd(x); }
/* lanes 0..3 = a, b, c, d */
static inline rbs__wd wd_make(double a, double b, double c, double d) { return _mm256_setr_pd(a, b, c, d); }
static inline rbs__wd wd_zero(void) { return _mm256_setzero_pd(); }
static inline rbs__wd wd_add(rbs__wd a, rbs__wd b) { return _mm256_add_pd(a, b); }
static inline rbs__wd wd_sub(rbs__wd a, rbs__wd b) { return _mm256_sub_pd(a, b); }
static inline rbs__wd wd_mul(rbs__wd a, rbs__wd b) { return _mm256_mul_pd(a, b); }
static inline rbs__wd wd_div(rbs__wd a, rbs__wd b) { return _mm256_div_pd(a, b); }
static inline rbs__wd wd_sqrt(rbs__wd a) { return _mm256_sqrt_pd(a); }
/* -a (the sign bit flipped, as C's unary minus) */
static inline rbs__wd wd_neg(rbs__wd a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
/* a < b, a <= b, a > b (false for NaN), a != b (true for NaN) */
static inline rbs__wm wm_lt(rbs__wd a, rbs__wd b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
static inline rbs__wm wm_le(rbs__wd a, rbs__wd b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
static inline rbs__wm wm_gt(rbs__wd a, rbs__wd b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
static inline rbs__wm wm_ne(rbs__wd a, rbs__wd b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
static inline rbs__wm wm_and(rbs__wm a, rbs__wm b) { return _mm256_and_pd(a, b); }
static inline rbs__wm wm_or(rbs__wm a, rbs__wm b) { return _mm256_or_pd(a, b); }
/* a && !b */
static inline rbs__wm wm_andnot(rbs__wm a, rbs__wm b) { return _mm256_andnot_pd(b, a); }
/* m ? a : b, as bit operations (GCC 12 turns _mm256_blendv_pd, without
 * AVX2, into a branch per lane) */
static inline rbs__wd wd_sel(rbs__wm m, rbs__wd a, rbs__wd b)
{
    return _mm256_or_pd(_mm256_and_pd(m, a), _mm256_andnot_pd(m, b));
}
/* bit l set when lane l is true */
static inline unsigned wm_bits(rbs__wm m) { return (unsigned)_mm256_movemask_pd(m); }
/* the mask of bits (bit l: lane l), from a table (the lane's own bit as a
 * double would be a denormal, which a denormals-are-zero mode set by the
 * host program would take for zero) */
static inline rbs__wm wm_from_bits(unsigned bits)
{
    static const uint64_t table[16][4] = {
#define RBS__M(b) {(b) & 1u ? ~0ull : 0ull, (b) & 2u ? ~0ull : 0ull, (b) & 4u ? ~0ull : 0ull, (b) & 8u ? ~0ull : 0ull}
        RBS__M(0u),  RBS__M(1u),  RBS__M(2u),  RBS__M(3u),  RBS__M(4u),  RBS__M(5u),  RBS__M(6u),  RBS__M(7u),
        RBS__M(8u),  RBS__M(9u),  RBS__M(10u), RBS__M(11u), RBS__M(12u), RBS__M(13u), RBS__M(14u), RBS__M(15u),
#undef RBS__M
    };
    return _mm256_loadu_pd((const double *)(const void *)table[bits & 15u]);
}

/* The 4x4 transpose: out[k] lane l = in[l] element k. */
static inline void wd_transpose(rbs__wd *c0, rbs__wd *c1, rbs__wd *c2, rbs__wd *c3)
{
    __m256d t0 = _mm256_unpacklo_pd(*c0, *c1), t1 = _mm256_unpackhi_pd(*c0, *c1);
    __m256d t2 = _mm256_unpacklo_pd(*c2, *c3), t3 = _mm256_unpackhi_pd(*c2, *c3);
    *c0 = _mm256_permute2f128_pd(t0, t2, 0x20);
    *c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
    *c2 = _mm256_permute2f128_pd(t0, t2, 0x31);
    *c3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/* out[4 k + e] lane l = rec[l][4 k + e] for blocks k < nblocks of four
 * doubles: the first 4 nblocks doubles of four records, as lanes. */
static inline void wd_gather(const double *const rec[4], int nblocks, rbs__wd *out)
{
    int k;
    for (k = 0; k < nblocks; ++k) {
        out[4 * k] = _mm256_loadu_pd(rec[0] + 4 * k);
        out[4 * k + 1] = _mm256_loadu_pd(rec[1] + 4 * k);
        out[4 * k + 2] = _mm256_loadu_pd(rec[2] + 4 * k);
        out[4 * k + 3] = _mm256_loadu_pd(rec[3] + 4 * k);
        wd_transpose(&out[4 * k], &out[4 * k + 1], &out[4 * k + 2], &out[4 * k + 3]);
    }
}

/* The inverse of wd_gather: rec[l][4 k + e] = in[4 k + e] lane l, lane 0
 * first (lanes that share a record leave lane 3's values). */
static inline void wd_scatter(double *const rec[4], int nblocks, const rbs__wd *in)
{
    int k;
    for (k = 0; k < nblocks; ++k) {
        rbs__wd c0 = in[4 * k], c1 = in[4 * k + 1], c2 = in[4 * k + 2], c3 = in[4 * k + 3];
        wd_transpose(&c0, &c1, &c2, &c3);
        _mm256_storeu_pd(rec[0] + 4 * k, c0);
        _mm256_storeu_pd(rec[1] + 4 * k, c1);
        _mm256_storeu_pd(rec[2] + 4 * k, c2);
        _mm256_storeu_pd(rec[3] + 4 * k, c3);
    }
}

#else /* four plain doubles */
#include <math.h>

typedef struct rbs__wd {
    double v[RBS__LANES];
} rbs__wd;
typedef struct rbs__wm {
    int v[RBS__LANES];
} rbs__wm;

#define RBS__WIDE_EACH(l) for (l = 0; l < RBS__LANES; ++l)

static inline rbs__wd wd_load(const double *p)
{
    rbs__wd r;
    int l;
    RBS__WIDE_EACH(l) r.v[l] = p[l];
    return r;
}
static inline void wd_store(double *p, rbs__wd a)
{
    int l;
    RBS__WIDE_EACH(l) p[l] = a.v[l];
}
static inline rbs__wd wd_set(double x)
{
    rbs__wd r;
    int l;
    RBS__WIDE_EACH(l) r.v[l] = x;
    return r;
}
static inline rbs__wd wd_make(double a, double b, double c, double d)
{
    rbs__wd r;
    r.v[0] = a;
    r.v[1] = b;
    r.v[2] = c;
    r.v[3] = d;
    return r;
}
static inline rbs__wd wd_zero(void) { return wd_set(0.0); }
static inline rbs__wd wd_add(rbs__wd a, rbs__wd b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] + b.v[l];
    return a;
}
static inline rbs__wd wd_sub(rbs__wd a, rbs__wd b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] - b.v[l];
    return a;
}
static inline rbs__wd wd_mul(rbs__wd a, rbs__wd b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] * b.v[l];
    return a;
}
static inline rbs__wd wd_div(rbs__wd a, rbs__wd b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] / b.v[l];
    return a;
}
static inline rbs__wd wd_sqrt(rbs__wd a)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = sqrt(a.v[l]);
    return a;
}
static inline rbs__wd wd_neg(rbs__wd a)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = -a.v[l];
    return a;
}
static inline rbs__wm wm_lt(rbs__wd a, rbs__wd b)
{
    rbs__wm m;
    int l;
    RBS__WIDE_EACH(l) m.v[l] = a.v[l] < b.v[l];
    return m;
}
static inline rbs__wm wm_le(rbs__wd a, rbs__wd b)
{
    rbs__wm m;
    int l;
    RBS__WIDE_EACH(l) m.v[l] = a.v[l] <= b.v[l];
    return m;
}
static inline rbs__wm wm_gt(rbs__wd a, rbs__wd b)
{
    rbs__wm m;
    int l;
    RBS__WIDE_EACH(l) m.v[l] = a.v[l] > b.v[l];
    return m;
}
static inline rbs__wm wm_ne(rbs__wd a, rbs__wd b)
{
    rbs__wm m;
    int l;
    RBS__WIDE_EACH(l) m.v[l] = a.v[l] != b.v[l];
    return m;
}
static inline rbs__wm wm_and(rbs__wm a, rbs__wm b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] && b.v[l];
    return a;
}
static inline rbs__wm wm_or(rbs__wm a, rbs__wm b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] || b.v[l];
    return a;
}
static inline rbs__wm wm_andnot(rbs__wm a, rbs__wm b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = a.v[l] && !b.v[l];
    return a;
}
static inline rbs__wd wd_sel(rbs__wm m, rbs__wd a, rbs__wd b)
{
    int l;
    RBS__WIDE_EACH(l) a.v[l] = m.v[l] ? a.v[l] : b.v[l];
    return a;
}
static inline unsigned wm_bits(rbs__wm m)
{
    unsigned bits = 0;
    int l;
    RBS__WIDE_EACH(l) bits |= (unsigned)(m.v[l] != 0) << l;
    return bits;
}
static inline rbs__wm wm_from_bits(unsigned bits)
{
    rbs__wm m;
    int l;
    RBS__WIDE_EACH(l) m.v[l] = (int)(bits >> l & 1u);
    return m;
}
static inline void wd_gather(const double *const rec[4], int nblocks, rbs__wd *out)
{
    int k, e, l;
    for (k = 0; k < 4 * nblocks; k += 4)
        for (e = 0; e < 4; ++e)
            RBS__WIDE_EACH(l) out[k + e].v[l] = rec[l][k + e];
}
static inline void wd_scatter(double *const rec[4], int nblocks, const rbs__wd *in)
{
    int k, e, l;
    RBS__WIDE_EACH(l)
    for (k = 0; k < 4 * nblocks; k += 4)
        for (e = 0; e < 4; ++e)
            rec[l][k + e] = in[k + e].v[l];
}
#undef RBS__WIDE_EACH
#endif

/* a b + c d and the like, in the order written (nothing fused) */
static inline rbs__wd wd_dot3(rbs__wd ax, rbs__wd ay, rbs__wd az, rbs__wd bx, rbs__wd by, rbs__wd bz)
{
    return wd_add(wd_add(wd_mul(ax, bx), wd_mul(ay, by)), wd_mul(az, bz));
}

#endif
