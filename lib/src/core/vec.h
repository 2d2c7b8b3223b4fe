/* vec.h - small vector, quaternion and 3x3 helpers for the core (internal). */
#ifndef RBS_CORE_VEC_H
#define RBS_CORE_VEC_H

#include <math.h>

#include "core/ieee.h"

#define RBS__PI 3.14159265358979323846

typedef struct v3 {
    double x, y, z;
} v3;

static inline v3 v3_make(double x, double y, double z) { v3 r = {x, y, z}; return r; }
static inline v3 v3_load(const double *p) { v3 r = {p[0], p[1], p[2]}; return r; }
static inline void v3_store(double *p, v3 a) { p[0] = a.x; p[1] = a.y; p[2] = a.z; }
static inline v3 v3_add(v3 a, v3 b) { return v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline v3 v3_sub(v3 a, v3 b) { return v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline v3 v3_scale(v3 a, double s) { return v3_make(a.x * s, a.y * s, a.z * s); }
static inline v3 v3_mad(v3 a, v3 b, double s) { return v3_make(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline double v3_dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline v3 v3_cross(v3 a, v3 b)
{
    return v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_len(v3 a) { return sqrt(v3_dot(a, a)); }
/* |a| also where its square underflows (|a| under about 1e-154; below 1e-162
 * the square is 0): a scaled by 2^600 and back, exact powers of two; the
 * same bits as v3_len from 1e-150 up. */
static inline double v3_len_small(v3 a)
{
    const double s = v3_len(a);
    if (s >= 1e-150 || (a.x == 0.0 && a.y == 0.0 && a.z == 0.0))
        return s;
    return v3_len(v3_scale(a, 0x1p600)) * 0x1p-600;
}
/* a / len for len = v3_len_small(a) > 0, also where 1 / len would
 * overflow (len subnormal); the same bits as a scaled by 1 / len from
 * 1e-150 up. */
static inline v3 v3_unit_small(v3 a, double len)
{
    if (len >= 1e-150)
        return v3_scale(a, 1.0 / len);
    return v3_scale(v3_scale(a, 0x1p600), 1.0 / (len * 0x1p600));
}
static inline int v3_finite(v3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* Quaternion [w x y z] stored as 4 doubles. */
typedef struct quat {
    double w, x, y, z;
} quat;

static inline quat q_load(const double *p) { quat q = {p[0], p[1], p[2], p[3]}; return q; }
static inline void q_store(double *p, quat q) { p[0] = q.w; p[1] = q.x; p[2] = q.y; p[3] = q.z; }
static inline quat q_mul(quat a, quat b)
{
    quat r;
    r.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    r.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    r.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    r.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return r;
}
static inline quat q_normalize(quat q)
{
    double n = sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    quat r = {q.w / n, q.x / n, q.y / n, q.z / n};
    return r;
}
/* Rotate v by unit quaternion q (body -> world). */
static inline v3 q_rotate(quat q, v3 v)
{
    v3 u = v3_make(q.x, q.y, q.z);
    v3 t = v3_scale(v3_cross(u, v), 2.0);
    return v3_add(v3_add(v, v3_scale(t, q.w)), v3_cross(u, t));
}
/* Rotate v by the inverse of q (world -> body). */
static inline v3 q_rotate_inv(quat q, v3 v)
{
    quat c = {q.w, -q.x, -q.y, -q.z};
    return q_rotate(c, v);
}

/* sin x and cos x.  For |x| <= 1/8 -- every turn of a step in a pile --
 * from their Taylor series to x^9 and x^10, whose remainders (below
 * x^11 / 11! and x^12 / 12!) are under 3e-18 and 3e-20, a fraction of an
 * ulp of the results: within the rounding of the Horner sums (about 1 ulp;
 * tests/core/test_vec.c compares with extended precision).  Beyond,
 * libm's.  The series keep a pile from calling libm at all: a process's
 * first sin or cos faults in about 280 KB of libm's code and tables
 * (measured in /proc/self/smaps), a fifth of what a 1,000-sphere pile
 * otherwise holds beyond a lone ball. */
static inline void rbs__sincos(double x, double *s, double *c)
{
    if (fabs(x) <= 0.125) {
        double x2 = x * x;
        if (x2 == 0.0) { /* (sin x = x, keeping the sign of a zero) */
            *s = x;
            *c = 1.0;
            return;
        }
        *s = x + x * x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0))));
        *c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0 + x2 * (-1.0 / 3628800.0)))));
        return;
    }
    *s = sin(x);
    *c = cos(x);
}

/* The exact rotation by angle |w|*h about w, as a unit quaternion. */
static inline quat q_from_rotation(v3 w, double h)
{
    double wl = v3_len(w);
    double half = 0.5 * wl * h;
    quat r = {1.0, 0.0, 0.0, 0.0};
    if (wl > 0.0) {
        double sh, ch, s;
        rbs__sincos(half, &sh, &ch);
        s = sh / wl;
        r.w = ch;
        r.x = w.x * s;
        r.y = w.y * s;
        r.z = w.z * s;
    }
    return r;
}

/* The rotation by the rotation vector th (angle |th| rad about th), as a
 * unit quaternion (cos x, sin x th / |th|) with x = |th| / 2: for x at most
 * 1/8 (every turn of a frame in a pile) cos x and sin x / (2 x) from their
 * Taylor series in x^2 (remainders below x^12 / 12! and x^10 / 11!, a
 * fraction of an ulp, as rbs__sincos), without |th| and its square root;
 * beyond, q_from_rotation. */
static inline quat q_from_turn(v3 th)
{
    const double x2 = 0.25 * v3_dot(th, th);
    quat t;
    double so;
    if (!(x2 <= 1.0 / 64.0))
        return q_from_rotation(th, 1.0);
    so = 0.5 * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0)))));
    t.w = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0 + x2 * (-1.0 / 3628800.0)))));
    t.x = th.x * so;
    t.y = th.y * so;
    t.z = th.z * so;
    return t;
}

/* Symmetric 3x3 as a full row-major matrix. */
static inline v3 m3_mul(const double *m, v3 v)
{
    return v3_make(m[0] * v.x + m[1] * v.y + m[2] * v.z,
                   m[3] * v.x + m[4] * v.y + m[5] * v.z,
                   m[6] * v.x + m[7] * v.y + m[8] * v.z);
}
/* World-frame product (R M R^T) v for a body-frame matrix M. */
static inline v3 m3_mul_world(const double *m, quat q, v3 v)
{
    return q_rotate(q, m3_mul(m, q_rotate_inv(q, v)));
}

#endif
