/*
 * soft_rows_avx.c - the soft step's rows with AVX: every function here is
 * compiled for AVX (and nothing fused: the library's -ffp-contract=off, and
 * AVX has no fused multiply-add), and step_soft.c enters them only when the
 * processor has AVX; the same bits as soft_rows.c.  Empty where the
 * compiler cannot target AVX (soft.h: RBS_HAVE_AVX_KERNELS).
 */
#include "core/soft.h"

#if defined(RBS_HAVE_AVX_KERNELS)
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC target("avx")
#endif
#define RBS__WIDE_AVX 1
#define RBS__SOFT_KERNELS rbs__soft_kernels_avx
#include "core/soft_rows.h"
#if defined(__clang__)
#pragma clang attribute pop
#endif
#else
typedef int rbs__soft_rows_avx_empty; /* (ISO C: a translation unit declares something) */
#endif
