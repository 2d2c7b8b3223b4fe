/*
 * ieee.h - the library needs IEEE-754 double arithmetic as the C standard
 * defines it (internal; included by every module's internal header).
 *
 * Bad input is an error that names what is wrong, never a silent value:
 * the checks for NaN and infinity (isfinite) are how the library keeps that
 * promise, and -ffinite-math-only (part of -ffast-math) lets the compiler
 * fold every such check to "finite".  Results are also the same bits on
 * every build (docs/design.md), which -ffast-math's reassociation breaks.
 * So a build with either fails here instead of at run time.
 */
#ifndef RBS_CORE_IEEE_H
#define RBS_CORE_IEEE_H

/* No fused multiply-add unless the code asks for one (it never does), so
 * that results are the same bits with and without FMA hardware.  The
 * library's build passes -ffp-contract=off; this pragma holds for Clang
 * also in a build of the sources that does not (GCC ignores the standard
 * pragma: in a GNU -std mode it needs the flag). */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
#error "rbsim must be compiled without -ffast-math and -ffinite-math-only: its NaN and infinity checks and its bit-for-bit results need IEEE-754 arithmetic"
#endif

/* x for a message, in its shortest form that reads back as the same double
 * (0.1, not 0.10000000000000001; 1.0000001, not %g's 1), in buf (32 bytes
 * or more); returns buf. */
#include <stdio.h>
#include <stdlib.h>
static inline const char *rbs__shortest(char *buf, double x)
{
    int prec;
    for (prec = 1; prec < 17; ++prec) {
        snprintf(buf, 32, "%.*g", prec, x);
        if (strtod(buf, NULL) == x || x != x)
            return buf;
    }
    snprintf(buf, 32, "%.17g", x);
    return buf;
}

#endif
