/*
 * cases.h - the extreme cases of rbsim, each run for one stepping method.
 *
 * A case builds a small world, runs it and reports one measured number and
 * the bound that number must meet, both stated in its description.  The same
 * cases drive the cmocka suite (test_extremes.c) and the table generator
 * (extremes_table.c, which writes docs/extremes.md), so the published table
 * is what the tests measure.
 */
#ifndef RBS_TEST_EXTREMES_CASES_H
#define RBS_TEST_EXTREMES_CASES_H

#include <stdint.h>

#include "rbsim/rbsim.h"

/* Outcome of one case for one method. */
typedef struct xres {
    int skipped;      /* 1: the method does not cover this scene (RBS_E_UNSUPPORTED) */
    int failed;       /* 1: a call failed unexpectedly (note says which) */
    double value;     /* the measured number (unit in the case's text) */
    double bound;     /* the bound it must meet: value <= bound */
    double extra;     /* a second reported number (see the case), or NAN */
    char note[256];   /* why skipped / failed, or a remark */
} xres;

typedef void (*xcase_fn)(rbs_method method, xres *out);

/* One case: its id, what it measures and the reason for its bound. */
typedef struct xcase {
    const char *id;      /* short id, e.g. "mass_ratio_1e9" */
    const char *what;    /* what is measured (with unit) */
    const char *bound;   /* the bound in words, with its reason */
    const char *extra;   /* what xres.extra holds, or NULL */
    int heavy;           /* 1: long run (own test, > 10 s) */
    xcase_fn run;
    /* Methods for which the bound is NOT promised (bit per rbs_method), with
     * the reason; the tests still run them and the table shows the number. */
    uint32_t not_promised;
    const char *why_not;
} xcase;

/* The cases, in table order; count in *n. */
const xcase *xcases(uint32_t *n);

/* Methods the table and tests try (every rbs_method but auto). */
#define XMETHODS RBS_METHOD_AUTO /* the concrete methods: auto takes euler or soft, bit for bit (test_auto.c) */

/* Passes = measured, not failed, value <= bound. */
int xres_pass(const xres *r);

#endif
