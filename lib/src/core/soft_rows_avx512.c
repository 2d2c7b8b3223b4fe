/*
 * soft_rows_avx512.c - the soft step's rows with AVX as soft_rows_avx.c
 * has them, compiled for AVX-512VL: the same four lanes of 256 bits, and
 * the same operations, but 32 registers instead of 16, so that a row's
 * values stay in registers (with 16 they spill to the stack: about a fifth
 * of the AVX kernel's instructions).  Entered only when the processor has
 * AVX-512F and AVX-512VL; the same bits as soft_rows.c.
 */
#include "core/soft.h"

#if defined(RBS_HAVE_AVX_KERNELS)
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx,avx512f,avx512vl"))), apply_to = function)
#else
#pragma GCC target("avx,avx512f,avx512vl")
#endif
#define RBS__WIDE_AVX 1
#define RBS__SOFT_KERNELS rbs__soft_kernels_avx512
#include "core/soft_rows.h"
#if defined(__clang__)
#pragma clang attribute pop
#endif
#else
typedef int rbs__soft_rows_avx512_empty; /* (ISO C: a translation unit declares something) */
#endif
