/*
 * soft_rows.c - the soft step's rows on four plain doubles a value: the
 * kernels every build has (soft_rows.h; soft_rows_avx.c gives the same
 * bits with AVX).
 */
#define RBS__SOFT_KERNELS rbs__soft_kernels_plain
#include "core/soft_rows.h"
