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

#endif
